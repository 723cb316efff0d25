//! `grimace check [--rig RIG] [--table T]`: every AU and expression of a table deformed at
//! full intensity with the deformation grimace uses, measured for tears, lids that stay open
//! and a jaw that does not open ([`crate::fit::quality`]). Exits 1 when any entry fails.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{anyhow, bail, Context};
use clap::Args;

use super::export::{self, ModelArgs};
use crate::facs::combo::parse_combo;
use crate::facs::{AuKey, AuMapper, AuTable};
use crate::fit::quality::{Expect, Eyes, Gauge, Quality};
use crate::io::landmarks::{check_against, load_landmarks};
use crate::io::load::{load_rig_ref, load_table_and_rig, LoadedRig};
use crate::io::{builtin, table_file, LoadError};
use crate::landmarks::Landmarks;
use crate::model::{Activations, Rig, Side};

/// Arguments of `grimace check`.
#[derive(Debug, Args)]
#[command(after_help = AFTER_HELP)]
pub struct CheckArgs {
    /// The rig (*.rig.ron, builtin:default or builtin:paper). Default: the rig the table
    /// names; with neither, the built-in default face.
    #[arg(long, value_name = "RIG")]
    pub rig: Option<PathBuf>,
    /// The AU table (*.au.ron or builtin:default). Default: the built-in table.
    #[arg(long, value_name = "TABLE")]
    pub table: Option<PathBuf>,
    /// The mesh's 68 iBUG landmarks: a *.landmarks.ron file, or `mediapipe` for a MediaPipe
    /// face mesh. Default: MESH.landmarks.ron beside the rig's mesh (built in for the
    /// built-in face).
    #[arg(long, value_name = "FILE|mediapipe")]
    pub landmarks: Option<String>,
    /// Millimetres per mesh unit. Default: 11.5 for the built-in face, else from the outer
    /// canthal distance (landmarks 36-45) taken as 90 mm.
    #[arg(long, value_name = "MM")]
    pub unit_mm: Option<f32>,
    /// The deformation.
    #[command(flatten)]
    pub model: ModelArgs,
}

/// What `grimace help check` prints after the options.
pub const AFTER_HELP: &str = "\
Per entry: skin triangles turned over (normal against the rest normal), the largest skin edge
stretch (deformed over rest length), the lid gap at AU43/AU45 (the opening left between the lid
landmarks 37/41, 38/40, 43/47, 44/46, as a fraction of the rest opening), the jaw drop at
AU26/AU27 (chin and lower lip, landmarks 8 and 57, down the face, the smaller, in mm), and how
far the most-moved vertex went (mm) and where. An entry fails on a turned triangle, a stretch
over 2.5x, a lid gap of 10% or more, or a jaw drop under 15 mm. Exits 1 when any entry fails.";

/// Runs `grimace check`.
pub fn run(args: &CheckArgs) -> ExitCode {
    match check(args) {
        Ok((report, failed)) => {
            if let Err(e) = super::print(&report) {
                super::report("check", &e);
                return ExitCode::from(1);
            }
            if failed > 0 {
                ExitCode::from(1)
            } else {
                ExitCode::SUCCESS
            }
        }
        Err(e) => {
            super::report("check", &e);
            ExitCode::from(1)
        }
    }
}

/// One entry to measure: its label, its activations and what it should do.
struct Entry {
    label: String,
    act: Activations,
    expect: Expect,
}

/// The report and the number of failing entries.
fn check(args: &CheckArgs) -> anyhow::Result<(String, usize)> {
    let table_path = args
        .table
        .clone()
        .unwrap_or_else(|| PathBuf::from(export::DEFAULT_TABLE));
    let (rig, table) = load(args, &table_path)?;
    let mapper = AuMapper::new(&table, &rig.rig);
    let unit_mm = match args.unit_mm {
        Some(mm) if mm.is_finite() && mm > 0.0 => Some(mm),
        Some(mm) => bail!("--unit-mm must be a positive number of millimetres (got {mm})"),
        None => crate::io::builtin::mm_per_unit(&rig.mesh),
    };
    let landmarks = landmarks(args, &rig)?;
    let gauge = Gauge::new(&rig.mesh, &landmarks.vertices(&rig.mesh), unit_mm)
        .map_err(|e| anyhow!("{}: {e}", rig.path.display()))?;
    let bound = export::bind(&rig, args.model.deformation)?;
    let entries = entries(&table, &rig.rig, &mapper)?;
    let mut report = String::new();
    if let Some(notice) = mapper.unknown_notice() {
        let _ = writeln!(report, "note: {notice}");
    }
    let _ = write!(
        report,
        "{} with {} ({} deformation, {} mm per unit)\n{:<16} {:>6} {:>7} {:>7} {:>8} {:>9}  {:<6} verdict\n",
        rig.path.display(),
        table_path.display(),
        args.model.deformation,
        scale_text(gauge.mm_per_unit()),
        "entry",
        "turned",
        "stretch",
        "lid gap",
        "jaw drop",
        "moved",
        "where",
    );
    let mut positions = Vec::new();
    let mut failed = 0;
    for entry in &entries {
        bound
            .deform(&entry.act, &mut positions)
            .map_err(|e| anyhow!("{}: {e}", entry.label))?;
        let quality = gauge.measure(&positions, entry.expect);
        let failures = quality.failures();
        failed += usize::from(!failures.is_empty());
        let _ = writeln!(report, "{}", line(&entry.label, &quality, &failures));
    }
    let _ = writeln!(
        report,
        "{failed} of {} entries fail (tears: a turned triangle or a stretch over 2.5x; lids: a gap of 10% or more; jaw: a drop under 15 mm)",
        entries.len()
    );
    Ok((report, failed))
}

