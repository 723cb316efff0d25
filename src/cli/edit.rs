//! `grimace edit [FILE]` (and `grimace` alone): the terminal editor.
//!
//! Loading happens before the terminal is touched: a file that fails to load stops grimace
//! with a message naming file, line and column (exit status 1); nothing opens silently.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::facs::{AuTable, TABLE_VERSION};
use crate::io::load::rig_ref;
use crate::io::load::{load_rig_ref, LoadedRig};
use crate::io::{recovery, reference};
use crate::model::{Mesh, Rig};
use crate::render::Framing;
use crate::tui;
use crate::tui::app::{App, ColorMode, FileStamp, Mode, Question, Recovered, View};
use crate::tui::face::Face;
use crate::tui::session::{self, Session};

/// The notes at the end of `grimace edit --help`.
pub const AFTER_HELP: &str = "\
Keys: ? in the editor lists every key and : command.

Unsaved changes are kept in a recovery file, written a second after the last edit and at once on
SIGHUP or SIGTERM: .NAME.recover beside the table file NAME (for the built-in table,
$XDG_STATE_HOME/grimace/builtin.recover). The next start on the same table offers to recover
them; the table file itself changes only when you save. Saves are atomic and keep the previous
version as NAME~; a file changed on disk since it was loaded is overwritten only after asking.
A lock file .NAME.lock warns when the table is already open in another grimace.

A table or rig that fails to load stops grimace before the screen changes, with the message
FILE:LINE:COLUMN: what is wrong (exit status 1). A big mesh (16384 vertices or more) is shown
at rest while its rig is bound (binding... in the status line); a rig that does not bind to it
then stops grimace with the reason.";

/// Options of `grimace edit`.
#[derive(Debug, Clone, Default, Args)]
pub struct EditArgs {
    /// The AU table to edit (`.au.ron`). Created by `:w` if it does not exist yet.
    /// Without it, grimace edits the built-in default table.
    pub file: Option<PathBuf>,
    /// The rig to edit with (instead of the table's own rig).
    #[arg(long, value_name = "RIG")]
    pub rig: Option<PathBuf>,
    /// The mesh to place the rig on (instead of the rig's own mesh).
    #[arg(long, value_name = "OBJ")]
    pub mesh: Option<PathBuf>,
    /// Braille, half-block or ASCII cells.
    #[command(flatten)]
    pub cells: super::CellsArgs,
    /// Which way the face stands in its mesh (when the rig would guess wrong).
    #[command(flatten)]
    pub facing: super::FacingArgs,
    /// Colours: auto (from NO_COLOR, TERM, COLORTERM and the terminal's name), truecolor,
    /// 256, 16 or none. Over SSH COLORTERM is often lost; set this to what the terminal has.
    #[arg(long, value_name = "MODE", default_value = "auto", value_parser = parse_colors)]
    pub colors: ColorsChoice,
}

/// `--colors`: a colour mode, or `None` for auto (detected from the environment).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ColorsChoice(pub Option<ColorMode>);

/// Parses `--colors`: `auto` or a mode's name.
pub(crate) fn parse_colors(text: &str) -> Result<ColorsChoice, String> {
    match text.trim().to_ascii_lowercase().as_str() {
        "auto" => Ok(ColorsChoice(None)),
        other => other
            .parse()
            .map(|mode| ColorsChoice(Some(mode)))
            .map_err(|e: String| e.replace("(expected", "(expected auto,")),
    }
}

/// Runs the editor.
pub fn run(args: &EditArgs) -> anyhow::Result<()> {
    // A big head's bind frees blocks the levels of detail would otherwise pile on top of.
    tui::memory::give_back_big_blocks();
    let (app, session) = prepare(args).map_err(anyhow::Error::msg)?;
    tui::run(app, session)
}

/// Loads everything the editor needs and checks for a recovery file and a lock; the result
/// is ready to run. Errors are messages naming file, line and column where known.
pub fn prepare(args: &EditArgs) -> Result<(App, Session), String> {
    let loaded = match &args.file {
        Some(path) => load_table_file(path)?,
        None => None,
    };
    let table_path = args
        .file
        .clone()
        .unwrap_or_else(|| PathBuf::from("builtin.au.ron"));
    let (table, stamp, new_file) = match (&args.file, &loaded) {
        (_, Some(loaded)) => {
            // While the editor runs, references are absolute: a save under another name
            // writes them relative to the new file (see `io::reference`).
            let mut table = loaded.table.clone();
            table.rig = reference::absolute(&table_path, &table.rig);
            (table, Some(loaded.stamp), false)
        }
        (Some(_), None) => (new_table(args.rig.as_deref()), None, true),
        (None, None) => (builtin_table()?, None, false),
    };
    let (face, rig_path) = load_face(args, &table, &table_path)?;
    if let Some(loaded) = &loaded {
        crate::io::table_file::check_table_rig(&loaded.table, &face.rig, &loaded.text, &table_path)
            .map_err(|e| e.to_string())?;
    }
    let facing = args.facing.basis().map_err(|e| e.to_string())?;
    let (framing, framing_warning) = Framing::of_loaded(&face, facing);
    let LoadedRig {
        rig, mesh, notice, ..
    } = face;
    // A big head is bound on a thread: the first screen shows its rest pose at once.
    let scene = Face::start(rig, mesh, framing)?;
    let mut app = App::new(scene, table, args.file.clone());
    app.doc.file_stamp = stamp;
    // Rig mode's `:w` writes the rig file back; the stamp notices changes made meanwhile.
    let rig_bytes = rig_path.as_deref().and_then(|p| std::fs::read(p).ok());
    app.rig_edit = crate::tui::rig::RigEdit::for_file(rig_path, rig_bytes.as_deref());
    app.view = View::new(args.cells.mode());
    app.view.colors = args
        .colors
        .0
        .unwrap_or_else(crate::tui::term::colors_from_env);
    if new_file {
        if let Some(path) = &args.file {
            app.info(format!(
                "new table: {} does not exist yet; :w creates it",
                path.display()
            ));
        }
    }
    for warning in notice.into_iter().chain(framing_warning) {
        app.warn(warning);
    }
    for warning in app.doc.face.take_bind_warnings() {
        app.warn(warning);
    }
    let (mut session, warning) = Session::start(
        args.file.as_deref(),
        recovery::recovery_path(args.file.as_deref()),
        "changes",
    );
    if let Some(warning) = warning {
        app.warn(warning);
    }
    if let Some(path) = session.recovery.clone() {
        offer_recovery(&mut app, &mut session, &path);
    }
    Ok((app, session))
}

