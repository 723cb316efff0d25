//! `grimace export --gltf`: the written .glb read back with the `gltf` crate, every morph
//! target compared with `grimace export`'s OBJ of the same state; the node's scale; the
//! Khronos glTF Validator on each target set.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::grimace_in;
use glam::Vec3;
use grimace::io::arkit::ArkitMap;
use grimace::io::obj::read_obj;

/// A .glb read back: rest positions, target names, each target's position displacements,
/// and the node's scale.
pub(crate) struct Read {
    pub(crate) rest: Vec<Vec3>,
    pub(crate) names: Vec<String>,
    pub(crate) deltas: Vec<Vec<Vec3>>,
    scale: [f32; 3],
    triangles: usize,
}

pub(crate) fn read_glb(path: &Path) -> Read {
    let bytes = std::fs::read(path).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).expect("the crate reads the file");
    let bin = gltf.blob.clone().expect("a BIN chunk");
    let mesh = gltf.meshes().next().expect("one mesh");
    assert_eq!(gltf.meshes().count(), 1);
    let primitive = mesh.primitives().next().expect("one primitive");
    let reader = primitive.reader(|_| Some(&bin));
    let rest: Vec<Vec3> = reader
        .read_positions()
        .unwrap()
        .map(Vec3::from_array)
        .collect();
    let triangles = reader.read_indices().unwrap().into_u32().count() / 3;
    let deltas: Vec<Vec<Vec3>> = reader
        .read_morph_targets()
        .map(|(positions, _, _)| {
            positions
                .expect("every target has positions")
                .map(Vec3::from_array)
                .collect()
        })
        .collect();
    let extras: serde_json::Value =
        serde_json::from_str(mesh.extras().as_ref().expect("extras").get()).unwrap();
    let names: Vec<String> = extras["targetNames"]
        .as_array()
        .expect("targetNames")
        .iter()
        .map(|n| n.as_str().unwrap().to_string())
        .collect();
    assert_eq!(names.len(), deltas.len());
    assert_eq!(mesh.weights().map(<[f32]>::len), Some(names.len()));
    let node = gltf.nodes().next().unwrap();
    let (_, _, scale) = node.transform().decomposed();
    Read {
        rest,
        names,
        deltas,
        scale,
        triangles,
    }
}

