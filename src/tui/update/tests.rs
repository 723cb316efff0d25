//! Tests of `update`, through actions and commands as the user gives them.

use std::collections::BTreeMap;
use std::path::PathBuf;

use super::*;
use crate::facs::AuTable;
use crate::model::Side;
use crate::tui::app::{FileStamp, Message, Severity, Style};

mod table;

fn app() -> App {
    crate::tui::fixture::app()
}

fn run(app: &mut App, actions: &[Action]) -> Vec<Effect> {
    actions
        .iter()
        .flat_map(|a| update(app, a.clone()))
        .collect()
}

fn command(app: &mut App, line: &str) -> Vec<Effect> {
    update(app, Action::Command(line.into()))
}

fn typed(app: &mut App, text: &str) {
    for c in text.chars() {
        update(app, Action::InputChar(c));
    }
}

fn error(app: &App) -> String {
    match &app.message {
        Some(Message {
            text,
            severity: Severity::Error,
        }) => text.clone(),
        other => panic!("expected an error message, got {other:?}"),
    }
}

fn muscle(app: &App, name: &str) -> f32 {
    app.doc.activations.muscles[app.rig().muscle_index(name).unwrap()]
}

#[test]
fn rows_are_grouped_linear_sheet_sphincter_jaw() {
    let app = app();
    assert_eq!(
        app.selection.rows,
        vec![
            Row::Muscle(1),
            Row::Muscle(2),
            Row::Muscle(3),
            Row::Muscle(0),
            Row::Jaw
        ]
    );
}

#[test]
fn selection_moves_and_stops_at_the_ends() {
    let mut app = app();
    run(&mut app, &[Action::SelectPrev]);
    assert_eq!(app.selection.selected, 0);
    run(&mut app, &[Action::SelectNext, Action::SelectNext]);
    assert_eq!(app.selection.selected, 2);
    run(&mut app, &[Action::SelectLast]);
    assert_eq!(app.selected_row(), Row::Jaw);
    run(&mut app, &[Action::SelectNext]);
    assert_eq!(app.selected_row(), Row::Jaw);
    run(&mut app, &[Action::SelectFirst]);
    assert_eq!(app.selection.selected, 0);
    run(&mut app, &[Action::SelectRow(Row::Muscle(0))]);
    assert_eq!(app.selection.selected, 3);
}

#[test]
fn fine_and_coarse_steps_stay_in_range() {
    let mut app = app();
    let fx = run(&mut app, &[Action::StepFine(1)]);
    assert!(fx.contains(&Effect::RecoveryDue));
    assert!((muscle(&app, "L_Zygomatic_Major") - 0.05).abs() < 1e-6);
    run(&mut app, &[Action::StepCoarse(1)]);
    assert!((muscle(&app, "L_Zygomatic_Major") - 0.30).abs() < 1e-6);
    for _ in 0..20 {
        update(&mut app, Action::StepCoarse(1));
    }
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 2.0);
    for _ in 0..20 {
        update(&mut app, Action::StepCoarse(-1));
    }
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 0.0);
    let fx = update(&mut app, Action::StepFine(-1));
    assert!(fx.is_empty(), "no edit at the minimum");
    // The jaw goes to 4.
    run(&mut app, &[Action::SelectLast]);
    for _ in 0..20 {
        update(&mut app, Action::StepCoarse(1));
    }
    assert_eq!(app.doc.activations.jaw, 4.0);
}

#[test]
fn consecutive_steps_on_one_muscle_undo_together() {
    let mut app = app();
    run(
        &mut app,
        &[
            Action::StepFine(1),
            Action::StepFine(1),
            Action::StepFine(1),
        ],
    );
    assert_eq!(app.history.undo.len(), 1);
    run(&mut app, &[Action::SelectNext, Action::StepFine(1)]);
    assert_eq!(app.history.undo.len(), 2);
    run(&mut app, &[Action::Undo]);
    assert_eq!(muscle(&app, "R_Zygomatic_Major"), 0.0);
    assert!((muscle(&app, "L_Zygomatic_Major") - 0.15).abs() < 1e-6);
    run(&mut app, &[Action::Undo]);
    assert!(app.doc.activations.is_rest());
    run(&mut app, &[Action::Undo]);
    assert_eq!(error(&app), "nothing to undo");
    run(&mut app, &[Action::Redo, Action::Redo]);
    assert!((muscle(&app, "R_Zygomatic_Major") - 0.05).abs() < 1e-6);
    run(&mut app, &[Action::Redo]);
    assert_eq!(error(&app), "nothing to redo");
}

