//! Combination strings as FACS writes them: `1+2+5B+26`, `R12A+R14A`, `6+12@0.5`.
//!
//! Grammar (spaces and tabs allowed around every term and `+`):
//!
//! ```text
//! combo     = term { "+" term }
//! term      = [ "L" | "R" ] number [ intensity ]
//! number    = digit { digit }                  (a FACS AU number, 1-99)
//! intensity = letter | "@" scale
//! letter    = "A" | "B" | "C" | "D" | "E"      (scale 0.15, 0.3, 0.5, 0.75, 1.0)
//! scale     = digit { digit } [ "." { digit } ] | "." digit { digit }   (finite, 0 or more)
//! ```
//!
//! Side and intensity letters may also be written in lower case. A term without an intensity
//! has scale 1.0, the AU as recorded.
//!
//! The letters are FACS's intensity scale (Ekman, Friesen & Hager 2002): A trace, B slight,
//! C marked or pronounced, D severe or extreme, E maximum. The manual draws the scale with
//! unequal intervals, the middle ones wider: most of the range of appearance falls in C and
//! D, while A (just visible) and E (as far as the face goes) are narrow. Here the range of an
//! AU recorded at its maximum (1.0) is divided the same way, starting where the action
//! becomes visible (0.1): A 0.1-0.2, B 0.2-0.4, C 0.4-0.65, D 0.65-0.9, E 0.9-1.0. Each
//! letter scales by its band's middle, rounded (A 0.15, B 0.3, C 0.5, D 0.75), and E by the
//! maximum itself, 1.0, so an AU written without a letter equals its E.

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

use super::au::{AuKey, MAX_AU_NUMBER};
use crate::model::Side;

/// How strongly a term applies its AU.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Intensity {
    /// No intensity given: the AU as recorded (scale 1.0).
    Full,
    /// A FACS intensity letter `A` (trace) to `E` (maximum).
    Letter(char),
    /// An explicit scale after `@`.
    Scale(f32),
}

impl Intensity {
    /// The factor the recorded AU is multiplied by.
    pub fn factor(self) -> f32 {
        match self {
            Intensity::Full => 1.0,
            Intensity::Letter(c) => letter_factor(c).unwrap_or(1.0),
            Intensity::Scale(s) => s,
        }
    }
}

/// The scale of a FACS intensity letter: A 0.15, B 0.3, C 0.5, D 0.75, E 1.0, the middles of
/// FACS's unequal bands (module documentation).
pub fn letter_factor(letter: char) -> Option<f32> {
    match letter.to_ascii_uppercase() {
        'A' => Some(0.15),
        'B' => Some(0.3),
        'C' => Some(0.5),
        'D' => Some(0.75),
        'E' => Some(1.0),
        _ => None,
    }
}

/// One AU of a combination, with its intensity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    /// The AU, with its side.
    pub key: AuKey,
    /// How strongly it applies.
    pub intensity: Intensity,
}

/// A parsed combination: AUs applied together, in the order written.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Combo {
    /// The terms in the order written (repeats allowed: they add).
    pub terms: Vec<Term>,
}

/// A combination string that does not parse.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("column {column}: {message}")]
pub struct ComboError {
    /// The column (from 1, in characters) where the problem is.
    pub column: usize,
    /// What was expected there.
    pub message: String,
}

/// Parses a combination string such as `1+2+5B+26` or `6+12@0.5`.
pub fn parse_combo(text: &str) -> Result<Combo, ComboError> {
    let mut parser = Parser {
        chars: text.chars().collect(),
        at: 0,
    };
    let mut terms = vec![];
    loop {
        parser.skip_space();
        terms.push(parser.term()?);
        parser.skip_space();
        match parser.peek() {
            None => break,
            Some('+') => parser.at += 1,
            Some(c) => {
                return Err(parser.error(format!("unexpected `{c}`; expected `+` or the end")))
            }
        }
    }
    Ok(Combo { terms })
}

impl FromStr for Combo {
    type Err = ComboError;

    fn from_str(text: &str) -> Result<Combo, ComboError> {
        parse_combo(text)
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.key)?;
        match self.intensity {
            Intensity::Full => Ok(()),
            Intensity::Letter(c) => write!(f, "{}", c.to_ascii_uppercase()),
            Intensity::Scale(s) => write!(f, "@{s}"),
        }
    }
}

impl fmt::Display for Combo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, term) in self.terms.iter().enumerate() {
            if i > 0 {
                f.write_str("+")?;
            }
            write!(f, "{term}")?;
        }
        Ok(())
    }
}

struct Parser {
    chars: Vec<char>,
    at: usize,
}

