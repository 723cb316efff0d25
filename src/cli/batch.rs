//! `grimace batch PLAN --out DIR`: a plan's items drawn into a labelled data set, one shard
//! at a time (`--shard K/N`, or `--shard slurm` inside a Slurm array job); `grimace batch
//! merge DIR` checks the shards' work and writes the labels. The work itself is
//! [`crate::batch`]; this is loading, the environment, progress and Ctrl-C.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail};
use clap::{Args, Subcommand};

use super::export::{self, SourceArgs};
use crate::batch::{Batch, Face, Plan, Progress, RunOptions, Shard};
use crate::io::obj::MovedObj;
use crate::io::LoadError;
use crate::model::Deformation;

/// Arguments of `grimace batch`.
#[derive(Debug, Args)]
#[command(
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true,
    after_help = "Shards: --shard K/N runs items K, K+N, K+2N, ... of the plan (0 <= K < N);\n\
--shard slurm takes K and N from SLURM_ARRAY_TASK_ID, _MIN and _COUNT (an array --array=0-M);\n\
--shard slurm/N takes K = SLURM_ARRAY_TASK_ID (for resubmitting some shards of N).\n\
A rerun skips finished items. See docs/batch.md and examples/slurm/."
)]
pub struct BatchArgs {
    /// `merge DIR`: check every planned item and write DIR/labels.csv and DIR/manifest.json.
    #[command(subcommand)]
    pub command: Option<BatchCommand>,
    /// The plan (*.plan.ron; see docs/formats.md).
    #[arg(value_name = "PLAN", required = true)]
    pub plan: Option<PathBuf>,
    /// The output folder (files, label rows and the plan's record).
    #[arg(long, value_name = "DIR", required_unless_present = "dry_run")]
    pub out: Option<PathBuf>,
    /// Which shard to run: K/N (from 0), `slurm` or `slurm/N`.
    #[arg(long, value_name = "K/N|slurm", default_value = "0/1")]
    pub shard: String,
    /// Print the item count, an output size estimate and a suggested array size; write nothing.
    #[arg(long)]
    pub dry_run: bool,
    /// Worker threads (default: every CPU this process may use; inside Slurm, the CPUs
    /// allocated to the task).
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// The deformation.
    #[command(flatten)]
    pub model: export::ModelArgs,
}

/// `grimace batch` subcommands.
#[derive(Debug, Subcommand)]
pub enum BatchCommand {
    /// Check that every planned item is finished and write DIR/labels.csv and
    /// DIR/manifest.json (exit 1 naming what is missing).
    Merge {
        /// The batch's output folder.
        #[arg(value_name = "DIR")]
        dir: PathBuf,
    },
}

/// Runs `grimace batch`.
pub fn run(args: &BatchArgs) -> ExitCode {
    let result = match &args.command {
        Some(BatchCommand::Merge { dir }) => merge(dir),
        None => run_plan(args),
    };
    super::finish("batch", result)
}

fn merge(dir: &Path) -> anyhow::Result<()> {
    let summary = crate::batch::labels::merge(dir)?;
    eprintln!(
        "merged {} items ({}) into {}",
        summary.items,
        megabytes(summary.bytes),
        dir.join("labels.csv").display()
    );
    Ok(())
}

fn run_plan(args: &BatchArgs) -> anyhow::Result<()> {
    let plan_path = args
        .plan
        .as_deref()
        .ok_or_else(|| anyhow!("give a plan file"))?;
    let shard = shard_from(&args.shard, &|name| std::env::var(name).ok())?;
    let batch = load(plan_path, args.model.deformation)?;
    let jobs = match args.jobs {
        Some(0) => bail!("--jobs 0: give at least 1"),
        Some(n) => n,
        None => default_jobs(&|name| std::env::var(name).ok()),
    };
    if args.dry_run {
        return dry_run(&batch, shard);
    }
    let out = args
        .out
        .as_deref()
        .ok_or_else(|| anyhow!("give --out DIR"))?;
    let stop = Arc::new(AtomicBool::new(false));
    register_stop(&stop)?;
    let mut meter = Meter::new(shard);
    let summary = batch.run_shard(
        out,
        shard,
        RunOptions {
            jobs,
            stop: &stop,
            progress: &mut |p| meter.show(p),
        },
    )?;
    meter.finish();
    let p = summary.progress;
    let rate = p.made as f64 / p.elapsed.as_secs_f64().max(1e-9);
    eprintln!(
        "shard {shard}: {} made, {} already done, {} of {} items finished; {} written in {:.1} s ({rate:.0} items/s on {jobs} threads){}",
        p.made,
        p.skipped,
        p.made + p.skipped,
        p.total,
        megabytes(summary.bytes),
        p.elapsed.as_secs_f64(),
        if summary.stopped { "; stopped early: rerun the same command to finish" } else { "" }
    );
    if summary.stopped {
        bail!("stopped before the shard was finished");
    }
    Ok(())
}

