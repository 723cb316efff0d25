//! The command line: argument parsing and one module per subcommand.

pub mod play;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod gen_face;

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
        None => {
            eprintln!("grimace: the editor is not built yet; see `grimace --help`");
            ExitCode::from(1)
        }
        Some(command) => match command {
            Command::GenFace(args) => gen_face::run(&args),
            Command::Play(args) => play::main(&args),
        },
    }
}