fn export_glb(dir: &Path, targets: &str) -> Read {
    let out = grimace_in(dir, &["export", "--gltf", "face.glb", "--targets", targets]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    read_glb(&dir.join("face.glb"))
}

/// `grimace export ARGS --out state.obj`, read back.
fn export_obj(dir: &Path, args: &[&str]) -> Vec<Vec3> {
    let mut all = vec!["export", "--out", "state.obj"];
    all.extend_from_slice(args);
    let out = grimace_in(dir, &all);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    read_obj(&dir.join("state.obj")).unwrap().positions
}

fn assert_target_is(read: &Read, index: usize, expected: &[Vec3]) {
    let name = &read.names[index];
    assert_eq!(expected.len(), read.rest.len(), "{name}");
    let mut worst = 0.0f32;
    for ((rest, delta), want) in read.rest.iter().zip(&read.deltas[index]).zip(expected) {
        worst = worst.max((*rest + *delta - *want).abs().max_element());
    }
    assert!(worst <= 1e-5, "target {name}: off by {worst}");
}

#[test]
fn every_au_target_matches_the_obj_export() {
    let dir = tempfile::tempdir().unwrap();
    let read = export_glb(dir.path(), "aus");
    let rest = export_obj(dir.path(), &[]);
    assert_eq!(read.rest, rest, "the rest mesh is written as it is");
    assert_eq!(
        read.triangles, 8600,
        "the skin, both eyeballs and the mouth's parts"
    );
    assert!(read.names.contains(&"AU12".to_string()));
    assert!(read.names.contains(&"AU_L12".to_string()));
    let mut moving = 0;
    for (i, name) in read.names.iter().enumerate() {
        let key = name
            .strip_prefix("AU_")
            .or_else(|| name.strip_prefix("AU"))
            .unwrap();
        assert_target_is(&read, i, &export_obj(dir.path(), &["--au", key]));
        if read.deltas[i].iter().any(|d| *d != Vec3::ZERO) {
            moving += 1;
        }
    }
    assert_eq!(moving, read.names.len(), "every recorded AU moves the face");
}

#[test]
fn expression_and_muscle_targets_match_the_obj_export() {
    let dir = tempfile::tempdir().unwrap();
    let read = export_glb(dir.path(), "expressions");
    assert_eq!(
        read.names,
        [
            "anger",
            "contempt",
            "disgust",
            "fear",
            "happiness",
            "sadness",
            "surprise"
        ]
    );
    for (i, name) in read.names.iter().enumerate() {
        assert_target_is(&read, i, &export_obj(dir.path(), &["--expr", name]));
    }
    let read = export_glb(dir.path(), "muscles");
    assert_eq!(read.names.last().map(String::as_str), Some("jaw"));
    for (i, name) in read.names.iter().enumerate() {
        let set = format!("{name}=1");
        let args: Vec<&str> = if name == "jaw" {
            vec!["--jaw", "1"]
        } else {
            vec!["--set", &set]
        };
        assert_target_is(&read, i, &export_obj(dir.path(), &args));
    }
}

#[test]
fn arkit_targets_are_the_52_names_through_the_map() {
    let dir = tempfile::tempdir().unwrap();
    let read = export_glb(dir.path(), "arkit");
    assert_eq!(read.names, grimace::io::arkit::ARKIT_NAMES);
    let map = ArkitMap::builtin();
    let table = grimace::io::load_table(Path::new("presets/default.au.ron")).unwrap();
    let bilateral = |key: grimace::facs::AuKey| grimace::facs::AuKey {
        number: key.number,
        side: None,
    };
    let mut shown = 0;
    for (i, name) in read.names.iter().enumerate() {
        let moves = read.deltas[i].iter().any(|d| *d != Vec3::ZERO);
        match map.au(name) {
            Some(key) if table.aus.contains_key(&key) => {
                let expected = export_obj(dir.path(), &["--au", &key.to_string()]);
                assert_target_is(&read, i, &expected);
                shown += 1;
            }
            // A side the table records only bilaterally: that recording's side.
            Some(key) if key.side.is_some() && table.aus.contains_key(&bilateral(key)) => {
                assert!(moves, "{name}");
                shown += 1;
            }
            _ => assert!(!moves, "{name} has no AU in the table and must not move"),
        }
    }
    assert_eq!(shown, 33, "ARKit shapes that move on the built-in table");
    // eyeBlink_L + eyeBlink_R is AU 45: the two sides add up to the bilateral recording.
    let at = |n: &str| read.names.iter().position(|x| x == n).unwrap();
    let blink = export_obj(dir.path(), &["--au", "45"]);
    let (l, r) = (at("eyeBlink_L"), at("eyeBlink_R"));
    let mut worst = 0.0f32;
    for (v, want) in blink.iter().enumerate() {
        let sum = read.rest[v] + read.deltas[l][v] + read.deltas[r][v];
        worst = worst.max((sum - *want).abs().max_element());
    }
    assert!(worst < 1e-4, "L + R blink is off AU 45 by {worst}");
    assert!(share_at_positive_x(&read, "eyeBlink_L") > 0.95);
}

#[test]
fn the_node_scale_turns_face_units_into_metres() {
    let dir = tempfile::tempdir().unwrap();
    let read = export_glb(dir.path(), "expressions");
    // The built-in face: 1 unit = 11.5 mm (docs/face.md).
    assert_eq!(read.scale, [0.0115; 3]);
    let (min, max) = read.rest.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(a, b), p| (a.min(*p), b.max(*p)),
    );
    let height_m = (max.y - min.y) * read.scale[1];
    assert!(
        (0.15..0.25).contains(&height_m),
        "face height {height_m} m is not a head's"
    );
    let out = grimace_in(
        dir.path(),
        &[
            "export",
            "--gltf",
            "mm.glb",
            "--unit-mm",
            "2",
            "--targets",
            "muscles",
        ],
    );
    assert!(out.status.success());
    assert_eq!(read_glb(&dir.path().join("mm.glb")).scale, [0.002; 3]);
    let out = grimace_in(dir.path(), &["export", "--gltf", "x.glb", "--unit-mm=-1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--unit-mm"));
    assert!(!dir.path().join("x.glb").exists());
}

