//! The OpenFace CSV reader: no panic on any input; a header error names the file; every
//! malformed row is reported with its line and a message.
#![no_main]

use libfuzzer_sys::fuzz_target;

mod checks;

fuzz_target!(|bytes: &[u8]| checks::openface(bytes));
