//! Reading the one JSON shape live AU streams use: a flat object of names to numbers,
//! `{"AU1": 0.0, "AU2": 1.5, ..., "AU45": 0.0}` (OpenFACS's message shape).
//!
//! The JSON itself is read by `serde_json`; this module adds what the shape asks for. Nested
//! values, strings and booleans are refused with the column where the value starts; `null`
//! values are passed over (some senders write `null` for an AU they did not measure); a key
//! given twice refuses the frame (adding the two, or picking one, would guess what the
//! sender meant).

use serde::de::{Deserialize, Deserializer, MapAccess, Visitor};
use serde_json::value::RawValue;

/// A flat object that cannot be read; `column` is 1-based, in characters.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JsonError {
    /// Where the problem starts (1-based, characters, on the frame's first line; a frame of
    /// several lines names the line in `message`).
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for JsonError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "column {}: {}", self.column, self.message)
    }
}

/// Parses `{"name": number, ...}` into its pairs, in order.
pub fn parse_flat_object(text: &str) -> Result<Vec<(String, f64)>, JsonError> {
    // Anything but an object is refused at its first character.
    let start = text.len() - text.trim_start().len();
    match text[start..].chars().next() {
        Some('{') => {}
        Some(found) => {
            return Err(error_at(
                text,
                start,
                format!("expected `{{`, found `{found}`"),
            ))
        }
        None => {
            return Err(error_at(
                text,
                start,
                "expected `{`, found the end of the line",
            ))
        }
    }
    let entries = serde_json::from_str::<Entries>(text).map_err(|e| syntax_error(text, &e))?;
    let mut pairs: Vec<(String, f64)> = Vec::with_capacity(entries.0.len());
    let mut seen: Vec<(&str, usize)> = Vec::with_capacity(entries.0.len());
    for (name, raw) in &entries.0 {
        let at = offset_in(text, raw.get());
        if let Some(&(_, first)) = seen.iter().find(|(seen, _)| seen == name) {
            let first = char_column(text, first);
            return Err(error_at(
                text,
                at,
                format!("key `{name}` appears twice (first value at column {first})"),
            ));
        }
        seen.push((name, at));
        if let Some(value) = number(raw.get()).map_err(|message| error_at(text, at, message))? {
            pairs.push((name.clone(), value));
        }
    }
    Ok(pairs)
}

/// A value of the flat object: a finite number, or `None` for `null`.
fn number(raw: &str) -> Result<Option<f64>, &'static str> {
    match raw.as_bytes().first() {
        Some(b'n') => Ok(None),
        Some(b'{' | b'[') => Err("nested values are not supported"),
        _ => match raw.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(Some(value)),
            // Strings, booleans, and numbers beyond f64 (1e999).
            _ => Err("expected a number"),
        },
    }
}

/// The object's entries in order, each value kept as its JSON text (borrowed from the input,
/// so its place in the line is known).
struct Entries<'a>(Vec<(String, &'a RawValue)>);

impl<'de> Deserialize<'de> for Entries<'de> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct EntriesVisitor;
        impl<'de> Visitor<'de> for EntriesVisitor {
            type Value = Entries<'de>;

            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an object of names to numbers")
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Entries<'de>, A::Error> {
                // Kept as a list, not a map: a key given twice must be seen.
                let mut entries = Vec::new();
                while let Some(entry) = map.next_entry::<String, &'de RawValue>()? {
                    entries.push(entry);
                }
                Ok(Entries(entries))
            }
        }
        deserializer.deserialize_map(EntriesVisitor)
    }
}

/// The byte offset of `part`, a slice of `text`, in `text`.
fn offset_in(text: &str, part: &str) -> usize {
    (part.as_ptr() as usize)
        .saturating_sub(text.as_ptr() as usize)
        .min(text.len())
}

/// A serde_json error as a [`JsonError`]: its message without the position, at its place.
fn syntax_error(text: &str, e: &serde_json::Error) -> JsonError {
    let full = e.to_string();
    let position = format!(" at line {} column {}", e.line(), e.column());
    let message = full.strip_suffix(&position).unwrap_or(&full).to_string();
    // serde_json counts the line from 1 and the column in bytes, 1 at the line's first
    // byte (0 when nothing of the line was read).
    let line_start: usize = text
        .split_inclusive('\n')
        .take(e.line().saturating_sub(1))
        .map(str::len)
        .sum();
    error_at(text, line_start + e.column().saturating_sub(1), message)
}

