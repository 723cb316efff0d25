//! `grimace play --headless` on real OpenFace output and on small hand-made CSVs, end to end
//! through the built binary.

use crate::play_common;

use play_common::{lines, play_headless, shared, stderr};

fn sample(name: &str) -> Option<String> {
    shared(&format!("openface-samples/{name}")).map(|p| p.display().to_string())
}

/// The frame lines (all but the final count) and the final count line.
fn split(output: &std::process::Output) -> (Vec<String>, String) {
    let mut all = lines(output);
    let last = all.pop().unwrap_or_default();
    (all, last)
}

#[test]
fn facsvatar_demo_faceid_plays_490_frames() {
    let Some(path) = sample("facsvatar_demo_faceid.csv") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = play_headless(dir.path(), &[&path], None);
    assert!(out.status.success(), "{}", stderr(&out));
    let (frames, last) = split(&out);
    assert_eq!(last, "played 490 frames, skipped 0");
    assert_eq!(frames.len(), 490);
    // Frame 1: AU01 0.50, AU06 1.04, AU12 1.74, AU26 0.37 on the 0-5 scale. Through the
    // fixture table: brow = 0.5/5, cheek = 1.04/5 + 0.5 * 1.74/5, mouth = 2 * 1.74/5,
    // jaw = 2 * 0.37/5.
    assert!(
        frames[0].starts_with("0.000 AU1=0.50 AU4=0.62 AU6=1.04"),
        "{}",
        frames[0]
    );
    assert!(
        frames[0].ends_with("| brow=0.10 cheek=0.38 mouth=0.70 jaw=0.15"),
        "{}",
        frames[0]
    );
    // 25 fps, timestamps from the file.
    assert!(frames[1].starts_with("0.040 "), "{}", frames[1]);
    assert!(frames[489].starts_with("19.560 "), "{}", frames[489]);
}

#[test]
fn unityhdrp_skips_the_five_untracked_rows() {
    let Some(path) = sample("unityhdrp_ok_nod_test.csv") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = play_headless(dir.path(), &[&path], None);
    assert!(out.status.success(), "{}", stderr(&out));
    let (frames, last) = split(&out);
    assert_eq!(last, "played 20 frames, skipped 5");
    assert_eq!(frames.len(), 20);
    assert!(frames[19].starts_with("0.760 "), "{}", frames[19]);
    // Untracked rows are not named one by one, only counted at the end, after the
    // missing-AU notice.
    let err = stderr(&out);
    assert_eq!(err.lines().count(), 2, "{err}");
    assert!(err.contains("the AU table has no AU2, AU4"), "{err}");
    assert!(
        err.ends_with("skipped 5 rows: 5 untracked (no face found, success 0)\n"),
        "{err}"
    );
}

#[test]
fn pyfeat_older_layout_without_final_newline_plays_100_frames() {
    let Some(path) = sample("pyfeat_OpenFace_Test.csv") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = play_headless(dir.path(), &[&path], None);
    assert!(out.status.success(), "{}", stderr(&out));
    let (frames, last) = split(&out);
    assert_eq!(last, "played 100 frames, skipped 0");
    assert_eq!(frames.len(), 100);
    assert!(frames[99].starts_with("0.099 "), "{}", frames[99]);
}

#[test]
fn facsvatar_clean_is_on_a_0_1_scale_with_scale_flag() {
    let Some(path) = sample("facsvatar_demo_clean.csv") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = play_headless(dir.path(), &["--scale", &path], None);
    assert!(out.status.success(), "{}", stderr(&out));
    let (frames, last) = split(&out);
    assert_eq!(last, "played 490 frames, skipped 0");
    // First row AU12 0.266 on 0-1: mouth = 2 * 0.266.
    assert!(frames[0].contains(" mouth=0.53"), "{}", frames[0]);
    // Without --scale the same value is read as 0.266 of 5.
    let out = play_headless(dir.path(), &[&path], None);
    let (frames, _) = split(&out);
    assert!(frames[0].contains(" mouth=0.11"), "{}", frames[0]);
}

const BAD: &str = "frame, timestamp, success, AU01_r, AU12_r\n\
1, 0.00, 1, 1.0, 2.5\n\
2, 0.04, 1, 1.0\n\
3, 0.08, 0, 0, 0\n\
4, 0.12, 1, 1.0, high\n\
5, 0.16, 1, 7.0, 9.0\n\
6, 0.20, 1, 0, 0";