#[test]
fn a_new_edit_clears_redo() {
    let mut app = app();
    run(&mut app, &[Action::StepFine(1), Action::Undo]);
    assert_eq!(app.history.redo.len(), 1);
    run(&mut app, &[Action::ZeroSelected, Action::StepCoarse(1)]);
    assert!(app.history.redo.is_empty());
}

#[test]
fn edits_deform_the_face_and_undo_restores_it() {
    let mut app = app();
    let rest = app.doc.face.mesh().positions.clone();
    run(
        &mut app,
        &[
            Action::ToggleMirror,
            Action::StepCoarse(1),
            Action::StepCoarse(1),
        ],
    );
    assert_ne!(
        app.doc.face.positions(),
        &rest[..],
        "the zygomatics move the grid"
    );
    // The incremental update matches a full deformation.
    let mut full = app.doc.face.clone();
    full.deform(&app.doc.activations);
    assert_eq!(app.doc.face.positions(), full.positions());
    command(&mut app, "jaw 2");
    let mut full = app.doc.face.clone();
    full.deform(&app.doc.activations);
    assert_eq!(app.doc.face.positions(), full.positions());
    run(&mut app, &[Action::Undo, Action::Undo]);
    assert_eq!(app.doc.face.positions(), &rest[..]);
}

#[test]
fn mirror_mode_moves_the_partner() {
    let mut app = app();
    run(&mut app, &[Action::ToggleMirror, Action::StepCoarse(1)]);
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 0.25);
    assert_eq!(muscle(&app, "R_Zygomatic_Major"), 0.25);
    run(&mut app, &[Action::ToggleMirror, Action::StepCoarse(1)]);
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 0.5);
    assert_eq!(muscle(&app, "R_Zygomatic_Major"), 0.25);
    // Muscles without a partner move alone.
    run(
        &mut app,
        &[
            Action::ToggleMirror,
            Action::SelectRow(Row::Muscle(3)),
            Action::StepCoarse(1),
        ],
    );
    assert_eq!(muscle(&app, "Frontalis"), 0.25);
}

#[test]
fn exact_value_prompt_accepts_in_range_and_rejects_the_rest() {
    let mut app = app();
    update(&mut app, Action::StartSetValue);
    // The field starts empty: what is typed is the value (the prompt names the current one).
    assert!(matches!(&app.mode, Mode::Input(i) if i.text.is_empty()
        && i.kind == InputKind::Value("L_Zygomatic_Major 0.00, 0-2".into())));
    typed(&mut app, "1.5");
    update(&mut app, Action::InputSubmit);
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 1.5);
    command(&mut app, "set L_Zygomatic_Major 9");
    update(&mut app, Action::InputSubmit);
    assert!(
        error(&app).contains("must be between 0.00 and 2.00"),
        "{}",
        error(&app)
    );
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 1.5);
    command(&mut app, "set L_Zygomatic_Major abc");
    assert_eq!(error(&app), "`abc` is not a number");
    command(&mut app, "set L_Zygomatic_Major NaN");
    assert_eq!(error(&app), "`NaN` is not a number");
}

#[test]
fn zero_and_reset_all() {
    let mut app = app();
    command(&mut app, "set Frontalis 1");
    command(&mut app, "jaw 3");
    command(&mut app, "set L_Zygomatic_Major 0.7");
    update(&mut app, Action::ZeroSelected);
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 0.0);
    assert_eq!(muscle(&app, "Frontalis"), 1.0);
    update(&mut app, Action::ResetAll);
    assert!(app.doc.activations.is_rest());
    update(&mut app, Action::Undo);
    assert_eq!(app.doc.activations.jaw, 3.0);
}

