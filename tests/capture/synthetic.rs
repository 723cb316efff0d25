//! Synthetic recordings: known activations deform the built-in face; its landmark vertices,
//! turned, moved, scaled to millimetres, noised and put in OpenFace's camera coordinates
//! (x right, y down, z away from the camera), are written as an OpenFace CSV.

use std::path::Path;

use glam::{DVec3, Vec3};
use grimace::capture::synthetic::{self, Motion};
use grimace::capture::{pose, LandmarkModel, Regularisation, Session};
use grimace::io::openface::{OpenFaceReader, RowOutcome};
use grimace::model::{Activations, BoundRig, Deformation};

use crate::common;

pub(crate) struct Face {
    pub(crate) bound: BoundRig,
    pub(crate) vertices: Vec<u32>,
}

impl Face {
    /// The rig's muscle names, in the rig's order (the solver's columns).
    pub(crate) fn names(&self) -> Vec<&str> {
        self.bound
            .rig()
            .muscles
            .iter()
            .map(|m| m.name.as_str())
            .collect()
    }
}

pub(crate) fn face() -> Face {
    let mesh = grimace::io::builtin::default_mesh();
    let rig = grimace::io::builtin::default_rig();
    let bound = Deformation::default().bind(&rig, &mesh).unwrap();
    let vertices = grimace::io::builtin::landmarks("default")
        .unwrap()
        .vertices(&mesh);
    Face { bound, vertices }
}

pub(crate) fn act(face: &Face, muscles: &[(&str, f32)], jaw: f32) -> Activations {
    let rig = face.bound.rig();
    let mut a = Activations::zero(rig);
    for (name, value) in muscles {
        a.muscles[rig.muscle_index(name).unwrap()] = *value;
    }
    a.jaw = jaw;
    a
}

/// The tracked rows of a CSV, read as capture reads them.
pub(crate) fn read(text: &str) -> Vec<Vec<Vec3>> {
    let mut reader = OpenFaceReader::with_landmarks(text.as_bytes(), Path::new("s.csv")).unwrap();
    let mut rows = Vec::new();
    while let Some(outcome) = reader.next_row().unwrap() {
        if let RowOutcome::Row(row) = outcome {
            if row.success {
                rows.push(row.landmarks);
            }
        }
    }
    rows
}

/// Solves every frame with an estimated neutral, as `capture` estimates it (the calm-frame
/// median, then the least-work neutral).
fn solve(face: &Face, rows: &[Vec<Vec3>]) -> Vec<Option<grimace::capture::Captured>> {
    let model = LandmarkModel::new(&face.bound, &face.vertices);
    let frames: Vec<&[Vec3]> = rows.iter().map(Vec::as_slice).collect();
    let (median, _) = pose::estimate_neutral(&frames).unwrap();
    let regularisation = Regularisation::default();
    let (neutral, _) =
        grimace::capture::neutral::least_work(&face.bound, &model, &frames, median, regularisation)
            .unwrap();
    let mut session = Session::new(
        &face.bound,
        &model,
        neutral,
        grimace::capture::NeutralSource::Frame(1),
        Regularisation::default(),
    )
    .unwrap();
    rows.iter().map(|r| session.frame(r)).collect()
}

