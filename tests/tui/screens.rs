//! Whole-screen snapshots of the editor on the built-in default face, drawn with ratatui's
//! TestBackend at 80x24 and 200x60 (and the too-small message).

use grimace::tui::action::Action;
use grimace::tui::app::{App, ColorMode};
use grimace::tui::face::Face;
use grimace::tui::update::update;
use grimace::tui::view;
use ratatui::backend::TestBackend;
use ratatui::Terminal;

fn app(cols: u16, rows: u16) -> App {
    let (rig, mesh, table) = grimace::cli::edit::default_face().expect("the built-in face");
    let scene = Face::new(rig, mesh).expect("the default rig binds");
    let mut app = App::new(scene, table, Some("expressions.au.ron".into()));
    app.view.colors = ColorMode::None;
    update(&mut app, Action::Resize(cols, rows));
    app
}

fn screen(app: &App) -> String {
    let mut terminal = Terminal::new(TestBackend::new(app.view.size.0, app.view.size.1)).unwrap();
    terminal
        .draw(|frame| view::draw(app, &mut Default::default(), frame))
        .unwrap();
    terminal.backend().to_string()
}

fn act(app: &mut App, actions: &[Action]) {
    for action in actions {
        update(app, action.clone());
    }
}

#[test]
fn rest_face_80x24() {
    let app = app(80, 24);
    insta::assert_snapshot!(screen(&app));
}

#[test]
fn rest_face_200x60() {
    let app = app(200, 60);
    insta::assert_snapshot!(screen(&app));
}

#[test]
fn smile_recorded_200x60() {
    let mut app = app(200, 60);
    act(
        &mut app,
        &[
            Action::ToggleMirror,
            Action::StepCoarse(1),
            Action::StepCoarse(1),
            Action::StepCoarse(1),
            Action::Command("record 12".into()),
        ],
    );
    insta::assert_snapshot!(screen(&app));
}

#[test]
fn jaw_open_ascii_80x24() {
    let mut app = app(80, 24);
    act(
        &mut app,
        &[
            Action::ToggleAscii,
            Action::Command("jaw 4".into()),
            Action::Command("set Orbicularis_Oris 1".into()),
        ],
    );
    insta::assert_snapshot!(screen(&app));
}

#[test]
fn help_overlay_80x24() {
    let mut app = app(80, 24);
    act(&mut app, &[Action::ToggleHelp]);
    insta::assert_snapshot!(screen(&app));
}

#[test]
fn command_line_and_muscle_overlay_200x60() {
    let mut app = app(200, 60);
    act(
        &mut app,
        &[
            Action::ToggleMuscles,
            Action::Preset(grimace::tui::app::ViewPreset::ThreeQuarter),
            Action::StartCommand,
            Action::InputChar('s'),
            Action::InputChar('e'),
            Action::InputComplete,
        ],
    );
    insta::assert_snapshot!(screen(&app));
}

#[test]
fn rejected_input_says_why_80x24() {
    let mut app = app(80, 24);
    act(&mut app, &[Action::Command("set Nope 3".into())]);
    let text = screen(&app);
    assert!(
        text.contains("the rig has no muscle named `Nope`"),
        "{text}"
    );
    insta::assert_snapshot!(text);
}

#[test]
fn too_small_says_so() {
    let app = app(40, 10);
    let text = screen(&app);
    assert!(text.contains("Terminal too small: 40x10"), "{text}");
    insta::assert_snapshot!(text);
}

#[test]
fn table_focus_gives_the_table_more_room_80x24() {
    let mut app = app(80, 24);
    act(
        &mut app,
        &[Action::SwitchFocus, Action::SelectLast, Action::Activate],
    );
    let text = screen(&app);
    assert!(text.contains("surprise = 1D+2D+5B+26C"), "{text}");
    assert!(text.contains("loaded expression surprise"), "{text}");
    insta::assert_snapshot!(text);
}

/// A message longer than the terminal is wide wraps onto extra bottom rows instead of being
/// cut off at the edge.
#[test]
fn a_long_message_wraps_at_80x24() {
    let mut app = app(80, 24);
    let long = "/a/rather/deep/folder/of/research/data/subject-017/session-3/expressions.au.ron";
    act(
        &mut app,
        &[Action::SaveFailed {
            path: long.into(),
            error: "No such file or directory (os error 2)".into(),
        }],
    );
    let text = screen(&app);
    let rows: Vec<&str> = text.lines().collect();
    let bottom: String = rows[rows.len() - 3..]
        .iter()
        .map(|r| r.trim_matches('"').trim())
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        bottom.contains("your edits are kept, nothing was lost"),
        "{text}"
    );
    insta::assert_snapshot!(text);
}