#[test]
fn set_and_jaw_commands_check_names_and_ranges() {
    let mut app = app();
    command(&mut app, "set frontalis 1.25");
    assert_eq!(muscle(&app, "Frontalis"), 1.25);
    command(&mut app, "set Nope 1");
    assert!(error(&app).contains("no muscle named `Nope`"));
    command(&mut app, "jaw 4.5");
    assert!(error(&app).contains("jaw must be between 0.00 and 4.00"));
    command(&mut app, "jaw 2");
    assert_eq!(app.doc.activations.jaw, 2.0);
    assert_eq!(app.message.as_ref().unwrap().text, "jaw = 2.00");
    update(&mut app, Action::ToggleMirror);
    command(&mut app, "set l_zygomatic_major 0.5");
    assert_eq!(muscle(&app, "R_Zygomatic_Major"), 0.5);
    let said = &app.message.as_ref().unwrap().text;
    assert_eq!(said, "L_Zygomatic_Major = 0.50 (and R_Zygomatic_Major)");
    command(&mut app, "view side");
    assert_eq!(app.message.as_ref().unwrap().text, "view: side");
    command(&mut app, "style wireframe");
    assert_eq!(app.message.as_ref().unwrap().text, "style: wireframe");
    command(&mut app, "set");
    assert!(error(&app).starts_with("usage: :set"));
    command(&mut app, "frobnicate");
    assert!(error(&app).contains("unknown command `frobnicate`"));
}

#[test]
fn find_selects_the_next_matching_muscle() {
    let mut app = app();
    update(&mut app, Action::StartFind);
    typed(&mut app, "oris");
    update(&mut app, Action::InputSubmit);
    assert_eq!(app.selected_row(), Row::Muscle(0));
    update(&mut app, Action::StartFind);
    typed(&mut app, "zygomatic");
    update(&mut app, Action::InputSubmit);
    assert_eq!(app.selected_row(), Row::Muscle(1));
    update(&mut app, Action::StartFind);
    typed(&mut app, "zygomatic");
    update(&mut app, Action::InputSubmit);
    assert_eq!(app.selected_row(), Row::Muscle(2));
    update(&mut app, Action::StartFind);
    typed(&mut app, "buccinator");
    update(&mut app, Action::InputSubmit);
    assert_eq!(error(&app), "no muscle matches `buccinator`");
}

#[test]
fn view_actions_move_the_camera_within_limits() {
    let mut app = app();
    run(&mut app, &[Action::Rotate(200.0, 100.0)]);
    assert_eq!(app.view.yaw, -160.0);
    assert_eq!(app.view.pitch, 90.0);
    run(&mut app, &[Action::Zoom(100.0), Action::Pan(5.0, -5.0)]);
    assert_eq!(app.view.zoom, 8.0);
    assert_eq!(app.view.pan, (1.0, -1.0));
    run(&mut app, &[Action::Preset(ViewPreset::Side)]);
    assert_eq!(
        (app.view.yaw, app.view.zoom, app.view.pan),
        (90.0, crate::tui::app::DEFAULT_ZOOM, (0.0, 0.0))
    );
    run(&mut app, &[Action::ResetView]);
    assert_eq!(app.view.yaw, 0.0);
    run(&mut app, &[Action::CycleStyle]);
    assert_eq!(app.view.style, Style::Shaded);
    run(&mut app, &[Action::ToggleAscii]);
    assert_eq!(app.view.cells, CellMode::Ascii);
    run(&mut app, &[Action::CycleCells]);
    assert_eq!(app.view.cells, CellMode::Braille);
    run(
        &mut app,
        &[
            Action::ToggleMuscles,
            Action::ToggleGhost,
            Action::ToggleDisplacement,
        ],
    );
    assert!(app.view.show_muscles && app.view.show_ghost && app.view.show_displacement);
    // View changes are not edits.
    assert!(app.history.undo.is_empty());
    assert!(!app.dirty());
}

#[test]
fn help_opens_scrolls_and_closes() {
    let mut app = app();
    update(&mut app, Action::ToggleHelp);
    assert_eq!(app.mode, Mode::Help(0));
    run(&mut app, &[Action::HelpScroll(3), Action::HelpScroll(-1)]);
    assert_eq!(app.mode, Mode::Help(2));
    update(&mut app, Action::Cancel);
    assert_eq!(app.mode, Mode::Normal);
}

#[test]
fn tab_completes_commands_muscles_and_aus() {
    let mut app = app();
    update(&mut app, Action::StartCommand);
    typed(&mut app, "se");
    update(&mut app, Action::InputComplete);
    assert!(matches!(&app.mode, Mode::Input(i) if i.text == "set "));
    typed(&mut app, "l_zy");
    update(&mut app, Action::InputComplete);
    assert!(matches!(&app.mode, Mode::Input(i) if i.text == "set L_Zygomatic_Major "));
    update(&mut app, Action::Cancel);
    update(&mut app, Action::StartCommand);
    typed(&mut app, "set z");
    update(&mut app, Action::InputComplete);
    assert_eq!(error(&app), "nothing completes `z`");
    update(&mut app, Action::Cancel);
    update(&mut app, Action::StartCommand);
    typed(&mut app, "load 1");
    update(&mut app, Action::InputComplete);
    assert!(matches!(&app.mode, Mode::Input(i) if i.text == "load 12 "));
    update(&mut app, Action::Cancel);
    update(&mut app, Action::StartCommand);
    typed(&mut app, "r");
    update(&mut app, Action::InputComplete);
    assert!(app.message.as_ref().unwrap().text.contains("record"));
    assert!(app.message.as_ref().unwrap().text.contains("rename"));
}

