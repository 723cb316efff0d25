//! Combination strings (`6+12@0.5`, `L12C`): no panic; errors have a message; a combination
//! that parses prints as text that parses to the same combination.
#![no_main]

use libfuzzer_sys::fuzz_target;

mod checks;

fuzz_target!(|bytes: &[u8]| checks::combo(bytes));
