//! The command line: argument parsing and one module per subcommand.
//!
//! Exit status: 0 on success, 1 on errors (a file that does not load, a value out of range),
//! 2 on usage errors (clap's own exit code for bad arguments). Errors are printed to stderr
//! as `grimace COMMAND: FILE:LINE:COL: message`.

use std::fmt::Display;
use std::io::Write;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::io::printable::printable;
use crate::render::CellMode;

pub(crate) mod batch;
pub(crate) mod capture;
pub(crate) mod check;
pub(crate) mod completions;
pub mod edit;
pub mod export;
pub(crate) mod fit_au;
pub(crate) mod fit_rig;
pub(crate) mod gen_face;
pub(crate) mod import_waters;
pub(crate) mod landmarks;
pub(crate) mod list;
pub(crate) mod play;
pub mod render;
pub mod validate;

/// grimace: shape facial expressions with muscles, in the terminal.
#[derive(Debug, Parser)]
#[command(name = "grimace", version, about, long_about = None, args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// The subcommand; without one, grimace opens the editor on the built-in default face.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Editor options for `grimace` without a subcommand (the same as `grimace edit`'s).
    #[command(flatten)]
    pub editor: EditorOptions,
}

/// The options `grimace` alone accepts: those of `grimace edit` without a table file, so a
/// mistyped subcommand is an error rather than a new table.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct EditorOptions {
    /// The rig to edit with (instead of the built-in default rig).
    #[arg(long, value_name = "RIG")]
    pub rig: Option<std::path::PathBuf>,
    /// The mesh to place the rig on (instead of the rig's own mesh).
    #[arg(long, value_name = "OBJ")]
    pub mesh: Option<std::path::PathBuf>,
    /// Braille, half-block or ASCII cells.
    #[command(flatten)]
    pub cells: CellsArgs,
    /// Colours: auto (from NO_COLOR, TERM, COLORTERM and the terminal's name), truecolor,
    /// 256, 16 or none.
    #[arg(long, value_name = "MODE", default_value = "auto", value_parser = edit::parse_colors)]
    pub colors: edit::ColorsChoice,
    /// Which way the face stands in its mesh (when the rig would guess wrong).
    #[command(flatten)]
    pub facing: FacingArgs,
}

impl EditorOptions {
    /// The same options as `grimace edit` arguments, on the built-in default table.
    pub fn to_edit_args(&self) -> edit::EditArgs {
        edit::EditArgs {
            file: None,
            rig: self.rig.clone(),
            mesh: self.mesh.clone(),
            cells: self.cells,
            colors: self.colors,
            facing: self.facing,
        }
    }
}

/// Which way the face stands in its mesh, when the rig (or the mesh's shape) would guess
/// wrong: `--up AXIS` and `--front AXIS` (x, y, z, -x, -y, -z). Shared by `edit`, `render`
/// and `landmarks`.
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct FacingArgs {
    /// The mesh axis that is up on the face (e.g. z for a Blender export).
    #[arg(long, value_name = "AXIS", value_parser = parse_axis, allow_hyphen_values = true)]
    pub up: Option<glam::Vec3>,
    /// The mesh axis the face looks along, out of the face (e.g. -y for a Blender export).
    #[arg(long, value_name = "AXIS", value_parser = parse_axis, allow_hyphen_values = true)]
    pub front: Option<glam::Vec3>,
}

impl FacingArgs {
    /// The face's axes asked for, `None` when neither flag is given.
    pub fn basis(&self) -> anyhow::Result<Option<glam::Mat3>> {
        if self.up.is_none() && self.front.is_none() {
            return Ok(None);
        }
        crate::render::framing::facing(self.up, self.front)
            .map(Some)
            .ok_or_else(|| {
                anyhow::anyhow!("--up and --front must be two different axes at right angles")
            })
    }
}

/// The framing of a loaded rig ([`crate::render::Framing::of_loaded`]) for a command that
/// prints: a landmark file that cannot be used is a warning on stderr, never an error.
pub(crate) fn framing(
    loaded: &crate::io::load::LoadedRig,
    given: Option<glam::Mat3>,
) -> crate::render::Framing {
    let (framing, warning) = crate::render::Framing::of_loaded(loaded, given);
    if let Some(warning) = warning {
        eprintln!("warning: {warning}");
    }
    framing
}

/// Parses an axis: `x`, `y`, `z`, optionally with a sign.
fn parse_axis(text: &str) -> Result<glam::Vec3, String> {
    let t = text.trim().to_ascii_lowercase();
    let (sign, name) = match t.strip_prefix('-') {
        Some(rest) => (-1.0, rest),
        None => (1.0, t.strip_prefix('+').unwrap_or(&t)),
    };
    let axis = match name {
        "x" => glam::Vec3::X,
        "y" => glam::Vec3::Y,
        "z" => glam::Vec3::Z,
        _ => return Err(format!("`{text}` is not an axis (x, y, z, -x, -y or -z)")),
    };
    Ok(axis * sign)
}

