//! Text from files and streams made safe to print on a terminal.
//!
//! A name in an AU table, a path inside a rig or a field of a JSON stream may hold control
//! characters; printed raw, `ESC ] 0 ; ... BEL` retitles the window and `ESC [ 2 J` clears the
//! screen. Every command prints such text through [`printable`], which shows each control
//! character as an escape (`\x1b`) instead, so it is seen, never obeyed.

use std::borrow::Cow;
use std::fmt::Write;

/// `text` with every control character except line feed and tab written as an escape:
/// `\x1b` for C0 controls and DEL, `\u{9b}` for C1 controls (which some terminals obey too).
/// Text without control characters comes back borrowed, unchanged.
pub fn printable(text: &str) -> Cow<'_, str> {
    if !text.chars().any(needs_escape) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if !needs_escape(c) {
            out.push(c);
        } else if (c as u32) < 0x80 {
            let _ = write!(out, "\\x{:02x}", c as u32);
        } else {
            let _ = write!(out, "\\u{{{:x}}}", c as u32);
        }
    }
    Cow::Owned(out)
}

fn needs_escape(c: char) -> bool {
    c.is_control() && c != '\n' && c != '\t'
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_are_shown_not_obeyed() {
        assert_eq!(
            printable("a\u{1b}]0;owned\u{7}b\u{1b}[2J\n\tc\u{9b}d\u{7f}\r"),
            "a\\x1b]0;owned\\x07b\\x1b[2J\n\tc\\u{9b}d\\x7f\\x0d"
        );
        assert!(matches!(printable("plain ünïcode\n"), Cow::Borrowed(_)));
    }
}
