//! AU tables: recorded AUs (muscle activations per FACS AU) and named expressions.
//!
//! The table is pure data plus the operations an editor or a script needs: evaluate a
//! combination into activations, record an AU from activations, rename, remove, and define
//! expressions. Every operation keeps the table valid: at most [`MAX_AUS`] AUs, FACS codes
//! only, activations finite and in range, expressions naming AUs of the table.

use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;

use serde::{Deserialize, Deserializer, Serialize};
use thiserror::Error;

use super::au::AuKey;
use super::au::{resolve, Resolved};
use super::catalogue;
use super::combo::{parse_combo, Combo, ComboError};
use crate::model::{Activations, Rig, JAW_RANGE, MUSCLE_RANGE};

/// The AU table file format version this build reads and writes.
pub const TABLE_VERSION: u32 = 1;

/// The most AU entries a table may hold (the paper's editor has 64 slots).
pub const MAX_AUS: usize = 64;

/// One recorded AU: the muscle activations (and jaw) that express it on a rig.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, rename = "AU")]
pub struct AuEntry {
    /// The FACS name, e.g. `Lip Corner Puller`.
    pub name: String,
    /// Activation per muscle name; muscles not listed are at 0.
    #[serde(default, deserialize_with = "unique_map")]
    pub muscles: BTreeMap<String, f32>,
    /// Jaw activation.
    #[serde(default)]
    pub jaw: f32,
}

/// An AU table: up to [`MAX_AUS`] AU entries and named expressions, for one rig.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "table")]
pub struct AuTable {
    /// File format version; see [`TABLE_VERSION`].
    pub version: u32,
    /// The rig the table is for: a path relative to the table file, or `builtin:NAME`.
    pub rig: PathBuf,
    /// Recorded AUs, keyed by AU.
    #[serde(default, deserialize_with = "unique_map")]
    pub aus: BTreeMap<AuKey, AuEntry>,
    /// Named expressions, each an AU combination string such as `6+12`.
    #[serde(default, deserialize_with = "unique_map")]
    pub expressions: BTreeMap<String, String>,
}

/// Reads a map, refusing a key given twice (a plain map would silently keep the last).
fn unique_map<'de, D, K, V>(d: D) -> Result<BTreeMap<K, V>, D::Error>
where
    D: Deserializer<'de>,
    K: Deserialize<'de> + Ord + fmt::Display,
    V: Deserialize<'de>,
{
    struct Visit<K, V>(std::marker::PhantomData<(K, V)>);
    impl<'de, K, V> serde::de::Visitor<'de> for Visit<K, V>
    where
        K: Deserialize<'de> + Ord + fmt::Display,
        V: Deserialize<'de>,
    {
        type Value = BTreeMap<K, V>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("a map `{ key: value, ... }`")
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(
            self,
            mut map: A,
        ) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(key) = map.next_key::<K>()? {
                if out.contains_key(&key) {
                    return Err(serde::de::Error::custom(format!(
                        "key \"{key}\" given twice; each key may appear once"
                    )));
                }
                let value = map.next_value()?;
                out.insert(key, value);
            }
            Ok(out)
        }
    }
    d.deserialize_map(Visit(std::marker::PhantomData))
}

/// Why a table operation or check failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TableError {
    /// The file format version is not [`TABLE_VERSION`].
    #[error("table version {0} is not supported; this grimace reads version {TABLE_VERSION}")]
    WrongVersion(u32),
    /// More than [`MAX_AUS`] AUs.
    #[error("the table has {0} AUs, more than the limit of {MAX_AUS}")]
    TooManyAus(usize),
    /// Adding an AU to a full table.
    #[error("the table is full ({MAX_AUS} AUs); remove one first")]
    Full,
    /// An AU number that is not a FACS code.
    #[error("AU {0} is not a FACS code (see `grimace list --catalogue`)")]
    NotFacs(AuKey),
    /// AUs a combination or expression names that the table lacks.
    #[error("the table has no AU {}", list(.0))]
    MissingAus(Vec<AuKey>),
    /// An AU is already in the table.
    #[error("AU {0} is already in the table")]
    Exists(AuKey),
    /// An AU is not in the table.
    #[error("the table has no AU {0}")]
    NoSuchAu(AuKey),
    /// Removing an AU that expressions use.
    #[error("AU {au} is used by expression {}; change or remove those first", quoted(.expressions))]
    InUse {
        /// The AU.
        au: AuKey,
        /// The expressions that use it.
        expressions: Vec<String>,
    },
    /// An AU names a muscle the rig does not have.
    #[error("AU {au} names muscle `{muscle}`, which the rig does not have")]
    UnknownMuscle {
        /// The AU.
        au: AuKey,
        /// The muscle name.
        muscle: String,
    },
    /// A muscle name that is empty.
    #[error("AU {au} has an empty muscle name")]
    EmptyMuscleName {
        /// The AU.
        au: AuKey,
    },
    /// An activation that is not finite or out of range.
    #[error("AU {au}: activation of `{muscle}` is {value}; expected {min} to {max}")]
    Activation {
        /// The AU.
        au: AuKey,
        /// The muscle (`jaw` for the jaw).
        muscle: String,
        /// The value.
        value: f32,
        /// Lowest allowed.
        min: f32,
        /// Highest allowed.
        max: f32,
    },
    /// Activations given to [`AuTable::record`] that do not fit the rig.
    #[error("{0}")]
    BadActivations(#[from] crate::model::ActivationError),
    /// An expression whose combination does not parse.
    #[error("expression `{expression}`: {error}")]
    BadCombo {
        /// The expression's name.
        expression: String,
        /// The parse error.
        error: ComboError,
    },
    /// An expression naming AUs the table lacks.
    #[error("expression `{expression}` uses AU {}, which the table does not have", list(.missing))]
    ExpressionMissingAus {
        /// The expression's name.
        expression: String,
        /// The AUs it lacks.
        missing: Vec<AuKey>,
    },
    /// An expression name that is empty or has surrounding spaces.
    #[error("expression name {0:?} is empty or starts or ends with a space")]
    BadExpressionName(String),
    /// No expression of that name.
    #[error("the table has no expression `{0}`")]
    NoSuchExpression(String),
}

