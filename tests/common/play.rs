//! Shared helpers of the `play` end-to-end tests: a small rig and AU table written to a
//! temporary folder, the shared-sample lookup, and running the built binary.
#![allow(dead_code)]

use crate::common;

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use glam::Vec3;
use grimace::facs::{AuEntry, AuKey, AuTable};
use grimace::model::{Linear, Muscle, MuscleKind, Rig, Side};

/// The built binary.
pub fn grimace() -> Command {
    Command::new(env!("CARGO_BIN_EXE_grimace"))
}

/// The shared sample `sub` (see `tests/common`): `None` (with a printed reason) when it is
/// missing outside CI; a panic under `CI=true`.
pub fn shared(sub: &str) -> Option<PathBuf> {
    common::shared_with(&[sub]).map(|root| root.join(sub))
}

fn muscle(name: &str) -> Muscle {
    Muscle {
        name: name.into(),
        side: Side::Centre,
        mirror: None,
        kind: MuscleKind::Linear(Linear {
            attachment: Vec3::ZERO,
            insertion: Vec3::X,
            zone: 30.0,
            falloff_start: 0.0,
            falloff_end: 1.0,
        }),
    }
}

/// A small rig (`brow`, `cheek`, `mouth`) and a table recording AU1, AU6, AU12 and AU26.
pub fn fixture_rig_and_table() -> (Rig, AuTable) {
    let rig = Rig {
        masks: Vec::new(),
        version: grimace::model::RIG_VERSION,
        mesh: PathBuf::from("builtin:default"),
        landmarks: None,
        combine: Default::default(),
        muscles: vec![muscle("brow"), muscle("cheek"), muscle("mouth")],
        jaw: None,
    };
    let entry = |pairs: &[(&str, f32)], jaw: f32| AuEntry {
        name: String::new(),
        muscles: pairs.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
        jaw,
    };
    let mut aus = BTreeMap::new();
    aus.insert(AuKey::new(1), entry(&[("brow", 1.0)], 0.0));
    aus.insert(AuKey::new(6), entry(&[("cheek", 1.0)], 0.0));
    aus.insert(
        AuKey::new(12),
        entry(&[("cheek", 0.5), ("mouth", 2.0)], 0.0),
    );
    aus.insert(AuKey::new(26), entry(&[], 2.0));
    let mut expressions = BTreeMap::new();
    expressions.insert("smile".to_string(), "6+12".to_string());
    let table = AuTable {
        version: 1,
        rig: PathBuf::from("face.rig.ron"),
        aus,
        expressions,
    };
    (rig, table)
}

/// Writes the fixture rig and table into `dir`; returns their paths.
pub fn write_fixture(dir: &Path) -> (PathBuf, PathBuf) {
    let (rig, table) = fixture_rig_and_table();
    let rig_path = dir.join("face.rig.ron");
    let table_path = dir.join("face.au.ron");
    std::fs::write(&rig_path, grimace::io::rig_to_ron(&rig)).unwrap();
    std::fs::write(&table_path, grimace::io::table_to_ron(&table)).unwrap();
    (rig_path, table_path)
}

/// Runs `grimace play --headless --rig R --table T ARGS...` with `stdin` fed in.
pub fn play_headless(dir: &Path, args: &[&str], stdin: Option<&[u8]>) -> Output {
    let (rig, table) = write_fixture(dir);
    let mut command = grimace();
    command
        .arg("play")
        .arg("--headless")
        .arg("--rig")
        .arg(&rig)
        .arg("--table")
        .arg(&table)
        .args(args)
        .stdin(if stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = command.spawn().expect("run grimace");
    if let Some(bytes) = stdin {
        let mut pipe = child.stdin.take().unwrap();
        // A run that fails early closes its stdin; the output says why.
        let _ = pipe.write_all(bytes);
    }
    child.wait_with_output().expect("wait for grimace")
}

/// The stdout lines of a run.
pub fn lines(output: &Output) -> Vec<String> {
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(str::to_string)
        .collect()
}

/// The stderr of a run.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Runs `command` (its output piped) and fails the test when it has not ended within
/// `seconds`: a run that stalls (a frame due in years, a pipe read twice) is a failure, not a
/// hung test.
pub fn output_within(command: &mut Command, seconds: u64) -> Output {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run grimace");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(seconds);
    while child.try_wait().expect("wait for grimace").is_none() {
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let out = child.wait_with_output().expect("wait for grimace");
            panic!(
                "still running after {seconds} s; stderr so far:\n{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().expect("wait for grimace")
}

/// `grimace play --headless --rig R --table T ARGS...` with the fixture written into `dir`
/// and stdin closed, ready for [`output_within`].
pub fn play_command(dir: &Path, args: &[&str]) -> Command {
    let (rig, table) = write_fixture(dir);
    let mut command = grimace();
    command
        .arg("play")
        .arg("--headless")
        .arg("--rig")
        .arg(&rig)
        .arg("--table")
        .arg(&table)
        .args(args)
        .stdin(Stdio::null());
    command
}