/// The rig (given, or the one the table names) and the table.
fn load(args: &CheckArgs, table_path: &Path) -> anyhow::Result<(LoadedRig, AuTable)> {
    let (rig, table) = match &args.rig {
        Some(path) => (load_rig_ref(path, None)?, load_table(table_path)?),
        None => {
            let (table, rig) = load_table_and_rig(table_path, None)?;
            (rig, table)
        }
    };
    if let Some(notice) = &rig.notice {
        eprintln!("warning: {notice}");
    }
    Ok((rig, table))
}

/// Every AU of the table at full intensity, then every expression, through the mapper.
fn entries(table: &AuTable, rig: &Rig, mapper: &AuMapper) -> anyhow::Result<Vec<Entry>> {
    let mut entries = Vec::new();
    for key in table.aus.keys() {
        let mut act = Activations::zero(rig);
        mapper.map([(*key, 1.0)], &mut act);
        entries.push(Entry {
            label: format!("AU {key}"),
            act,
            expect: expect_of(*key),
        });
    }
    for (name, combo) in &table.expressions {
        let combo = parse_combo(combo).map_err(|e| anyhow!("expression `{name}`: {e}"))?;
        let mut act = Activations::zero(rig);
        mapper.map(
            combo.terms.iter().map(|t| (t.key, t.intensity.factor())),
            &mut act,
        );
        entries.push(Entry {
            label: name.clone(),
            act,
            expect: Expect::default(),
        });
    }
    Ok(entries)
}

/// A mesh's scale to three significant digits and at least two decimals: a head in
/// micrometres has a thousandth of a millimetre per unit, which two decimals print as 0.
fn scale_text(mm_per_unit: f32) -> String {
    let magnitude = f64::from(mm_per_unit).abs().log10().floor();
    let decimals = if magnitude.is_finite() {
        (2.0 - magnitude).clamp(2.0, 12.0) as usize
    } else {
        2
    };
    format!("{mm_per_unit:.decimals$}")
}

/// One entry's row.
fn line(label: &str, q: &Quality, failures: &[String]) -> String {
    let gap = q
        .lid_gap
        .map_or("-".to_string(), |g| format!("{:.0}%", g * 100.0));
    let drop = q
        .jaw_drop_mm
        .map_or("-".to_string(), |d| format!("{d:.1} mm"));
    let verdict = if failures.is_empty() {
        "ok".to_string()
    } else {
        format!("FAIL: {}", failures.join("; "))
    };
    format!(
        "{label:<16} {:>6} {:>6.2}x {gap:>7} {drop:>8} {:>6.1} mm  {:<6} {verdict}",
        q.turned,
        q.stretch,
        q.moved_mm,
        q.moved_region.name(),
    )
}

/// What an AU should do: AU43 and AU45 close the lids (of their side), AU26 and AU27 open
/// the jaw.
fn expect_of(key: AuKey) -> Expect {
    let eyes = match key.side {
        Some(Side::Left) => Eyes::Left,
        Some(Side::Right) => Eyes::Right,
        _ => Eyes::Both,
    };
    Expect {
        lids_close: matches!(key.number, 43 | 45).then_some(eyes),
        jaw_opens: matches!(key.number, 26 | 27) && key.side.is_none(),
    }
}

/// A table by reference (`builtin:NAME` or a file), checked on its own: a rig it was not
/// made for plays it without the muscles it lacks.
fn load_table(path: &Path) -> anyhow::Result<AuTable> {
    match builtin::builtin_name(path) {
        Some(name) => builtin::table(name).ok_or_else(|| {
            anyhow!(LoadError::new(
                path,
                format!("there is no built-in table named `{name}`")
            ))
        }),
        None => Ok(table_file::load_table(path)?),
    }
}

/// The rig's landmarks: given, built in for a built-in mesh, or beside the rig's mesh.
fn landmarks(args: &CheckArgs, rig: &LoadedRig) -> anyhow::Result<Landmarks> {
    let (landmarks, path) = match args.landmarks.as_deref() {
        Some("mediapipe") => (
            Landmarks::mediapipe(&rig.mesh)
                .map_err(|e| anyhow!(LoadError::new(&rig.path, e.to_string())))?,
            rig.path.clone(),
        ),
        Some(file) => (load_landmarks(Path::new(file))?, PathBuf::from(file)),
        None => rig.landmarks("--landmarks")?,
    };
    check_against(&landmarks, &rig.mesh, &path, None)
        .with_context(|| format!("the landmarks do not fit {}", rig.path.display()))?;
    Ok(landmarks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scale_keeps_three_significant_digits() {
        assert_eq!(scale_text(11.5), "11.50");
        assert_eq!(scale_text(10.123), "10.12");
        assert_eq!(scale_text(0.97), "0.970");
        assert_eq!(scale_text(0.000_834_8), "0.000835");
        assert_eq!(scale_text(1000.0), "1000.00");
    }
}
