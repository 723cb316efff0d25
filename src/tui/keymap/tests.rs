//! Tests of the key tables: every binding reachable, unique, and shown in help and hints.

use super::*;

fn key(code: KeyCode, mods: KeyModifiers) -> KeyEvent {
    KeyEvent::new(code, mods)
}

#[test]
fn upper_case_letters_with_shift_map_to_their_binding() {
    let action = dispatch(&Mode::Normal, key(KeyCode::Char('L'), KeyModifiers::SHIFT));
    assert_eq!(action, Some(Action::StepCoarse(1)));
}

#[test]
fn control_keys_are_distinct_from_plain_ones() {
    assert_eq!(
        dispatch(&Mode::Normal, key(KeyCode::Char('s'), CTRL)),
        Some(Action::Save)
    );
    assert_eq!(
        dispatch(&Mode::Normal, key(KeyCode::Char('s'), NONE)),
        Some(Action::CycleStyle)
    );
}

#[test]
fn no_key_is_bound_twice() {
    let table = bindings();
    for (i, a) in table.iter().enumerate() {
        for b in &table[i + 1..] {
            assert!(
                !(a.code == b.code && a.mods == b.mods),
                "{:?} bound twice",
                a.code
            );
        }
    }
}

#[test]
fn rig_keys_are_bound_once_shown_in_help_and_win_only_in_rig_mode() {
    let table = rig_bindings();
    let help = help_lines();
    for (i, a) in table.iter().enumerate() {
        assert!(
            !table[i + 1..]
                .iter()
                .any(|b| a.code == b.code && a.mods == b.mods),
            "{:?} bound twice",
            a.code
        );
        let label = key_label(a.code, a.mods);
        assert!(
            help.iter()
                .any(|(keys, _, section)| *section == "rig mode (R)"
                    && keys.split(" / ").any(|k| k == label)),
            "{label} missing from help"
        );
    }
    let mut app = crate::tui::fixture::app();
    let tab = key(KeyCode::Tab, NONE);
    assert_eq!(dispatch_for(&app, tab), Some(Action::SwitchFocus));
    app.rig_edit.on = true;
    assert_eq!(
        dispatch_for(&app, tab),
        Some(Action::Rig(RigAction::NextPoint))
    );
    assert_eq!(
        dispatch_for(&app, key(KeyCode::Left, SHIFT)),
        Some(rig_move(-1, 0, true))
    );
    // Keys rig mode does not bind keep their normal meaning.
    assert_eq!(
        dispatch_for(&app, key(KeyCode::Char('j'), NONE)),
        Some(Action::SelectNext)
    );
}

#[test]
fn every_binding_appears_in_help() {
    let help = help_lines();
    for b in bindings() {
        let label = key_label(b.code, b.mods);
        assert!(
            help.iter()
                .any(|(keys, _, _)| keys.split(" / ").any(|k| k == label)),
            "{label} missing from help"
        );
    }
}

#[test]
fn play_keys_dispatch_show_in_help_and_are_bound_once() {
    assert_eq!(
        play_dispatch(key(KeyCode::Char(' '), NONE)),
        Some(PlayKey::Pause)
    );
    assert_eq!(
        play_dispatch(key(KeyCode::Char('+'), KeyModifiers::SHIFT)),
        Some(PlayKey::Faster)
    );
    assert_eq!(
        play_dispatch(key(KeyCode::Char('c'), CTRL)),
        Some(PlayKey::Quit)
    );
    assert_eq!(play_dispatch(key(KeyCode::Char('c'), NONE)), None);
    let help = play_help_lines();
    for (i, a) in PLAY_BINDINGS.iter().enumerate() {
        assert!(
            !PLAY_BINDINGS[i + 1..]
                .iter()
                .any(|b| a.code == b.code && a.mods == b.mods),
            "{:?} bound twice",
            a.code
        );
        let label = key_label(a.code, a.mods);
        assert!(
            help.iter()
                .any(|(keys, _)| keys.split(" / ").any(|k| k == label)),
            "{label} missing from help"
        );
    }
    assert_eq!(
        play_hints(),
        "Space pause   . step   + faster   - slower   q quit"
    );
}

#[test]
fn input_mode_types_letters_that_are_commands_in_normal_mode() {
    let mode = Mode::Input(super::super::app::Input::new(
        super::super::app::InputKind::Command,
        "",
    ));
    assert_eq!(
        dispatch(&mode, key(KeyCode::Char('q'), NONE)),
        Some(Action::InputChar('q'))
    );
}
