//! The properties every fuzz target checks, one function per target, shared with
//! `tests/model/fuzz_regressions.rs` (which replays saved inputs under plain `cargo test`).
//!
//! For every input: no panic; an error is a value whose message is not empty and names the
//! file it is about; what loads is valid and survives being written and read back.

// Each fuzz target uses only one of these.
#![allow(dead_code)]

use std::fmt::Display;
use std::path::Path;

use grimace::facs::combo::parse_combo;
use grimace::io::openface::{OpenFaceReader, RowOutcome};
use grimace::io::timeline::parse_timeline;
use grimace::io::waters::{self, ImportOptions, WatersData};
use grimace::io::LoadError;

/// Turns bytes into text the way the loaders do (`read_text`), checking the error for bytes
/// that are not UTF-8.
fn text(path: &Path, bytes: &[u8]) -> Option<String> {
    match grimace::io::error::text_from_bytes(path, bytes.to_vec()) {
        Ok(text) => Some(text),
        Err(err) => {
            load_error(path, &err);
            None
        }
    }
}

/// A load error names `path`, has a message, and a line and column only from 1.
fn load_error(path: &Path, err: &LoadError) {
    assert_eq!(err.path, path, "{err}");
    assert!(!err.message.trim().is_empty(), "empty message: {err:?}");
    assert!(err.line.is_none_or(|l| l >= 1), "{err:?}");
    assert!(err.column.is_none_or(|c| c >= 1), "{err:?}");
    names_file(path, err);
}

/// The displayed error starts with the file name and says something after it.
fn names_file(path: &Path, err: &dyn Display) {
    let shown = err.to_string();
    let name = path.display().to_string();
    assert!(shown.starts_with(&name), "does not name {name}: {shown}");
    let rest = shown[name.len()..].trim_start_matches(|c: char| c == ':' || c.is_ascii_digit());
    assert!(
        !rest.trim().is_empty(),
        "no message after the file name: {shown}"
    );
}

/// The rig RON loader; a rig that loads writes back to text that loads to the same rig.
pub fn rig(bytes: &[u8]) {
    let path = Path::new("fuzz/input.rig.ron");
    let Some(text) = text(path, bytes) else {
        return;
    };
    match grimace::io::parse_rig(&text, path) {
        Ok(rig) => {
            let written = grimace::io::rig_to_ron(&rig);
            let again = grimace::io::parse_rig(&written, path)
                .unwrap_or_else(|e| panic!("a loaded rig does not read back: {e}\n{written}"));
            assert_eq!(rig, again, "a rig changed on the way through its file");
        }
        Err(err) => load_error(path, &err),
    }
}

/// The AU table RON loader; a table that loads writes back to text that loads to the same
/// table.
pub fn table(bytes: &[u8]) {
    let path = Path::new("fuzz/input.au.ron");
    let Some(text) = text(path, bytes) else {
        return;
    };
    match grimace::io::parse_table(&text, path) {
        Ok(table) => {
            let written = grimace::io::table_to_ron(&table);
            let again = grimace::io::parse_table(&written, path)
                .unwrap_or_else(|e| panic!("a loaded table does not read back: {e}\n{written}"));
            assert_eq!(table, again, "a table changed on the way through its file");
        }
        Err(err) => load_error(path, &err),
    }
}

/// The OBJ reader; a mesh that loads is valid and writes back to text that reads to the
/// same vertices and triangles.
pub fn obj(bytes: &[u8]) {
    let path = Path::new("fuzz/input.obj");
    let Some(text) = text(path, bytes) else {
        return;
    };
    match grimace::io::obj::parse_obj(&text, path) {
        Ok(mesh) => {
            mesh.validate().expect("a loaded mesh is valid");
            let written = grimace::io::obj::write_obj(&mesh, &mesh.positions);
            let again = grimace::io::obj::parse_obj(&written, path)
                .unwrap_or_else(|e| panic!("a loaded mesh does not read back: {e}"));
            assert_eq!(mesh.positions, again.positions);
            assert_eq!(mesh.triangles, again.triangles);
        }
        Err(err) => load_error(path, &err),
    }
}