fn list(keys: &[AuKey]) -> String {
    keys.iter()
        .map(AuKey::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl AuTable {
    /// An empty table for a rig (a path relative to the table file, or `builtin:NAME`).
    pub fn new(rig: impl Into<PathBuf>) -> AuTable {
        AuTable {
            version: TABLE_VERSION,
            rig: rig.into(),
            aus: BTreeMap::new(),
            expressions: BTreeMap::new(),
        }
    }

    /// Checks the table on its own: version, size, FACS codes, activation ranges, and
    /// expressions that parse and name AUs of the table.
    pub fn check(&self) -> Result<(), TableError> {
        if self.version != TABLE_VERSION {
            return Err(TableError::WrongVersion(self.version));
        }
        if self.aus.len() > MAX_AUS {
            return Err(TableError::TooManyAus(self.aus.len()));
        }
        for (key, entry) in &self.aus {
            if !catalogue::is_code(key.number) {
                return Err(TableError::NotFacs(*key));
            }
            check_entry(*key, entry)?;
        }
        for (name, combo) in &self.expressions {
            self.check_expression(name, combo)?;
        }
        Ok(())
    }

    /// Checks the table against a rig: every muscle an AU names exists in the rig.
    pub fn check_rig(&self, rig: &Rig) -> Result<(), TableError> {
        for (key, entry) in &self.aus {
            if let Some(muscle) = entry.muscles.keys().find(|m| rig.muscle_index(m).is_none()) {
                return Err(TableError::UnknownMuscle {
                    au: *key,
                    muscle: muscle.clone(),
                });
            }
        }
        Ok(())
    }

    pub(super) fn check_expression(&self, name: &str, combo: &str) -> Result<Combo, TableError> {
        if name.is_empty() || name.trim() != name {
            return Err(TableError::BadExpressionName(name.to_string()));
        }
        let parsed = parse_combo(combo).map_err(|error| TableError::BadCombo {
            expression: name.to_string(),
            error,
        })?;
        let missing = self.missing(&parsed);
        if !missing.is_empty() {
            return Err(TableError::ExpressionMissingAus {
                expression: name.to_string(),
                missing,
            });
        }
        Ok(parsed)
    }

    /// The AUs of a combination the table cannot give, each once, in the order written. A
    /// one-sided AU recorded only bilaterally, or a bilateral one recorded only by side, is
    /// not missing ([`crate::facs::au::resolve`]).
    pub fn missing(&self, combo: &Combo) -> Vec<AuKey> {
        let mut missing: Vec<AuKey> = vec![];
        for term in &combo.terms {
            if !self.gives(term.key) && !missing.contains(&term.key) {
                missing.push(term.key);
            }
        }
        missing
    }

    /// Whether the table gives an AU: recorded, or resolved from recordings by the mapper's
    /// rule (`L45` from `45`, `12` from `L12` and `R12`).
    pub fn gives(&self, key: AuKey) -> bool {
        resolve(&self.aus, key) != Resolved::Missing
    }

    /// The recorded keys an AU is played from.
    pub(super) fn sources_of(&self, key: AuKey) -> Vec<AuKey> {
        match resolve(&self.aus, key) {
            Resolved::Recorded => vec![key],
            Resolved::Sides(sides) => sides,
            Resolved::FromBilateral(bilateral) => vec![bilateral],
            Resolved::Missing => Vec::new(),
        }
    }

    /// Records an AU from the current activations: the non-zero muscles by name, and the jaw.
    /// Replaces an existing entry of the same key; a new key needs a free slot. An empty
    /// `name` takes the FACS name from the catalogue.
    pub fn record(
        &mut self,
        key: AuKey,
        name: &str,
        rig: &Rig,
        activations: &Activations,
    ) -> Result<(), TableError> {
        if !catalogue::is_code(key.number) {
            return Err(TableError::NotFacs(key));
        }
        activations.validate(rig)?;
        if !self.aus.contains_key(&key) && self.aus.len() >= MAX_AUS {
            return Err(TableError::Full);
        }
        let muscles = rig
            .muscles
            .iter()
            .zip(&activations.muscles)
            .filter(|(_, &a)| a != 0.0)
            .map(|(m, &a)| (m.name.clone(), a))
            .collect();
        let name = if name.is_empty() {
            catalogue::name_of(key.number).unwrap_or_default()
        } else {
            name
        };
        self.aus.insert(
            key,
            AuEntry {
                name: name.to_string(),
                muscles,
                jaw: activations.jaw,
            },
        );
        Ok(())
    }

    /// The expressions whose combination uses an AU.
    pub fn expressions_using(&self, key: &AuKey) -> Vec<String> {
        self.expressions
            .iter()
            .filter(|(_, combo)| {
                parse_combo(combo).is_ok_and(|c| {
                    c.terms
                        .iter()
                        .any(|t| t.key == *key || self.sources_of(t.key).contains(key))
                })
            })
            .map(|(name, _)| name.clone())
            .collect()
    }

    /// Removes an AU. Refused while an expression uses it, so the table stays valid.
    pub fn remove(&mut self, key: &AuKey) -> Result<AuEntry, TableError> {
        if !self.aus.contains_key(key) {
            return Err(TableError::NoSuchAu(*key));
        }
        let expressions = self.expressions_using(key);
        if !expressions.is_empty() {
            return Err(TableError::InUse {
                au: *key,
                expressions,
            });
        }
        self.aus.remove(key).ok_or(TableError::NoSuchAu(*key))
    }

    /// Moves an AU to another key (for example `12` to `L12`), rewriting the expressions that
    /// use it. The new key must be a FACS code not already in the table.
    pub fn rename(&mut self, from: &AuKey, to: AuKey) -> Result<(), TableError> {
        if from == &to {
            return if self.aus.contains_key(from) {
                Ok(())
            } else {
                Err(TableError::NoSuchAu(*from))
            };
        }
        if !catalogue::is_code(to.number) {
            return Err(TableError::NotFacs(to));
        }
        if self.aus.contains_key(&to) {
            return Err(TableError::Exists(to));
        }
        let entry = self.aus.remove(from).ok_or(TableError::NoSuchAu(*from))?;
        self.aus.insert(to, entry);
        for combo in self.expressions.values_mut() {
            if let Ok(mut parsed) = parse_combo(combo) {
                if parsed.terms.iter().any(|t| t.key == *from) {
                    for term in &mut parsed.terms {
                        if term.key == *from {
                            term.key = to;
                        }
                    }
                    *combo = parsed.to_string();
                }
            }
        }
        Ok(())
    }

    /// Adds or replaces a named expression. The combination must parse and name AUs of the
    /// table; it is stored as written.
    pub fn set_expression(&mut self, name: &str, combo: &str) -> Result<(), TableError> {
        self.check_expression(name, combo)?;
        self.expressions.insert(name.to_string(), combo.to_string());
        Ok(())
    }

    /// Removes a named expression, returning its combination.
    pub fn remove_expression(&mut self, name: &str) -> Result<String, TableError> {
        self.expressions
            .remove(name)
            .ok_or_else(|| TableError::NoSuchExpression(name.to_string()))
    }
}

fn check_entry(key: AuKey, entry: &AuEntry) -> Result<(), TableError> {
    let range_error =
        |muscle: &str, value: f32, range: &std::ops::RangeInclusive<f32>| TableError::Activation {
            au: key,
            muscle: muscle.to_string(),
            value,
            min: *range.start(),
            max: *range.end(),
        };
    for (muscle, &value) in &entry.muscles {
        if muscle.is_empty() {
            return Err(TableError::EmptyMuscleName { au: key });
        }
        if !(value.is_finite() && MUSCLE_RANGE.contains(&value)) {
            return Err(range_error(muscle, value, &MUSCLE_RANGE));
        }
    }
    if !(entry.jaw.is_finite() && JAW_RANGE.contains(&entry.jaw)) {
        return Err(range_error("jaw", entry.jaw, &JAW_RANGE));
    }
    Ok(())
}
