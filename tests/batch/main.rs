//! `grimace batch` end to end through the built binary: the example plan sharded, killed and
//! resumed, bad input, Slurm's environment, and a real single-node Slurm cluster.

#[path = "../common/mod.rs"]
mod common;

mod bad_input;
mod shards;
mod slurm;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The example plan (`presets/example.plan.ron`) written in `dir` with small pictures (24 x
/// 24), so its 336 items run in seconds.
fn small_example(dir: &Path) -> PathBuf {
    example_sized(dir, 24)
}

/// The example plan written in `dir` with pictures `side` x `side`: its 336 items cost time
/// in proportion to their pixels, not to the code's speed alone.
fn example_sized(dir: &Path, side: u32) -> PathBuf {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/example.plan.ron"),
    )
    .expect("presets/example.plan.ron");
    assert!(
        text.contains("size: (128, 128)"),
        "the example plan's size changed"
    );
    let path = dir.join("example.plan.ron");
    let size = format!("size: ({side}, {side})");
    std::fs::write(&path, text.replace("size: (128, 128)", &size)).expect("write plan");
    path
}

/// A plan file of this text in `dir`.
fn plan(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("test.plan.ron");
    std::fs::write(&path, text).expect("write plan");
    path
}

/// A small plan: two AUs at one intensity, as text and PNG.
const TINY: &str = r#"(
    version: 1,
    faces: [(name: "face", rig: "builtin:default")],
    show: [Aus(["1", "12"])],
    intensities: ["C"],
    text_size: (10, 5),
    size: (200, 200),
    outputs: [Txt, Png],
)"#;

/// `grimace batch ARGS` without Slurm's environment.
fn batch(args: &[&std::ffi::OsStr]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_grimace"));
    command.arg("batch").args(args);
    for (name, _) in std::env::vars_os() {
        if name.to_string_lossy().starts_with("SLURM_") {
            command.env_remove(name);
        }
    }
    command
}

fn run(args: &[&std::ffi::OsStr]) -> Output {
    batch(args).output().expect("grimace runs")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Every file under `dir` (relative paths), sorted.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("read folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                out.push(path.strip_prefix(dir).expect("inside").to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// Asserts that two batch folders hold the same merged labels, manifest and files, byte for
/// byte (the shards' own label files aside).
fn assert_same_batch(a: &Path, b: &Path) {
    let outputs = |dir: &Path| -> Vec<PathBuf> {
        files_under(dir)
            .into_iter()
            .filter(|p| !p.starts_with("labels"))
            .collect()
    };
    let (fa, fb) = (outputs(a), outputs(b));
    assert_eq!(fa, fb, "the two batches hold different files");
    for file in &fa {
        let same = std::fs::read(a.join(file)).unwrap() == std::fs::read(b.join(file)).unwrap();
        assert!(same, "{} differs between the batches", file.display());
    }
    assert!(fa.iter().any(|f| f == Path::new("labels.csv")));
}

/// A face whose rig names a mesh file writes its OBJ stimuli over that file (its groups,
/// materials and texture coordinates kept, `io::obj::MovedObj`), as `export` does: a
/// textured head's stimuli stay textured.
#[test]
fn obj_stimuli_of_a_mesh_file_keep_its_groups_and_materials() {
    let dir = tempfile::tempdir().expect("temp dir");
    let root = dir.path();
    let ok = |out: Output| assert!(out.status.success(), "{}", stderr(&out));
    common::fit_textured_head(root);
    let plan = plan(
        root,
        r#"(
    version: 1,
    faces: [(name: "head", rig: "head.rig.ron", table: "builtin:default")],
    show: [Aus(["12"])],
    intensities: ["E"],
    outputs: [Obj],
)"#,
    );
    let out = root.join("out");
    ok(run(&[plan.as_os_str(), "--out".as_ref(), out.as_os_str()]));
    let objs: Vec<PathBuf> = files_under(&out)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    assert!(!objs.is_empty(), "{:?}", files_under(&out));
    for path in objs {
        let text = std::fs::read_to_string(out.join(&path)).expect("stimulus");
        assert!(text.lines().any(|l| l == "usemtl skin"), "{path:?}");
        assert!(text.lines().any(|l| l == "vt 0 0"), "{path:?}");
        assert!(!text.lines().any(|l| l.starts_with("vn ")), "{path:?}");
        assert!(
            text.lines()
                .any(|l| l.starts_with("f ") && l.ends_with("/3")),
            "{path:?}"
        );
    }
}
