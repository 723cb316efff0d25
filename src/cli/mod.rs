//! The command line: argument parsing and one module per subcommand.

pub mod play;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

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
        Some(command) => {
            let result = match command {
                Command::Play(args) => play::run(&args),
            };
            match result {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("grimace: {e:#}");
                    ExitCode::from(1)
                }
            }
        }
    }
}
