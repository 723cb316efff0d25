//! Recordings of more than one face (OpenFace's multi-face tracker: one row per face and
//! frame, told apart by `face_id`): one face is captured and played, never a mix of two.

use grimace::capture::synthetic::{self, Motion};
use grimace::model::Activations;

use crate::common;
use crate::synthetic::{act, face};

/// Two people in one recording, interleaved row by row as OpenFace writes them: face 0
/// smiles on the left from the ninth frame, face 1 on the right.
fn two_faces() -> String {
    let face = face();
    let recording = |muscle: &str, seed: u64| {
        let poses: Vec<Option<Activations>> = (0..12)
            .map(|k| {
                let on = if k < 8 { 0.0 } else { 1.0 };
                Some(act(&face, &[(muscle, on)], 0.0))
            })
            .collect();
        let motion = Motion {
            seed,
            ..Motion::default()
        };
        synthetic::csv(&synthetic::landmarks(
            &face.bound,
            &face.vertices,
            &poses,
            motion,
        ))
    };
    let first = recording("L_Zygomatic_Major", 7);
    let second = recording("R_Zygomatic_Major", 11);
    let mut lines = first.lines();
    let mut text = format!("{}\n", lines.next().unwrap());
    for (a, b) in lines.zip(second.lines().skip(1)) {
        text.push_str(a);
        text.push('\n');
        // `frame, face_id, ...`: the second face's rows carry face_id 1.
        let (frame, rest) = b.split_once(", 0, ").unwrap();
        text.push_str(&format!("{frame}, 1, {rest}\n"));
    }
    text
}

/// The last row's value of `muscle` in an activation CSV.
fn last_value(acts: &str, muscle: &str) -> f64 {
    let mut lines = acts.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').map(str::trim).collect();
    let column = header.iter().position(|n| *n == muscle).unwrap();
    let last = lines.next_back().unwrap();
    last.split(',').nth(column).unwrap().trim().parse().unwrap()
}

#[test]
fn capture_follows_one_face_of_several() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("two.csv"), two_faces()).unwrap();

    let out = common::grimace_in(dir.path(), &["capture", "two.csv", "--out", "a.csv"]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{said}");
    assert!(
        said.contains("followed face 0; skipped 12 rows of face 1"),
        "{said}"
    );
    let acts = std::fs::read_to_string(dir.path().join("a.csv")).unwrap();
    assert_eq!(
        acts.lines().count(),
        13,
        "one row per frame of face 0: {acts}"
    );
    let (left, right) = (
        last_value(&acts, "L_Zygomatic_Major"),
        last_value(&acts, "R_Zygomatic_Major"),
    );
    assert!(left > 0.9 && right < 0.05, "left {left}, right {right}");
    let manifest = std::fs::read_to_string(dir.path().join("a.capture.txt")).unwrap();
    assert!(manifest.contains("followed face 0"), "{manifest}");

    let out = common::grimace_in(
        dir.path(),
        &["capture", "two.csv", "--out", "b.csv", "--face", "1"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let acts = std::fs::read_to_string(dir.path().join("b.csv")).unwrap();
    // OpenFace's bookkeeping columns name the face followed and carry the tracker's confidence.
    assert!(
        acts.lines()
            .nth(1)
            .unwrap()
            .starts_with("1, 1, 0.000, 0.980, 1, "),
        "{acts}"
    );
    let (left, right) = (
        last_value(&acts, "L_Zygomatic_Major"),
        last_value(&acts, "R_Zygomatic_Major"),
    );
    assert!(right > 0.9 && left < 0.05, "left {left}, right {right}");

    let out = common::grimace_in(
        dir.path(),
        &["capture", "two.csv", "--out", "c.csv", "--face", "2"],
    );
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        said.contains("two.csv: no tracked row of face 2; the recording's faces: 0, 1"),
        "{said}"
    );
    assert!(!dir.path().join("c.csv").exists());
}

#[test]
fn play_follows_one_face_of_several() {
    let dir = tempfile::tempdir().unwrap();
    let text = "frame, face_id, timestamp, success, AU01_r, AU12_r\n\
                1, 0, 0.000, 1, 0, 2\n1, 1, 0.000, 1, 4, 0\n\
                2, 1, 0.033, 1, 4, 0\n2, 0, 0.033, 1, 0, 2\n";
    std::fs::write(dir.path().join("two.csv"), text).unwrap();

    let out = common::grimace_in(dir.path(), &["play", "two.csv", "--headless"]);
    let (shown, said) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{said}");
    let frames: Vec<&str> = shown.lines().filter(|l| l.contains(" | ")).collect();
    assert_eq!(frames.len(), 2, "{shown}");
    assert!(
        frames
            .iter()
            .all(|l| l.contains("AU12=") && !l.contains("AU1=")),
        "{shown}"
    );
    assert!(said.contains("--face 1"), "the other face is named: {said}");
    assert!(
        said.contains("followed face 0; skipped 2 rows of face 1"),
        "and counted at the end: {said}"
    );

    let out = common::grimace_in(
        dir.path(),
        &["play", "two.csv", "--headless", "--face", "1"],
    );
    let shown = String::from_utf8_lossy(&out.stdout);
    let frames: Vec<&str> = shown.lines().filter(|l| l.contains(" | ")).collect();
    assert_eq!(frames.len(), 2, "{shown}");
    assert!(
        frames
            .iter()
            .all(|l| l.contains("AU1=") && !l.contains("AU12=")),
        "{shown}"
    );
}

/// Two recordings joined end to end (frames 1-12, then 1-12 again): the second run's first
/// frame is solved afresh, not held near the first run's last, so it reads as the first
/// run's first frame does.
#[test]
fn a_recording_joined_to_itself_starts_afresh() {
    let dir = tempfile::tempdir().unwrap();
    let face = face();
    let poses: Vec<Option<Activations>> = (0..12)
        .map(|k| {
            let on = if k < 6 { 0.0 } else { 1.0 };
            Some(act(&face, &[("L_Zygomatic_Major", on)], 0.0))
        })
        .collect();
    let once = synthetic::csv(&synthetic::landmarks(
        &face.bound,
        &face.vertices,
        &poses,
        Motion::default(),
    ));
    let rows: Vec<&str> = once.lines().skip(1).collect();
    let twice = format!("{once}{}\n", rows.join("\n"));
    std::fs::write(dir.path().join("twice.csv"), twice).unwrap();
    let out = common::grimace_in(
        dir.path(),
        &["capture", "twice.csv", "--out", "a.csv", "--neutral", "1"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let acts = std::fs::read_to_string(dir.path().join("a.csv")).unwrap();
    let lines: Vec<&str> = acts.lines().collect();
    assert_eq!(lines.len(), 25, "{acts}");
    // The columns after the frame's own bookkeeping (frame, face, time) agree exactly.
    let solved = |line: &str| line.splitn(4, ", ").nth(3).unwrap().to_string();
    assert_eq!(solved(lines[13]), solved(lines[1]));
}
