//! The landmark picker's keys: one table that drives dispatch, the `?` help and the status
//! line hints.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use super::state::{Mode, PickAction, COARSE, TILT_DEGREES, TURN_DEGREES, ZOOM_STEP};
use crate::tui::keymap::{find_action, key_label, list_help_lines, KeyBinding};

/// One key of the picker.
pub type PickBinding = KeyBinding<PickAction>;

const NONE: KeyModifiers = KeyModifiers::NONE;
const SHIFT: KeyModifiers = KeyModifiers::SHIFT;
const CTRL: KeyModifiers = KeyModifiers::CONTROL;

use crate::tui::keymap::key_binding as key;

const fn ch(c: char) -> KeyCode {
    KeyCode::Char(c)
}

/// Every key of the picker, in help order.
pub fn bindings() -> &'static [PickBinding] {
    use PickAction as A;
    const LEFT: &str = "move the cursor one cell left (it snaps to the nearest visible vertex)";
    const RIGHT: &str = "move the cursor one cell right";
    const UP: &str = "move the cursor one cell up";
    const DOWN: &str = "move the cursor one cell down";
    const FAR_LEFT: &str = "move the cursor five cells left";
    const FAR_RIGHT: &str = "move the cursor five cells right";
    const FAR_UP: &str = "move the cursor five cells up";
    const FAR_DOWN: &str = "move the cursor five cells down";
    static TABLE: &[PickBinding] = &[
        key(
            KeyCode::Enter,
            NONE,
            A::Confirm,
            "take the vertex under the cursor (or the proposal)",
            Some("confirm"),
        ),
        key(
            KeyCode::Tab,
            NONE,
            A::Skip,
            "skip this landmark for now",
            Some("skip"),
        ),
        key(
            ch('u'),
            NONE,
            A::Undo,
            "undo the last pick or skip",
            Some("undo"),
        ),
        key(KeyCode::Left, NONE, A::Move(-1, 0), LEFT, Some("move")),
        key(ch('h'), NONE, A::Move(-1, 0), LEFT, None),
        key(KeyCode::Right, NONE, A::Move(1, 0), RIGHT, None),
        key(ch('l'), NONE, A::Move(1, 0), RIGHT, None),
        key(KeyCode::Up, NONE, A::Move(0, -1), UP, None),
        key(ch('k'), NONE, A::Move(0, -1), UP, None),
        key(KeyCode::Down, NONE, A::Move(0, 1), DOWN, None),
        key(ch('j'), NONE, A::Move(0, 1), DOWN, None),
        key(KeyCode::Left, SHIFT, A::Move(-COARSE, 0), FAR_LEFT, None),
        key(ch('H'), NONE, A::Move(-COARSE, 0), FAR_LEFT, None),
        key(KeyCode::Right, SHIFT, A::Move(COARSE, 0), FAR_RIGHT, None),
        key(ch('L'), NONE, A::Move(COARSE, 0), FAR_RIGHT, None),
        key(KeyCode::Up, SHIFT, A::Move(0, -COARSE), FAR_UP, None),
        key(ch('K'), NONE, A::Move(0, -COARSE), FAR_UP, None),
        key(KeyCode::Down, SHIFT, A::Move(0, COARSE), FAR_DOWN, None),
        key(ch('J'), NONE, A::Move(0, COARSE), FAR_DOWN, None),
        key(
            ch('n'),
            NONE,
            A::Step(1),
            "go to the next landmark (to check or correct it)",
            None,
        ),
        key(
            ch('p'),
            NONE,
            A::Step(-1),
            "go to the previous landmark",
            None,
        ),
        key(
            ch('['),
            NONE,
            A::Turn(-TURN_DEGREES, 0.0),
            "turn the face to show its right side",
            Some("turn"),
        ),
        key(
            ch(']'),
            NONE,
            A::Turn(TURN_DEGREES, 0.0),
            "turn the face to show its left side",
            None,
        ),
        key(
            ch('{'),
            NONE,
            A::Turn(0.0, -TILT_DEGREES),
            "tilt: look from below",
            None,
        ),
        key(
            ch('}'),
            NONE,
            A::Turn(0.0, TILT_DEGREES),
            "tilt: look from above",
            None,
        ),
        key(
            ch('+'),
            NONE,
            A::Zoom(ZOOM_STEP),
            "zoom in about the cursor",
            Some("zoom"),
        ),
        key(
            ch('='),
            NONE,
            A::Zoom(ZOOM_STEP),
            "zoom in about the cursor",
            None,
        ),
        key(ch('-'), NONE, A::Zoom(1.0 / ZOOM_STEP), "zoom out", None),
        key(
            ch('v'),
            NONE,
            A::ResetView,
            "front view of the whole face",
            None,
        ),
        key(
            ch(':'),
            NONE,
            A::Command,
            "a command: :w save, :wq save and quit, :q quit, :q! quit without saving",
            None,
        ),
        key(
            ch('s'),
            CTRL,
            A::Save,
            "save the landmarks (every one needs a vertex)",
            Some("save"),
        ),
        key(ch('?'), NONE, A::Help, "these keys", Some("help")),
        key(
            ch('q'),
            NONE,
            A::Quit,
            "quit (asks when picks are not saved)",
            Some("quit"),
        ),
        key(
            ch('c'),
            CTRL,
            A::Quit,
            "quit (asks when picks are not saved)",
            None,
        ),
    ];
    TABLE
}

