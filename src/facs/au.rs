//! AU keys: a FACS Action Unit number with an optional side (`12`, `L12`, `R12`).

use std::collections::BTreeMap;
use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::model::Side;

/// The highest AU number grimace accepts (FACS codes run from 1 to 99 with gaps; the
/// catalogue in [`crate::facs::catalogue`] says which exist).
pub const MAX_AU_NUMBER: u8 = 99;

/// A FACS Action Unit, optionally unilateral.
///
/// Written as FACS writes it: `12` (both sides), `L12` (the subject's left), `R12` (right).
/// Ordered by number, then bilateral before left before right.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(into = "String", try_from = "String")]
pub struct AuKey {
    /// The FACS AU number (1-99).
    pub number: u8,
    /// `None` for a bilateral AU, `Some(Left)` or `Some(Right)` for a unilateral one.
    pub side: Option<Side>,
}

/// A string that is not an AU key.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("`{text}` is not an AU: {why} (expected a FACS number such as 12, optionally with L or R before it)")]
pub struct AuKeyError {
    /// The text given.
    pub text: String,
    /// What is wrong with it.
    pub why: &'static str,
}

impl AuKey {
    /// A bilateral AU.
    pub fn new(number: u8) -> AuKey {
        AuKey { number, side: None }
    }

    /// The same AU on the other side (bilateral stays bilateral).
    pub fn mirrored(self) -> AuKey {
        AuKey {
            number: self.number,
            side: self.side.map(Side::mirrored),
        }
    }

    fn order(&self) -> (u8, u8) {
        let side = match self.side {
            None | Some(Side::Centre) => 0,
            Some(Side::Left) => 1,
            Some(Side::Right) => 2,
        };
        (self.number, side)
    }
}

impl PartialOrd for AuKey {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for AuKey {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.order().cmp(&other.order())
    }
}

impl fmt::Display for AuKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.side {
            Some(Side::Left) => write!(f, "L{}", self.number),
            Some(Side::Right) => write!(f, "R{}", self.number),
            _ => write!(f, "{}", self.number),
        }
    }
}

impl FromStr for AuKey {
    type Err = AuKeyError;

    fn from_str(text: &str) -> Result<AuKey, AuKeyError> {
        let err = |why| AuKeyError {
            text: text.to_string(),
            why,
        };
        let trimmed = text.trim();
        let (side, digits) = match trimmed.chars().next() {
            Some('L' | 'l') => (Some(Side::Left), &trimmed[1..]),
            Some('R' | 'r') => (Some(Side::Right), &trimmed[1..]),
            Some(_) => (None, trimmed),
            None => return Err(err("it is empty")),
        };
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(err("the number is missing or not a whole number"));
        }
        let number: u32 = digits.parse().map_err(|_| err("the number is too large"))?;
        if number == 0 || number > u32::from(MAX_AU_NUMBER) {
            return Err(err("AU numbers run from 1 to 99"));
        }
        Ok(AuKey {
            number: number as u8,
            side,
        })
    }
}

impl From<AuKey> for String {
    fn from(key: AuKey) -> String {
        key.to_string()
    }
}

impl TryFrom<String> for AuKey {
    type Error = AuKeyError;

    fn try_from(text: String) -> Result<AuKey, AuKeyError> {
        text.parse()
    }
}

/// Where an AU key's activations come from in a table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Resolved {
    /// The key is recorded.
    Recorded,
    /// A bilateral key recorded only by side: the recorded sides, played together.
    Sides(Vec<AuKey>),
    /// A one-sided key recorded only bilaterally: derived from this bilateral key.
    FromBilateral(AuKey),
    /// The table cannot give this key.
    Missing,
}

/// How a key resolves against the recorded keys `recorded`: the one rule by which a table
/// gives an AU (see [`crate::facs::mapper`]).
pub fn resolve<T>(recorded: &BTreeMap<AuKey, T>, key: AuKey) -> Resolved {
    if recorded.contains_key(&key) {
        return Resolved::Recorded;
    }
    let bilateral = AuKey::new(key.number);
    match key.side {
        None | Some(Side::Centre) => {
            let sides: Vec<AuKey> = [Side::Left, Side::Right]
                .into_iter()
                .map(|side| AuKey {
                    number: key.number,
                    side: Some(side),
                })
                .filter(|k| recorded.contains_key(k))
                .collect();
            if sides.is_empty() {
                Resolved::Missing
            } else {
                Resolved::Sides(sides)
            }
        }
        Some(_) if recorded.contains_key(&bilateral) => Resolved::FromBilateral(bilateral),
        Some(_) => Resolved::Missing,
    }
}
