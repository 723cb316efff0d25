//! Shared pieces of the RON formats: error mapping, the version check, number and string
//! writing, and finding where a named item sits in the text for semantic errors.

use std::path::Path;

use serde::de::DeserializeOwned;
use serde::Deserialize;

use super::error::LoadError;

/// Parses `text` as RON into `T`, mapping ron's error position to the file's line and column.
pub(crate) fn parse<T: DeserializeOwned>(
    path: &Path,
    text: &str,
    what: &str,
) -> Result<T, LoadError> {
    if is_blank(text) {
        return Err(LoadError::new(
            path,
            format!("the file is empty; expected {what} in RON"),
        ));
    }
    ron::Options::default()
        .from_str::<T>(text)
        .map_err(|e| ron_error(path, text, &e))
}

/// True when the text holds nothing but whitespace and `//` comments.
fn is_blank(text: &str) -> bool {
    text.lines().all(|l| {
        let l = l.trim();
        l.is_empty() || l.starts_with("//")
    })
}

/// Converts a ron error into a load error at the same line and column. An error at the very
/// end of the text means the file stops early, which ron reports as whatever it expected
/// next; say so.
pub(crate) fn ron_error(path: &Path, text: &str, error: &ron::error::SpannedError) -> LoadError {
    let start = error.span.start;
    let mut message = describe(&error.code);
    let (end_line, end_column) = super::error::line_column(text.trim_end(), text.trim_end().len());
    let at_end = (start.line, start.col) >= (end_line, end_column);
    if at_end && !matches!(error.code, ron::Error::Eof) {
        message = format!("the file ends too early (truncated?); {message}");
    }
    if start.line == 0 {
        LoadError::new(path, message)
    } else {
        LoadError::at(path, start.line, start.col.max(1), message)
    }
}

/// A plain-language message for a ron error.
fn describe(code: &ron::Error) -> String {
    use ron::Error as E;
    let outer = |outer: &Option<String>| match outer {
        Some(o) => format!(" in {o}"),
        None => String::new(),
    };
    match code {
        E::Eof => "the file ends too early (truncated?); expected more RON".to_string(),
        E::NoSuchStructField {
            expected,
            found,
            outer: o,
        } => format!(
            "unknown field `{found}`{}; expected one of: {}",
            outer(o),
            expected.join(", ")
        ),
        E::MissingStructField { field, outer: o } => {
            format!("missing field `{field}`{}", outer(o))
        }
        E::DuplicateStructField { field, outer: o } => {
            format!("field `{field}` given twice{}", outer(o))
        }
        E::NoSuchEnumVariant {
            expected,
            found,
            outer: o,
        } => format!(
            "unknown value `{found}`{}; expected one of: {}",
            outer(o),
            expected.join(", ")
        ),
        E::TrailingCharacters => "unexpected text after the end of the document".to_string(),
        E::Message(m) => m.clone(),
        other => {
            // ron's own wording, with a lower-case start to match the rest.
            let text = other.to_string();
            let mut chars = text.chars();
            match chars.next() {
                Some(c) => c.to_lowercase().chain(chars).collect(),
                None => text,
            }
        }
    }
}

#[derive(Deserialize)]
struct VersionOnly {
    version: u32,
}

/// Checks the `version` field before anything else, so a file from another version gets a
/// clear message rather than a confusing one about a field it does not know.
///
/// Only a readable version that differs is reported here; any other problem (no version,
/// broken syntax) is left to the full parse, which gives its exact position.
pub(crate) fn check_version(
    path: &Path,
    text: &str,
    expected: u32,
    what: &str,
) -> Result<(), LoadError> {
    check_version_in(path, text, expected..=expected, what).map(|_| ())
}

/// Like [`check_version`] for a format that still reads older versions: accepts any version
/// in `versions` and returns it (`None` when the text has no readable version field, which
/// the full parse then reports).
pub(crate) fn check_version_in(
    path: &Path,
    text: &str,
    versions: std::ops::RangeInclusive<u32>,
    what: &str,
) -> Result<Option<u32>, LoadError> {
    let Ok(found) = ron::Options::default().from_str::<VersionOnly>(text) else {
        return Ok(None);
    };
    if versions.contains(&found.version) {
        return Ok(Some(found.version));
    }
    let (oldest, newest) = (*versions.start(), *versions.end());
    let reads = if oldest == newest {
        format!("version {oldest}")
    } else if oldest + 1 == newest {
        format!("versions {oldest} and {newest}")
    } else {
        format!("versions {oldest} to {newest}")
    };
    let message = format!(
        "{what} version {} is not supported; this grimace reads {reads}",
        found.version
    );
    Err(match find_field(text, 0, "version") {
        Some(offset) => LoadError::at_offset(path, text, offset, message),
        None => LoadError::new(path, message),
    })
}

/// The byte offset of the first `"name"` string literal at or after `from`.
pub(crate) fn find_string(text: &str, from: usize, name: &str) -> Option<usize> {
    let quoted = ron::to_string(name).ok()?;
    text.get(from..)?.find(&quoted).map(|i| i + from)
}

/// The byte offset of the first `field:` (a field name followed by a colon) at or after
/// `from`, with the field name not part of a longer identifier.
pub(crate) fn find_field(text: &str, from: usize, field: &str) -> Option<usize> {
    let rest = text.get(from..)?;
    let mut search = 0;
    while let Some(i) = rest[search..].find(field) {
        let at = search + i;
        let before_ok = rest[..at]
            .chars()
            .next_back()
            .is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
        let after = rest[at + field.len()..].trim_start();
        if before_ok && after.starts_with(':') {
            return Some(from + at);
        }
        search = at + field.len();
    }
    None
}

/// Writes an `f32` so that it reads back as exactly the same value (the shortest decimal
/// that round-trips, always with a `.0` or an exponent).
pub(crate) fn float(value: f32) -> String {
    format!("{value:?}")
}

/// Writes a RON string literal (quoted and escaped).
pub(crate) fn string(value: &str) -> String {
    // Serialising a plain string cannot fail; fall back to a debug quote just in case.
    ron::to_string(value).unwrap_or_else(|_| format!("{value:?}"))
}

/// Writes a point as a RON tuple `(x, y, z)`.
pub(crate) fn point(p: glam::Vec3) -> String {
    format!("({}, {}, {})", float(p.x), float(p.y), float(p.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_round_trip_exactly() {
        for v in [
            0.1f32,
            -0.0,
            1.0,
            1e-7,
            3.402_823_5e38,
            f32::MIN_POSITIVE,
            f32::from_bits(0x3fc8_f5c4),
            123_456_790.0,
        ] {
            let text = float(v);
            let back: f32 = ron::from_str(&text).unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{text}");
        }
    }

    #[test]
    fn finds_fields_not_substrings() {
        let text = "(subversion: 2, version: 3)";
        assert_eq!(find_field(text, 0, "version"), Some(16));
        assert_eq!(find_string("(a: \"x\", b: \"xy\")", 0, "xy"), Some(12));
    }

    #[test]
    fn wrong_version_is_reported_at_its_line() {
        let err = check_version(Path::new("t"), "(\n  version: 7,\n)", 1, "rig").unwrap_err();
        assert_eq!((err.line, err.column), (Some(2), Some(3)));
        assert_eq!(
            err.message,
            "rig version 7 is not supported; this grimace reads version 1"
        );
    }
}
