//! The OpenFace CSV reader: no panic on any input; a header error names the file; every
//! malformed row is reported with its line and a message.
#![no_main]

use std::path::Path;

use grimace::io::openface::{OpenFaceReader, RowOutcome};
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|bytes: &[u8]| {
    let path = Path::new("fuzz/input.csv");
    let mut reader = match OpenFaceReader::new(bytes, path) {
        Ok(reader) => reader,
        Err(err) => {
            assert_eq!(err.path, path);
            assert!(!err.message.trim().is_empty(), "{err:?}");
            common::names_file(path, &err);
            return;
        }
    };
    let columns = reader.columns().clone();
    assert!(!columns.aus.is_empty());
    let mut last_line = 0;
    for outcome in reader.by_ref() {
        match outcome.expect("reading from memory cannot fail") {
            RowOutcome::Row(row) => {
                assert!(row.line > last_line, "lines go forward: {}", row.line);
                last_line = row.line;
                if row.success {
                    assert_eq!(row.intensities.len(), columns.aus.len());
                    assert!(row.intensities.iter().all(|v| v.is_finite()), "{row:?}");
                }
            }
            RowOutcome::Malformed(err) => {
                assert!(err.line > last_line, "lines go forward: {err}");
                last_line = err.line;
                assert!(!err.message.trim().is_empty(), "{err:?}");
            }
        }
    }
});