/// Offers a recovery file back; one that belongs to another grimace that still runs is left
/// alone (and this editor keeps no recovery file of its own).
fn offer_recovery(app: &mut App, session: &mut Session, path: &Path) {
    match recovery::read(path) {
        Ok(Some(state)) => {
            if let Some(owner) = state.live_owner() {
                app.warn(session.yield_recovery(owner, "changes"));
                return;
            }
            let activations = state.activations(app.rig());
            let rig = state.rig.filter(|rig| rig != app.rig());
            if activations == app.doc.activations && state.table == app.doc.table && rig.is_none() {
                // Nothing that differs from what is on disk: nothing to offer.
                let _ = recovery::remove(path);
                return;
            }
            app.mode = Mode::Confirm(Question::Recover(Box::new(Recovered {
                activations,
                table: state.table,
                when: session::describe_age(state.written_at),
                base: state.base.map(|(len, hash)| FileStamp { len, hash }),
                rig,
            })));
        }
        Ok(None) => {}
        Err(e) => app.warn(format!("the recovery file cannot be read: {e}")),
    }
}

/// An empty table for `rig` (the built-in default rig when `None`). A rig file is kept as an
/// absolute path while the editor runs and written relative to the table's folder.
fn new_table(rig: Option<&Path>) -> AuTable {
    let rig = match rig {
        None => PathBuf::from("builtin:default"),
        Some(path) if crate::io::builtin::builtin_name(path).is_some() => path.to_path_buf(),
        Some(path) => reference::real_path(path),
    };
    AuTable {
        version: TABLE_VERSION,
        rig,
        aus: Default::default(),
        expressions: Default::default(),
    }
}

/// A table file as loaded: the table, its text (for locating later errors) and its stamp.
struct LoadedTable {
    table: AuTable,
    text: String,
    stamp: FileStamp,
}

/// Reads a table file: `Ok(None)` when it does not exist.
fn load_table_file(path: &Path) -> Result<Option<LoadedTable>, String> {
    if !path.exists() {
        return Ok(None);
    }
    let text =
        crate::io::error::read_text(path, crate::io::MAX_FILE_BYTES).map_err(|e| e.to_string())?;
    let table = crate::io::parse_table(&text, path).map_err(|e| e.to_string())?;
    let stamp = FileStamp::of(text.as_bytes());
    Ok(Some(LoadedTable { table, text, stamp }))
}

fn builtin_table() -> Result<AuTable, String> {
    crate::io::builtin::table("default").ok_or_else(|| "the built-in table is missing".to_string())
}

/// The built-in default rig, its mesh and the built-in AU table.
pub fn default_face() -> Result<(Rig, Mesh, AuTable), String> {
    let loaded = load_rig_ref(Path::new("builtin:default"), None).map_err(|e| e.to_string())?;
    Ok((loaded.rig, loaded.mesh, builtin_table()?))
}

/// The rig loaded with its mesh, and its file (`None` when built in).
type FaceParts = (LoadedRig, Option<PathBuf>);

/// The rig and mesh to edit with: `--rig` (a file or `builtin:NAME`) if given, else the
/// table's rig; `--mesh` replaces the rig's mesh. Also what loading an older rig file did
/// (see [`crate::io::LoadedRig::notice`]), for the status line.
fn load_face(args: &EditArgs, table: &AuTable, table_path: &Path) -> Result<FaceParts, String> {
    let reference = match &args.rig {
        Some(rig) => rig.clone(),
        None => rig_ref(table_path, &table.rig).to_path(),
    };
    let mut loaded = load_rig_ref(&reference, args.mesh.as_deref()).map_err(|e| e.to_string())?;
    let file = (!reference.to_string_lossy().starts_with("builtin:")).then_some(reference);
    if let Some(file) = &file {
        // Absolute while the editor runs (see `new_table`).
        loaded.rig.mesh = reference::absolute(file, &loaded.rig.mesh);
        if let Some(landmarks) = loaded.rig.landmarks.as_mut() {
            *landmarks = reference::absolute(file, landmarks);
        }
    }
    Ok((loaded, file))
}
