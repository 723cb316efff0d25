//! No input makes the OpenFace, JSON-frame or timeline readers panic; well-formed rows
//! always read back their values.

use std::path::Path;

use grimace::io::openface::{OpenFaceReader, RowOutcome};
use grimace::io::timeline::parse_timeline;
use grimace::play::json::parse_flat_object;
use proptest::prelude::*;

const HEADER: &str = "frame, timestamp, success, AU01_r, AU12_r, AU12_c";

/// Pieces real and broken rows are made of.
fn field() -> impl Strategy<Value = String> {
    prop_oneof![
        (-10.0f64..10.0).prop_map(|v| format!("{v:.3}")),
        Just(" 1".to_string()),
        Just("0".to_string()),
        Just("".to_string()),
        Just("nan".to_string()),
        Just("1e999".to_string()),
        Just("1e300".to_string()),
        "[ -~]{0,6}",
        ".{0,4}",
    ]
}

fn line() -> impl Strategy<Value = String> {
    prop::collection::vec(field(), 0..8).prop_map(|f| f.join(","))
}

proptest! {
    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..2000)) {
        if let Ok(reader) = OpenFaceReader::new(&bytes[..], Path::new("r.csv")) {
            for row in reader.take(10_000) {
                let _ = row;
            }
        }
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse_flat_object(&text);
        let _ = parse_timeline(&text, Path::new("r.timeline.ron"));
    }

    #[test]
    fn random_lines_after_a_real_header_never_panic(
        lines in prop::collection::vec(line(), 0..30),
        crlf in any::<bool>(),
        final_newline in any::<bool>(),
    ) {
        let end = if crlf { "\r\n" } else { "\n" };
        let mut text = format!("{HEADER}{end}{}", lines.join(end));
        if final_newline {
            text.push_str(end);
        }
        // A field may hold a CR, which ends a line like LF does.
        let data_lines = text.replace("\r\n", "\n").replace('\r', "\n").lines().count() - 1;
        let reader = OpenFaceReader::new(text.as_bytes(), Path::new("r.csv")).unwrap();
        let mut seen = 0;
        for outcome in reader {
            let outcome = outcome.unwrap();
            seen += 1;
            match outcome {
                RowOutcome::Row(row) => {
                    prop_assert!(row.line >= 2);
                    prop_assert!(row.intensities.iter().all(|v| v.is_finite()));
                    if row.success {
                        prop_assert_eq!(row.intensities.len(), 2);
                    }
                }
                RowOutcome::Malformed(e) => prop_assert!(e.line >= 2 && e.line <= data_lines + 1),
            }
        }
        prop_assert!(seen <= data_lines);
    }

    #[test]
    fn well_formed_rows_read_back(
        rows in prop::collection::vec((0.0f32..5.0, 0.0f32..5.0, any::<bool>()), 1..20),
        pad in 0usize..3,
    ) {
        let sep = format!(",{}", " ".repeat(pad));
        let mut text = HEADER.to_string();
        for (i, (a, b, success)) in rows.iter().enumerate() {
            let fields = [
                (i + 1).to_string(),
                format!("{:.3}", i as f64 * 0.04),
                u8::from(*success).to_string(),
                a.to_string(),
                b.to_string(),
                "1".to_string(),
            ];
            text.push('\n');
            text.push_str(&fields.join(&sep));
        }
        let reader = OpenFaceReader::new(text.as_bytes(), Path::new("w.csv")).unwrap();
        let read: Vec<RowOutcome> = reader.map(Result::unwrap).collect();
        prop_assert_eq!(read.len(), rows.len());
        for (outcome, (a, b, success)) in read.iter().zip(&rows) {
            let RowOutcome::Row(row) = outcome else {
                return Err(TestCaseError::fail(format!("{outcome:?}")));
            };
            prop_assert_eq!(row.success, *success);
            if *success {
                prop_assert_eq!(&row.intensities, &vec![*a, *b]);
            }
        }
    }

    #[test]
    fn json_objects_read_back(pairs in prop::collection::vec(("[A-Za-z0-9_ ]{1,8}", -1e6f64..1e6), 0..20)) {
        let body: Vec<String> = pairs.iter().map(|(k, v)| format!("\"{k}\": {v}")).collect();
        let text = format!("{{{}}}", body.join(", "));
        let unique = pairs.iter().map(|(k, _)| k).collect::<std::collections::BTreeSet<_>>();
        if unique.len() == pairs.len() {
            prop_assert_eq!(parse_flat_object(&text).unwrap(), pairs);
        } else {
            // A key given twice refuses the frame.
            let e = parse_flat_object(&text).unwrap_err();
            prop_assert!(e.message.contains("appears twice"), "{}", e);
        }
    }
}