#[test]
fn gltf_and_a_state_do_not_mix() {
    let dir = tempfile::tempdir().unwrap();
    let out = grimace_in(dir.path(), &["export", "--gltf", "x.glb", "--au", "12"]);
    assert_eq!(out.status.code(), Some(2));
    let out = grimace_in(dir.path(), &["export", "--au", "12"]);
    assert_eq!(out.status.code(), Some(2), "neither --out nor --gltf");
}

/// Runs tests/gltf_validator/validate.js on a file: `None` (with the reason printed) where
/// node or the package is absent, which under `CI=true` is a failure.
fn validate(file: &Path) -> Option<String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gltf_validator/validate.js");
    let skip = |why: String| {
        if std::env::var("CI").as_deref() == Ok("true") {
            panic!("{why} (CI=true: .ci/run installs it)");
        }
        eprintln!("skipped: {why}");
        None
    };
    let out = match Command::new("node").arg(&script).arg(file).output() {
        Ok(out) => out,
        Err(e) => return skip(format!("node is not available ({e})")),
    };
    match out.status.code() {
        Some(0) => Some(String::from_utf8_lossy(&out.stdout).into_owned()),
        Some(3) => skip(
            "the npm package gltf-validator is not installed (npm install --prefix tests/gltf_validator)"
                .into(),
        ),
        _ => panic!(
            "{}: the glTF Validator reports errors:\n{}\n{}",
            file.display(),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    }
}

#[test]
fn the_khronos_validator_finds_no_errors() {
    let dir = tempfile::tempdir().unwrap();
    for targets in ["aus", "expressions", "muscles", "arkit"] {
        let file = format!("{targets}.glb");
        let out = grimace_in(
            dir.path(),
            &["export", "--gltf", &file, "--targets", targets],
        );
        assert!(out.status.success());
        let Some(report) = validate(&dir.path().join(&file)) else {
            return;
        };
        let report: serde_json::Value = serde_json::from_str(&report).unwrap();
        let issues = &report["issues"];
        assert_eq!(issues["numErrors"], 0, "{targets}: {issues}");
        assert_eq!(issues["numWarnings"], 0, "{targets}: {issues}");
        assert_eq!(report["info"]["hasMorphTargets"], true);
        let vertices = grimace::io::builtin::default_mesh().vertex_count();
        assert_eq!(report["info"]["totalVertexCount"], vertices);
    }
}

/// The share of a target's displacement (by length) on vertices at positive x.
fn share_at_positive_x(read: &Read, name: &str) -> f32 {
    let i = read.names.iter().position(|n| n == name).unwrap();
    let (mut plus, mut all) = (0.0f32, 0.0f32);
    for (rest, delta) in read.rest.iter().zip(&read.deltas[i]) {
        all += delta.length();
        if rest.x > 0.0 {
            plus += delta.length();
        }
    }
    plus / all
}

#[test]
fn sides_follow_gltf_the_subjects_left_at_positive_x() {
    let dir = tempfile::tempdir().unwrap();
    let read = export_glb(dir.path(), "aus");
    assert!(share_at_positive_x(&read, "AU_L12") > 0.95);
    assert!(share_at_positive_x(&read, "AU_R12") < 0.05);
    let read = export_glb(dir.path(), "arkit");
    assert!(share_at_positive_x(&read, "mouthSmile_L") > 0.95);
    assert!(share_at_positive_x(&read, "mouthSmile_R") < 0.05);
}
