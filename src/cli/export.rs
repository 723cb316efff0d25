//! `grimace export`: the mesh deformed by an AU, an expression, a combination or muscle
//! values, written as OBJ.
//!
//! The source and state arguments ([`SourceArgs`], [`StateArgs`]) and their loading
//! ([`load_sources`], [`activations`]) are shared with other commands that show one state.

use std::path::PathBuf;

use anyhow::{anyhow, bail};
use clap::Args;

use crate::facs::combo::Combo;
use crate::facs::{AuKey, AuTable};
use crate::io::obj;
use crate::io::rig_file::{self, LoadedRig};
use crate::io::table_file;
use crate::model::{Activations, BoundRig};

/// Where the rig, mesh and AU table come from.
#[derive(Debug, Clone, Args)]
pub struct SourceArgs {
    /// The rig (*.rig.ron, or builtin:default, builtin:paper). Default: the rig the table
    /// names; with neither, the built-in default face.
    #[arg(long, value_name = "RIG")]
    pub rig: Option<PathBuf>,
    /// A mesh (*.obj) to use instead of the one the rig names (same vertex order).
    #[arg(long, value_name = "MESH")]
    pub mesh: Option<PathBuf>,
    /// The AU table (*.au.ron, or builtin:default) for --au, --expr and --combo. Default:
    /// the built-in table when no rig is given either.
    #[arg(long, value_name = "TABLE")]
    pub table: Option<PathBuf>,
}

/// Which state to show: at most one of an AU, an expression or a combination from the
/// table, then individual muscle values and the jaw on top. Nothing given is the rest state.
#[derive(Debug, Clone, Args)]
pub struct StateArgs {
    /// One recorded AU of the table at full intensity, e.g. 12 or R12.
    #[arg(long, value_name = "AU", conflicts_with_all = ["expr", "combo"])]
    pub au: Option<AuKey>,
    /// A named expression of the table.
    #[arg(long, value_name = "NAME", conflicts_with = "combo")]
    pub expr: Option<String>,
    /// An AU combination as FACS writes it, e.g. "1+2+5B+26" or "6+12@0.5".
    #[arg(long, value_name = "COMBO")]
    pub combo: Option<Combo>,
    /// Set one muscle's activation (0 to 2), replacing what the table gave; repeatable.
    #[arg(long = "set", value_name = "MUSCLE=VALUE", value_parser = parse_set)]
    pub set: Vec<(String, f32)>,
    /// Set the jaw activation (0 to 4).
    #[arg(long, value_name = "VALUE")]
    pub jaw: Option<f32>,
}

/// Arguments of `grimace export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Rig, mesh and table.
    #[command(flatten)]
    pub source: SourceArgs,
    /// The state to export.
    #[command(flatten)]
    pub state: StateArgs,
    /// The OBJ file to write.
    #[arg(long, value_name = "FILE.obj")]
    pub out: PathBuf,
}

/// Parses `MUSCLE=VALUE` (split at the last `=`).
pub fn parse_set(text: &str) -> Result<(String, f32), String> {
    let (name, value) = text
        .rsplit_once('=')
        .ok_or_else(|| format!("`{text}` is not MUSCLE=VALUE"))?;
    let value: f32 = value
        .trim()
        .parse()
        .map_err(|_| format!("`{value}` is not a number (in `{text}`)"))?;
    if name.trim().is_empty() {
        return Err(format!("`{text}` has no muscle name before `=`"));
    }
    Ok((name.trim().to_string(), value))
}

/// A loaded rig with its mesh, and the AU table if one was given.
#[derive(Debug, Clone)]
pub struct Sources {
    /// The rig and its mesh.
    pub rig: LoadedRig,
    /// The AU table, checked against the rig.
    pub table: Option<AuTable>,
    /// The table's file.
    pub table_path: Option<PathBuf>,
}