#[test]
fn malformed_rows_are_named_by_line_and_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("bad.csv");
    std::fs::write(&csv, BAD).unwrap();
    let out = play_headless(dir.path(), &[csv.to_str().unwrap()], None);
    assert!(out.status.success(), "{}", stderr(&out));
    let (frames, last) = split(&out);
    assert_eq!(last, "played 3 frames, skipped 3");
    assert_eq!(
        frames,
        vec![
            "0.000 AU1=1.00 AU12=2.50 | brow=0.20 cheek=0.25 mouth=1.00",
            // 7 and 9 clamp to 5: AU1 at full, AU12 at full (mouth 2.0, cheek 0.5).
            "0.160 AU1=5.00 AU12=5.00 | brow=1.00 cheek=0.50 mouth=2.00",
            "0.200 | rest",
        ]
    );
    let err = stderr(&out);
    assert!(
        err.contains("bad.csv:3: 4 of 5 fields, the row is cut short (row skipped)"),
        "{err}"
    );
    assert!(
        err.contains("bad.csv:5:18: AU12_r `high` is not a number (row skipped)"),
        "{err}"
    );
    assert_eq!(
        err.matches("clamped").count(),
        1,
        "one clamp warning: {err}"
    );
    assert!(
        err.contains("bad.csv:6: AU1 intensity 7 is outside 0 to 5"),
        "{err}"
    );
}

#[test]
fn strict_stops_at_the_first_malformed_row() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("bad.csv");
    std::fs::write(&csv, BAD).unwrap();
    let out = play_headless(dir.path(), &["--strict", csv.to_str().unwrap()], None);
    assert_eq!(out.status.code(), Some(1));
    let (frames, last) = split(&out);
    assert!(
        frames.is_empty() && last.starts_with("0.000 "),
        "{frames:?} {last}"
    );
    assert!(
        stderr(&out).contains("bad.csv:3: 4 of 5 fields, the row is cut short"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn missing_file_and_bad_header_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = play_headless(dir.path(), &["/nonexistent/x.csv"], None);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("/nonexistent/x.csv"),
        "{}",
        stderr(&out)
    );
    let csv = dir.path().join("nope.csv");
    std::fs::write(&csv, "a, b, c\n1, 2, 3\n").unwrap();
    let out = play_headless(dir.path(), &[csv.to_str().unwrap()], None);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("nope.csv:1: the header has no AU intensity column"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn frames_limit_and_loop() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("two.csv");
    std::fs::write(&csv, "timestamp, AU06_r\n0.0, 5\n0.5, 0\n").unwrap();
    let out = play_headless(
        dir.path(),
        &["--loop", "--frames", "5", csv.to_str().unwrap()],
        None,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let (frames, last) = split(&out);
    assert_eq!(last, "played 5 frames, skipped 0");
    let times: Vec<&str> = frames.iter().map(|l| &l[..5]).collect();
    assert_eq!(times, ["0.000", "0.500", "0.000", "0.500", "0.000"]);
}

#[test]
fn realtime_keeps_the_source_pace() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("pace.csv");
    std::fs::write(&csv, "timestamp, AU06_r\n0.0, 1\n0.6, 1\n1.2, 1\n").unwrap();
    let started = std::time::Instant::now();
    let out = play_headless(
        dir.path(),
        &["--realtime", "--stats", csv.to_str().unwrap()],
        None,
    );
    let took = started.elapsed().as_secs_f64();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(took >= 1.2, "1.2 s of frames took {took} s");
    assert!(
        stderr(&out).contains("frames shown 3, dropped 0"),
        "{}",
        stderr(&out)
    );
    let started = std::time::Instant::now();
    let out = play_headless(
        dir.path(),
        &["--realtime", "--speed", "4", csv.to_str().unwrap()],
        None,
    );
    assert!(out.status.success());
    let took = started.elapsed().as_secs_f64();
    // 1.2 s of frames at 4x is paced to at least 0.3 s; no upper bound, since a busy machine
    // may start the process slowly (speed is measured by benches, not asserted).
    assert!(took >= 0.3, "at 4x 1.2 s took {took} s");
}