/// Reads a plan, loads its faces and expands it: every error is a [`LoadError`] naming the
/// place in the plan (also for `grimace validate`).
pub fn load(path: &Path, deformation: Deformation) -> Result<Batch, LoadError> {
    let plan = Plan::load(path)?;
    let faces = load_faces(&plan, deformation)?;
    Batch::new(plan, faces)
}

/// Loads every face of the plan as `render` loads a rig and table, errors naming the face's
/// place in the plan.
fn load_faces(plan: &Plan, deformation: Deformation) -> Result<Vec<Face>, LoadError> {
    let mut faces = Vec::new();
    for spec in &plan.file.faces {
        let at = |e: anyhow::Error| {
            plan.error_at("faces", &spec.name, format!("face `{}`: {e:#}", spec.name))
        };
        let sources = export::load_sources(&SourceArgs {
            rig: Some(plan.resolve(&spec.rig)),
            mesh: None,
            table: (!spec.table.as_os_str().is_empty()).then(|| plan.resolve(&spec.table)),
        })
        .map_err(at)?;
        let table = sources.table.clone().ok_or_else(|| {
            at(anyhow!(
                "the rig's muscles are not the built-in table's: give its table (`table: \"...\"`)"
            ))
        })?;
        let bound = export::bind(&sources.rig, deformation).map_err(at)?;
        // As `export --gltf` scales without --unit-mm: the built-in face's known scale, else
        // a millimetre per unit.
        let mm = crate::io::builtin::mm_per_unit(&sources.rig.mesh).unwrap_or(1.0);
        faces.push(Face {
            obj: MovedObj::new(sources.rig.mesh_path.as_deref(), &sources.rig.mesh),
            framing: super::framing(&sources.rig, None),
            rig: sources.rig,
            table,
            bound,
            metres_per_unit: mm / 1000.0,
        });
    }
    Ok(faces)
}

/// The shard `--shard` names; `slurm` reads the array job's environment through `env`.
pub fn shard_from(text: &str, env: &dyn Fn(&str) -> Option<String>) -> anyhow::Result<Shard> {
    let Some(rest) = text.trim().strip_prefix("slurm") else {
        return Shard::parse(text).map_err(|e| anyhow!(e));
    };
    let var = |name: &str| -> anyhow::Result<usize> {
        let value = env(name).ok_or_else(|| {
            anyhow!("--shard {text}: {name} is not set: this is not a Slurm array job (submit it with `sbatch --array=0-N ...`; see examples/slurm), or give --shard K/N")
        })?;
        value
            .trim()
            .parse()
            .map_err(|_| anyhow!("--shard {text}: {name}={value} is not a whole number"))
    };
    let id = var("SLURM_ARRAY_TASK_ID")?;
    if let Some(count) = rest.strip_prefix('/') {
        // Resubmitted shards: the task ID is the shard.
        return Shard::parse(&format!("{id}/{count}"))
            .map_err(|e| anyhow!("{e} (from SLURM_ARRAY_TASK_ID)"));
    }
    if !rest.is_empty() {
        bail!("--shard {text}: expected `slurm` or `slurm/N`");
    }
    let (min, count) = (var("SLURM_ARRAY_TASK_MIN")?, var("SLURM_ARRAY_TASK_COUNT")?);
    let max = var("SLURM_ARRAY_TASK_MAX").unwrap_or(min + count.saturating_sub(1));
    if max + 1 != min + count || id < min {
        bail!(
            "--shard slurm: the array is not one run of task IDs ({min}-{max} with {count} tasks); give the number of shards: --shard slurm/N"
        );
    }
    Shard::parse(&format!("{}/{count}", id - min)).map_err(|e| anyhow!(e))
}

/// The worker threads when `--jobs` is not given: inside Slurm the task's CPUs
/// (`SLURM_CPUS_PER_TASK`), else every CPU this process may run on (its affinity mask).
pub fn default_jobs(env: &dyn Fn(&str) -> Option<String>) -> usize {
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    match env("SLURM_CPUS_PER_TASK").and_then(|v| v.trim().parse::<usize>().ok()) {
        Some(n) if n > 0 => n,
        _ => cpus,
    }
}

/// Ctrl-C (and Slurm's SIGTERM at the time limit) stops after the items being drawn; a
/// second Ctrl-C stops at once.
fn register_stop(stop: &Arc<AtomicBool>) -> anyhow::Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    for signal in [SIGINT, SIGTERM] {
        signal_hook::flag::register_conditional_shutdown(signal, 130, Arc::clone(stop))?;
        signal_hook::flag::register(signal, Arc::clone(stop))?;
    }
    Ok(())
}

