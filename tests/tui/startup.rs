//! Starting the editor (without a terminal): loading, the recovery offer, the lock, --cells.

use std::path::PathBuf;

use grimace::cli::edit::{prepare, EditArgs};
use grimace::cli::CellsArgs;
use grimace::io::recovery::{self, RecoveryState};
use grimace::tui::action::{Action, Effect};
use grimace::tui::app::{CellMode, Mode, Question, Severity};
use grimace::tui::update::update;

fn args(file: PathBuf) -> EditArgs {
    EditArgs {
        file: Some(file),
        ..EditArgs::default()
    }
}

#[test]
fn a_new_file_starts_an_empty_table_on_the_default_rig() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("new.au.ron");
    let (app, session) = prepare(&args(file.clone())).unwrap();
    assert!(app.doc.table.aus.is_empty());
    assert_eq!(app.doc.table.rig, PathBuf::from("builtin:default"));
    assert!(app.new_file() && !app.dirty());
    assert!(app.message.as_ref().unwrap().text.contains(":w creates it"));
    assert_eq!(
        session.recovery,
        Some(dir.path().join(".new.au.ron.recover"))
    );
    assert!(session.lock.is_some());
    drop(session);
    assert!(!dir.path().join(".new.au.ron.lock").exists());
}

#[test]
fn unsaved_state_is_offered_back_and_restored() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("t.au.ron");
    let (mut app, session) = prepare(&args(file.clone())).unwrap();
    update(
        &mut app,
        Action::Command("set L_Zygomatic_Major 1.25".into()),
    );
    update(&mut app, Action::Command("record 12".into()));
    let state = RecoveryState::new(Some(&file), app.rig(), &app.doc.activations, &app.doc.table);
    recovery::write(session.recovery.as_ref().unwrap(), &state).unwrap();
    let expected = (app.doc.activations.clone(), app.doc.table.clone());
    drop(session);

    let (mut app, _session) = prepare(&args(file.clone())).unwrap();
    assert!(matches!(app.mode, Mode::Confirm(Question::Recover(_))));
    assert!(app.doc.activations.is_rest());
    update(&mut app, Action::Answer(true));
    assert_eq!(
        (app.doc.activations.clone(), app.doc.table.clone()),
        expected
    );
    assert!(app.dirty());
    assert!(!file.exists(), "the table file is untouched until saved");
}

#[test]
fn declining_the_offer_discards_the_recovery_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("t.au.ron");
    let (mut app, session) = prepare(&args(file.clone())).unwrap();
    update(&mut app, Action::Command("jaw 2".into()));
    let state = RecoveryState::new(Some(&file), app.rig(), &app.doc.activations, &app.doc.table);
    recovery::write(session.recovery.as_ref().unwrap(), &state).unwrap();
    drop(session);
    let (mut app, _session) = prepare(&args(file)).unwrap();
    assert_eq!(
        update(&mut app, Action::Answer(false)),
        vec![Effect::RemoveRecovery]
    );
    assert!(app.doc.activations.is_rest());
}

#[test]
fn a_damaged_recovery_file_is_reported_and_the_editor_still_opens() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("t.au.ron");
    std::fs::write(dir.path().join(".t.au.ron.recover"), "(version: 1, garbage").unwrap();
    let (app, _session) = prepare(&args(file)).unwrap();
    assert_eq!(app.mode, Mode::Normal);
    let message = app.message.unwrap();
    assert_eq!(message.severity, Severity::Warning);
    assert!(
        message.text.contains("recovery file cannot be read"),
        "{}",
        message.text
    );
    assert!(
        message.text.contains(".t.au.ron.recover:1:"),
        "{}",
        message.text
    );
}

#[test]
fn a_table_that_fails_to_load_names_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bad.au.ron");
    std::fs::write(&file, "(\n  version: 1,\n  rig: \"builtin:default\",\n  aus: {\"12\": (name: \"x\", muscles: {\"Nope\": 1.0})},\n)\n").unwrap();
    let err = prepare(&args(file.clone())).map(|_| ()).unwrap_err();
    assert!(err.starts_with(&format!("{}:4:", file.display())), "{err}");
    assert!(err.contains("Nope"), "{err}");
}

#[test]
fn cells_flags_choose_the_starting_cells() {
    let dir = tempfile::tempdir().unwrap();
    let start = |cells: CellsArgs| {
        let (app, _session) = prepare(&EditArgs {
            file: Some(dir.path().join("a.au.ron")),
            cells,
            ..EditArgs::default()
        })
        .unwrap();
        app.view.cells
    };
    let ascii = CellsArgs {
        ascii: true,
        ..CellsArgs::default()
    };
    assert_eq!(start(ascii), CellMode::Ascii);
    let half_block = CellsArgs {
        cells: Some(CellMode::HalfBlock),
        ..CellsArgs::default()
    };
    assert_eq!(start(half_block), CellMode::HalfBlock);
    assert_eq!(start(CellsArgs::default()), CellMode::Braille);
}

#[test]
fn a_saved_table_opens_clean_with_its_stamp() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("t.au.ron");
    let (mut app, session) = prepare(&args(file.clone())).unwrap();
    update(
        &mut app,
        Action::Command("set L_Zygomatic_Major 0.5".into()),
    );
    update(&mut app, Action::Command("record 12".into()));
    let fx = update(&mut app, Action::Save);
    let Some(Effect::Save {
        path,
        table,
        expected,
        force,
        quit_after,
    }) = fx.into_iter().next()
    else {
        panic!("no save effect")
    };
    let contents =
        grimace::io::table_to_ron(&grimace::io::reference::table_for_file(&path, &table));
    let outcome = grimace::tui::save(&path, &contents, expected, force, quit_after);
    assert!(matches!(outcome, Action::Saved { .. }), "{outcome:?}");
    drop(session);
    let (app2, _session) = prepare(&args(file)).unwrap();
    assert!(!app2.dirty() && !app2.new_file());
    assert_eq!(app2.doc.table, app.doc.table);
}
