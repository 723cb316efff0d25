//! The OBJ reader: no panic; errors name the file; a mesh that loads is valid and writes
//! back to text that reads to the same vertices and triangles.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|bytes: &[u8]| {
    let path = Path::new("fuzz/input.obj");
    let Some(text) = common::text(path, bytes) else {
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
        Err(err) => common::load_error(path, &err),
    }
});