/// `--dry-run`: counts, a size and time estimate from a few items drawn, and an array size.
fn dry_run(batch: &Batch, shard: Shard) -> anyhow::Result<()> {
    let items = &batch.expanded.items;
    let mut counts = std::collections::BTreeMap::new();
    for item in items {
        *counts.entry(item.output.ext()).or_insert(0usize) += 1;
    }
    let samples: Vec<usize> = (0..8)
        .map(|k| k * items.len() / 8)
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let start = Instant::now();
    let mut bytes = 0;
    let mut positions = Vec::new();
    let mut renderers = batch.renderers();
    for &i in &samples {
        let item = &items[i];
        batch.deform(item.face, item.state, &mut positions)?;
        bytes += batch
            .draw(item, &positions, &mut renderers[item.face])?
            .len();
    }
    let per_item = start.elapsed().as_secs_f64() / samples.len().max(1) as f64;
    let per_bytes = bytes as f64 / samples.len().max(1) as f64;
    let cpu_seconds = per_item * items.len() as f64;
    // Shards of about ten minutes on 4 CPUs each.
    let shards =
        ((cpu_seconds / (4.0 * 600.0)).ceil() as usize).clamp(1, items.len().clamp(1, 1000));
    let by_output: Vec<String> = counts.iter().map(|(k, v)| format!("{v} {k}")).collect();
    let faces = batch.faces.len();
    let mine = batch.shard_items(shard).len();
    println!(
        "{} items ({}) over {faces} face{}; shard {shard} takes {mine}",
        items.len(),
        by_output.join(", "),
        if faces == 1 { "" } else { "s" }
    );
    println!(
        "about {} of files, {:.0} CPU-seconds ({:.1} ms an item, from {} drawn here)",
        megabytes((per_bytes * items.len() as f64) as u64),
        cpu_seconds,
        per_item * 1000.0,
        samples.len()
    );
    println!(
        "suggested: sbatch --array=0-{}%{} --cpus-per-task=4 (about {:.0} min a shard)",
        shards - 1,
        shards.min(50),
        cpu_seconds / shards as f64 / 4.0 / 60.0
    );
    Ok(())
}

fn megabytes(bytes: u64) -> String {
    format!("{:.1} MB", bytes as f64 / 1e6)
}

/// Progress: a bar redrawn in place on a terminal, a plain line every 10 seconds otherwise
/// (Slurm's log files).
struct Meter {
    shard: Shard,
    terminal: bool,
    last: Option<Instant>,
    drawn: bool,
}

impl Meter {
    fn new(shard: Shard) -> Meter {
        Meter {
            shard,
            terminal: std::io::stderr().is_terminal(),
            last: None,
            drawn: false,
        }
    }

    fn show(&mut self, p: &Progress) {
        let every = if self.terminal {
            Duration::from_millis(200)
        } else {
            Duration::from_secs(10)
        };
        let done = p.made + p.skipped;
        if self.last.is_some_and(|t| t.elapsed() < every) && done < p.total {
            return;
        }
        self.last = Some(Instant::now());
        let rate = p.made as f64 / p.elapsed.as_secs_f64().max(1e-9);
        let left = p.total - done;
        let eta = if rate > 0.0 {
            format_duration(left as f64 / rate)
        } else {
            "?".to_string()
        };
        if self.terminal {
            let width = 30;
            let filled = (done * width).checked_div(p.total).unwrap_or(width);
            eprint!(
                "\r[{}{}] {done}/{} items  {rate:.0}/s  ETA {eta}  ",
                "#".repeat(filled),
                " ".repeat(width - filled),
                p.total
            );
            self.drawn = true;
        } else {
            eprintln!(
                "shard {}: {done}/{} items, {rate:.0}/s, ETA {eta}",
                self.shard, p.total
            );
        }
    }

    fn finish(&self) {
        if self.drawn {
            eprintln!();
        }
    }
}

fn format_duration(seconds: f64) -> String {
    let s = seconds.round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(vars: &'static [(&'static str, &'static str)]) -> impl Fn(&str) -> Option<String> {
        move |name| {
            vars.iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn slurm_shards_come_from_the_array() {
        let vars = env(&[
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_MIN", "5"),
            ("SLURM_ARRAY_TASK_MAX", "8"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]);
        assert_eq!(
            shard_from("slurm", &vars).unwrap(),
            Shard { index: 2, count: 4 }
        );
        assert_eq!(
            shard_from("slurm/10", &vars).unwrap(),
            Shard {
                index: 7,
                count: 10
            }
        );
        assert!(shard_from("slurm/5", &vars).is_err());
        let outside = shard_from("slurm", &env(&[])).unwrap_err().to_string();
        assert!(outside.contains("not a Slurm array job"), "{outside}");
        let gaps = env(&[
            ("SLURM_ARRAY_TASK_ID", "2"),
            ("SLURM_ARRAY_TASK_MIN", "2"),
            ("SLURM_ARRAY_TASK_MAX", "5"),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
        ]);
        assert!(shard_from("slurm", &gaps)
            .unwrap_err()
            .to_string()
            .contains("slurm/N"));
    }

    #[test]
    fn jobs_follow_the_slurm_allocation() {
        assert_eq!(default_jobs(&env(&[("SLURM_CPUS_PER_TASK", "3")])), 3);
        assert!(default_jobs(&env(&[])) >= 1);
    }
}
