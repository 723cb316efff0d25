//! `grimace completions SHELL`: shell completion scripts generated from the argument parser.

use std::process::ExitCode;

use clap::{Args, CommandFactory};
use clap_complete::Shell;

use super::Cli;

/// Arguments of `grimace completions`.
#[derive(Debug, Args)]
#[command(after_help = "Examples:\n  \
    grimace completions bash > ~/.local/share/bash-completion/completions/grimace\n  \
    grimace completions zsh > ~/.zfunc/_grimace\n  \
    grimace completions fish > ~/.config/fish/completions/grimace.fish")]
pub struct CompletionsArgs {
    /// The shell to write completions for.
    #[arg(value_enum)]
    pub shell: Shell,
}

/// Writes the completion script for the chosen shell to stdout.
pub fn run(args: &CompletionsArgs) -> ExitCode {
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut Cli::command(), "grimace", &mut script);
    // A closed pipe (`grimace completions bash | head`) is not an error worth a message; a
    // full disk is.
    super::finish("completions", super::print_raw(&script))
}
