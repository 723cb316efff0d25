//! `grimace fit-au TARGET.obj --rig RIG --au KEY [--table T]`: the activations that best
//! reproduce a target shape of the rig's mesh (an artist's blendshape, a scan of the
//! expression), written into an AU table; `--map FILE --dir DIR` fits a whole blendshape set.
//!
//! Without `--table` the entry is printed and nothing is written. With it, the entry is added
//! to the table or replaces the one with the same key (a new table is made if the file does
//! not exist), and the table is saved once, after every target has been fitted.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail};
use clap::Args;

use crate::facs::{AuKey, AuTable};
use crate::fit::{fit_au, AuFit};
use crate::io::inputs::Inputs;
use crate::io::load::{load_rig_ref, LoadedRig};
use crate::io::shape_map::load_map;
use crate::io::{obj, table_file, LoadError};
use crate::model::BoundRig;

/// Arguments of `grimace fit-au`.
#[derive(Debug, Args)]
pub struct FitAuArgs {
    /// The target shape: the rig's mesh, same vertices in the same order, displaced.
    #[arg(
        value_name = "TARGET.obj",
        required_unless_present = "map",
        conflicts_with = "map"
    )]
    pub target: Option<PathBuf>,
    /// The rig (a *.rig.ron, builtin:default or builtin:paper).
    #[arg(long, value_name = "RIG")]
    pub rig: PathBuf,
    /// The AU key the target shows, e.g. 12, L12.
    #[arg(
        long,
        value_name = "KEY",
        required_unless_present = "map",
        conflicts_with = "map"
    )]
    pub au: Option<AuKey>,
    /// The AU table to write the entries into (made when it does not exist).
    #[arg(long, value_name = "TABLE")]
    pub table: Option<PathBuf>,
    /// A map from shape names to AU keys (RON, e.g. { "mouthSmile_L": "L12" }), or
    /// `builtin:arkit` for ARKit's 52 blendshape names; with --dir.
    #[arg(long, value_name = "FILE", requires = "dir")]
    pub map: Option<PathBuf>,
    /// The folder holding NAME.obj for every shape name of the map.
    #[arg(long, value_name = "DIR", requires = "map")]
    pub dir: Option<PathBuf>,
    /// The deformation the entries are fitted to.
    #[command(flatten)]
    pub model: super::export::ModelArgs,
}

/// Runs `grimace fit-au`.
pub fn run(args: &FitAuArgs) -> anyhow::Result<()> {
    let loaded = load_rig_ref(&args.rig, None)?;
    let bound = args
        .model
        .deformation
        .bind(&loaded.rig, &loaded.mesh)
        .map_err(|e| anyhow!(LoadError::new(&args.rig, e.to_string())))?;
    let jobs = jobs(args)?;
    let mut table = match &args.table {
        Some(path) if path.exists() => table_file::load_table_for(path, &loaded.rig)?,
        Some(path) => AuTable::new(table_rig_reference(&loaded, path)),
        None => AuTable::new(args.rig.clone()),
    };
    let mut report = String::new();
    let mut fitted = 0;
    for (target, key) in &jobs {
        if let Some(reason) = crate::io::error::not_a_file(target) {
            let _ = writeln!(report, "{key}: skipped, {} {reason}", target.display());
            continue;
        }
        let explained = match fit_one(&bound, &mut table, target, *key) {
            Ok(explained) => explained,
            // One target alone fails as a command; in a set it is skipped and the rest kept.
            Err(e) if jobs.len() == 1 => return Err(e),
            Err(e) => {
                let _ = writeln!(report, "{key}: skipped, {e}");
                continue;
            }
        };
        fitted += 1;
        let _ = writeln!(
            report,
            "{key}: {} explained {:.4} ({})",
            target.display(),
            explained,
            describe(&table, key)
        );
    }
    if fitted == 0 {
        eprint!("{report}");
        bail!("no target shape could be fitted; nothing written");
    }
    match &args.table {
        Some(path) => {
            fit_inputs(args, &loaded, &jobs).check_output(path)?;
            table_file::save_table(path, &table)?;
            let _ = writeln!(report, "wrote {fitted} AU entries to {}", path.display());
        }
        None => report.push_str("(no --table given: nothing written)\n"),
    }
    super::print(&report)
}

/// The files `fit-au` reads besides the table it adds to: what the table may not replace.
fn fit_inputs(args: &FitAuArgs, rig: &LoadedRig, jobs: &[(PathBuf, AuKey)]) -> Inputs {
    let mut inputs = Inputs::new();
    inputs.add_rig(rig);
    if let Some(map) = &args.map {
        inputs.add("the shape map", map);
    }
    for (target, _) in jobs {
        inputs.add("a target shape", target);
    }
    inputs
}

/// Reads one target, fits it and records the entry; returns the fraction explained.
fn fit_one(
    bound: &BoundRig,
    table: &mut AuTable,
    target: &Path,
    key: AuKey,
) -> anyhow::Result<f64> {
    let mesh = obj::read_obj(target)?;
    let AuFit {
        activations,
        explained,
    } = fit_au(bound, &mesh.positions)
        .map_err(|e| anyhow!(LoadError::new(target, e.to_string())))?;
    table
        .record(key, "", bound.rig(), &activations)
        .map_err(|e| anyhow!("{}: AU {key}: {e}", target.display()))?;
    Ok(explained)
}

/// The (target file, AU key) pairs to fit.
fn jobs(args: &FitAuArgs) -> anyhow::Result<Vec<(PathBuf, AuKey)>> {
    match (&args.target, args.au, &args.map, &args.dir) {
        (Some(target), Some(key), None, None) => {
            if let Some(reason) = crate::io::error::not_a_file(target) {
                return Err(anyhow!(LoadError::new(
                    target,
                    format!("the target file {reason}")
                )));
            }
            Ok(vec![(target.clone(), key)])
        }
        (None, None, Some(map), Some(dir)) => {
            let map = load_map(map)?;
            Ok(map
                .into_iter()
                .map(|(name, key)| (dir.join(format!("{name}.obj")), key))
                .collect())
        }
        _ => bail!("give TARGET.obj with --au, or --map with --dir"),
    }
}

/// The rig as a new table names it: built in, or relative to the table's real folder (see
/// [`crate::io::reference`]).
fn table_rig_reference(loaded: &LoadedRig, table: &Path) -> PathBuf {
    crate::io::reference::written_reference(table, &loaded.path)
}

/// The entry's muscles and jaw, largest first, as `NAME=VALUE`.
fn describe(table: &AuTable, key: &AuKey) -> String {
    let Some(entry) = table.aus.get(key) else {
        return String::new();
    };
    let mut parts: Vec<(&String, f32)> = entry.muscles.iter().map(|(n, v)| (n, *v)).collect();
    parts.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut text: Vec<String> = parts.iter().map(|(n, v)| format!("{n}={v:.3}")).collect();
    if entry.jaw != 0.0 {
        text.push(format!("jaw={:.3}", entry.jaw));
    }
    if text.is_empty() {
        "no muscle".into()
    } else {
        text.join(" ")
    }
}
