//! `grimace completions`: scripts for each shell name every subcommand.

use std::process::Command;

fn grimace(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(args)
        .output()
        .expect("run grimace")
}

fn completions(shell: &str) -> String {
    let out = grimace(&["completions", shell]);
    assert!(
        out.status.success(),
        "{shell}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Every subcommand, as `grimace --help` lists them (without `help`).
const SUBCOMMANDS: [&str; 15] = [
    "edit",
    "gen-face",
    "import-waters",
    "export",
    "validate",
    "list",
    "play",
    "render",
    "fit-rig",
    "landmarks",
    "fit-au",
    "capture",
    "check",
    "batch",
    "completions",
];

/// The subcommands `grimace --help` lists: a new one fails the tests below until it is
/// added to [`SUBCOMMANDS`], and so is checked in every shell.
#[test]
fn the_list_is_every_subcommand_of_the_help() {
    let out = grimace(&["--help"]);
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    let listed: Vec<&str> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        // Entries start two spaces in; wrapped descriptions further.
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .collect();
    assert_eq!(listed, SUBCOMMANDS, "{help}");
}

#[test]
fn every_shell_script_names_every_subcommand() {
    // How each shell's script offers a subcommand.
    let offered = |shell: &str, sub: &str| match shell {
        "bash" => format!("grimace,{sub})"),
        "zsh" => format!("'{sub}:"),
        "fish" => format!("-a \"{sub}\""),
        _ => unreachable!(),
    };
    for (shell, marker) in [
        ("bash", "_grimace()"),
        ("zsh", "#compdef grimace"),
        ("fish", "complete -c grimace"),
    ] {
        let script = completions(shell);
        assert!(script.contains(marker), "{shell} script lacks `{marker}`");
        for sub in SUBCOMMANDS {
            let entry = offered(shell, sub);
            assert!(
                script.contains(&entry),
                "{shell} completions lack `{sub}` (no `{entry}`)"
            );
        }
    }
}

#[test]
fn unknown_shell_is_a_usage_error() {
    let out = grimace(&["completions", "tcsh-unknown"]);
    assert_eq!(out.status.code(), Some(2));
}
