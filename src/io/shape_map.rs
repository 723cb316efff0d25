//! Shape maps (`*.map.ron`): which AU each shape of a blendshape set shows, for
//! `grimace fit-au --map`.
//!
//! ```text
//! {
//!     "mouthSmile_L": "L12",
//!     "mouthLeft": "-",          // no AU shows this shape: left out
//! }
//! ```
//!
//! Each AU key may be named once. `builtin:arkit` is the map for ARKit's 52 blendshapes.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use super::error::{read_text, LoadError, MAX_FILE_BYTES};
use super::{builtin, ron_text};
use crate::facs::AuKey;

/// Reads a shape map: a file, or `builtin:arkit`.
pub fn load_map(path: &Path) -> Result<BTreeMap<String, AuKey>, LoadError> {
    let text = if path == Path::new("builtin:arkit") {
        builtin::ARKIT_MAP.to_string()
    } else {
        read_text(path, MAX_FILE_BYTES)?
    };
    parse_map(&text, path)
}

/// Parses a shape map: `{ "NAME": "KEY", ... }`; `"-"` leaves a shape out (no AU shows it).
pub fn parse_map(text: &str, path: &Path) -> Result<BTreeMap<String, AuKey>, LoadError> {
    #[derive(Deserialize)]
    #[serde(transparent)]
    struct MapFile(BTreeMap<String, String>);
    let file: MapFile = ron_text::parse(path, text, "a shape map")?;
    let mut out = BTreeMap::new();
    let mut seen: BTreeMap<AuKey, String> = BTreeMap::new();
    for (name, key) in file.0 {
        if key == "-" {
            continue;
        }
        let au: AuKey = key.parse().map_err(|e| {
            LoadError::new(
                path,
                format!("shape `{name}`: `{key}` is not an AU key ({e})"),
            )
        })?;
        if let Some(other) = seen.insert(au, name.clone()) {
            return Err(LoadError::new(
                path,
                format!(
                    "shapes `{other}` and `{name}` both map to AU {au}; each AU takes one shape"
                ),
            ));
        }
        out.insert(name, au);
    }
    Ok(out)
}
