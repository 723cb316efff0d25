//! The corpus of bad inputs in `tests/bad_inputs/`: each file `NAME` has its exact expected
//! error in `NAME.err`. Checked through the library (`cli::validate::check`) and through the
//! built binary (`grimace validate NAME`: that message on stderr, exit status 1, never a
//! panic). The `good.*` files must validate.

use std::path::{Path, PathBuf};

use crate::common;
use common::grimace_in as grimace;

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs")
}

fn inputs() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.ends_with(".err"))
        .collect();
    names.sort();
    names
}

fn expected(name: &str) -> String {
    let path = corpus().join(format!("{name}.err"));
    std::fs::read_to_string(&path)
        .unwrap_or_else(|_| panic!("{name} has no expected error file {}", path.display()))
        .trim_end()
        .to_string()
}

#[test]
fn the_corpus_is_substantial() {
    let bad = inputs().iter().filter(|n| !n.starts_with("good.")).count();
    assert!(bad >= 40, "only {bad} bad inputs");
}

#[test]
fn every_bad_input_gives_its_exact_error_through_the_library() {
    let dir = corpus();
    let prefix = format!("{}/", dir.display());
    for name in inputs() {
        let result = grimace::cli::validate::check(&dir.join(&name));
        if name.starts_with("good.") {
            assert!(result.is_ok(), "{name}: {}", result.unwrap_err());
            continue;
        }
        let err = result.expect_err(&name).to_string().replace(&prefix, "");
        assert_eq!(err, expected(&name), "{name}");
    }
}

#[test]
fn every_bad_input_exits_1_with_its_error_through_the_binary() {
    let dir = corpus();
    for name in inputs() {
        let out = grimace(&dir, &["validate", &name]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        if name.starts_with("good.") {
            assert_eq!(out.status.code(), Some(0), "{name}: {stderr}");
            continue;
        }
        assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
        assert_eq!(
            stderr.trim_end(),
            format!("grimace validate: {}", expected(&name)),
            "{name}"
        );
    }
}

#[test]
fn validate_of_many_files_fails_if_any_fails() {
    let dir = corpus();
    let out = grimace(
        &dir,
        &["validate", "good.rig.ron", "good.au.ron", "good.obj"],
    );
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&out.stdout).lines().count(), 3);
    let out = grimace(&dir, &["validate", "good.rig.ron", "nan.obj", "good.obj"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(String::from_utf8_lossy(&out.stdout).lines().count(), 2);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim_end(),
        format!("grimace validate: {}", expected("nan.obj"))
    );
}

#[test]
fn export_refuses_bad_rigs_and_tables_with_exit_1() {
    let dir = corpus();
    let out_file = tempfile::tempdir().unwrap();
    let out = out_file.path().join("x.obj");
    let out = out.to_str().unwrap();
    for name in inputs() {
        if name.starts_with("good.") || !name.ends_with(".ron") {
            continue;
        }
        let args: Vec<&str> = if name.ends_with(".rig.ron") {
            vec!["export", "--rig", &name, "--out", out]
        } else {
            vec!["export", "--table", &name, "--au", "12", "--out", out]
        };
        let result = grimace(&dir, &args);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(1), "{name}: {stderr}");
        assert!(stderr.starts_with("grimace export: "), "{name}: {stderr}");
        assert!(stderr.contains(&name), "{name}: {stderr}");
    }
    assert!(!Path::new(out).exists());
}

#[test]
fn a_huge_file_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["huge.rig.ron", "huge.au.ron", "huge.obj"] {
        let path = dir.path().join(name);
        // A sparse file: large to the loader, nothing on disk.
        let file = std::fs::File::create(&path).unwrap();
        file.set_len(grimace::io::MAX_FILE_BYTES + 1).unwrap();
        let err = grimace::cli::validate::check(&path).unwrap_err();
        assert_eq!(
            err.message,
            "the file is too large (268435457 bytes); grimace reads files up to 256 MiB"
        );
        let out = grimace(dir.path(), &["validate", name]);
        assert_eq!(out.status.code(), Some(1));
    }
}