/// Loads the rig (given, or named by the table) with its mesh, and the table checked
/// against the rig.
pub fn load_sources(source: &SourceArgs) -> anyhow::Result<Sources> {
    let mesh = source.mesh.as_deref();
    let (rig, table, table_path) = match (&source.rig, &source.table) {
        (Some(rig_path), table_path) => {
            let rig = rig_file::load_rig_ref(rig_path, mesh)?;
            let table = match table_path {
                Some(path) => Some(table_file::load_table_ref_for(path, &rig.rig)?),
                None => None,
            };
            (rig, table, table_path.clone())
        }
        (None, Some(table_path)) => {
            let (table, rig) = table_file::load_table_and_rig(table_path, mesh)?;
            (rig, Some(table), Some(table_path.clone()))
        }
        (None, None) => {
            // The built-in default face: its rig and its table.
            let default = PathBuf::from(DEFAULT_TABLE);
            let (table, rig) = table_file::load_table_and_rig(&default, mesh)?;
            (rig, Some(table), Some(default))
        }
    };
    if let Some(notice) = &rig.notice {
        eprintln!("warning: {notice}");
    }
    Ok(Sources {
        rig,
        table,
        table_path,
    })
}

/// The built-in table used when neither a rig nor a table is given.
pub const DEFAULT_TABLE: &str = "builtin:default";

/// Binds a loaded rig to its mesh, naming the rig file on failure.
pub fn bind(rig: &LoadedRig) -> anyhow::Result<BoundRig> {
    BoundRig::bind(&rig.rig, &rig.mesh).map_err(|e| anyhow!("{}: {e}", rig.path.display()))
}

/// The activations a state asks for, checked against the rig's ranges.
pub fn activations(state: &StateArgs, sources: &Sources) -> anyhow::Result<Activations> {
    let rig = &sources.rig.rig;
    let table_name = || {
        sources
            .table_path
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_default()
    };
    let need_table = |flag: &str| -> anyhow::Result<&AuTable> {
        sources
            .table
            .as_ref()
            .ok_or_else(|| anyhow!("{flag} needs an AU table: pass --table TABLE"))
    };
    let mut act = if let Some(key) = &state.au {
        need_table("--au")?
            .entry_activations(key, rig)
            .map_err(|e| anyhow!("{}: {e}", table_name()))?
    } else if let Some(name) = &state.expr {
        need_table("--expr")?
            .expression_activations(name, rig)
            .map_err(|e| anyhow!("{}: {e}", table_name()))?
    } else if let Some(combo) = &state.combo {
        need_table("--combo")?
            .evaluate(combo, rig)
            .map_err(|e| anyhow!("{}: {e}", table_name()))?
    } else {
        Activations::zero(rig)
    };
    for (name, value) in &state.set {
        let index = rig.muscle_index(name).ok_or_else(|| {
            anyhow!(
                "--set {name}={value}: the rig {} has no muscle named `{name}` (see `grimace list --rig`)",
                sources.rig.path.display()
            )
        })?;
        act.muscles[index] = *value;
    }
    if let Some(jaw) = state.jaw {
        if rig.jaw.is_none() && jaw != 0.0 {
            bail!(
                "--jaw {jaw}: the rig {} has no jaw",
                sources.rig.path.display()
            );
        }
        act.jaw = jaw;
    }
    act.validate(rig)?;
    Ok(act)
}

/// Runs `grimace export`.
pub fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let sources = load_sources(&args.source)?;
    let act = activations(&args.state, &sources)?;
    let bound = bind(&sources.rig)?;
    let mut positions = Vec::new();
    bound.deform(&act, &mut positions)?;
    obj::save_obj(&args.out, &sources.rig.mesh, &positions)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_values_parse() {
        assert_eq!(parse_set("L_Zyg=1.5"), Ok(("L_Zyg".into(), 1.5)));
        assert_eq!(parse_set(" a = 0 "), Ok(("a".into(), 0.0)));
        assert!(parse_set("a").is_err());
        assert!(parse_set("=1").is_err());
        assert!(parse_set("a=x").is_err());
    }
}
