//! The rig RON loader: no panic; errors name the file; a rig that loads writes back to text
//! that loads to the same rig.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|bytes: &[u8]| {
    let path = Path::new("fuzz/input.rig.ron");
    let Some(text) = common::text(path, bytes) else {
        return;
    };
    match grimace::io::parse_rig(&text, path) {
        Ok(rig) => {
            let written = grimace::io::rig_to_ron(&rig);
            let again = grimace::io::parse_rig(&written, path)
                .unwrap_or_else(|e| panic!("a loaded rig does not read back: {e}\n{written}"));
            assert_eq!(rig, again, "a rig changed on the way through its file");
        }
        Err(err) => common::load_error(path, &err),
    }
});
