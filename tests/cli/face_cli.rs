//! `grimace gen-face` end to end: it writes exactly the committed face and presets.

use std::process::Command;

#[test]
fn gen_face_writes_the_committed_files() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let out = dir.path().join("nested/face.obj");
    let presets = dir.path().join("presets");
    let status = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .arg("gen-face")
        .arg("--out")
        .arg(&out)
        .arg("--presets")
        .arg(&presets)
        .status()
        .expect("grimace runs");
    assert!(status.success());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let same = |written: &std::path::Path, committed: &str| {
        let a = std::fs::read(written).expect("written file");
        let b = std::fs::read(root.join(committed)).expect("committed file");
        assert!(a == b, "{} differs from {committed}", written.display());
    };
    same(&out, "assets/face.obj");
    for name in ["paper.rig.ron", "default.rig.ron", "default.au.ron"] {
        same(&presets.join(name), &format!("presets/{name}"));
    }
}

#[test]
fn gen_face_reports_a_path_it_cannot_write() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let blocker = dir.path().join("file");
    std::fs::write(&blocker, "not a folder").expect("write");
    let output = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .arg("gen-face")
        .arg("--out")
        .arg(blocker.join("face.obj"))
        .output()
        .expect("grimace runs");
    assert_eq!(output.status.code(), Some(1));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(
        message.contains("gen-face") && message.contains("file"),
        "{message}"
    );
}
