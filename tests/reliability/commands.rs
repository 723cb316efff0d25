//! Every bad file through every command that reads it: exit status 1 and the file's error
//! on stderr, never 101 (a panic) or a signal. Meshes go through `export --mesh` (the
//! `validate` path is in `cli_bad_inputs.rs`), OpenFace CSVs and timelines through
//! `play --headless`, each with its exact message.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common;
use common::grimace_in as grimace;

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs")
}

fn expected(name: &str) -> String {
    std::fs::read_to_string(corpus().join(format!("{name}.err")))
        .unwrap()
        .trim_end()
        .to_string()
}

/// Exit 1 and exactly `grimace COMMAND: MESSAGE` on stderr.
fn assert_refused(out: &Output, command: &str, message: &str, what: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{what}: {stderr}");
    assert_eq!(
        stderr.trim_end(),
        format!("grimace {command}: {message}"),
        "{what}"
    );
}

#[test]
fn export_refuses_every_bad_mesh_with_its_exact_error() {
    let dir = corpus();
    let out_dir = tempfile::tempdir().unwrap();
    let out_file = out_dir.path().join("x.obj");
    let out_file = out_file.to_str().unwrap();
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if !name.ends_with(".obj") || name.starts_with("good.") {
            continue;
        }
        let out = grimace(
            &dir,
            &[
                "export",
                "--rig",
                "good.rig.ron",
                "--mesh",
                &name,
                "--set",
                "L_pull=1",
                "--out",
                out_file,
            ],
        );
        assert_refused(&out, "export", &expected(&name), &name);
        checked += 1;
    }
    assert!(checked >= 8, "{checked}");
    assert!(!Path::new(out_file).exists());
}

/// Bad OpenFace CSV files and the exact error `play` stops with.
const BAD_CSV: &[(&str, &[u8], &str)] = &[
    ("empty.csv", b"", "empty.csv: empty input: no header line"),
    ("blank.csv", b"\n \n\r\n", "blank.csv: empty input: no header line"),
    (
        "no_aus.csv",
        b"frame, timestamp, success\n1, 0.0, 1\n",
        "no_aus.csv:1: the header has no AU intensity column (AU01_r ... AU45_r); is this OpenFace output?",
    ),
    (
        "duplicate.csv",
        b"frame, AU12_r, AU12_r\n1, 0.5, 0.5\n",
        "duplicate.csv:1: column `AU12_r` appears twice in the header",
    ),
    (
        "garbage.csv",
        b"\x00\x01\x02\xff\xfe\x7f\x80\n\x00\x00",
        "garbage.csv:1: the header has no AU intensity column (AU01_r ... AU45_r); is this OpenFace output?",
    ),
];

#[test]
fn play_refuses_every_bad_csv_with_its_exact_error() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes, message) in BAD_CSV {
        std::fs::write(dir.path().join(name), bytes).unwrap();
        let out = grimace(dir.path(), &["play", "--headless", name]);
        assert_refused(&out, "play", message, name);
    }
}

