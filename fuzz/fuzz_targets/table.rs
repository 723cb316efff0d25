//! The AU table RON loader: no panic; errors name the file; a table that loads writes back
//! to text that loads to the same table.
#![no_main]

use libfuzzer_sys::fuzz_target;

mod checks;

fuzz_target!(|bytes: &[u8]| checks::table(bytes));
