//! The command line: argument parsing and one module per subcommand.
//!
//! Exit status: 0 on success, 1 on errors (a file that does not load, a value out of range),
//! 2 on usage errors (clap's own exit code for bad arguments). Errors are printed to stderr
//! as `grimace COMMAND: FILE:LINE:COL: message`.

use std::fmt::Display;
use std::io::Write;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod completions;
pub mod edit;
pub mod export;
pub mod gen_face;
pub mod import_waters;
pub mod list;
pub mod play;
pub mod render;
pub mod validate;

/// grimace: shape facial expressions with muscles, in the terminal.
#[derive(Debug, Parser)]
#[command(name = "grimace", version, about, long_about = None)]
pub struct Cli {
    /// The subcommand; without one, grimace opens the editor on the built-in default face.
    #[command(subcommand)]
    pub command: Option<Command>,
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
    /// Check rig (*.rig.ron), AU table (*.au.ron) and mesh (*.obj) files.
    Validate(validate::ValidateArgs),
    /// List the muscles of a rig, the AUs and expressions of a table, or the FACS catalogue.
    List(list::ListArgs),
    /// Animate the face from an OpenFace CSV, a timeline, or a live AU stream.
    Play(play::PlayArgs),
    /// Draw one state of the face as braille or ASCII text, SVG or PNG (or every AU and
    /// expression of a table with --all).
    Render(render::RenderArgs),
    /// Write a shell completion script (bash, zsh, fish, elvish, powershell) to stdout.
    Completions(completions::CompletionsArgs),
}

/// Parses the command line, runs it, and maps errors to exit codes (1 for errors; clap exits
/// with 2 on usage errors).
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        None => finish("edit", edit::run(&edit::EditArgs::default())),
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
        },
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

/// Prints an error of a command to stderr.
pub fn report(command: &str, err: &dyn Display) {
    let _ = writeln!(std::io::stderr(), "grimace {command}: {err:#}");
}

/// Writes text to stdout, ignoring a closed pipe (`grimace list | head` must not fail).
pub fn print(text: &str) {
    let mut out = std::io::stdout().lock();
    let _ = out.write_all(text.as_bytes());
    let _ = out.flush();
}