#[test]
fn play_strict_stops_at_a_malformed_row_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    // (file, text, the line of the bad row); `\u{1}` stands for a byte that is not UTF-8.
    let rows: &[(&str, &str, usize)] = &[
        (
            "short.csv",
            "frame, success, AU12_r, AU06_r\n1, 1, 0.5, 0.5\n2, 1, 0.5\n",
            3,
        ),
        (
            "word.csv",
            "frame, success, AU12_r\n1, 1, 0.5\n2, 1, lots\n",
            3,
        ),
        ("nan.csv", "frame, success, AU12_r\n1, 1, NaN\n", 2),
        (
            "invalid_utf8.csv",
            "frame, success, AU12_r\n1, 1, 0.\u{1}5\n",
            2,
        ),
    ];
    for &(name, text, line) in rows {
        let bytes: Vec<u8> = text
            .bytes()
            .map(|b| if b == 1 { 0xff } else { b })
            .collect();
        std::fs::write(dir.path().join(name), bytes).unwrap();
        let at = format!("{name}:{line}:");
        let out = grimace(dir.path(), &["play", "--headless", "--strict", name]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
        assert!(
            stderr.starts_with(&format!("grimace play: {at}")),
            "{name}: {stderr}"
        );
        assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
        // Without --strict the row is skipped, named on stderr, and play succeeds.
        let out = grimace(dir.path(), &["play", "--headless", name]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{name}: {stderr}");
        assert!(stderr.starts_with(&at), "{name}: {stderr}");
        let lines: Vec<&str> = stderr.lines().collect();
        assert!(lines[0].ends_with("(row skipped)"), "{name}: {stderr}");
        assert_eq!(
            lines[1..],
            ["skipped 1 row: 1 malformed (1 named above)"],
            "{name}: {stderr}"
        );
    }
}

const TIMELINE_HEAD: &str = "Timeline(version: 1, frame_rate: 10.0, keyframes: [";

/// Bad timelines and the exact error `play` stops with.
fn bad_timelines() -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let with = |keys: &str| format!("{TIMELINE_HEAD}{keys}])").into_bytes();
    vec![
        (
            "empty.timeline.ron",
            vec![],
            "empty.timeline.ron:1:1: Expected opening `(` for struct `Timeline`",
        ),
        (
            "truncated.timeline.ron",
            format!("{TIMELINE_HEAD}(time: 0.0), (ti").into_bytes(),
            "truncated.timeline.ron:1:66: Unexpected field named `ti` in `Keyframe`, expected one of `time`, `aus`, `muscles`, or `jaw` instead",
        ),
        (
            "wrong_version.timeline.ron",
            b"Timeline(version: 9, frame_rate: 10.0, keyframes: [(time: 0.0)])".to_vec(),
            "wrong_version.timeline.ron: timeline version 9 is not supported (this build reads version 1)",
        ),
        (
            "unknown_field.timeline.ron",
            with("(time: 0.0, speed: 2.0)"),
            "unknown_field.timeline.ron:1:64: Unexpected field named `speed` in `Keyframe`, expected one of `time`, `aus`, `muscles`, or `jaw` instead",
        ),
        (
            "no_keyframes.timeline.ron",
            with(""),
            "no_keyframes.timeline.ron: the timeline has no keyframes",
        ),
        (
            "backwards.timeline.ron",
            with("(time: 1.0), (time: 0.5)"),
            "backwards.timeline.ron: keyframe 2 (time 0.5): times must not go backwards (previous 1)",
        ),
        (
            "nan_time.timeline.ron",
            with("(time: NaN)"),
            "nan_time.timeline.ron: keyframe 1 (time NaN): time must be a number of seconds from 0",
        ),
        (
            "negative_jaw.timeline.ron",
            with("(time: 0.0, jaw: -1.0)"),
            "negative_jaw.timeline.ron: keyframe 1 (time 0): activation of `jaw` is -1",
        ),
        (
            "zero_rate.timeline.ron",
            b"Timeline(version: 1, frame_rate: 0.0, keyframes: [(time: 0.0)])".to_vec(),
            "zero_rate.timeline.ron: frame_rate 0 is outside 0 to 1000 frames per second",
        ),
        (
            "too_long.timeline.ron",
            with("(time: 0.0), (time: 1e9)"),
            "too_long.timeline.ron: keyframe 2 (time 1000000000): the timeline is too long to sample",
        ),
        (
            "not_facs.timeline.ron",
            with("(time: 0.0, aus: \"3\")"),
            "not_facs.timeline.ron: keyframe 1 (time 0): the table has no AU 3",
        ),
        (
            "bad_combo.timeline.ron",
            with("(time: 0.0, aus: \"12@@\")"),
            "bad_combo.timeline.ron: keyframe 1 (time 0): `12@@`: column 4: expected a scale such as 0.5 after `@`, found nothing",
        ),
        (
            "unknown_muscle.timeline.ron",
            with("(time: 0.0, muscles: {\"nose\": 1.0})"),
            "unknown_muscle.timeline.ron: keyframe 1 (time 0): the rig has no muscle named `nose`",
        ),
        (
            "invalid_utf8.timeline.ron",
            b"Timeline(\xff)".to_vec(),
            "invalid_utf8.timeline.ron:1:10: invalid UTF-8 (byte 0xff); expected a text file",
        ),
        (
            "binary_garbage.timeline.ron",
            b"\x00\x9f\x92\x96\x00\x01".to_vec(),
            "binary_garbage.timeline.ron:1:2: invalid UTF-8 (byte 0x9f); expected a text file",
        ),
    ]
}

#[test]
fn play_refuses_every_bad_timeline_with_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes, message) in bad_timelines() {
        std::fs::write(dir.path().join(name), &bytes).unwrap();
        let out = grimace(dir.path(), &["play", "--headless", name]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        eprintln!("{name} => {}", stderr.trim_end());
        if message.is_empty() {
            assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
            assert!(
                stderr.starts_with(&format!("grimace play: {name}")),
                "{stderr}"
            );
        } else {
            assert_refused(&out, "play", message, name);
        }
    }
}

#[test]
fn play_of_a_missing_file_or_a_folder_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("folder.csv")).unwrap();
    std::fs::create_dir(dir.path().join("folder.timeline.ron")).unwrap();
    for name in [
        "missing.csv",
        "missing.timeline.ron",
        "folder.csv",
        "folder.timeline.ron",
    ] {
        let out = grimace(dir.path(), &["play", "--headless", name]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
        assert!(stderr.starts_with("grimace play: "), "{name}: {stderr}");
        assert!(stderr.contains(name), "{name}: {stderr}");
    }
}
