//! The classic Waters importer: the input is split at NUL bytes into faceline.dat,
//! index.dat and muscle.dat; each parser must not panic and its errors name its file; data
//! that parses is built into a face and rig without a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

mod checks;

fuzz_target!(|bytes: &[u8]| checks::waters(bytes));
