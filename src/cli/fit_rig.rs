//! `grimace fit-rig MESH.obj --landmarks FILE --out NAME.rig.ron`: carries a rig (the built-in
//! default rig unless `--template` names another) to a mesh from its 68 landmarks, and
//! writes it as an ordinary rig file that names the mesh. With `--pick` the landmarks are
//! picked first in the terminal ([`super::landmarks`]) and saved (to `--landmarks FILE`, or
//! `MESH.landmarks.ron` beside the mesh), then the rig is fitted from them.
//!
//! The mesh is used as it is, in its own units and orientation. The command prints how the
//! faces were aligned and which parts of the mesh it took for skin, for still parts and for
//! parts that turn with the jaw. Nothing is written when anything fails.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context};
use clap::Args;

use crate::fit::{self, Part, PartOverrides, Template};
use crate::io::inputs::Inputs;
use crate::io::landmarks::{beside, check_against, load_landmarks, parse_landmarks};
use crate::io::load::{load_rig_ref, LoadedRig};
use crate::io::rig_file;
use crate::io::{error::read_text, obj, reference, LoadError, MAX_FILE_BYTES};
use crate::landmarks::{self, Landmarks};
use crate::model::{Deformation, Mesh};

/// A landmark bend (see [`fit::Fitted::bend`]) from which `fit-rig` warns: public faces of
/// other shapes bend up to about half of the face from the built-in template.
const SUSPICIOUS_BEND: f64 = 0.9;

/// Arguments of `grimace fit-rig`.
#[derive(Debug, Args)]
pub struct FitRigArgs {
    /// The mesh to rig (Wavefront OBJ), in its own units and orientation.
    #[arg(value_name = "MESH.obj")]
    pub mesh: PathBuf,
    /// The mesh's 68 iBUG landmarks: a *.landmarks.ron file, or `mediapipe` for a MediaPipe
    /// face mesh (468 or 478 vertices, numbered like MediaPipe's landmarks). With --pick, the
    /// file the picked landmarks are saved to (default: MESH.landmarks.ron beside the mesh).
    #[arg(long, value_name = "FILE|mediapipe", required_unless_present = "pick")]
    pub landmarks: Option<String>,
    /// Pick the landmarks in the terminal first, then fit.
    #[arg(long)]
    pub pick: bool,
    /// Braille, half-block or ASCII cells for --pick.
    #[command(flatten)]
    pub cells: super::CellsArgs,
    /// The rig file to write.
    #[arg(long, value_name = "NAME.rig.ron")]
    pub out: PathBuf,
    /// The rig to carry over (a *.rig.ron, builtin:default or builtin:paper).
    #[arg(long, value_name = "RIG", default_value = "builtin:default")]
    pub template: PathBuf,
    /// The template's landmarks, when its mesh is not built in and has no
    /// MESH.landmarks.ron beside it.
    #[arg(long, value_name = "FILE")]
    pub template_landmarks: Option<PathBuf>,
    /// Groups of the mesh that are skin, whatever their names say (repeatable).
    #[arg(long = "skin", value_name = "GROUP")]
    pub skin: Vec<String>,
    /// Groups of the mesh that muscles must not move (repeatable); those inside the mouth
    /// below the lips, or named like lower teeth or a tongue, turn with the jaw.
    #[arg(long = "rigid", value_name = "GROUP")]
    pub rigid: Vec<String>,
}

