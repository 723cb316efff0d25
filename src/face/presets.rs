//! The preset files of the default face: the two rigs and the AU table, as RON text.

use anyhow::Context;
use ron::ser::PrettyConfig;
use serde::Serialize;

use super::rigs;
use crate::model::Mesh;

/// File name of the paper's rig.
pub const PAPER_RIG_FILE: &str = "paper.rig.ron";
/// File name of the default rig.
pub const DEFAULT_RIG_FILE: &str = "default.rig.ron";

/// The preset files for a generated default face, as `(file name, RON text)`.
pub fn preset_files(mesh: &Mesh) -> anyhow::Result<Vec<(&'static str, String)>> {
    let paper = rigs::paper_rig(mesh).context("cannot place the paper's rig")?;
    let default = rigs::default_rig(mesh).context("cannot place the default rig")?;
    Ok(vec![
        (PAPER_RIG_FILE, to_ron(&paper)?),
        (DEFAULT_RIG_FILE, to_ron(&default)?),
    ])
}

/// Pretty RON with a trailing newline; the same value always gives the same text.
pub fn to_ron<T: Serialize>(value: &T) -> anyhow::Result<String> {
    let config = PrettyConfig::new()
        .struct_names(false)
        .compact_arrays(false)
        .indentor("  ".to_string());
    let mut text = ron::ser::to_string_pretty(value, config).context("cannot write RON")?;
    text.push('\n');
    Ok(text)
}
