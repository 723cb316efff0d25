//! Helpers shared by the integration tests (`mod common;` in each test file).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `grimace` binary with `args` in `dir`, capturing its output.
pub fn grimace_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// The shared reference folder: `GRIMACE_SHARED`, else `../shared` beside the package.
fn shared_root() -> PathBuf {
    std::env::var_os("GRIMACE_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"))
}

/// The shared reference folder when every path in `needed` (relative to it) exists.
/// Missing: a panic naming what is missing when `CI=true`, else `None` with the reason
/// printed, so the caller skips.
pub fn shared_with(needed: &[&str]) -> Option<PathBuf> {
    let dir = shared_root();
    let missing: Vec<String> = needed
        .iter()
        .map(|sub| dir.join(sub))
        .filter(|path| !path.exists())
        .map(|path| path.display().to_string())
        .collect();
    if missing.is_empty() {
        return Some(dir);
    }
    let what = missing.join(", ");
    if std::env::var("CI").as_deref() == Ok("true") {
        panic!("shared reference material missing: {what} (CI=true; set GRIMACE_SHARED)");
    }
    eprintln!("skipped: shared reference material missing: {what} (set GRIMACE_SHARED)");
    None
}

/// The shared reference folder with its classic golden outputs and Waters mesh files.
pub fn shared() -> Option<PathBuf> {
    shared_with(&["golden", "waters-geoface"])
}
