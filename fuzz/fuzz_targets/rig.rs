//! The rig RON loader: no panic; errors name the file; a rig that loads writes back to text
//! that loads to the same rig.
#![no_main]

use libfuzzer_sys::fuzz_target;

mod checks;

fuzz_target!(|bytes: &[u8]| checks::rig(bytes));
