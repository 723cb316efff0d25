//! Combination strings (`6+12@0.5`, `L12C`): no panic; errors have a message; a combination
//! that parses prints as text that parses to the same combination.
#![no_main]

use grimace::facs::combo::parse_combo;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    match parse_combo(text) {
        Ok(combo) => {
            let shown = combo.to_string();
            let again = parse_combo(&shown)
                .unwrap_or_else(|e| panic!("`{text}` prints as `{shown}`, which fails: {e}"));
            assert_eq!(combo, again, "`{text}` prints as `{shown}`");
        }
        Err(err) => {
            assert!(!err.message.trim().is_empty(), "{err:?}");
            assert!(err.column >= 1, "{err:?}");
        }
    }
});