/// A [`JsonError`] at byte offset `at` of `text`.
fn error_at(text: &str, at: usize, message: impl Into<String>) -> JsonError {
    let mut message = message.into();
    let at = floor_char_boundary(text, at);
    let line = text[..at].matches('\n').count() + 1;
    if line > 1 {
        message.push_str(&format!(" (line {line} of the frame)"));
    }
    JsonError {
        column: char_column(text, at),
        message,
    }
}

/// The 1-based column, in characters on its line, of byte offset `at` of `text`.
fn char_column(text: &str, at: usize) -> usize {
    let at = floor_char_boundary(text, at);
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    text[line_start..at].chars().count() + 1
}

/// `at` moved back to the start of the character it falls in (and into `text`).
fn floor_char_boundary(text: &str, at: usize) -> usize {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_openfacs_messages() {
        let pairs =
            parse_flat_object(r#" {"AU1": 0, "AU12":2.5e0 ,"AU45":-1, "x":null} "#).unwrap();
        assert_eq!(
            pairs,
            vec![
                ("AU1".to_string(), 0.0),
                ("AU12".to_string(), 2.5),
                ("AU45".to_string(), -1.0)
            ]
        );
        assert_eq!(parse_flat_object("{}").unwrap(), vec![]);
        assert_eq!(
            parse_flat_object(r#"{"a\"\u0041": 1}"#).unwrap(),
            vec![("a\"A".to_string(), 1.0)]
        );
    }

    fn error(text: &str) -> (usize, String) {
        let e = parse_flat_object(text).unwrap_err();
        (e.column, e.message)
    }

    #[test]
    fn refuses_other_shapes_with_a_column() {
        assert_eq!(error(r#"{"AU1": "high"}"#), (9, "expected a number".into()));
        assert_eq!(error(r#"{"AU1": true}"#), (9, "expected a number".into()));
        assert_eq!(
            error(r#"{"AU1": [1]}"#),
            (9, "nested values are not supported".into())
        );
        assert_eq!(
            error(r#"{"AU1": {"x": 1}}"#),
            (9, "nested values are not supported".into())
        );
        assert_eq!(error(r#"{"AU1": 1e999}"#), (9, "expected a number".into()));
        assert_eq!(error("x"), (1, "expected `{`, found `x`".into()));
        assert_eq!(error("  [1]"), (3, "expected `{`, found `[`".into()));
        assert_eq!(
            error(""),
            (1, "expected `{`, found the end of the line".into())
        );
        // serde_json's own messages, at its place.
        assert_eq!(error(r#"{"AU1": 1,}"#), (11, "trailing comma".into()));
        assert_eq!(error(r#"{"AU1": 1} x"#), (12, "trailing characters".into()));
        assert_eq!(error(r#"{"AU1": 1"#).0, 9);
        for bad in [
            r#"{"AU1": -}"#,
            r#"{"AU1": nul}"#,
            r#"{"\u12": 1}"#,
            "{AU1: 1}",
        ] {
            assert!(parse_flat_object(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        // "é" is two bytes; the value starts at character 10.
        assert_eq!(error(r#"{"éAU1": "x"}"#), (10, "expected a number".into()));
        assert_eq!(error(r#"{"é": 1,}"#).0, 9);
    }

    #[test]
    fn a_frame_of_several_lines_names_the_line() {
        assert_eq!(
            error("{\"AU1\": 1,\n  \"AU2\": \"x\"}"),
            (10, "expected a number (line 2 of the frame)".into())
        );
    }

    #[test]
    fn a_key_given_twice_refuses_the_frame() {
        assert_eq!(
            error(r#"{"AU12": 1, "AU12": 2}"#),
            (
                21,
                "key `AU12` appears twice (first value at column 10)".into()
            )
        );
        // Even when one of them is null.
        assert!(parse_flat_object(r#"{"AU12": null, "AU12": 2}"#).is_err());
    }
}
