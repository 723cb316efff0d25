//! The `grimace` command.

fn main() -> std::process::ExitCode {
    grimace::cli::main()
}
