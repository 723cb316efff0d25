//! Tests of the AU table operations: record, load, delete, rename, save, quit, recovery.

use super::*;

#[test]
fn record_prompts_for_key_then_name_and_asks_before_overwriting() {
    let mut app = app();
    command(&mut app, "set Frontalis 0.8");
    update(&mut app, Action::StartRecord);
    typed(&mut app, "1");
    update(&mut app, Action::InputSubmit);
    match &app.mode {
        Mode::Input(i) => assert_eq!(i.kind, InputKind::RecordName(AuKey::new(1))),
        other => panic!("{other:?}"),
    }
    run(&mut app, &[Action::InputHome]);
    while matches!(&app.mode, Mode::Input(i) if !i.text.is_empty()) {
        update(&mut app, Action::InputDelete);
    }
    typed(&mut app, "Brow raiser");
    update(&mut app, Action::InputSubmit);
    let entry = &app.doc.table.aus[&AuKey::new(1)];
    assert_eq!(entry.name, "Brow raiser");
    assert_eq!(
        entry.muscles,
        BTreeMap::from([("Frontalis".to_string(), 0.8)])
    );
    assert!(app.dirty());
    assert_eq!(app.doc.loaded, Some(AuKey::new(1)));
    // Recording over AU 12 asks first; "no" keeps the old entry.
    command(&mut app, "record 12 Smile");
    assert!(matches!(
        app.mode,
        Mode::Confirm(Question::OverwriteAu { .. })
    ));
    update(&mut app, Action::Answer(false));
    assert_eq!(app.doc.table.aus[&AuKey::new(12)].name, "Lip Corner Puller");
    command(&mut app, "record 12 Smile");
    update(&mut app, Action::Answer(true));
    assert_eq!(app.doc.table.aus[&AuKey::new(12)].name, "Smile");
    assert_eq!(
        app.doc.table.aus[&AuKey::new(12)].muscles,
        BTreeMap::from([("Frontalis".to_string(), 0.8)])
    );
    command(&mut app, "record R99x");
    assert!(error(&app).contains("`R99x` is not an AU"));
}

#[test]
fn record_refuses_a_65th_au() {
    let mut app = app();
    let codes: Vec<u8> = (1..=99u8)
        .filter(|&n| crate::facs::catalogue::is_code(n) && n != 12)
        .collect();
    assert!(
        codes.len() >= 22,
        "the catalogue has enough codes for this test"
    );
    let sides = [None, Some(Side::Left), Some(Side::Right)];
    let keys = codes
        .iter()
        .flat_map(|&n| sides.iter().map(move |&side| AuKey { number: n, side }));
    for key in keys.take(63) {
        command(&mut app, &format!("record {key} x"));
    }
    assert_eq!(app.doc.table.aus.len(), 64);
    command(&mut app, &format!("record {} x", codes[40]));
    assert!(error(&app).contains("full"), "{}", error(&app));
    assert_eq!(app.doc.table.aus.len(), 64);
}

#[test]
fn load_delete_rename_and_add() {
    let mut app = app();
    command(&mut app, "load 12");
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 1.0);
    assert_eq!(app.doc.loaded, Some(AuKey::new(12)));
    command(&mut app, "zero");
    command(&mut app, "add 12 0.5");
    assert_eq!(muscle(&app, "R_Zygomatic_Major"), 0.5);
    command(&mut app, "add 12 2");
    assert_eq!(
        muscle(&app, "R_Zygomatic_Major"),
        2.0,
        "clamped at the maximum"
    );
    command(&mut app, "add 12 3");
    assert!(error(&app).contains("intensity must be between 0 and 2"));
    command(&mut app, "zero");
    command(&mut app, "add 12C");
    assert!((muscle(&app, "L_Zygomatic_Major") - 0.5).abs() < 1e-6);
    command(&mut app, "add 12A 0.5");
    assert!((muscle(&app, "L_Zygomatic_Major") - 0.575).abs() < 1e-6);
    command(&mut app, "add 12Z");
    assert!(error(&app).starts_with("`12Z`"), "{}", error(&app));
    command(&mut app, "rename 12 Smile wide");
    assert_eq!(app.doc.table.aus[&AuKey::new(12)].name, "Smile wide");
    command(&mut app, "load 4");
    assert_eq!(error(&app), "the table has no AU 4");
    command(&mut app, "delete 12");
    assert!(app.doc.table.aus.is_empty());
    assert_eq!(app.doc.loaded, None);
    update(&mut app, Action::Undo);
    assert_eq!(app.doc.table.aus[&AuKey::new(12)].name, "Smile wide");
}