#[test]
fn input_editing_moves_the_cursor_and_backspace_on_empty_closes() {
    let mut app = app();
    update(&mut app, Action::StartCommand);
    typed(&mut app, "ac");
    run(
        &mut app,
        &[
            Action::InputLeft,
            Action::InputChar('b'),
            Action::InputEnd,
            Action::InputChar('d'),
        ],
    );
    assert!(matches!(&app.mode, Mode::Input(i) if i.text == "abcd" && i.cursor == 4));
    run(
        &mut app,
        &[
            Action::InputHome,
            Action::InputDelete,
            Action::InputRight,
            Action::InputBackspace,
        ],
    );
    assert!(matches!(&app.mode, Mode::Input(i) if i.text == "cd" && i.cursor == 0));
    run(&mut app, &[Action::InputDelete, Action::InputDelete]);
    assert!(matches!(&app.mode, Mode::Input(i) if i.text.is_empty()));
    update(&mut app, Action::InputBackspace);
    assert_eq!(app.mode, Mode::Normal);
}

#[test]
fn expressions_need_a_valid_combination() {
    let mut app = app();
    command(&mut app, "expr smile");
    assert_eq!(error(&app), "the table has no expression named `smile`");
    command(&mut app, "expr");
    assert!(error(&app).starts_with("usage: :expr"));
    command(&mut app, "expr smile 12+4");
    assert!(error(&app).contains('4'), "{}", error(&app));
    assert!(app.doc.table.expressions.is_empty());
    command(&mut app, "expr smile 12C");
    assert_eq!(app.doc.table.expressions["smile"], "12C");
    assert!(app.dirty());
    command(&mut app, "expr smile");
    assert!((muscle(&app, "L_Zygomatic_Major") - 0.5).abs() < 1e-6);
    command(&mut app, "zero");
    command(&mut app, "combo 12B");
    assert!((muscle(&app, "R_Zygomatic_Major") - 0.3).abs() < 1e-6);
    command(&mut app, "combo 12+");
    assert!(error(&app).starts_with("`12+`"), "{}", error(&app));
    // An AU an expression uses cannot be deleted.
    command(&mut app, "delete 12");
    assert!(error(&app).contains("smile"), "{}", error(&app));
    // Expressions are listed after the AUs; Enter loads, d deletes.
    run(&mut app, &[Action::SwitchFocus, Action::SelectLast]);
    update(&mut app, Action::Activate);
    assert!((muscle(&app, "L_Zygomatic_Major") - 0.5).abs() < 1e-6);
    update(&mut app, Action::DeleteSelected);
    assert!(app.doc.table.expressions.is_empty());
    update(&mut app, Action::StartExpression);
    typed(&mut app, "grin = 12E");
    update(&mut app, Action::InputSubmit);
    assert_eq!(app.doc.table.expressions["grin"], "12E");
}

#[test]
fn table_selection_record_suggestion_and_enter_on_a_muscle() {
    let mut app = app();
    command(&mut app, "record 1 Brow");
    update(&mut app, Action::SelectTableItem(1));
    assert_eq!(
        (app.selection.focus, app.selection.table_selected),
        (Focus::Table, 1)
    );
    update(&mut app, Action::SelectTableItem(9));
    assert_eq!(
        app.selection.table_selected, 1,
        "no such line: the selection stays"
    );
    update(&mut app, Action::StartRecord);
    assert!(
        matches!(&app.mode, Mode::Input(i) if i.kind == InputKind::RecordKey && i.text == "12")
    );
    update(&mut app, Action::InputSubmit);
    assert!(
        matches!(&app.mode, Mode::Input(i) if i.kind == InputKind::RecordName(AuKey::new(12)) && i.text == "Lip Corner Puller")
    );
    update(&mut app, Action::Cancel);
    update(&mut app, Action::SwitchFocus);
    update(&mut app, Action::Activate);
    assert!(matches!(&app.mode, Mode::Input(i) if matches!(i.kind, InputKind::Value(_))));
    update(&mut app, Action::Cancel);
    update(&mut app, Action::StartFind);
    assert!(matches!(&app.mode, Mode::Input(i) if i.kind == InputKind::Find));
}