/// The classic Waters importer: the input is split at NUL bytes into faceline.dat,
/// index.dat and muscle.dat; each parser runs on its part whatever the others hold, and
/// data that parses is built into a valid face and rig or refused with a message.
pub fn waters(bytes: &[u8]) {
    let mut parts = bytes.splitn(3, |&b| b == 0);
    let faceline_bytes = parts.next().unwrap_or_default();
    let index_bytes = parts.next().unwrap_or_default();
    let muscle_bytes = parts.next().unwrap_or_default();
    let faceline = Path::new("fuzz/faceline.dat");
    let index = Path::new("fuzz/index.dat");
    let muscle = Path::new("fuzz/muscle.dat");

    let vertices = text(faceline, faceline_bytes).and_then(|text| {
        waters::parse_faceline(&text, faceline)
            .map_err(|e| load_error(faceline, &e))
            .ok()
    });
    let count = vertices.as_ref().map_or(8, Vec::len);
    let polygons = text(index, index_bytes).and_then(|text| {
        waters::parse_index(&text, index, count)
            .map_err(|e| load_error(index, &e))
            .ok()
    });
    let muscles = text(muscle, muscle_bytes).and_then(|text| {
        waters::parse_muscles(&text, muscle)
            .map_err(|e| load_error(muscle, &e))
            .ok()
    });

    let (Some(vertices), Some(polygons), Some(muscles)) = (vertices, polygons, muscles) else {
        return;
    };
    let data = WatersData {
        vertices,
        polygons,
        muscles,
    };
    for drop_duplicate_triangles in [false, true] {
        let options = ImportOptions {
            drop_duplicate_triangles,
            extras: None,
        };
        match waters::build(&data, &options, muscle) {
            Ok(imported) => imported.mesh.validate().expect("an imported mesh is valid"),
            Err(err) => {
                assert!(err.path == muscle || err.path == index, "{err}");
                load_error(&err.path.clone(), &err);
            }
        }
    }
}

/// The OpenFace CSV reader: a header error names the file; rows come in line order; a
/// tracked row has one finite intensity per AU column; a malformed row has a message.
pub fn openface(bytes: &[u8]) {
    let path = Path::new("fuzz/input.csv");
    let mut reader = match OpenFaceReader::new(bytes, path) {
        Ok(reader) => reader,
        Err(err) => {
            assert_eq!(err.path, path);
            assert!(!err.message.trim().is_empty(), "{err:?}");
            names_file(path, &err);
            return;
        }
    };
    let columns = reader.columns().clone();
    assert!(!columns.aus.is_empty());
    let mut last_line = 0;
    for outcome in reader.by_ref() {
        match outcome.expect("reading from memory cannot fail") {
            RowOutcome::Row(row) => {
                assert!(row.line > last_line, "lines go forward: {}", row.line);
                last_line = row.line;
                if row.success {
                    assert_eq!(row.intensities.len(), columns.aus.len());
                    assert!(row.intensities.iter().all(|v| v.is_finite()), "{row:?}");
                }
            }
            RowOutcome::Malformed(err) => {
                assert!(err.line > last_line, "lines go forward: {err}");
                last_line = err.line;
                assert!(!err.message.trim().is_empty(), "{err:?}");
            }
        }
    }
}

/// The timeline RON loader; a timeline that loads can be sampled across its length.
pub fn timeline(bytes: &[u8]) {
    let path = Path::new("fuzz/input.timeline.ron");
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    match parse_timeline(text, path) {
        Ok(timeline) => {
            let frames = timeline.frame_count();
            assert!(frames >= 1);
            let last = timeline.keyframes.last().map_or(0.0, |k| k.time);
            for t in [-1.0, 0.0, last * 0.5, last, last + 1.0, f64::NAN] {
                let (i, j, w) = timeline.bracket(t);
                assert!(i < timeline.keyframes.len() && j < timeline.keyframes.len());
                assert!((0.0..=1.0).contains(&w), "weight {w} at {t}");
            }
        }
        Err(err) => {
            assert!(!err.message.trim().is_empty(), "{err:?}");
            names_file(path, &err);
        }
    }
}

/// Combination strings (`6+12@0.5`, `L12C`): an error has a message and a column from 1; a
/// combination that parses prints as text that parses to the same combination.
pub fn combo(bytes: &[u8]) {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    match parse_combo(text) {
        Ok(combo) => {
            let shown = combo.to_string();
            let again = parse_combo(&shown)
                .unwrap_or_else(|e| panic!("`{text}` prints as `{shown}`, which fails: {e}"));
            assert_eq!(combo, again, "`{text}` prints as `{shown}`");
        }
        Err(err) => {
            assert!(!err.message.trim().is_empty(), "{err:?}");
            assert!(err.column >= 1, "{err:?}");
        }
    }
}

/// For the regression tests: applies the file-naming check to an error about
/// `fuzz/input.timeline.ron`.
pub fn names_file_for_test(err: &dyn Display) {
    names_file(Path::new("fuzz/input.timeline.ron"), err);
}