/// How the face's dots become characters: `--cells MODE`, with `--ascii` and `--half-block`
/// kept as short forms. Shared by `edit`, `render` and `play`.
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct CellsArgs {
    /// How dots become characters: braille (2x4 dots a cell), half-block (1x2, in colour) or
    /// ascii (for fonts without braille).
    #[arg(long, value_name = "MODE", value_parser = parse_cells)]
    pub cells: Option<CellMode>,
    /// The same as --cells ascii.
    #[arg(long, conflicts_with_all = ["cells", "half_block"])]
    pub ascii: bool,
    /// The same as --cells half-block.
    #[arg(long, conflicts_with = "cells")]
    pub half_block: bool,
}

impl CellsArgs {
    /// The cell mode asked for (braille when none is).
    pub fn mode(&self) -> CellMode {
        if self.ascii {
            CellMode::Ascii
        } else if self.half_block {
            CellMode::HalfBlock
        } else {
            self.cells.unwrap_or_default()
        }
    }
}

fn parse_cells(text: &str) -> Result<CellMode, String> {
    text.parse()
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Edit an AU table in the terminal (the default when no subcommand is given).
    #[command(after_help = edit::AFTER_HELP)]
    Edit(edit::EditArgs),
    /// Write the built-in default face as OBJ (and, with --presets, its rigs and AU table).
    GenFace(gen_face::GenFaceArgs),
    /// Import the classic Waters face (faceline.dat, index.dat, muscle.dat) as OBJ and rig.
    ImportWaters(import_waters::ImportWatersArgs),
    /// Write the mesh deformed by an AU, expression, combination or muscle values as OBJ.
    Export(export::ExportArgs),
    /// Check rig (*.rig.ron), AU table (*.au.ron), landmark (*.landmarks.ron) and mesh (*.obj)
    /// files.
    Validate(validate::ValidateArgs),
    /// List the muscles of a rig, the AUs and expressions of a table, or the FACS catalogue.
    List(list::ListArgs),
    /// Animate the face from an OpenFace CSV, a timeline, or a live AU stream.
    Play(play::PlayArgs),
    /// Draw one state of the face as braille or ASCII text, SVG or PNG (or every AU and
    /// expression of a table with --all).
    Render(render::RenderArgs),
    /// Fit a rig to your own mesh from its 68 landmarks (or pick them first with --pick).
    FitRig(fit_rig::FitRigArgs),
    /// Pick a mesh's 68 landmarks in the terminal and save them as a landmark file.
    #[command(after_help = landmarks::AFTER_HELP)]
    Landmarks(landmarks::LandmarksArgs),
    /// Fit AU entries to target shapes of a rig's mesh (blendshapes, scans).
    FitAu(fit_au::FitAuArgs),
    /// Solve each frame's muscles from an OpenFace recording's 3D landmarks (capture).
    Capture(capture::CaptureArgs),
    /// Deform every AU and expression of a table and report tears, lids that stay open and
    /// a jaw that does not open (exits 1 when one is found).
    Check(check::CheckArgs),
    /// Render a plan's faces, AUs, views and styles into a labelled data set, one shard at
    /// a time (Slurm array jobs too); `batch merge DIR` checks it and writes the labels.
    Batch(batch::BatchArgs),
    /// Write a shell completion script (bash, zsh, fish, elvish, powershell) to stdout.
    Completions(completions::CompletionsArgs),
}

/// Parses the command line, runs it, and maps errors to exit codes (1 for errors; clap exits
/// with 2 on usage errors).
pub fn main() -> ExitCode {
    ignore_file_size_signal();
    let cli = Cli::parse();
    match cli.command {
        None => finish("edit", edit::run(&cli.editor.to_edit_args())),
        Some(command) => match command {
            Command::Edit(args) => finish("edit", edit::run(&args)),
            Command::GenFace(args) => gen_face::run(&args),
            Command::ImportWaters(args) => finish("import-waters", import_waters::run(&args)),
            Command::Export(args) => finish("export", export::run(&args)),
            Command::Validate(args) => validate::run(&args),
            Command::List(args) => finish("list", list::run(&args)),
            Command::Play(args) => finish("play", play::run(&args)),
            Command::Render(args) => finish("render", render::run(&args)),
            Command::Completions(args) => completions::run(&args),
            Command::Batch(args) => batch::run(&args),
            Command::FitRig(args) => finish("fit-rig", fit_rig::run(&args)),
            Command::FitAu(args) => finish("fit-au", fit_au::run(&args)),
            Command::Capture(args) => finish("capture", capture::run(&args)),
            Command::Check(args) => check::run(&args),
            Command::Landmarks(args) => finish("landmarks", landmarks::run(&args)),
        },
    }
}

