//! The timeline RON loader: no panic; errors name the file; a timeline that loads can be
//! sampled across its whole length.
#![no_main]

use libfuzzer_sys::fuzz_target;

mod checks;

fuzz_target!(|bytes: &[u8]| checks::timeline(bytes));