/// Muscle names and activations.
type Muscles<'a> = &'a [(&'a str, f32)];

/// The recording: neutral frames, then each pose held for a few frames.
fn poses(face: &Face) -> Vec<(Activations, &'static str)> {
    let mut list = vec![(act(face, &[], 0.0), "neutral"); 12];
    let held: [(Muscles, f32, &str); 5] = [
        (&[("L_Zygomatic_Major", 0.8)], 0.0, "left smile"),
        (&[("R_Zygomatic_Major", 0.5)], 0.0, "right smile"),
        // AU1's muscle in the default rig (with it, a pose made with the overlapping
        // `Frontalis_Inner` is explained only 0.965)
        (
            &[("L_Frontalis_Medial", 0.75), ("R_Frontalis_Medial", 0.75)],
            0.0,
            "inner brows",
        ),
        (&[], 2.0, "jaw"),
        (
            &[("R_Angular_Depressor", 1.2)],
            1.0,
            "right depressor and jaw",
        ),
    ];
    for (muscles, jaw, what) in held {
        for _ in 0..4 {
            list.push((act(face, muscles, jaw), what));
        }
    }
    list
}

/// Muscles whose landmark column is closer than this (cosine) to another muscle's cannot be
/// told apart by the 68 landmarks; only their joint motion is checked.
const CONFUSABLE: f64 = 0.9;

#[test]
fn known_activations_are_solved_back_through_pose_and_noise() {
    let face = face();
    let poses = poses(&face);
    let acts: Vec<Option<Activations>> = poses.iter().map(|(a, _)| Some(a.clone())).collect();
    let frames = synthetic::landmarks(&face.bound, &face.vertices, &acts, Motion::default());
    let solved = solve(&face, &read(&synthetic::csv(&frames)));
    let names = face.names();
    let confusion = confusion(&face);
    for (k, ((want, what), got)) in poses.iter().zip(&solved).enumerate() {
        let got = got.as_ref().expect("every synthetic frame is usable");
        if what != &"neutral" {
            let e = got
                .explained
                .expect("a moving frame has an explained fraction");
            assert!(e > 0.97, "{what}: explained {e}");
        }
        // The temporal term lags a step change by design: a pose is checked once held.
        if k < 2 || poses[k - 2].1 != *what {
            continue;
        }
        for (i, (w, g)) in want
            .muscles
            .iter()
            .zip(&got.activations.muscles)
            .enumerate()
        {
            if confusion[i].0 < CONFUSABLE {
                assert!(
                    (w - g).abs() < 0.05,
                    "{what}: {} wanted {w}, solved {g}",
                    names[i]
                );
            }
        }
        let jaw = (want.jaw, got.activations.jaw);
        assert!((jaw.0 - jaw.1).abs() < 0.05, "{what}: jaw {jaw:?}");
    }
}

#[test]
fn pose_alone_gives_activations_near_zero() {
    let face = face();
    let rest = act(&face, &[], 0.0);
    let motion = Motion {
        noise: 0.05,
        seed: 11,
        ..Motion::default()
    };
    let frames = synthetic::landmarks(&face.bound, &face.vertices, &vec![Some(rest); 30], motion);
    for got in solve(&face, &read(&synthetic::csv(&frames))) {
        let got = got.unwrap();
        let most = got
            .activations
            .muscles
            .iter()
            .fold(got.activations.jaw / 2.0, |m, a| m.max(*a));
        assert!(most < 0.05, "pose alone woke a muscle to {most}");
        assert_eq!(got.explained, None, "a still face is below the noise floor");
    }
}

#[test]
fn garbage_frames_are_skipped_and_counted_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let face = face();
    let rest = act(&face, &[], 0.0);
    let smile = act(&face, &[("L_Zygomatic_Major", 1.0)], 0.0);
    let poses: Vec<Option<Activations>> = (0..12)
        .map(|k| Some(if k < 8 { rest.clone() } else { smile.clone() }))
        .collect();
    let mut frames = synthetic::landmarks(&face.bound, &face.vertices, &poses, Motion::default());
    frames.push(None);
    frames.push(Some(vec![Vec3::new(1.0, 2.0, 500.0); 68]));
    let mut text = synthetic::csv(&frames);
    // A NaN landmark, and a truncated last row.
    let mut fields: Vec<String> = text
        .lines()
        .nth(2)
        .unwrap()
        .split(", ")
        .map(String::from)
        .collect();
    fields[5] = "nan".into();
    text.push_str(&fields.join(", "));
    text.push('\n');
    text.push_str("99, 0, 3.3, 0.9, 1, 1.0, 2.0");
    std::fs::write(dir.path().join("rec.csv"), &text).unwrap();
    let out = common::grimace_in(dir.path(), &["capture", "rec.csv", "--out", "acts.csv"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("skipped 1 frames whose landmarks are not a usable face"),
        "{stderr}"
    );
    assert!(
        stderr.contains("1 untracked") && stderr.contains("2 malformed"),
        "{stderr}"
    );
    assert!(
        stderr.contains("cut short"),
        "the truncated row is named: {stderr}"
    );
    let acts = std::fs::read_to_string(dir.path().join("acts.csv")).unwrap();
    assert_eq!(acts.lines().count(), 1 + 12, "{acts}");
    let manifest = std::fs::read_to_string(dir.path().join("acts.capture.txt")).unwrap();
    assert!(manifest.contains("neutral: estimated"), "{manifest}");
    let _ = DVec3::ZERO;
}

#[test]
fn a_recording_without_3d_landmarks_says_which_columns_are_needed() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("2d.csv"),
        "frame, success, x_0, y_0, AU12_r\n1, 1, 3, 4, 0\n",
    )
    .unwrap();
    let out = common::grimace_in(dir.path(), &["capture", "2d.csv", "--out", "a.csv"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr.contains("2d.csv:1: the header lacks 204 of the 204 3D landmark columns"),
        "{stderr}"
    );
    assert!(stderr.contains("X_0..X_67"), "{stderr}");
}

/// For each muscle, the largest cosine between its landmark column and another muscle's
/// (weighted as the solve weighs): near 1, the landmarks cannot tell the two apart.
fn confusion(face: &Face) -> Vec<(f64, usize)> {
    let model = LandmarkModel::new(&face.bound, &face.vertices);
    let w: Vec<DVec3> = (0..68).map(pose::landmark_weight).collect();
    let dot = |a: usize, b: usize| {
        grimace::capture::solver::weighted_dot(&w, model.column(a), model.column(b))
    };
    (0..model.muscle_count())
        .map(|i| {
            (0..model.muscle_count())
                .filter(|&j| j != i && dot(j, j) > 0.0 && dot(i, i) > 0.0)
                .map(|j| (dot(i, j) / (dot(i, i) * dot(j, j)).sqrt(), j))
                .fold((0.0, i), |m, c| if c.0 > m.0 { c } else { m })
        })
        .collect()
}

#[test]
fn a_capture_replays_in_play_and_render_by_muscle_name() {
    let dir = tempfile::tempdir().unwrap();
    let face = face();
    let smile = act(&face, &[("L_Zygomatic_Major", 1.0)], 0.0);
    let poses: Vec<Option<Activations>> = (0..12)
        .map(|k| {
            Some(if k < 8 {
                act(&face, &[], 0.0)
            } else {
                smile.clone()
            })
        })
        .collect();
    let frames = synthetic::landmarks(&face.bound, &face.vertices, &poses, Motion::default());
    std::fs::write(dir.path().join("rec.csv"), synthetic::csv(&frames)).unwrap();
    let out = common::grimace_in(
        dir.path(),
        &["capture", "rec.csv", "--out", "acts.csv", "--aus"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let acts = std::fs::read_to_string(dir.path().join("acts.csv")).unwrap();
    assert!(
        acts.lines().next().unwrap().contains(", jaw, AU01_r"),
        "{acts}"
    );
    let play = common::grimace_in(dir.path(), &["play", "acts.csv", "--headless"]);
    let shown = String::from_utf8_lossy(&play.stdout);
    assert!(
        play.status.success(),
        "{}",
        String::from_utf8_lossy(&play.stderr)
    );
    let last = shown.lines().rfind(|l| l.contains(" | ")).unwrap();
    assert!(
        last.contains("L_Zygomatic_Major=1.0") || last.contains("L_Zygomatic_Major=0.9"),
        "{shown}"
    );
    assert!(
        !last.contains("R_Zygomatic_Major"),
        "the right side stays still: {last}"
    );
    let render = common::grimace_in(
        dir.path(),
        &["render", "--acts", "acts.csv", "--frame", "12"],
    );
    assert!(
        render.status.success(),
        "{}",
        String::from_utf8_lossy(&render.stderr)
    );
    let missing = common::grimace_in(
        dir.path(),
        &["render", "--acts", "acts.csv", "--frame", "99"],
    );
    assert!(String::from_utf8_lossy(&missing.stderr).contains("acts.csv: no frame 99"));
}

#[test]
fn live_reads_stdin_and_writes_each_frame() {
    use std::io::Write as _;
    let face = face();
    let smile = act(&face, &[("R_Zygomatic_Major", 0.8)], 0.0);
    let poses: Vec<Option<Activations>> = (0..10)
        .map(|k| match k {
            3 => None,
            0..=4 => Some(act(&face, &[], 0.0)),
            _ => Some(smile.clone()),
        })
        .collect();
    let frames = synthetic::landmarks(&face.bound, &face.vertices, &poses, Motion::default());
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["capture", "-", "--live", "--out", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let text = synthetic::csv(&frames);
    child
        .stdin
        .take()
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(
        lines.len(),
        1 + 9,
        "a header and one row per tracked frame: {stdout}"
    );
    let header: Vec<&str> = lines[0].split(", ").collect();
    let right = header
        .iter()
        .position(|n| *n == "R_Zygomatic_Major")
        .unwrap();
    let last: f64 = lines[9].split(", ").nth(right).unwrap().parse().unwrap();
    assert!((last - 0.8).abs() < 0.1, "{}", lines[9]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("1 untracked"));
}

#[test]
fn live_reads_udp_datagrams_on_loopback() {
    use std::io::{BufRead, BufReader};
    let face = face();
    let poses: Vec<Option<Activations>> = (0..4)
        .map(|k| Some(act(&face, &[("L_Zygomatic_Major", 0.3 * k as f32)], 0.0)))
        .collect();
    let frames = synthetic::landmarks(&face.bound, &face.vertices, &poses, Motion::default());
    let text = synthetic::csv(&frames);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["capture", "--live", "--udp", "127.0.0.1:0", "--out", "-"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut first = String::new();
    stderr.read_line(&mut first).unwrap();
    let address = first
        .trim()
        .strip_prefix("listening on udp ")
        .unwrap()
        .to_string();
    let socket = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    for line in text.lines() {
        socket.send_to(line.as_bytes(), &address).unwrap();
    }
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut lines = Vec::new();
    for _ in 0..5 {
        let mut line = String::new();
        stdout.read_line(&mut line).unwrap();
        lines.push(line);
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        lines[0].starts_with("frame, face_id, timestamp, confidence, success, explained, "),
        "{lines:?}"
    );
    assert!(lines[4].starts_with("4, 0, 0.100, 0.980, 1, "), "{lines:?}");
    let refused = common::grimace_in(
        std::path::Path::new("."),
        &["capture", "--live", "--udp", "8.8.8.8:9000", "--out", "-"],
    );
    assert!(String::from_utf8_lossy(&refused.stderr).contains("only loopback"));
}
