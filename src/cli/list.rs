//! `grimace list`: the muscles of a rig, the AUs and expressions of a table, the FACS
//! catalogue.

use crate::io::load::{load_rig_ref, load_table_and_rig};
use std::fmt::Write;
use std::path::PathBuf;

use clap::Args;

use crate::facs::catalogue::CATALOGUE;
use crate::facs::AuTable;
use crate::io::{builtin, rig_file};
use crate::model::{Muscle, MuscleKind, Rig, Side};

/// Arguments of `grimace list`. With none, lists the FACS catalogue.
#[derive(Debug, Args)]
pub struct ListArgs {
    /// List the muscles of this rig (*.rig.ron, or builtin:default, builtin:paper).
    #[arg(long, value_name = "RIG")]
    pub rig: Option<PathBuf>,
    /// List the AUs and expressions of this table (*.au.ron, or builtin:default).
    #[arg(long, value_name = "TABLE")]
    pub table: Option<PathBuf>,
    /// List the FACS Action Unit catalogue.
    #[arg(long)]
    pub catalogue: bool,
}

/// Runs `grimace list`.
pub fn run(args: &ListArgs) -> anyhow::Result<()> {
    let mut out = String::new();
    if let Some(path) = &args.rig {
        let rig = match builtin::builtin_name(path) {
            Some(_) => load_rig_ref(path, None)?.rig,
            None => {
                let text = crate::io::error::read_text(path, crate::io::MAX_FILE_BYTES)?;
                let (rig, notice) = rig_file::parse_rig_with(&text, path, builtin::mesh)?;
                if let Some(notice) = notice {
                    eprintln!("warning: {notice}");
                }
                rig
            }
        };
        out.push_str(&muscles(&rig));
    }
    if let Some(path) = &args.table {
        let table = match builtin::builtin_name(path) {
            Some(_) => load_table_and_rig(path, None)?.0,
            None => crate::io::load_table(path)?,
        };
        if !out.is_empty() {
            out.push('\n');
        }
        out.push_str(&aus(&table));
    }
    if args.catalogue || (args.rig.is_none() && args.table.is_none()) {
        if !out.is_empty() {
            out.push('\n');
        }
        out.push_str(&catalogue());
    }
    super::print(&out)
}

fn side(side: Side) -> &'static str {
    match side {
        Side::Left => "left",
        Side::Right => "right",
        Side::Centre => "centre",
    }
}

fn kind(muscle: &Muscle) -> String {
    match &muscle.kind {
        MuscleKind::Sphincter(s) => format!("sphincter ({:?})", s.convergence).to_lowercase(),
        other => other.label().to_string(),
    }
}

/// The muscles of a rig, one per line: name, kind, side, mirror partner; then the jaw.
pub fn muscles(rig: &Rig) -> String {
    let width = rig.muscles.iter().map(|m| m.name.len()).max().unwrap_or(0);
    let mut out = format!("muscles ({}):\n", rig.muscles.len());
    for m in &rig.muscles {
        let mirror = m
            .mirror
            .as_deref()
            .map(|p| format!("  mirror {p}"))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "  {:width$}  {:22}  {:6}{mirror}",
            m.name,
            kind(m),
            side(m.side)
        );
    }
    match &rig.jaw {
        Some(jaw) => {
            let _ = writeln!(
                out,
                "jaw: pivot {}, {} degrees per unit, {} weighted vertices",
                jaw.pivot,
                jaw.degrees_per_unit,
                jaw.weights.len()
            );
        }
        None => out.push_str("jaw: none\n"),
    }
    out
}

/// The AUs (key, name, muscles and jaw) and expressions of a table.
pub fn aus(table: &AuTable) -> String {
    let mut out = format!("AUs ({}):\n", table.aus.len());
    for (key, entry) in &table.aus {
        let mut parts: Vec<String> = entry
            .muscles
            .iter()
            .map(|(m, v)| format!("{m} {v}"))
            .collect();
        if entry.jaw != 0.0 {
            parts.push(format!("jaw {}", entry.jaw));
        }
        let _ = writeln!(
            out,
            "  {:>4}  {:28}  {}",
            key.to_string(),
            entry.name,
            parts.join(", ")
        );
    }
    let _ = writeln!(out, "expressions ({}):", table.expressions.len());
    let width = table.expressions.keys().map(|n| n.len()).max().unwrap_or(0);
    for (name, combo) in &table.expressions {
        let _ = writeln!(out, "  {name:width$}  {combo}");
    }
    out
}

/// The FACS catalogue: number, name, muscular basis.
pub fn catalogue() -> String {
    let mut out = format!("FACS Action Units ({}):\n", CATALOGUE.len());
    for au in CATALOGUE {
        let _ = writeln!(out, "  {:>2}  {:24}  {}", au.number, au.name, au.basis);
    }
    out
}