/// Runs `grimace fit-rig`.
pub fn run(args: &FitRigArgs) -> anyhow::Result<()> {
    let mesh = obj::read_obj(&args.mesh)?;
    check_groups(args, &mesh)?;
    let landmark_arg = landmark_source(args)?;
    let (landmarks, landmark_file) = target_landmarks(&landmark_arg, args, &mesh)?;
    let template = load_rig_ref(&args.template, None)?;
    let (template_points, template_file) = template_landmarks(args, &template)?;
    let mesh_path = mesh_reference(&args.mesh, &args.out)?;
    let mut inputs = Inputs::new();
    inputs.add("the mesh to rig", &args.mesh);
    inputs.add("the landmark file", &landmark_file);
    inputs.add_rig(&template);
    if let Some(path) = &args.template_landmarks {
        inputs.add("the template's landmark file", path);
    }
    inputs.check_output(&args.out)?;
    let overrides = PartOverrides {
        skin: args.skin.clone(),
        rigid: args.rigid.clone(),
    };
    let fitted = fit::fit_rig(
        Template {
            rig: &template.rig,
            mesh: &template.mesh,
            landmarks: &template_points,
        },
        &mesh,
        &landmarks,
        mesh_path,
        &overrides,
    )
    .map_err(|e| match e {
        // The template's own landmarks are at fault, not the mesh's.
        e @ fit::FitError::Template(_) => {
            anyhow!(LoadError::new(&template_file, e.to_string()))
        }
        e => anyhow!(LoadError::new(&landmark_file, e.to_string())),
    })?;
    warn_order(&landmark_file, &landmarks, &mesh);
    for o in fitted.outliers(&template.rig, OUTLIER_FACTOR) {
        eprintln!(
            "warning: {}: its {} came out {:.2} times the template's at this face's scale \
             (check the landmarks around it)",
            o.muscle, o.what, o.ratio
        );
    }
    Deformation::default()
        .bind(&fitted.rig, &mesh)
        .with_context(|| format!("the fitted rig does not bind to {}", args.mesh.display()))?;
    rig_file::save_rig(&args.out, &fitted.rig)?;
    if fitted.bend >= SUSPICIOUS_BEND {
        eprintln!(
            "warning: a landmark bend of {:.0}% of the face usually means a landmark on the wrong feature or another numbering; check {} (docs/fitting.md, \"When a fit looks wrong\")",
            100.0 * fitted.bend,
            landmark_file.display()
        );
    }
    super::print(&summary(args, &mesh, &fitted))
}

