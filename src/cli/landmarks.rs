//! `grimace landmarks MESH.obj [--out F.landmarks.ron]`: pick a mesh's 68 landmarks in the
//! terminal ([`crate::tui::pick`]) and save them as a landmark file.
//!
//! The mesh and an existing landmark file are read before the terminal is touched: one that
//! fails to load stops grimace with a message naming file, line and column (exit status 1)
//! and nothing is written.

use std::path::{Path, PathBuf};

use anyhow::anyhow;
use clap::Args;
use glam::Vec3;

use crate::io::landmarks::{check_against, parse_landmarks};
use crate::io::pick_recovery;
use crate::io::{error::read_text, obj, LoadError, MAX_FILE_BYTES};
use crate::landmarks::Landmarks;
use crate::model::Mesh;
use crate::render::{CellMode, Framing};
use crate::tui::pick::state::{Mode, Question};
use crate::tui::pick::{self, PickApp};
use crate::tui::session::Session;

/// The notes at the end of `grimace landmarks --help`.
pub const AFTER_HELP: &str = "\
Keys: arrows or hjkl move the cursor (Shift or HJKL by five cells), which snaps to the nearest
visible vertex; Enter takes it, Tab skips the landmark, u undoes, [ ] { } turn and tilt the
view, + - zoom, ? lists every key, :w saves, q quits.

The 17 landmarks of the minimal set come first (the subject's left side and the midline); the
right side is then proposed by symmetry and the other 51 from the picks, each needing only
Enter or a nudge. Every pick is kept at once in .NAME.recover beside the landmark file, so a
dropped connection loses nothing: the next start offers the picks back. An existing landmark
file is loaded, to be corrected.";

/// Arguments of `grimace landmarks`.
#[derive(Debug, Args)]
pub struct LandmarksArgs {
    /// The mesh to pick on (Wavefront OBJ).
    #[arg(value_name = "MESH.obj")]
    pub mesh: PathBuf,
    /// The landmark file to write (default: MESH.landmarks.ron beside the mesh). An existing
    /// file is loaded, to be corrected.
    #[arg(long, value_name = "F.landmarks.ron")]
    pub out: Option<PathBuf>,
    /// Braille, half-block or ASCII cells.
    #[command(flatten)]
    pub cells: super::CellsArgs,
    /// Which way the face stands in the mesh (when its shape would guess wrong).
    #[command(flatten)]
    pub facing: super::FacingArgs,
}

/// Runs `grimace landmarks`.
pub fn run(args: &LandmarksArgs) -> anyhow::Result<()> {
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| crate::io::landmarks::beside(&args.mesh));
    pick_landmarks(&args.mesh, &out, args.cells.mode(), args.facing.basis()?)?;
    Ok(())
}

/// Opens the picker on a mesh, facing the way `facing` says (else as the mesh's shape
/// suggests); `true` when the landmarks were saved to `out`.
pub fn pick_landmarks(
    mesh_path: &Path,
    out: &Path,
    cells: CellMode,
    facing: Option<glam::Mat3>,
) -> anyhow::Result<bool> {
    let (mut app, session) = prepare(mesh_path, out, cells, facing)?;
    pick::run(&mut app, &session)?;
    Ok(app.saved)
}

