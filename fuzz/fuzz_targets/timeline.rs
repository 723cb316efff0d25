//! The timeline RON loader: no panic; errors name the file; a timeline that loads can be
//! sampled across its whole length.
#![no_main]

use std::path::Path;

use grimace::io::timeline::parse_timeline;
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|bytes: &[u8]| {
    let path = Path::new("fuzz/input.timeline.ron");
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    match parse_timeline(text, path) {
        Ok(timeline) => {
            let frames = timeline.frame_count();
            assert!(frames >= 1);
            let last = timeline.keyframes.last().map_or(0.0, |k| k.time);
            for t in [-1.0, 0.0, last * 0.5, last, last + 1.0, f64::NAN] {
                let (i, j, w) = timeline.bracket(t);
                assert!(i < timeline.keyframes.len() && j < timeline.keyframes.len());
                assert!((0.0..=1.0).contains(&w), "weight {w} at {t}");
            }
        }
        Err(err) => {
            assert!(!err.message.trim().is_empty(), "{err:?}");
            common::names_file(path, &err);
        }
    }
});
