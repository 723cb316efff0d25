//! The command line: argument parsing and one module per subcommand.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod edit;
pub mod gen_face;
pub mod play;

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
    Edit(edit::EditArgs),
    /// Write the built-in default face as OBJ (and, with --presets, its rigs and AU table).
    GenFace(gen_face::GenFaceArgs),
    /// Animate the face from an OpenFace CSV, a timeline, or a live AU stream.
    Play(play::PlayArgs),
}

/// Parses the command line, runs it, and maps errors to exit codes (1 for errors; clap exits
/// with 2 on usage errors).
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        None => report(edit::run(&edit::EditArgs::default())),
        Some(Command::Edit(args)) => report(edit::run(&args)),
        Some(Command::GenFace(args)) => gen_face::run(&args),
        Some(Command::Play(args)) => report(play::run(&args)),
    }
}

/// Prints an error (with its causes) to stderr and turns the result into an exit code.
fn report(result: anyhow::Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("grimace: {e:#}");
            ExitCode::from(1)
        }
    }
}
