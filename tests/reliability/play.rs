//! `grimace play` against hostile timing and text: real-time output written when due, absurd
//! timestamps refused, skipped rows named and summarised, escapes in the input shown escaped.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common;
use common::grimace_in as grimace;

/// A folder with the corpus' good rig, mesh and table (AU 12 pulls `L_pull` and `R_pull`).
fn good_files() -> tempfile::TempDir {
    let corpus = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs");
    let dir = tempfile::tempdir().unwrap();
    for name in ["good.rig.ron", "good.obj", "good.au.ron"] {
        std::fs::copy(corpus.join(name), dir.path().join(name)).unwrap();
    }
    dir
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn play(dir: &Path, args: &[&str], input: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["play", "--headless", "--table", "good.au.ron"])
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(input).unwrap();
    drop(stdin);
    child.wait_with_output().unwrap()
}

/// Each frame is written when it is due: the first ones arrive while a later one waits.
#[test]
fn real_time_frames_are_written_when_due() {
    let dir = good_files();
    std::fs::write(
        dir.path().join("slow.csv"),
        "timestamp, AU12_r\n0.0, 5\n0.1, 2.5\n30.0, 0\n",
    )
    .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args([
            "play",
            "--headless",
            "--realtime",
            "--table",
            "good.au.ron",
            "slow.csv",
        ])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    let second = lines.next().unwrap().unwrap();
    let waited = start.elapsed();
    let still_running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(first, "0.000 AU12=5.00 | L_pull=1.00 R_pull=1.00");
    assert_eq!(second, "0.100 AU12=2.50 | L_pull=0.50 R_pull=0.50");
    assert!(still_running, "the frame due at 30 s was not waited for");
    assert!(waited < Duration::from_secs(20), "{waited:?}");
}

#[test]
fn absurd_timestamps_are_refused_not_waited_for() {
    let dir = good_files();
    std::fs::write(
        dir.path().join("far.csv"),
        "timestamp, AU12_r\n0.0, 5\n1e8, 5\n0.1, 2.5\n",
    )
    .unwrap();
    let start = Instant::now();
    let out = grimace(
        dir.path(),
        &[
            "play",
            "--headless",
            "--realtime",
            "--table",
            "good.au.ron",
            "far.csv",
        ],
    );
    assert!(start.elapsed() < Duration::from_secs(20));
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains(
            "far.csv:3: time 1e8 s is out of range (at most 1000000 in size) (row skipped)"
        ),
        "{}",
        stderr(&out)
    );
    assert!(String::from_utf8_lossy(&out.stdout).ends_with("played 2 frames, skipped 1\n"));
    let out = play(
        dir.path(),
        &["--stdin", "--realtime"],
        b"{\"timestamp\": 1e300, \"AU12\": 5}\n{\"timestamp\": 2, \"AU12\": 5}\n",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("stdin:1: time 1e300 s is out of range"),
        "{}",
        stderr(&out)
    );
}

/// Many bad rows: the first ten are named, the rest counted with the last one named, and
/// untracked rows counted by kind.
#[test]
fn skipped_rows_are_named_and_summarised() {
    let dir = good_files();
    let mut csv = String::from("frame, success, AU12_r, AU26_r\n1, 1, 5, 0\n2, 0, 0, 0\n");
    for frame in 3..103 {
        csv.push_str(&format!("{frame}, 1, 5\n"));
    }
    std::fs::write(dir.path().join("cut.csv"), csv).unwrap();
    let out = grimace(
        dir.path(),
        &["play", "--headless", "--table", "good.au.ron", "cut.csv"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 11, "{err}");
    assert_eq!(
        lines[0],
        "cut.csv:4: 3 of 4 fields, the row is cut short (row skipped)"
    );
    assert_eq!(
        lines[10],
        "skipped 101 rows: 1 untracked (no face found, success 0), 100 malformed (10 named above; 90 more not named, the last: cut.csv:103: 3 of 4 fields, the row is cut short)"
    );
}

/// Keys of a JSON stream and fields of a CSV reach stderr with their escapes shown.
#[test]
fn escapes_in_a_stream_are_shown_not_obeyed() {
    let dir = good_files();
    let out = play(
        dir.path(),
        &["--stdin"],
        b"{\"AU12\": 5, \"\\u001b]0;owned\\u0007\": 1}\n",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(!err.contains('\u{1b}') && !err.contains('\u{7}'), "{err:?}");
    assert!(err.contains("\\x1b]0;owned\\x07"), "{err}");
    std::fs::write(
        dir.path().join("esc.csv"),
        "frame, AU12_r\n1, \u{1b}[2J\u{1b}]0;x\u{7}\n",
    )
    .unwrap();
    let out = grimace(
        dir.path(),
        &["play", "--headless", "--table", "good.au.ron", "esc.csv"],
    );
    let err = stderr(&out);
    assert!(!err.contains('\u{1b}') && !err.contains('\u{7}'), "{err:?}");
    assert!(
        err.contains("AU12_r `\\x1b[2J\\x1b]0;x\\x07` is not a number"),
        "{err}"
    );
}