/// Loads the mesh (and the landmark file when it exists), checks for picks to recover and
/// takes the lock. Errors name file, line and column where known.
pub fn prepare(
    mesh_path: &Path,
    out: &Path,
    cells: CellMode,
    facing: Option<glam::Mat3>,
) -> anyhow::Result<(PickApp, Session)> {
    let mesh = obj::read_obj(mesh_path)?;
    check_mesh(&mesh, mesh_path)?;
    let mut inputs = crate::io::inputs::Inputs::new();
    inputs.add("the mesh being picked", mesh_path);
    inputs.check_output(out)?;
    if crate::io::landmark_text::form_of(out) != crate::io::landmark_text::Form::Ron {
        return Err(anyhow!(
            "{}: picked landmarks are saved as RON; name the file NAME.landmarks.ron (MeshLab's \
             .pp and .txt, .csv, .xyz lists are read, not written)",
            out.display()
        ));
    }
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            return Err(anyhow!(
                "{}: the folder {} does not exist",
                out.display(),
                dir.display()
            ));
        }
    }
    let existing = existing_picks(out, &mesh)?;
    let mut app = PickApp::new(
        mesh,
        mesh_path.to_path_buf(),
        out.to_path_buf(),
        crossterm::terminal::size().unwrap_or((80, 24)),
        cells,
    );
    app.out_stamp = std::fs::read(out)
        .ok()
        .map(|bytes| crate::tui::app::FileStamp::of(&bytes));
    // A file being corrected stands the face up and frames it by its own landmarks (the
    // mesh's shape only guesses); `--up`/`--front` still give the axes.
    let points = existing.as_ref().map(|(_, points)| points.as_slice());
    if points.is_some() || facing.is_some() {
        app.face(Framing::of_face(None, &app.mesh, points, facing));
    }
    if let Some((landmarks, _)) = existing {
        let vertices = landmarks.vertices(&app.mesh);
        if let Landmarks::Points(points) = &landmarks {
            app.kept_points = Some(
                vertices
                    .iter()
                    .copied()
                    .zip(points.iter().copied())
                    .collect(),
            );
        }
        let picks: Vec<Option<u32>> = vertices.into_iter().map(Some).collect();
        app.load_picks(&picks, &[]);
        app.info(format!(
            "{} loaded: Enter or Tab goes through the landmarks, n and p move between them",
            out.display()
        ));
    }
    let (mut session, warning) = Session::start(Some(out), pick_recovery::path_for(out), "picks");
    if let Some(warning) = warning {
        app.warn(warning);
    }
    if let Some(path) = session.recovery.clone() {
        offer_recovery(&mut app, &mut session, &path);
    }
    Ok((app, session))
}

/// A mesh the picker can work on: some triangles, and points that are not all in one place.
fn check_mesh(mesh: &Mesh, path: &Path) -> anyhow::Result<()> {
    if mesh.triangles.is_empty() {
        return Err(anyhow!(LoadError::new(
            path,
            "has no faces: the picker needs a surface to pick on"
        )));
    }
    let (lo, hi) = mesh.bounds();
    if !(hi - lo).is_finite() || (hi - lo).max_element() <= 0.0 {
        return Err(anyhow!(LoadError::new(
            path,
            "all its vertices lie on one point"
        )));
    }
    Ok(())
}

/// The landmarks of an existing landmark file, checked against the mesh, and their points.
fn existing_picks(out: &Path, mesh: &Mesh) -> anyhow::Result<Option<(Landmarks, Vec<Vec3>)>> {
    if !out.exists() {
        return Ok(None);
    }
    let text = read_text(out, MAX_FILE_BYTES)?;
    let landmarks = parse_landmarks(&text, out)?;
    let points = check_against(&landmarks, mesh, out, Some(&text))?;
    Ok(Some((landmarks, points)))
}

/// Offers picks kept by a session that stopped; a file another running picker owns is left
/// alone (and this session keeps none).
fn offer_recovery(app: &mut PickApp, session: &mut Session, path: &Path) {
    match pick_recovery::read(path) {
        Ok(Some(state)) => {
            if let Some(owner) = state.live_owner() {
                app.warn(session.yield_recovery(owner, "picks"));
                return;
            }
            if let Err(e) = state.check(path, app.mesh.vertex_count()) {
                app.warn(format!("the recovery file is not for this mesh: {e}"));
                return;
            }
            if state.picks == app.picks {
                let _ = pick_recovery::remove(path);
                return;
            }
            app.mode = Mode::Confirm(Question::Recover {
                picks: state.picks.clone(),
                skipped: state.skipped.clone(),
                when: crate::tui::session::describe_age(state.written_at),
            });
        }
        Ok(None) => {}
        Err(e) => app.warn(format!("the recovery file cannot be read: {e}")),
    }
}
