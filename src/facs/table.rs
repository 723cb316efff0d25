//! AU tables: recorded AUs (muscle activations per FACS AU) and named expressions.

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::au::AuKey;

/// The AU table file format version this build reads and writes.
pub const TABLE_VERSION: u32 = 1;

/// The most AU entries a table may hold (the paper's editor has 64 slots).
pub const MAX_AUS: usize = 64;

/// One recorded AU: the muscle activations (and jaw) that express it on a rig.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct AuEntry {
    /// The FACS name, e.g. `Lip Corner Puller`.
    pub name: String,
    /// Activation per muscle name; muscles not listed are at 0.
    #[serde(default)]
    pub muscles: BTreeMap<String, f32>,
    /// Jaw activation.
    #[serde(default)]
    pub jaw: f32,
}

/// An AU table: up to [`MAX_AUS`] AU entries and named expressions, for one rig.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AuTable {
    /// File format version; see [`TABLE_VERSION`].
    pub version: u32,
    /// The rig the table is for: a path relative to the table file, or `builtin:NAME`.
    pub rig: PathBuf,
    /// Recorded AUs, keyed by AU.
    #[serde(default)]
    pub aus: BTreeMap<AuKey, AuEntry>,
    /// Named expressions, each an AU combination string such as `6+12`.
    #[serde(default)]
    pub expressions: BTreeMap<String, String>,
}
