//! The classic Waters importer: the input is split at NUL bytes into faceline.dat,
//! index.dat and muscle.dat; each parser must not panic and its errors name its file; data
//! that parses is built into a face and rig without a panic.
#![no_main]

use std::path::Path;

use grimace::io::waters::{self, ImportOptions, WatersData};
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|bytes: &[u8]| {
    let mut parts = bytes.splitn(3, |&b| b == 0);
    let faceline_bytes = parts.next().unwrap_or_default();
    let index_bytes = parts.next().unwrap_or_default();
    let muscle_bytes = parts.next().unwrap_or_default();
    let faceline = Path::new("fuzz/faceline.dat");
    let index = Path::new("fuzz/index.dat");
    let muscle = Path::new("fuzz/muscle.dat");

    // Each parser is exercised on its own part, whatever the others hold.
    let vertices = common::text(faceline, faceline_bytes).and_then(|text| {
        waters::parse_faceline(&text, faceline)
            .map_err(|e| common::load_error(faceline, &e))
            .ok()
    });
    let count = vertices.as_ref().map_or(8, Vec::len);
    let polygons = common::text(index, index_bytes).and_then(|text| {
        waters::parse_index(&text, index, count)
            .map_err(|e| common::load_error(index, &e))
            .ok()
    });
    let muscles = common::text(muscle, muscle_bytes).and_then(|text| {
        waters::parse_muscles(&text, muscle)
            .map_err(|e| common::load_error(muscle, &e))
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
                common::load_error(&err.path.clone(), &err);
            }
        }
    }
});