impl Parser {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.at).copied()
    }

    fn skip_space(&mut self) {
        while self.peek().is_some_and(|c| c == ' ' || c == '\t') {
            self.at += 1;
        }
    }

    fn error(&self, message: String) -> ComboError {
        ComboError {
            column: self.at + 1,
            message,
        }
    }

    fn error_at(&self, at: usize, message: String) -> ComboError {
        ComboError {
            column: at + 1,
            message,
        }
    }

    fn take_while(&mut self, keep: impl Fn(char) -> bool) -> String {
        let start = self.at;
        while self.peek().is_some_and(&keep) {
            self.at += 1;
        }
        self.chars[start..self.at].iter().collect()
    }

    fn term(&mut self) -> Result<Term, ComboError> {
        let start = self.at;
        let side = match self.peek() {
            Some('L' | 'l') => Some(Side::Left),
            Some('R' | 'r') => Some(Side::Right),
            _ => None,
        };
        if side.is_some() {
            self.at += 1;
        }
        let number_at = self.at;
        let digits = self.take_while(|c| c.is_ascii_digit());
        if digits.is_empty() {
            return Err(match self.peek() {
                None => self.error("expected an AU number, found the end".to_string()),
                Some(c) => self.error(format!("expected an AU number, found `{c}`")),
            });
        }
        let number = digits
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=u32::from(MAX_AU_NUMBER)).contains(n))
            .ok_or_else(|| {
                self.error_at(
                    number_at,
                    format!("AU {digits} does not exist; AU numbers run from 1 to 99"),
                )
            })?;
        let key = AuKey {
            number: number as u8,
            side,
        };
        let intensity = self.intensity()?;
        if self
            .peek()
            .is_some_and(|c| c.is_alphanumeric() || c == '@' || c == '.')
        {
            let c = self.peek().unwrap_or(' ');
            return Err(self.error(format!(
                "unexpected `{c}` after AU {}; expected an intensity letter A-E or `@` with a number, then `+`",
                &self.chars[start..self.at].iter().collect::<String>()
            )));
        }
        Ok(Term { key, intensity })
    }

    fn intensity(&mut self) -> Result<Intensity, ComboError> {
        match self.peek() {
            Some(c) if letter_factor(c).is_some() => {
                self.at += 1;
                Ok(Intensity::Letter(c.to_ascii_uppercase()))
            }
            Some('@') => {
                self.at += 1;
                let scale_at = self.at;
                let digits = self.take_while(|c| c.is_ascii_digit() || c == '.');
                let scale = digits
                    .parse::<f32>()
                    .ok()
                    .filter(|s| s.is_finite() && *s >= 0.0)
                    .ok_or_else(|| {
                        let found = if digits.is_empty() {
                            "nothing".to_string()
                        } else {
                            format!("`{digits}`")
                        };
                        self.error_at(
                            scale_at,
                            format!("expected a scale such as 0.5 after `@`, found {found}"),
                        )
                    })?;
                Ok(Intensity::Scale(scale))
            }
            _ => Ok(Intensity::Full),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(s: &str) -> AuKey {
        s.parse().unwrap()
    }

    #[test]
    fn facs_examples() {
        let c = parse_combo("1+2+5B+26").unwrap();
        let keys: Vec<String> = c.terms.iter().map(|t| t.key.to_string()).collect();
        assert_eq!(keys, ["1", "2", "5", "26"]);
        assert_eq!(c.terms[2].intensity, Intensity::Letter('B'));
        assert_eq!(c.terms[2].intensity.factor(), 0.3);
        assert_eq!(c.terms[0].intensity.factor(), 1.0);

        let c = parse_combo("R12A+R14A").unwrap();
        assert_eq!(c.terms[0].key, key("R12"));
        assert_eq!(c.terms[1].key, key("R14"));
        assert_eq!(c.terms[1].intensity.factor(), 0.15);

        let c = parse_combo("6+12@0.5").unwrap();
        assert_eq!(c.terms[1].intensity, Intensity::Scale(0.5));
    }

    #[test]
    fn letters_follow_the_unequal_facs_bands() {
        let factors: Vec<f32> = "ABCDE"
            .chars()
            .map(|c| {
                parse_combo(&format!("12{c}")).unwrap().terms[0]
                    .intensity
                    .factor()
            })
            .collect();
        assert_eq!(factors, [0.15, 0.3, 0.5, 0.75, 1.0]);
        // the steps widen toward the middle of the scale: C and D span more than A and B
        let steps: Vec<f32> = factors.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(steps[0] < steps[1] && steps[1] < steps[2], "{steps:?}");
        assert_eq!(parse_combo("l12c").unwrap().terms[0].key, key("L12"));
    }

    #[test]
    fn whitespace_tolerant() {
        let a = parse_combo(" 1 +\t2B + 26@1.5 ").unwrap();
        assert_eq!(a, parse_combo("1+2B+26@1.5").unwrap());
        assert_eq!(a.to_string(), "1+2B+26@1.5");
    }

    #[test]
    fn display_round_trips() {
        for s in ["1+2+5B+26", "R12A+R14A", "6+12@0.5", "L46+12@2"] {
            assert_eq!(parse_combo(s).unwrap().to_string(), s);
        }
    }

    #[test]
    fn errors_name_the_column() {
        let cases = [
            ("", 1, "expected an AU number, found the end"),
            ("1+", 3, "expected an AU number, found the end"),
            ("1++2", 3, "expected an AU number, found `+`"),
            ("1+2F", 4, "unexpected `F` after AU 2;"),
            ("0", 1, "AU 0 does not exist"),
            ("12+100", 4, "AU 100 does not exist"),
            (
                "12@",
                4,
                "expected a scale such as 0.5 after `@`, found nothing",
            ),
            ("12@1.2.3", 4, "found `1.2.3`"),
            ("12@-1", 4, "found nothing"),
            ("12 13", 4, "unexpected `1`; expected `+` or the end"),
            ("12A@0.5", 4, "unexpected `@` after AU 12A"),
            ("R", 2, "expected an AU number, found the end"),
        ];
        for (text, column, start) in cases {
            let err = parse_combo(text).unwrap_err();
            assert_eq!(err.column, column, "{text:?}: {err}");
            assert!(
                err.message.starts_with(start) || err.message.contains(start),
                "{text:?}: {err}"
            );
        }
    }
}