/// Refuses `--skin`/`--rigid` groups the mesh does not have, listing those it has.
fn check_groups(args: &FitRigArgs, mesh: &Mesh) -> anyhow::Result<()> {
    for group in args.skin.iter().chain(&args.rigid) {
        if !mesh.groups.contains_key(group) {
            let known: Vec<&str> = mesh.groups.keys().map(String::as_str).collect();
            return Err(anyhow!(LoadError::new(
                &args.mesh,
                format!(
                    "has no group `{group}`; its groups are: {}",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            )));
        }
    }
    Ok(())
}

/// The landmarks argument: `--landmarks` as given, or with `--pick` the file the picker
/// saved (the template and the outputs are checked before the picking starts).
fn landmark_source(args: &FitRigArgs) -> anyhow::Result<String> {
    Ok(match (&args.landmarks, args.pick) {
        (Some(l), true) if l == "mediapipe" => {
            return Err(anyhow!(
                "--pick saves the picked landmarks to a file: give --landmarks FILE, not mediapipe"
            ))
        }
        (Some(l), false) => l.clone(),
        (given, true) => {
            let file = given
                .as_ref()
                .map_or_else(|| beside(&args.mesh), PathBuf::from);
            // The template and the output folder are checked before the picking starts.
            let template = load_rig_ref(&args.template, None)?;
            mesh_reference(&args.mesh, &args.out)?;
            let mut inputs = Inputs::new();
            inputs.add("the mesh to rig", &args.mesh);
            inputs.add_rig(&template);
            inputs.check_output(&file)?;
            inputs.add("the landmark file", &file);
            inputs.check_output(&args.out)?;
            let saved =
                super::landmarks::pick_landmarks(&args.mesh, &file, args.cells.mode(), None)?;
            if !saved {
                return Err(anyhow!(
                    "no landmarks were saved (:w saves them in the picker); no rig was fitted"
                ));
            }
            file.to_string_lossy().into_owned()
        }
        (None, false) => return Err(anyhow!("give --landmarks FILE or --pick")),
    })
}

/// A fitted muscle whose size or strength is more than this many times off the template's
/// (times the face's scale) is warned about.
const OUTLIER_FACTOR: f64 = 2.0;

/// Warns about landmarks out of the iBUG scheme's order (a contour listed backwards, a point
/// on the wrong side): the fit goes ahead, but crosses what is out of order.
fn warn_order(file: &Path, landmarks: &Landmarks, mesh: &Mesh) {
    let Ok(points) = landmarks.positions(mesh) else {
        return;
    };
    for problem in landmarks::order_problems(&points) {
        eprintln!("warning: {}: {problem}", file.display());
    }
}

/// The mesh's landmarks and the file to name in messages about them.
fn target_landmarks(
    given: &str,
    args: &FitRigArgs,
    mesh: &Mesh,
) -> anyhow::Result<(Landmarks, PathBuf)> {
    if given == "mediapipe" {
        let landmarks = Landmarks::mediapipe(mesh)
            .map_err(|e| anyhow!(LoadError::new(&args.mesh, e.to_string())))?;
        check_against(&landmarks, mesh, &args.mesh, None)?;
        return Ok((landmarks, args.mesh.clone()));
    }
    let path = PathBuf::from(given);
    let text = read_text(&path, MAX_FILE_BYTES)?;
    let landmarks = parse_landmarks(&text, &path)?;
    check_against(&landmarks, mesh, &path, Some(&text))?;
    Ok((landmarks, path))
}

/// The template's landmark positions: given, built in, or `MESH.landmarks.ron` beside the
/// template's mesh.
fn template_landmarks(
    args: &FitRigArgs,
    template: &LoadedRig,
) -> anyhow::Result<(Vec<glam::Vec3>, PathBuf)> {
    let (landmarks, path) = match &args.template_landmarks {
        Some(path) => (load_landmarks(path)?, path.clone()),
        None => template.landmarks("--template-landmarks")?,
    };
    let points = check_against(&landmarks, &template.mesh, &path, None)?;
    Ok((points, path))
}

/// The mesh as the new rig names it: relative to the rig file's real folder (see
/// [`crate::io::reference`]).
fn mesh_reference(mesh: &Path, out: &Path) -> anyhow::Result<PathBuf> {
    std::fs::canonicalize(mesh).with_context(|| format!("cannot resolve {}", mesh.display()))?;
    if let Some(dir) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        if !dir.is_dir() {
            return Err(anyhow!("the folder of {} does not exist", out.display()));
        }
    }
    Ok(reference::written_reference(out, mesh))
}

fn summary(args: &FitRigArgs, mesh: &Mesh, fitted: &fit::Fitted) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}: {} muscles from {} fitted to {} ({} vertices): scale {:.4}, landmark bend {:.1}% of the face",
        args.out.display(),
        fitted.rig.muscles.len(),
        args.template.display(),
        args.mesh.display(),
        mesh.vertex_count(),
        fitted.scale,
        100.0 * fitted.bend
    );
    for choice in &fitted.parts.choices {
        let what = match choice.part {
            Part::Skin => "skin",
            Part::Still => "kept still",
            Part::Jaw => "turns with the jaw",
        };
        let _ = writeln!(
            out,
            "  {}: {} ({} vertices, by {})",
            choice.name, what, choice.vertices, choice.reason
        );
    }
    let count = |p: Part| fitted.parts.of_vertex.iter().filter(|&&x| x == p).count();
    let _ = writeln!(
        out,
        "  vertices: {} skin, {} kept still, {} turn with the jaw",
        count(Part::Skin),
        count(Part::Still),
        count(Part::Jaw)
    );
    if let Some(jaw) = &fitted.rig.jaw {
        let _ = writeln!(out, "  jaw: {} weighted vertices", jaw.weights.len());
    }
    for (opening, upper, lower) in &fitted.sides {
        if !upper.is_empty() || !lower.is_empty() {
            let _ = writeln!(
                out,
                "  {opening}: {} muscles kept above its line, {} below",
                upper.len(),
                lower.len()
            );
        }
    }
    out
}
