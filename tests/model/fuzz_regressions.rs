//! Replays saved fuzz inputs under plain `cargo test`, with the very checks the fuzz targets
//! run (`fuzz/fuzz_targets/checks.rs`): no panic, errors that name their file, round trips
//! that hold. `tests/fuzz_regressions/TARGET/` holds, per target, inputs kept from fuzzing
//! runs (a sample of the corpus that reached new code) and any input that once failed.

#[path = "../../fuzz/fuzz_targets/checks.rs"]
mod checks;

use std::path::PathBuf;

fn inputs(target: &str) -> Vec<(String, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_regressions")
        .join(target);
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| {
            let entry = entry.unwrap();
            let name = entry.file_name().to_string_lossy().into_owned();
            (name, std::fs::read(entry.path()).unwrap())
        })
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no saved inputs in {}", dir.display());
    files
}

/// Runs `check` on every saved input of `target`, naming the input that fails.
fn replay(target: &str, check: fn(&[u8])) {
    for (name, bytes) in inputs(target) {
        let result = std::panic::catch_unwind(|| check(&bytes));
        assert!(result.is_ok(), "{target}/{name} fails its fuzz check");
    }
}

#[test]
fn rig_inputs() {
    replay("rig", checks::rig);
}

#[test]
fn table_inputs() {
    replay("table", checks::table);
}

#[test]
fn obj_inputs() {
    replay("obj", checks::obj);
}

#[test]
fn waters_inputs() {
    replay("waters", checks::waters);
}

#[test]
fn openface_inputs() {
    replay("openface", checks::openface);
}

#[test]
fn timeline_inputs() {
    replay("timeline", checks::timeline);
}

#[test]
fn combo_inputs() {
    replay("combo", checks::combo);
}

/// The checks themselves catch what they claim to: a message that does not name the file
/// fails them (so a passing replay means something).
#[test]
#[should_panic(expected = "does not name")]
fn the_checks_reject_an_error_that_does_not_name_its_file() {
    // A timeline error is displayed with its path; one for another path must be caught.
    let err =
        grimace::io::timeline::parse_timeline("", std::path::Path::new("other.ron")).unwrap_err();
    checks::names_file_for_test(&err);
}
