//! Colours: the shaded face in 256 colours (a snapshot of its grey steps), and the colour
//! mode the editor picks from the environment and `--colors`, shown on the status line.

use grimace::tui::action::Action;
use grimace::tui::app::{App, CellMode, ColorMode, Style};
use grimace::tui::face::Face;
use grimace::tui::update::update;
use grimace::tui::view;
use ratatui::backend::TestBackend;
use ratatui::style::Color;
use ratatui::Terminal;

use crate::common::pty::Launch;

fn shaded_app(colors: ColorMode) -> App {
    let (rig, mesh, table) = grimace::cli::edit::default_face().expect("the built-in face");
    let scene = Face::new(rig, mesh).expect("the default rig binds");
    let mut app = App::new(scene, table, Some("expressions.au.ron".into()));
    app.view.colors = colors;
    app.view.cells = CellMode::HalfBlock;
    app.view.style = Style::Shaded;
    update(&mut app, Action::Resize(100, 40));
    app
}

/// The viewport's half-block dots as letters: `a`-`x` for the 24 steps of the grey ramp
/// (232-255), `0` black (16), `#` white (231), `?` any other colour, space for none; two text
/// rows per screen row (top halves, then bottom halves).
fn grey_steps(app: &App) -> String {
    let mut terminal = Terminal::new(TestBackend::new(100, 40)).unwrap();
    terminal
        .draw(|frame| view::draw(app, &mut Default::default(), frame))
        .unwrap();
    let panels = view::layout(ratatui::layout::Rect::new(0, 0, 100, 40), app).unwrap();
    let area = panels.viewport;
    let buf = terminal.backend().buffer();
    let letter = |c: Color| match c {
        Color::Indexed(16) => '0',
        Color::Indexed(231) => '#',
        Color::Indexed(i @ 232..=255) => (b'a' + (i - 232)) as char,
        Color::Reset => ' ',
        _ => '?',
    };
    let mut out = String::new();
    for y in area.top() + 1..area.bottom() - 1 {
        let (mut top, mut bottom) = (String::new(), String::new());
        for x in area.left() + 1..area.right() - 1 {
            let cell = &buf[(x, y)];
            let (t, b) = match cell.symbol() {
                "▀" => (letter(cell.fg), letter(cell.bg)),
                "▄" => (letter(cell.bg), letter(cell.fg)),
                "█" => (letter(cell.fg), letter(cell.fg)),
                _ => (' ', ' '),
            };
            top.push(t);
            bottom.push(b);
        }
        out.push_str(top.trim_end());
        out.push('\n');
        out.push_str(bottom.trim_end());
        out.push('\n');
    }
    out
}

#[test]
fn shaded_face_in_256_colours() {
    let steps = grey_steps(&shaded_app(ColorMode::Ansi256));
    let used: std::collections::BTreeSet<char> =
        steps.chars().filter(|c| !c.is_whitespace()).collect();
    assert!(!used.contains(&'?'), "only greys: {used:?}");
    assert!(
        used.len() >= 16,
        "the ramp's steps are used, not 4 greys: {used:?}"
    );
    insta::assert_snapshot!(steps);
}

#[test]
fn the_status_line_names_the_colour_mode_detected_or_chosen() {
    let dir = tempfile::tempdir().unwrap();
    /// Flags, environment, and what the status line says.
    type Case = (
        &'static [&'static str],
        &'static [(&'static str, &'static str)],
        &'static str,
    );
    let cases: &[Case] = &[
        (&[], &[], "256 colours"),
        (&[], &[("COLORTERM", "truecolor")], "truecolor"),
        (&[], &[("TERM", "xterm-direct")], "truecolor"),
        (&[], &[("TERM", "xterm")], "16 colours"),
        (
            &["--colors", "16"],
            &[("COLORTERM", "truecolor")],
            "16 colours",
        ),
        (&["--colors", "none"], &[], "no colour"),
    ];
    for (flags, env, shown) in cases {
        let mut args = vec!["edit", "new.au.ron"];
        args.extend_from_slice(flags);
        let mut launch = Launch::grimace(dir.path()).args(&args).size(120, 30);
        for (key, value) in env.iter() {
            launch = launch.env(key, value);
        }
        let mut ed = launch.start();
        ed.wait_for(shown);
        ed.send(":q!\r");
        assert!(ed.wait_exit().success());
    }
}

#[test]
fn an_unknown_colour_mode_is_refused_by_name() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["edit", "--colors", "257"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("unknown colour mode `257`"), "{err}");
}
