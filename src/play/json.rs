//! A reader for the one JSON shape live AU streams use: a flat object of names to numbers,
//! `{"AU1": 0.0, "AU2": 1.5, ..., "AU45": 0.0}` (OpenFACS's message shape).
//!
//! Nested values, strings, booleans and arrays are refused with the column where they start;
//! `null` values are passed over (some senders write `null` for an AU they did not measure).

/// A flat object that cannot be read; `column` is 1-based, in characters.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JsonError {
    /// Where the problem starts (1-based, characters).
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
    let mut p = Parser {
        chars: text.chars().collect(),
        at: 0,
    };
    p.skip_space();
    p.expect('{')?;
    let mut pairs = Vec::new();
    p.skip_space();
    if p.eat('}') {
        return p.finish(pairs);
    }
    loop {
        p.skip_space();
        let name = p.string()?;
        p.skip_space();
        p.expect(':')?;
        p.skip_space();
        if let Some(value) = p.value()? {
            pairs.push((name, value));
        }
        p.skip_space();
        if p.eat(',') {
            continue;
        }
        p.expect('}')?;
        return p.finish(pairs);
    }
}

struct Parser {
    chars: Vec<char>,
    at: usize,
}

impl Parser {
    fn error(&self, message: impl Into<String>) -> JsonError {
        JsonError {
            column: self.at + 1,
            message: message.into(),
        }
    }

    fn peek(&self) -> Option<char> {
        self.chars.get(self.at).copied()
    }

    fn skip_space(&mut self) {
        while matches!(self.peek(), Some(' ' | '\t' | '\r' | '\n')) {
            self.at += 1;
        }
    }

    fn eat(&mut self, c: char) -> bool {
        if self.peek() == Some(c) {
            self.at += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, c: char) -> Result<(), JsonError> {
        if self.eat(c) {
            Ok(())
        } else {
            Err(match self.peek() {
                Some(found) => self.error(format!("expected `{c}`, found `{found}`")),
                None => self.error(format!("expected `{c}`, found the end of the line")),
            })
        }
    }

    fn finish(mut self, pairs: Vec<(String, f64)>) -> Result<Vec<(String, f64)>, JsonError> {
        self.skip_space();
        match self.peek() {
            None => Ok(pairs),
            Some(_) => Err(self.error("unexpected text after the object")),
        }
    }

    fn string(&mut self) -> Result<String, JsonError> {
        self.expect('"')?;
        let mut out = String::new();
        loop {
            let Some(c) = self.peek() else {
                return Err(self.error("unterminated string"));
            };
            self.at += 1;
            match c {
                '"' => return Ok(out),
                '\\' => {
                    let escaped = match self.peek() {
                        Some('"') => '"',
                        Some('\\') => '\\',
                        Some('/') => '/',
                        Some('n') => '\n',
                        Some('t') => '\t',
                        Some('r') => '\r',
                        Some('b') => '\u{8}',
                        Some('f') => '\u{c}',
                        Some('u') => {
                            self.at += 1;
                            let hex: String = self.chars.iter().skip(self.at).take(4).collect();
                            let code = u32::from_str_radix(&hex, 16)
                                .ok()
                                .filter(|_| hex.len() == 4)
                                .ok_or_else(|| self.error("bad \\u escape"))?;
                            self.at += 3;
                            char::from_u32(code).unwrap_or('\u{fffd}')
                        }
                        _ => return Err(self.error("bad escape in string")),
                    };
                    self.at += 1;
                    out.push(escaped);
                }
                c => out.push(c),
            }
        }
    }

    /// A number, or `None` for `null`.
    fn value(&mut self) -> Result<Option<f64>, JsonError> {
        let start = self.at;
        match self.peek() {
            Some('n') => {
                let word: String = self.chars.iter().skip(self.at).take(4).collect();
                if word == "null" {
                    self.at += 4;
                    return Ok(None);
                }
            }
            Some('{' | '[') => return Err(self.error("nested values are not supported")),
            Some('"' | 't' | 'f') => return Err(self.error("expected a number")),
            _ => {}
        }
        while matches!(self.peek(), Some('0'..='9' | '-' | '+' | '.' | 'e' | 'E')) {
            self.at += 1;
        }
        let text: String = self.chars[start..self.at].iter().collect();
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(Some(value)),
            _ => {
                self.at = start;
                Err(self.error("expected a number"))
            }
        }
    }
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

    #[test]
    fn refuses_other_shapes_with_a_column() {
        let e = parse_flat_object(r#"{"AU1": "high"}"#).unwrap_err();
        assert_eq!((e.column, e.message.as_str()), (9, "expected a number"));
        assert_eq!(parse_flat_object(r#"{"AU1": [1]}"#).unwrap_err().column, 9);
        assert!(parse_flat_object(r#"{"AU1": 1"#).is_err());
        assert!(parse_flat_object(r#"{"AU1": 1} x"#).is_err());
        assert!(parse_flat_object(r#"{"AU1": 1,}"#).is_err());
        assert!(parse_flat_object(r#"{"AU1": 1e999}"#).is_err());
        assert!(parse_flat_object(r#"{"AU1": -}"#).is_err());
        assert!(parse_flat_object(r#"{"AU1": nul}"#).is_err());
        assert!(parse_flat_object(r#"{"\u12": 1}"#).is_err());
        assert!(parse_flat_object("").is_err());
    }
}