/// What the mouse does, for the help.
pub const MOUSE: &[(&str, &str)] = &[
    (
        "click on the mesh",
        "put the cursor there (Enter takes the vertex)",
    ),
    ("wheel", "zoom in and out about the cursor"),
];

/// The action for a key in the picker's mode.
pub fn dispatch(mode: &Mode, key: KeyEvent) -> Option<PickAction> {
    match mode {
        Mode::Normal => find_action(bindings(), key),
        Mode::Command(_) => {
            let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
            Some(match key.code {
                KeyCode::Enter => PickAction::Submit,
                KeyCode::Esc => PickAction::Cancel,
                KeyCode::Char('c') if ctrl => PickAction::Cancel,
                KeyCode::Backspace => PickAction::Backspace,
                KeyCode::Char(c) if !ctrl => PickAction::Input(c),
                _ => return None,
            })
        }
        Mode::Help => Some(PickAction::Cancel),
        Mode::Confirm(_) => match key.code {
            KeyCode::Char('y') | KeyCode::Char('Y') => Some(PickAction::Answer(true)),
            KeyCode::Char('n') | KeyCode::Char('N') | KeyCode::Esc => {
                Some(PickAction::Answer(false))
            }
            _ => None,
        },
    }
}

/// The help's lines: keys doing the same thing share a line.
pub fn help_lines() -> Vec<(String, &'static str)> {
    list_help_lines(bindings())
}

/// The status line's hints (the cursor keys said as one).
pub fn hints() -> Vec<(String, &'static str)> {
    bindings()
        .iter()
        .filter_map(|b| {
            let label = match b.action {
                PickAction::Move(..) => "arrows".to_string(),
                _ => key_label(b.code, b.mods),
            };
            b.hint.map(|h| (label, h))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crossterm::event::KeyEvent;

    #[test]
    fn keys_dispatch_by_mode() {
        let press = |code, mods| KeyEvent::new(code, mods);
        let normal = Mode::Normal;
        assert_eq!(
            dispatch(&normal, press(KeyCode::Enter, NONE)),
            Some(PickAction::Confirm)
        );
        assert_eq!(
            dispatch(&normal, press(ch('L'), SHIFT)),
            Some(PickAction::Move(COARSE, 0))
        );
        assert_eq!(
            dispatch(&normal, press(KeyCode::Up, SHIFT)),
            Some(PickAction::Move(0, -COARSE))
        );
        assert_eq!(
            dispatch(&normal, press(ch(']'), NONE)),
            Some(PickAction::Turn(TURN_DEGREES, 0.0))
        );
        let command = Mode::Command("w".into());
        assert_eq!(
            dispatch(&command, press(ch('q'), NONE)),
            Some(PickAction::Input('q'))
        );
        assert_eq!(
            dispatch(&Mode::Help, press(ch('x'), NONE)),
            Some(PickAction::Cancel)
        );
    }

    #[test]
    fn every_key_is_bound_once_and_described() {
        let table = bindings();
        for (i, a) in table.iter().enumerate() {
            assert!(!a.description.is_empty());
            for b in &table[i + 1..] {
                assert!(
                    !(a.code == b.code && a.mods == b.mods),
                    "{:?} bound twice",
                    a.code
                );
            }
        }
        let help = help_lines();
        assert!(help.iter().any(|(k, _)| k == "Left / h"), "{help:?}");
        assert!(hints().iter().any(|(k, h)| k == "Enter" && *h == "confirm"));
    }
}