#[test]
fn resize_records_the_size() {
    let mut app = app();
    update(&mut app, Action::Resize(200, 60));
    assert_eq!(app.view.size, (200, 60));
}

#[test]
fn typing_a_value_gives_that_value_and_enter_on_nothing_keeps_it() {
    let mut app = app();
    update(&mut app, Action::StartSetValue);
    typed(&mut app, "2");
    update(&mut app, Action::InputSubmit);
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 2.0);
    update(&mut app, Action::StartSetValue);
    update(&mut app, Action::InputSubmit);
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 2.0);
    assert_eq!(app.mode, Mode::Normal);
}

#[test]
fn ctrl_u_clears_the_line_before_the_cursor() {
    let mut app = app();
    update(&mut app, Action::StartCommand);
    typed(&mut app, "set jaw 3");
    update(&mut app, Action::InputLeft);
    update(&mut app, Action::InputClear);
    assert!(matches!(&app.mode, Mode::Input(i) if i.text == "3" && i.cursor == 0));
    update(&mut app, Action::InputEnd);
    update(&mut app, Action::InputClear);
    assert!(matches!(&app.mode, Mode::Input(i) if i.text.is_empty()));
    typed(&mut app, "jaw 1");
    update(&mut app, Action::InputSubmit);
    assert_eq!(app.doc.activations.jaw, 1.0);
}

#[test]
fn the_jaws_coarse_step_is_an_eighth_of_its_range() {
    let mut app = app();
    update(&mut app, Action::StepCoarse(1));
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 0.25);
    update(&mut app, Action::SelectLast);
    assert_eq!(app.selected_row(), Row::Jaw);
    update(&mut app, Action::StepCoarse(1));
    assert_eq!(app.doc.activations.jaw, 0.5);
    run(&mut app, &vec![Action::StepCoarse(1); 7]);
    assert_eq!(app.doc.activations.jaw, 4.0);
}

#[test]
fn steps_store_the_decimal_exactly() {
    let mut app = app();
    update(&mut app, Action::SelectLast);
    for n in 1..=80 {
        update(&mut app, Action::StepFine(1));
        let decimal: f32 = format!("{}.{:02}", n * 5 / 100, n * 5 % 100)
            .parse()
            .unwrap();
        assert_eq!(app.doc.activations.jaw, decimal, "after {n} fine steps");
    }
    for n in (0..80).rev() {
        update(&mut app, Action::StepFine(-1));
        let decimal: f32 = format!("{}.{:02}", n * 5 / 100, n * 5 % 100)
            .parse()
            .unwrap();
        assert_eq!(app.doc.activations.jaw, decimal, "back at {n} fine steps");
    }
    run(&mut app, &vec![Action::StepFine(1); 4]);
    assert_eq!(app.doc.activations.jaw.to_string(), "0.2");
}

fn default_app(table: AuTable) -> App {
    let scene = crate::tui::face::Face::new(
        crate::io::builtin::default_rig(),
        crate::io::builtin::default_mesh(),
    )
    .unwrap();
    App::new(scene, table, Some(PathBuf::from("new.au.ron")))
}

#[test]
fn import_adds_the_missing_aus_and_keeps_the_rest() {
    let mut app = app();
    let mut from = app.doc.table.clone();
    let mine = app.doc.table.aus[&AuKey::new(12)].clone();
    from.aus.get_mut(&AuKey::new(12)).unwrap().name = "theirs".into();
    let mut entry = mine.clone();
    entry.name = "Cheek Raiser".into();
    from.aus.insert(AuKey::new(6), entry);
    let mut alien = mine.clone();
    alien.muscles = BTreeMap::from([("Buccinator".to_string(), 1.0)]);
    from.aus.insert(AuKey::new(14), alien);
    let fx = update(
        &mut app,
        Action::TableRead {
            source: "other.au.ron".into(),
            table: Ok(from),
        },
    );
    assert_eq!(fx, vec![Effect::RecoveryDue]);
    let keys: Vec<AuKey> = app.doc.table.aus.keys().copied().collect();
    assert_eq!(keys, [AuKey::new(6), AuKey::new(12)]);
    assert_eq!(
        app.doc.table.aus[&AuKey::new(12)],
        mine,
        "present AUs are kept"
    );
    assert_eq!(
        app.message.as_ref().unwrap().text,
        "added AU 6 from other.au.ron; 1 already here, kept; \
         AU 14 left out: they move muscles this rig lacks"
    );
    update(&mut app, Action::Undo);
    assert_eq!(app.doc.table.aus.len(), 1, "one undo takes the import back");
}

