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
pub mod fit_au;
pub mod fit_rig;
pub mod gen_face;
pub mod import_waters;
pub mod list;
pub mod play;
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
    /// Draw with ASCII characters instead of braille.
    #[arg(long)]
    pub ascii: bool,
}

impl EditorOptions {
    /// The same options as `grimace edit` arguments, on the built-in default table.
    pub fn to_edit_args(&self) -> edit::EditArgs {
        edit::EditArgs {
            file: None,
            rig: self.rig.clone(),
            mesh: self.mesh.clone(),
            ascii: self.ascii,
        }
    }
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
    /// Fit a rig to your own mesh from its 68 landmarks.
    FitRig(fit_rig::FitRigArgs),
    /// Fit AU entries to target shapes of a rig's mesh (blendshapes, scans).
    FitAu(fit_au::FitAuArgs),
    /// Write a shell completion script (bash, zsh, fish, elvish, powershell) to stdout.
    Completions(completions::CompletionsArgs),
}

/// Parses the command line, runs it, and maps errors to exit codes (1 for errors; clap exits
/// with 2 on usage errors).
pub fn main() -> ExitCode {
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
            Command::FitRig(args) => finish("fit-rig", fit_rig::run(&args)),
            Command::FitAu(args) => finish("fit-au", fit_au::run(&args)),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bare_grimace_takes_the_editor_options() {
        let cli = Cli::try_parse_from(["grimace", "--ascii", "--rig", "my.rig.ron"]).unwrap();
        assert!(cli.command.is_none());
        let args = cli.editor.to_edit_args();
        assert!(args.ascii);
        assert_eq!(
            args.rig.as_deref(),
            Some(std::path::Path::new("my.rig.ron"))
        );
        assert!(args.file.is_none());
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
        assert!(matches!(cli.command, Some(Command::Edit(ref a)) if a.ascii));
    }
}