#[test]
fn table_panel_keys_act_on_the_selected_au() {
    let mut app = app();
    command(&mut app, "record 1 Brow");
    run(
        &mut app,
        &[Action::SwitchFocus, Action::SelectLast, Action::Activate],
    );
    assert_eq!(app.doc.loaded, Some(AuKey::new(12)));
    assert_eq!(muscle(&app, "L_Zygomatic_Major"), 1.0);
    update(&mut app, Action::DeleteSelected);
    assert_eq!(app.mode, Mode::Confirm(Question::DeleteAu(AuKey::new(12))));
    update(&mut app, Action::Answer(true));
    assert!(!app.doc.table.aus.contains_key(&AuKey::new(12)));
    update(&mut app, Action::RenameSelected);
    assert!(
        matches!(&app.mode, Mode::Input(i) if i.kind == InputKind::Rename(AuKey::new(1)) && i.text == "Brow")
    );
    typed(&mut app, " raiser");
    update(&mut app, Action::InputSubmit);
    assert_eq!(app.doc.table.aus[&AuKey::new(1)].name, "Brow raiser");
    update(&mut app, Action::OverwriteSelected);
    assert!(
        matches!(app.mode, Mode::Confirm(Question::OverwriteAu { key, .. }) if key == AuKey::new(1))
    );
    update(&mut app, Action::Cancel);
    assert_eq!(app.mode, Mode::Normal);
    update(&mut app, Action::StartAddAu);
    assert!(matches!(&app.mode, Mode::Input(i) if i.text == "1 "));
    typed(&mut app, "0.5");
    update(&mut app, Action::InputSubmit);
    assert_eq!(app.message.as_ref().unwrap().text, "added 1 at 0.50");
}

#[test]
fn save_writes_the_table_and_clears_dirty() {
    let mut app = app();
    command(&mut app, "record 1 Brow");
    assert!(app.dirty());
    let fx = update(&mut app, Action::Save);
    let Some(Effect::Save {
        path,
        table,
        expected,
        force,
        quit_after,
    }) = fx.first().cloned()
    else {
        panic!("{fx:?}")
    };
    assert_eq!(path, PathBuf::from("t.au.ron"));
    assert_eq!(expected, Some(FileStamp { len: 1, hash: 1 }));
    assert!(!force && !quit_after);
    assert_eq!(*table, app.doc.table);
    let contents = crate::io::table_to_ron(&table);
    let back: AuTable = ron::from_str(&contents).unwrap();
    assert_eq!(back, app.doc.table);
    let stamp = FileStamp::of(contents.as_bytes());
    let fx = update(
        &mut app,
        Action::Saved {
            path,
            stamp,
            quit_after: false,
        },
    );
    assert_eq!(fx, vec![Effect::RemoveRecovery]);
    assert!(!app.dirty());
}

