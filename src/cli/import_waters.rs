//! `grimace import-waters DIR --out OUTDIR`: the classic Waters face as OBJ and rig: the 18
//! linear muscles of `muscle.dat` plus the paper's sheet and sphincter muscles and jaw, placed
//! for that face by [`crate::face::classic`] (`--linear-only` leaves them out), and the
//! face's 68 iBUG landmarks, carried over from the built-in face by
//! [`classic::ibug_landmarks`], so `grimace fit-rig` can fit any rig to it.

use std::path::PathBuf;

use anyhow::{bail, Context};
use clap::Args;

use crate::face::classic;
use crate::io::waters::{self, ExtraMuscles, ImportOptions};
use crate::io::{atomic, builtin, landmarks, obj, rig_file};
use crate::landmarks::Landmarks;

/// Arguments of `grimace import-waters`.
#[derive(Debug, Args)]
pub struct ImportWatersArgs {
    /// The folder holding faceline.dat, index.dat and muscle.dat.
    pub dir: PathBuf,
    /// The folder to write mesh.obj, mesh.landmarks.ron and rig.ron into (created if
    /// missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Drop the 6 triangles that repeat earlier ones exactly (kept by default, as in the
    /// original program; vertex numbering is the same either way).
    #[arg(long)]
    pub drop_duplicates: bool,
    /// Write only the 18 linear muscles of muscle.dat, without the paper's sheet and
    /// sphincter muscles and jaw (which are placed for the classic face by default).
    #[arg(long)]
    pub linear_only: bool,
}

/// Where the data comes from, kept with the mesh written.
const ATTRIBUTION: &str =
    "# Classic Waters face (\"geoface\"), from F. I. Parke and K. Waters, Computer Facial\n\
# Animation, Appendix 1, as distributed with GLUT 3.7 (Mark J. Kilgard). Freely\n\
# redistributable third-party data, not public domain; no warranty.\n";

/// Runs `grimace import-waters`.
pub fn run(args: &ImportWatersArgs) -> anyhow::Result<()> {
    let options = ImportOptions {
        drop_duplicate_triangles: args.drop_duplicates,
        extras: (!args.linear_only).then_some(classic::extra_muscles as ExtraMuscles),
    };
    let imported = waters::import_dir(&args.dir, &options)?;
    if !args.linear_only && imported.rig.jaw.is_none() {
        // The hook found no landmarks; ask again for the reason.
        if let Err(e) = classic::place_extras(&imported.mesh) {
            bail!("{e}; use --linear-only to import the 18 linear muscles alone");
        }
    }
    let template = builtin::default_mesh();
    let template_marks = builtin::landmarks("default")
        .context("the built-in face has no landmarks")?
        .vertices(&template);
    // Without --linear-only the extras already needed the same features, so only a
    // --linear-only import of a face without them gets no landmark file.
    let marks = classic::ibug_landmarks(&imported.mesh, &template, &template_marks);
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the folder {}", args.out.display()))?;
    let mut inputs = crate::io::inputs::Inputs::new();
    for name in [waters::FACELINE, waters::INDEX, waters::MUSCLE] {
        inputs.add("a file of the classic data", &args.dir.join(name));
    }
    let mesh_path = args.out.join("mesh.obj");
    for name in ["mesh.obj", "rig.ron", "mesh.landmarks.ron"] {
        inputs.check_output(&args.out.join(name))?;
    }
    let text = format!(
        "{ATTRIBUTION}{}",
        obj::write_obj(&imported.mesh, &imported.mesh.positions)
    );
    atomic::write_atomic(&mesh_path, text.as_bytes())
        .map_err(|e| crate::io::SaveError::io(&mesh_path, &e))?;
    let rig_path = args.out.join("rig.ron");
    rig_file::save_rig(&rig_path, &imported.rig)?;
    let marks_path = args.out.join("mesh.landmarks.ron");
    let marks_note = match marks {
        Ok(marks) => {
            landmarks::save_landmarks(&marks_path, &Landmarks::Vertices(marks))?;
            format!("wrote {} (68 landmarks)", marks_path.display())
        }
        Err(e) => format!("no landmarks written: {e}"),
    };
    super::print(&format!(
        "wrote {} ({} vertices, {} triangles) and {} ({} muscles{})\n{marks_note}\n",
        mesh_path.display(),
        imported.mesh.vertex_count(),
        imported.mesh.triangles.len(),
        rig_path.display(),
        imported.rig.muscles.len(),
        if imported.rig.jaw.is_some() {
            " and a jaw"
        } else {
            ""
        },
    ))
}
