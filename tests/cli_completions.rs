//! `grimace completions`: scripts for each shell name every subcommand.

use std::process::Command;

fn completions(shell: &str) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["completions", shell])
        .output()
        .expect("run grimace")
}

#[test]
fn bash_script_names_every_subcommand() {
    let out = completions("bash");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let script = String::from_utf8(out.stdout).unwrap();
    assert!(
        script.contains("_grimace()"),
        "not a bash completion function"
    );
    for sub in [
        "edit",
        "export",
        "import-waters",
        "validate",
        "list",
        "play",
        "gen-face",
    ] {
        assert!(script.contains(sub), "bash completions lack `{sub}`");
    }
}

#[test]
fn zsh_and_fish_scripts_are_written() {
    for (shell, marker) in [("zsh", "#compdef grimace"), ("fish", "complete -c grimace")] {
        let out = completions(shell);
        assert!(out.status.success());
        let script = String::from_utf8(out.stdout).unwrap();
        assert!(script.contains(marker), "{shell} script lacks `{marker}`");
    }
}

#[test]
fn unknown_shell_is_a_usage_error() {
    let out = completions("tcsh-unknown");
    assert_eq!(out.status.code(), Some(2));
}
