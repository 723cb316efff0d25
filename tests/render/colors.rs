//! `grimace render --colors`: the editor's colour modes for text output, and the shaded face
//! in 256 colours (a snapshot of its grey steps).

use std::process::{Command, Output};

fn render(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_grimace"));
    cmd.arg("render").args(args);
    for name in ["NO_COLOR", "TERM", "COLORTERM", "TERM_PROGRAM"] {
        cmd.env_remove(name);
    }
    cmd.envs(env.iter().copied());
    let out = cmd.output().expect("grimace runs");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn text(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("UTF-8")
}

/// The SGR colour codes of the text, in order of first use.
fn codes(text: &str) -> Vec<String> {
    let mut seen = Vec::new();
    for part in text.split("\x1b[").skip(1) {
        let code = part.split('m').next().unwrap_or("").to_string();
        if code != "0" && !seen.contains(&code) {
            seen.push(code);
        }
    }
    seen
}

const SHADED: &[&str] = &["--style", "shaded", "--width", "60", "--height", "26"];

#[test]
fn every_editor_mode_is_offered_for_text() {
    let with = |mode: &str| {
        let mut args = vec!["--colors", mode];
        args.extend_from_slice(SHADED);
        codes(&text(&render(&args, &[])))
    };
    let truecolor = with("truecolor");
    assert!(
        truecolor.iter().all(|c| c.starts_with("38;2;")),
        "{truecolor:?}"
    );
    let c256 = with("256");
    assert!(c256.iter().all(|c| c.starts_with("38;5;")), "{c256:?}");
    let c16 = with("16");
    assert!(
        c16.iter()
            .all(|c| matches!(c.parse::<u32>(), Ok(30..=37 | 90..=97))),
        "{c16:?}"
    );
    assert!(with("none").is_empty());
    // The older names still work.
    assert_eq!(with("always"), truecolor);
    assert!(with("never").is_empty());
    let out = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["render", "--colors", "257"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("unknown colour mode `257`"), "{err}");
}

#[test]
fn auto_colours_nothing_into_a_pipe() {
    let out = render(
        &["--colors", "auto", "--width", "40", "--height", "16"],
        &[("COLORTERM", "truecolor")],
    );
    assert!(!text(&out).contains('\x1b'));
}

/// The 256-colour greys of a shaded face as letters: `a`-`x` for the 24 steps of the grey
/// ramp (232-255), `0` black (16), `#` white (231), `?` any other colour (foreground or
/// background), space for none; for half blocks, the upper half's grey.
fn grey_steps(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let mut row = String::new();
        let mut current = ' ';
        for part in line.split('\x1b') {
            let rest = match part.strip_prefix('[') {
                Some(rest) => {
                    let (code, after) = rest.split_once('m').unwrap_or((rest, ""));
                    let grey = |i: Option<Result<u8, _>>| match i {
                        Some(Ok(16)) => '0',
                        Some(Ok(231)) => '#',
                        Some(Ok(i @ 232..=255)) => (b'a' + (i - 232)) as char,
                        _ => '?',
                    };
                    if let Some(bg) = code.strip_prefix("48;5;") {
                        // A half block's lower half: a grey too, not shown.
                        if grey(Some(bg.parse::<u8>())) == '?' {
                            current = '?';
                        }
                    } else if code == "0" {
                        current = ' ';
                    } else {
                        current = grey(code.strip_prefix("38;5;").map(str::parse::<u8>));
                    }
                    after
                }
                None => part,
            };
            for ch in rest.chars() {
                row.push(if ch == ' ' { ' ' } else { current });
            }
        }
        out.push_str(row.trim_end());
        out.push('\n');
    }
    out
}

#[test]
fn shaded_face_in_256_colours_braille_and_half_block() {
    for cells in ["braille", "half-block"] {
        let mut args = vec!["--colors", "256", "--cells", cells];
        args.extend_from_slice(SHADED);
        let steps = grey_steps(&text(&render(&args, &[])));
        let used: std::collections::BTreeSet<char> =
            steps.chars().filter(|c| !c.is_whitespace()).collect();
        assert!(!used.contains(&'?'), "{cells}: only greys: {used:?}");
        assert!(
            used.len() >= 12,
            "{cells}: the ramp's steps are used, not a few greys: {used:?}"
        );
        insta::assert_snapshot!(format!("shaded_face_256_{cells}"), steps);
    }
}

#[test]
fn displacement_outputs_carry_the_colour_scale() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("smile.svg");
    let svg_arg = svg.to_str().unwrap();
    render(
        &["--expr", "happiness", "--displacement", "--out", svg_arg],
        &[],
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("linearGradient"), "the ramp");
    assert!(text.contains(" mm+</text>"), "the full-colour distance");
    let coloured = text_of(&["--expr", "happiness", "--displacement", "--colors", "256"]);
    let last = coloured.lines().last().unwrap();
    assert!(last.contains('█') && last.contains(" mm+"), "{last}");
    let plain = text_of(&["--expr", "happiness", "--displacement", "--colors", "none"]);
    let last = plain.lines().last().unwrap();
    assert!(
        last.starts_with("moved: blue 0") && last.ends_with(" mm+"),
        "{last}"
    );
    let without = text_of(&["--expr", "happiness", "--colors", "none"]);
    assert!(!without.contains("moved:"));
}

fn text_of(args: &[&str]) -> String {
    text(&render(args, &[]))
}
