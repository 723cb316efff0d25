//! The AU table RON loader: no panic; errors name the file; a table that loads writes back
//! to text that loads to the same table.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|bytes: &[u8]| {
    let path = Path::new("fuzz/input.au.ron");
    let Some(text) = common::text(path, bytes) else {
        return;
    };
    match grimace::io::parse_table(&text, path) {
        Ok(table) => {
            let written = grimace::io::table_to_ron(&table);
            let again = grimace::io::parse_table(&written, path)
                .unwrap_or_else(|e| panic!("a loaded table does not read back: {e}\n{written}"));
            assert_eq!(table, again, "a table changed on the way through its file");
        }
        Err(err) => common::load_error(path, &err),
    }
});