#[test]
fn import_names_a_table_that_does_not_read() {
    let mut app = app();
    assert_eq!(
        command(&mut app, "import builtin:default"),
        vec![Effect::ReadTable(PathBuf::from("builtin:default"))]
    );
    update(
        &mut app,
        Action::TableRead {
            source: "x.au.ron".into(),
            table: Err("x.au.ron: no such file".into()),
        },
    );
    assert_eq!(
        error(&app),
        "could not import x.au.ron: x.au.ron: no such file"
    );
    command(&mut app, "import");
    assert!(error(&app).starts_with("usage: :import TABLE"));
}

#[test]
fn a_new_table_starts_from_the_builtin_aus() {
    let builtin = crate::io::builtin::default_table();
    let mut app = default_app(AuTable::new("builtin:default"));
    update(
        &mut app,
        Action::TableRead {
            source: "builtin:default".into(),
            table: crate::tui::table_ops::read(std::path::Path::new("builtin:default")),
        },
    );
    assert_eq!(app.doc.table.aus, builtin.aus);
    assert!(app.dirty());
}

#[test]
fn expr_offers_the_missing_aus_from_the_builtin_table() {
    let builtin = crate::io::builtin::default_table();
    let mut table = AuTable::new("builtin:default");
    let one = AuKey::new(1);
    table.aus.insert(one, builtin.aus[&one].clone());
    let mut app = default_app(table);
    command(&mut app, "expr surprise 1+2+5+26");
    let missing = vec![AuKey::new(2), AuKey::new(5), AuKey::new(26)];
    assert_eq!(
        app.mode,
        Mode::Confirm(Question::AddMissingAus {
            name: "surprise".into(),
            combo: "1+2+5+26".into(),
            missing: missing.clone(),
        })
    );
    let Mode::Confirm(q) = &app.mode else {
        unreachable!()
    };
    assert!(question_text(q).contains("2 Outer Brow Raiser, 5 Upper Lid Raiser, 26 Jaw Drop"));
    // No: nothing changes.
    update(&mut app, Action::Answer(false));
    assert_eq!(app.doc.table.aus.len(), 1);
    assert!(app.doc.table.expressions.is_empty());
    // Yes: the AUs come from the built-in table and the expression is stored, one undo step.
    command(&mut app, "expr surprise 1+2+5+26");
    update(&mut app, Action::Answer(true));
    for key in &missing {
        assert_eq!(app.doc.table.aus[key], builtin.aus[key]);
    }
    assert_eq!(app.doc.table.expressions["surprise"], "1+2+5+26");
    update(&mut app, Action::Undo);
    assert_eq!(app.doc.table.aus.len(), 1);
    assert!(app.doc.table.expressions.is_empty());
}

#[test]
fn expr_still_refuses_aus_the_builtin_table_cannot_give() {
    // The fixture's rig has none of the built-in table's muscles.
    let mut app = app();
    command(&mut app, "expr smile 6+12");
    assert_eq!(app.mode, Mode::Normal);
    assert!(error(&app).contains('6'), "{}", error(&app));
    assert!(app.doc.table.expressions.is_empty());
}

#[test]
fn shaded_braille_is_drawn_in_half_blocks_where_colours_allow() {
    use crate::render::ColorMode;
    let mut view = crate::tui::app::View::new(CellMode::Braille);
    for (style, colors, drawn) in [
        (Style::Shaded, ColorMode::TrueColor, CellMode::HalfBlock),
        (Style::Shaded, ColorMode::Ansi256, CellMode::HalfBlock),
        (Style::Shaded, ColorMode::Ansi16, CellMode::Braille),
        (Style::Shaded, ColorMode::None, CellMode::Braille),
        (Style::Lines, ColorMode::TrueColor, CellMode::Braille),
    ] {
        view.style = style;
        view.colors = colors;
        assert_eq!(view.drawn_cells(), drawn, "{style:?} in {colors:?}");
    }
    view.cells = CellMode::Ascii;
    view.style = Style::Shaded;
    assert_eq!(
        view.drawn_cells(),
        CellMode::Ascii,
        "ASCII is kept as asked"
    );
}