#[test]
fn save_as_expects_a_new_file_and_wq_quits_after() {
    let mut app = app();
    let fx = command(&mut app, "w other.au.ron");
    assert!(
        matches!(&fx[0], Effect::Save { path, expected: None, .. } if path == &PathBuf::from("other.au.ron"))
    );
    let fx = command(&mut app, "wq");
    assert!(matches!(
        &fx[0],
        Effect::Save {
            quit_after: true,
            ..
        }
    ));
    let fx = update(
        &mut app,
        Action::Saved {
            path: "t.au.ron".into(),
            stamp: FileStamp { len: 0, hash: 0 },
            quit_after: true,
        },
    );
    assert_eq!(fx, vec![Effect::RemoveRecovery, Effect::Quit]);
}

#[test]
fn the_built_in_table_needs_a_file_name() {
    let mut app = app();
    app.doc.file = None;
    let fx = update(&mut app, Action::Save);
    assert!(fx.is_empty());
    assert!(error(&app).contains(":w FILE"));
}

#[test]
fn a_file_changed_on_disk_is_overwritten_only_when_confirmed() {
    let mut app = app();
    let fx = update(
        &mut app,
        Action::SaveConflict {
            path: "t.au.ron".into(),
            quit_after: false,
        },
    );
    assert!(fx.is_empty());
    assert!(matches!(
        app.mode,
        Mode::Confirm(Question::OverwriteFile { .. })
    ));
    let fx = update(&mut app, Action::Answer(false));
    assert!(fx.is_empty());
    update(
        &mut app,
        Action::SaveConflict {
            path: "t.au.ron".into(),
            quit_after: true,
        },
    );
    let fx = update(&mut app, Action::Answer(true));
    assert!(matches!(
        &fx[0],
        Effect::Save {
            force: true,
            quit_after: true,
            ..
        }
    ));
}

#[test]
fn a_failed_save_keeps_the_edits_and_says_so() {
    let mut app = app();
    command(&mut app, "record 1 Brow");
    update(
        &mut app,
        Action::SaveFailed {
            path: "t.au.ron".into(),
            error: "Permission denied".into(),
        },
    );
    assert!(app.dirty());
    assert!(error(&app).contains("could not save t.au.ron: Permission denied; your edits are kept"));
}

#[test]
fn quit_asks_only_when_there_are_unsaved_changes() {
    let mut app = app();
    assert_eq!(
        update(&mut app, Action::Quit),
        vec![Effect::RemoveRecovery, Effect::Quit]
    );
    command(&mut app, "record 1 Brow");
    assert!(update(&mut app, Action::Quit).is_empty());
    assert_eq!(app.mode, Mode::Confirm(Question::QuitUnsaved));
    assert!(update(&mut app, Action::Answer(false)).is_empty());
    assert_eq!(app.mode, Mode::Normal);
    assert!(command(&mut app, "q").is_empty());
    assert_eq!(
        update(&mut app, Action::Answer(true)),
        vec![Effect::RemoveRecovery, Effect::Quit]
    );
    assert_eq!(
        command(&mut app, "q!"),
        vec![Effect::RemoveRecovery, Effect::Quit]
    );
}

#[test]
fn recovery_offer_restores_or_discards() {
    let mut app = app();
    let mut activations = app.doc.activations.clone();
    activations.muscles[3] = 1.5;
    let mut table = app.doc.table.clone();
    table.aus.clear();
    let question = Question::Recover(Box::new(crate::tui::app::Recovered {
        activations: activations.clone(),
        table: table.clone(),
        when: "5 s ago".into(),
        base: None,
        rig: None,
    }));
    app.mode = Mode::Confirm(question.clone());
    assert!(question_text(&question).contains("recover"));
    let fx = update(&mut app, Action::Answer(true));
    assert_eq!(fx, vec![Effect::RecoveryDue]);
    assert_eq!(app.doc.activations, activations);
    assert_eq!(app.doc.table, table);
    assert!(app.dirty());
    let mut app2 = self::app();
    app2.mode = Mode::Confirm(question);
    assert_eq!(
        update(&mut app2, Action::Answer(false)),
        vec![Effect::RemoveRecovery]
    );
    assert!(app2.doc.activations.is_rest());
}