/// Makes a file-size limit (`ulimit -f`) an error a write returns ("file too large"), reported
/// and handled like a full disk, instead of the signal SIGXFSZ, which would kill grimace
/// mid-save: edits lost, a temporary file and a lock left behind, the terminal not restored.
fn ignore_file_size_signal() {
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to SIG_IGN installs no handler and touches no
    // memory; it happens before any thread starts.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

/// Maps a command's result to the exit status, printing the error as
/// `grimace COMMAND: message` (the message names file, line and column where known).
pub fn finish<E: Display>(command: &str, result: Result<(), E>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            report(command, &err);
            ExitCode::from(1)
        }
    }
}

/// Prints an error of a command to stderr, control characters escaped (a message may quote
/// text from a file).
pub fn report(command: &str, err: &dyn Display) {
    let text = format!("grimace {command}: {err:#}");
    let _ = writeln!(std::io::stderr(), "{}", printable(&text));
}

/// Writes text to stdout with control characters escaped (names and paths come from files;
/// see [`printable`]). A closed pipe is not an error (`grimace list | head` must not fail);
/// any other failure (a full disk) is, so the command exits 1.
pub fn print(text: &str) -> anyhow::Result<()> {
    print_raw(printable(text).as_bytes())
}

/// Writes bytes to stdout as they are: for output grimace makes itself (a picture's colour
/// escapes), never for text from files. Errors as for [`print`].
pub fn print_raw(bytes: &[u8]) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(anyhow::anyhow!(
            "cannot write to stdout: {}",
            crate::io::error::io_reason(&e)
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bare_grimace_takes_the_editor_options() {
        let cli = Cli::try_parse_from(["grimace", "--ascii", "--rig", "my.rig.ron"]).unwrap();
        assert!(cli.command.is_none());
        let args = cli.editor.to_edit_args();
        assert_eq!(args.cells.mode(), CellMode::Ascii);
        assert_eq!(
            args.rig.as_deref(),
            Some(std::path::Path::new("my.rig.ron"))
        );
        assert!(args.file.is_none());
        let cli = Cli::try_parse_from(["grimace", "--colors", "256"]).unwrap();
        assert_eq!(
            cli.editor.to_edit_args().colors,
            edit::ColorsChoice(Some(crate::render::ColorMode::Ansi256))
        );
        assert_eq!(
            Cli::try_parse_from(["grimace"]).unwrap().editor.colors,
            edit::ColorsChoice(None)
        );
    }

    #[test]
    fn a_mistyped_subcommand_is_a_usage_error_not_a_new_table() {
        let err = Cli::try_parse_from(["grimace", "lst"]).unwrap_err();
        assert_eq!(err.exit_code(), 2);
    }

    #[test]
    fn editor_options_do_not_mix_with_other_subcommands() {
        assert!(Cli::try_parse_from(["grimace", "--ascii", "list"]).is_err());
        let cli = Cli::try_parse_from(["grimace", "edit", "--ascii"]).unwrap();
        assert!(
            matches!(cli.command, Some(Command::Edit(ref a)) if a.cells.mode() == CellMode::Ascii)
        );
    }

    #[test]
    fn cells_take_a_mode_or_the_short_forms() {
        let mode = |args: &[&str]| match Cli::try_parse_from(args) {
            Ok(Cli {
                command: Some(Command::Render(r)),
                ..
            }) => Ok(r.cells.mode()),
            Ok(other) => panic!("{other:?}"),
            Err(e) => Err(e.kind()),
        };
        assert_eq!(mode(&["grimace", "render"]), Ok(CellMode::Braille));
        for (args, expected) in [
            (&["--cells", "ascii"][..], CellMode::Ascii),
            (&["--cells", "half-block"][..], CellMode::HalfBlock),
            (&["--cells", "braille"][..], CellMode::Braille),
            (&["--ascii"][..], CellMode::Ascii),
            (&["--half-block"][..], CellMode::HalfBlock),
        ] {
            let all: Vec<&str> = ["grimace", "render"].iter().chain(args).copied().collect();
            assert_eq!(mode(&all), Ok(expected), "{args:?}");
        }
        assert!(mode(&["grimace", "render", "--cells", "dots"]).is_err());
        assert!(mode(&["grimace", "render", "--ascii", "--half-block"]).is_err());
        assert!(mode(&["grimace", "render", "--ascii", "--cells", "braille"]).is_err());
        let cli = Cli::try_parse_from(["grimace", "play", "x.csv", "--cells", "half-block"]);
        assert!(
            matches!(cli, Ok(Cli { command: Some(Command::Play(ref p)), .. }) if p.cells.mode() == CellMode::HalfBlock)
        );
        let cli = Cli::try_parse_from(["grimace", "--half-block"]).unwrap();
        assert_eq!(cli.editor.cells.mode(), CellMode::HalfBlock);
    }
}
