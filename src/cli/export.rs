//! `grimace export`: the mesh deformed by an AU, an expression, a combination or muscle
//! values, written as OBJ; or, with `--gltf`, the rest mesh with one morph target per AU,
//! expression, muscle or ARKit blendshape, written as binary glTF.
//!
//! The source and state arguments ([`SourceArgs`], [`StateArgs`]) and their loading
//! ([`load_sources`], [`activations`]) are shared with other commands that show one state.

use std::path::PathBuf;

use anyhow::{anyhow, bail};
use clap::Args;

use crate::facs::combo::Combo;
use crate::facs::{AuKey, AuTable};
use crate::io::arkit::ArkitMap;
use crate::io::inputs::Inputs;
use crate::io::load::{load_rig_ref, load_table_and_rig, load_table_ref_for, LoadedRig};
use crate::io::morph::{morph_targets, target_states, TargetSet, TargetStates};
use crate::io::{gltf, obj};
use crate::model::{Activations, BoundRig, Deformation};
use glam::Quat;

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
    /// the built-in table when no rig is given, or when the rig has every muscle it names
    /// (rigs fitted from the built-in template).
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
    #[arg(long, value_name = "FILE.obj", required_unless_present = "gltf")]
    pub out: Option<PathBuf>,
    /// Write the rest mesh with morph targets as binary glTF 2.0 instead (see docs/gltf.md).
    #[arg(
        long,
        value_name = "FILE.glb",
        conflicts_with_all = ["out", "au", "expr", "combo", "set", "jaw"]
    )]
    pub gltf: Option<PathBuf>,
    /// The morph targets of --gltf: one per AU of the table, per expression, per muscle at
    /// activation 1, or ARKit's 52 blendshapes through the ARKit map.
    #[arg(long, value_enum, default_value = "aus", requires = "gltf")]
    pub targets: Targets,
    /// Millimetres per mesh unit for --gltf (glTF is in metres; the node's scale converts).
    /// Default: 11.5 for the built-in face (docs/face.md), else 1 (a mesh in millimetres).
    #[arg(long, value_name = "MM", requires = "gltf")]
    pub unit_mm: Option<f32>,
    /// Keep the mesh's own axes in --gltf: by default a face whose mesh is not y up (a z-up
    /// scan) gets the node rotation that stands it up in glTF's y-up viewers.
    #[arg(long, requires = "gltf")]
    pub keep_axes: bool,
    /// The deformation.
    #[command(flatten)]
    pub model: ModelArgs,
}

/// `--model`: which deformation a command uses.
#[derive(Debug, Clone, Copy, Args)]
pub struct ModelArgs {
    /// The deformation: `skin` (the default: what the editor, `play` and `render` show) or
    /// `paper` (the paper's bare linear model, for comparison with the classic data; see
    /// docs/model.md).
    #[arg(
        long = "model",
        value_name = "MODEL",
        default_value = "skin",
        value_parser = parse_model
    )]
    pub deformation: Deformation,
}

/// Parses `--model`.
fn parse_model(text: &str) -> Result<Deformation, String> {
    text.parse()
}

/// The `--targets` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Targets {
    /// One per recorded AU (`AU12`, `AU_L12`).
    Aus,
    /// One per named expression.
    Expressions,
    /// One per muscle at activation 1, and `jaw` at 1.
    Muscles,
    /// ARKit's 52 blendshape names, through presets/arkit.map.ron.
    Arkit,
}

