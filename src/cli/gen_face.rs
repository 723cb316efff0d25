//! `grimace gen-face`: writes the built-in default face (and optionally its presets).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;

use crate::face;

/// Arguments of `grimace gen-face`.
#[derive(Debug, Args)]
pub struct GenFaceArgs {
    /// Where to write the face mesh (Wavefront OBJ).
    #[arg(long, default_value = "assets/face.obj")]
    pub out: PathBuf,
    /// Also write the rigs and the AU table (paper.rig.ron, default.rig.ron,
    /// default.au.ron) into this folder.
    #[arg(long)]
    pub presets: Option<PathBuf>,
}

/// Runs `grimace gen-face`.
pub fn run(args: &GenFaceArgs) -> ExitCode {
    match generate(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            super::report("gen-face", &err);
            ExitCode::from(1)
        }
    }
}

fn generate(args: &GenFaceArgs) -> anyhow::Result<()> {
    let mesh = face::generate();
    write(&args.out, &crate::io::presets::mesh_file(&mesh))?;
    if let Some(dir) = &args.presets {
        for (name, text) in
            crate::io::presets::preset_files(&mesh).context("cannot place the rigs")?
        {
            write(&dir.join(name), &text)?;
        }
    }
    Ok(())
}

fn write(path: &Path, text: &str) -> anyhow::Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create folder {}", parent.display()))?;
    }
    // Atomic: a full disk or a killed run leaves the previous file, never a truncated one.
    crate::io::atomic::write_atomic(path, text.as_bytes())
        .map_err(|e| crate::io::SaveError::io(path, &e).into())
}
