//! The OBJ reader: no panic; errors name the file; a mesh that loads is valid and writes
//! back to text that reads to the same vertices and triangles.
#![no_main]

use libfuzzer_sys::fuzz_target;

mod checks;

fuzz_target!(|bytes: &[u8]| checks::obj(bytes));