impl From<Targets> for TargetSet {
    fn from(targets: Targets) -> TargetSet {
        match targets {
            Targets::Aus => TargetSet::Aus,
            Targets::Expressions => TargetSet::Expressions,
            Targets::Muscles => TargetSet::Muscles,
            Targets::Arkit => TargetSet::Arkit,
        }
    }
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
        (Some(rig_path), Some(table_path)) => {
            let rig = load_rig_ref(rig_path, mesh)?;
            let table = load_table_ref_for(table_path, &rig.rig)?;
            (rig, Some(table), Some(table_path.clone()))
        }
        (Some(rig_path), None) => {
            let rig = load_rig_ref(rig_path, mesh)?;
            // A rig fitted from the built-in template keeps its muscle names, so the built-in
            // table drives it; any other rig has no table until one is given.
            let default = PathBuf::from(DEFAULT_TABLE);
            match load_table_ref_for(&default, &rig.rig) {
                Ok(table) => (rig, Some(table), Some(default)),
                Err(_) => (rig, None, None),
            }
        }
        (None, Some(table_path)) => {
            let (table, rig) = load_table_and_rig(table_path, mesh)?;
            (rig, Some(table), Some(table_path.clone()))
        }
        (None, None) => {
            // The built-in default face: its rig and its table.
            let default = PathBuf::from(DEFAULT_TABLE);
            let (table, rig) = load_table_and_rig(&default, mesh)?;
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

impl Sources {
    /// The files these sources were read from: what no output may replace.
    pub fn inputs(&self) -> Inputs {
        let mut inputs = Inputs::new();
        inputs.add_rig(&self.rig);
        if let Some(table) = &self.table_path {
            inputs.add("the AU table", table);
        }
        inputs
    }
}

/// The built-in table used when neither a rig nor a table is given.
pub const DEFAULT_TABLE: &str = "builtin:default";

/// Binds a loaded rig to its mesh with a deformation, naming the rig file on failure.
/// A big head's bind comes from the bind cache when it holds it (`io::bind_cache`); the
/// cache's warnings go to stderr.
pub fn bind(rig: &LoadedRig, model: Deformation) -> anyhow::Result<BoundRig> {
    let done = crate::io::bind_cache::bind(model, &rig.rig, &rig.mesh)
        .map_err(|e| anyhow!("{}: {e}", rig.path.display()))?;
    for warning in &done.warnings {
        eprintln!("warning: {warning}");
    }
    Ok(done.bound)
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
    if let Some(path) = &args.gltf {
        return export_gltf(args, &sources, path);
    }
    let act = activations(&args.state, &sources)?;
    let bound = bind(&sources.rig, args.model.deformation)?;
    let mut positions = Vec::new();
    bound.deform(&act, &mut positions)?;
    let out = args
        .out
        .as_ref()
        .ok_or_else(|| anyhow!("give --out FILE.obj or --gltf FILE.glb"))?;
    sources.inputs().check_output(out)?;
    let mesh = &sources.rig.mesh;
    obj::MovedObj::new(sources.rig.mesh_path.as_deref(), mesh).save(out, mesh, &positions)?;
    Ok(())
}

/// Writes the rest mesh and the chosen morph targets as `.glb`.
fn export_gltf(args: &ExportArgs, sources: &Sources, path: &std::path::Path) -> anyhow::Result<()> {
    let rig = &sources.rig.rig;
    let no_table = AuTable::new(sources.rig.path.clone());
    let table = match (&sources.table, args.targets) {
        (Some(table), _) => table,
        // One target per muscle needs nothing from a table.
        (None, Targets::Muscles) => &no_table,
        (None, _) => bail!("--gltf needs an AU table for these targets: pass --table TABLE"),
    };
    let mm = match args.unit_mm {
        Some(mm) if mm.is_finite() && mm > 0.0 && (mm / 1000.0).is_normal() => mm,
        Some(mm) if mm.is_finite() && mm > 0.0 => bail!(
            "--unit-mm {mm}: too small for a node scale (it would be written as 0 metres per unit)"
        ),
        Some(mm) => bail!("--unit-mm must be a positive number of millimetres (got {mm})"),
        None => match crate::io::builtin::mm_per_unit(&sources.rig.mesh) {
            Some(mm) => mm,
            None => {
                if let Some(guess) = mm_per_unit_from_landmarks(&sources.rig) {
                    if !(0.5..=2.0).contains(&guess) {
                        eprintln!(
                        "grimace export: --unit-mm not given, so 1 mm per unit is written; the landmarks' outer eye corners suggest about {guess:.3} mm per unit (pass --unit-mm {guess:.3} if so)"
                    );
                    }
                }
                1.0
            }
        },
    };
    let TargetStates { states, silent } =
        target_states(args.targets.into(), rig, table, &ArkitMap::builtin())
            .map_err(|e| anyhow!("{}: {e}", table_label(sources)))?;
    if states.is_empty() {
        bail!(
            "{}: it has no {} to export as morph targets (record some, or use --targets muscles)",
            table_label(sources),
            match args.targets {
                Targets::Expressions => "expressions",
                _ => "AUs",
            }
        );
    }
    if !silent.is_empty() {
        eprintln!(
            "grimace export: {} ARKit shapes move nothing on this table: {}",
            silent.len(),
            silent.join(", ")
        );
    }
    sources.inputs().check_output(path)?;
    let bound = bind(&sources.rig, args.model.deformation)?;
    let targets = morph_targets(&bound, &states)?;
    let rotation = if args.keep_axes {
        Quat::IDENTITY
    } else {
        // Face coordinates are glTF's (y up, the face toward +z).
        Quat::from_mat3(&super::framing(&sources.rig, None).basis)
    };
    let placement = gltf::Placement {
        metres_per_unit: mm / 1000.0,
        rotation,
    };
    gltf::save_glb(path, &sources.rig.mesh, &targets, placement)?;
    Ok(())
}

fn table_label(sources: &Sources) -> String {
    sources
        .table_path
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_default()
}

/// Millimetres per unit estimated from the landmarks of the rig's mesh (see
/// [`crate::landmarks::mm_per_unit`]); `None` when it has none to read.
fn mm_per_unit_from_landmarks(rig: &LoadedRig) -> Option<f32> {
    let (marks, path) = rig.landmarks("--landmarks").ok()?;
    let points = crate::io::landmarks::check_against(&marks, &rig.mesh, &path, None).ok()?;
    crate::landmarks::mm_per_unit(&points)
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
