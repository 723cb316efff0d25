//! Checks shared by the fuzz targets: an error must be a value with a message that names the
//! file it is about.

// Each target uses only some of these.
#![allow(dead_code)]

use std::fmt::Display;
use std::path::Path;

use grimace::io::LoadError;

/// Turns fuzz bytes into text the way the loaders do (`read_text`), checking the error for
/// bytes that are not UTF-8.
pub fn text(path: &Path, bytes: &[u8]) -> Option<String> {
    match grimace::io::error::text_from_bytes(path, bytes.to_vec()) {
        Ok(text) => Some(text),
        Err(err) => {
            load_error(path, &err);
            None
        }
    }
}

/// A load error names `path`, has a message, and a line and column only from 1.
pub fn load_error(path: &Path, err: &LoadError) {
    assert_eq!(err.path, path, "{err}");
    assert!(!err.message.trim().is_empty(), "empty message: {err:?}");
    assert!(err.line.is_none_or(|l| l >= 1), "{err:?}");
    assert!(err.column.is_none_or(|c| c >= 1), "{err:?}");
    names_file(path, err);
}

/// The displayed error starts with the file name and says something after it.
pub fn names_file(path: &Path, err: &dyn Display) {
    let shown = err.to_string();
    let name = path.display().to_string();
    assert!(shown.starts_with(&name), "does not name {name}: {shown}");
    let rest = shown[name.len()..].trim_start_matches(|c: char| c == ':' || c.is_ascii_digit());
    assert!(
        !rest.trim().is_empty(),
        "no message after the file name: {shown}"
    );
}
