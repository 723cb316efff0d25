//! The one table of key bindings. It drives dispatch, the `?` help overlay and the status
//! line hints, so the three never disagree.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use super::action::Action;
use super::action::RigAction;
use super::app::{App, Mode, ViewPreset};

/// One key binding in normal mode.
#[derive(Debug, Clone)]
pub struct Binding {
    /// The key.
    pub code: KeyCode,
    /// Modifiers that must be held (Shift is implied by upper-case letters and ignored).
    pub mods: KeyModifiers,
    /// What it does.
    pub action: Action,
    /// Said in the help overlay.
    pub description: &'static str,
    /// The help overlay's section.
    pub section: &'static str,
    /// A short hint for the status line, for the most useful keys.
    pub hint: Option<&'static str>,
}

const NONE: KeyModifiers = KeyModifiers::NONE;
const CTRL: KeyModifiers = KeyModifiers::CONTROL;

const fn bind(
    code: KeyCode,
    mods: KeyModifiers,
    action: Action,
    section: &'static str,
    description: &'static str,
    hint: Option<&'static str>,
) -> Binding {
    Binding {
        code,
        mods,
        action,
        description,
        section,
        hint,
    }
}

const fn ch(c: char) -> KeyCode {
    KeyCode::Char(c)
}

/// Every normal-mode binding, in help order.
pub fn bindings() -> &'static [Binding] {
    use Action as A;
    static TABLE: &[Binding] = &[
        bind(
            ch('j'),
            NONE,
            A::SelectNext,
            "select",
            "next muscle (or AU)",
            Some("select"),
        ),
        bind(
            KeyCode::Down,
            NONE,
            A::SelectNext,
            "select",
            "next muscle (or AU)",
            None,
        ),
        bind(
            ch('k'),
            NONE,
            A::SelectPrev,
            "select",
            "previous muscle (or AU)",
            None,
        ),
        bind(
            KeyCode::Up,
            NONE,
            A::SelectPrev,
            "select",
            "previous muscle (or AU)",
            None,
        ),
        bind(ch('g'), NONE, A::SelectFirst, "select", "first line", None),
        bind(ch('G'), NONE, A::SelectLast, "select", "last line", None),
        bind(
            ch('/'),
            NONE,
            A::StartFind,
            "select",
            "find a muscle by name",
            Some("find"),
        ),
        bind(
            KeyCode::Tab,
            NONE,
            A::SwitchFocus,
            "select",
            "switch between muscles and AU table",
            Some("table"),
        ),
        bind(
            ch('l'),
            NONE,
            A::StepFine(1),
            "adjust",
            "increase by a fine step (0.05)",
            Some("adjust"),
        ),
        bind(
            KeyCode::Right,
            NONE,
            A::StepFine(1),
            "adjust",
            "increase by a fine step",
            None,
        ),
        bind(
            ch('h'),
            NONE,
            A::StepFine(-1),
            "adjust",
            "decrease by a fine step",
            None,
        ),
        bind(
            KeyCode::Left,
            NONE,
            A::StepFine(-1),
            "adjust",
            "decrease by a fine step",
            None,
        ),
        bind(
            ch('L'),
            NONE,
            A::StepCoarse(1),
            "adjust",
            "increase by a coarse step (0.25; jaw 0.5)",
            None,
        ),
        bind(
            ch('H'),
            NONE,
            A::StepCoarse(-1),
            "adjust",
            "decrease by a coarse step",
            None,
        ),
        bind(
            ch('='),
            NONE,
            A::StartSetValue,
            "adjust",
            "type an exact value",
            None,
        ),
        bind(
            ch('0'),
            NONE,
            A::ZeroSelected,
            "adjust",
            "zero the selected muscle",
            None,
        ),
        bind(
            ch('X'),
            NONE,
            A::ResetAll,
            "adjust",
            "reset every muscle and the jaw to zero",
            None,
        ),
        bind(
            ch('m'),
            NONE,
            A::ToggleMirror,
            "adjust",
            "mirror mode: move left/right pairs together",
            Some("mirror"),
        ),
        bind(ch('u'), NONE, A::Undo, "adjust", "undo", Some("undo")),
        bind(ch('r'), CTRL, A::Redo, "adjust", "redo", None),
        bind(ch('U'), NONE, A::Redo, "adjust", "redo", None),
        bind(
            ch('r'),
            NONE,
            A::StartRecord,
            "AU table",
            "record the current state as an AU",
            Some("record"),
        ),
        bind(
            KeyCode::Enter,
            NONE,
            A::Activate,
            "AU table",
            "load the selected AU or expression (muscles: type a value)",
            None,
        ),
        bind(
            ch('w'),
            NONE,
            A::OverwriteSelected,
            "AU table",
            "overwrite the selected AU with the current state",
            None,
        ),
        bind(
            ch('d'),
            NONE,
            A::DeleteSelected,
            "AU table",
            "delete the selected AU or expression",
            None,
        ),
        bind(
            ch('n'),
            NONE,
            A::RenameSelected,
            "AU table",
            "rename the selected AU",
            None,
        ),
        bind(
            ch('a'),
            NONE,
            A::StartAddAu,
            "AU table",
            "add an AU at an intensity to the current state",
            None,
        ),
        bind(
            ch('e'),
            NONE,
            A::StartExpression,
            "AU table",
            "store a combination as a named expression",
            None,
        ),
        bind(
            ch('['),
            NONE,
            A::Rotate(-15.0, 0.0),
            "view",
            "turn left",
            None,
        ),
        bind(
            ch(']'),
            NONE,
            A::Rotate(15.0, 0.0),
            "view",
            "turn right",
            None,
        ),
        bind(
            ch('{'),
            NONE,
            A::Rotate(0.0, -10.0),
            "view",
            "tilt down",
            None,
        ),
        bind(ch('}'), NONE, A::Rotate(0.0, 10.0), "view", "tilt up", None),
        bind(ch('+'), NONE, A::Zoom(1.25), "view", "zoom in", None),
        bind(ch('-'), NONE, A::Zoom(0.8), "view", "zoom out", None),
        bind(
            KeyCode::Left,
            CTRL,
            A::Pan(-0.1, 0.0),
            "view",
            "pan left",
            None,
        ),
        bind(
            KeyCode::Right,
            CTRL,
            A::Pan(0.1, 0.0),
            "view",
            "pan right",
            None,
        ),
        bind(KeyCode::Up, CTRL, A::Pan(0.0, 0.1), "view", "pan up", None),
        bind(
            KeyCode::Down,
            CTRL,
            A::Pan(0.0, -0.1),
            "view",
            "pan down",
            None,
        ),
        bind(ch('v'), NONE, A::ResetView, "view", "reset the view", None),
        bind(
            ch('1'),
            NONE,
            A::Preset(ViewPreset::Front),
            "view",
            "front view",
            None,
        ),
        bind(
            ch('2'),
            NONE,
            A::Preset(ViewPreset::Side),
            "view",
            "side view",
            None,
        ),
        bind(
            ch('3'),
            NONE,
            A::Preset(ViewPreset::ThreeQuarter),
            "view",
            "three-quarter view",
            None,
        ),
        bind(
            ch('s'),
            NONE,
            A::CycleStyle,
            "view",
            "next style: lines, shaded, wireframe",
            Some("style"),
        ),
        bind(
            ch('c'),
            NONE,
            A::CycleCells,
            "view",
            "next cells: braille, half-block colour, ASCII",
            None,
        ),
        bind(
            ch('A'),
            NONE,
            A::ToggleAscii,
            "view",
            "ASCII mode on/off",
            None,
        ),
        bind(
            ch('M'),
            NONE,
            A::ToggleMuscles,
            "view",
            "show the muscles",
            None,
        ),
        bind(
            ch('R'),
            NONE,
            A::Rig(RigAction::Toggle),
            "view",
            "rig mode: place the selected muscle",
            Some("rig"),
        ),
        bind(
            ch('o'),
            NONE,
            A::ToggleGhost,
            "view",
            "show the rest pose as a ghost",
            None,
        ),
        bind(
            ch('D'),
            NONE,
            A::ToggleDisplacement,
            "view",
            "colour edges by displacement",
            None,
        ),
        bind(
            ch(':'),
            NONE,
            A::StartCommand,
            "file",
            "command line (:w, :q, :record ...)",
            Some("cmd"),
        ),
        bind(ch('s'), CTRL, A::Save, "file", "save", Some("save")),
        bind(
            ch('q'),
            NONE,
            A::Quit,
            "file",
            "quit (asks when there are unsaved changes)",
            Some("quit"),
        ),
        bind(
            ch('c'),
            CTRL,
            A::Quit,
            "file",
            "quit (asks when there are unsaved changes)",
            None,
        ),
        bind(
            ch('?'),
            NONE,
            A::ToggleHelp,
            "file",
            "this help",
            Some("help"),
        ),
    ];
    TABLE
}

const SHIFT: KeyModifiers = KeyModifiers::SHIFT;

const fn rig_move(right: i8, up: i8, coarse: bool) -> Action {
    Action::Rig(RigAction::Move { right, up, coarse })
}

/// Rig mode's own keys: looked up before the normal ones while rig mode is on, so they win
/// where both bind a key (Tab, arrows, h/l, u); every other normal key still works.
pub fn rig_bindings() -> &'static [Binding] {
    use RigAction as R;
    const SECTION: &str = "rig mode (R)";
    static TABLE: &[Binding] = &[
        bind(
            ch('R'),
            NONE,
            Action::Rig(R::Toggle),
            SECTION,
            "leave rig mode",
            Some("leave"),
        ),
        bind(
            KeyCode::Esc,
            NONE,
            Action::Rig(R::Toggle),
            SECTION,
            "leave rig mode",
            None,
        ),
        bind(
            KeyCode::Tab,
            NONE,
            Action::Rig(R::NextPoint),
            SECTION,
            "next point: attachment, insertion, centre, sheet line ends, jaw pivot",
            Some("point"),
        ),
        bind(
            KeyCode::Left,
            NONE,
            rig_move(-1, 0, false),
            SECTION,
            "move the point left in the view (fine)",
            Some("move"),
        ),
        bind(
            KeyCode::Right,
            NONE,
            rig_move(1, 0, false),
            SECTION,
            "move the point right in the view (fine)",
            None,
        ),
        bind(
            KeyCode::Up,
            NONE,
            rig_move(0, 1, false),
            SECTION,
            "move the point up in the view (fine)",
            None,
        ),
        bind(
            KeyCode::Down,
            NONE,
            rig_move(0, -1, false),
            SECTION,
            "move the point down in the view (fine)",
            None,
        ),
        bind(
            KeyCode::Left,
            SHIFT,
            rig_move(-1, 0, true),
            SECTION,
            "move the point left (coarse)",
            None,
        ),
        bind(
            KeyCode::Right,
            SHIFT,
            rig_move(1, 0, true),
            SECTION,
            "move the point right (coarse)",
            None,
        ),
        bind(
            KeyCode::Up,
            SHIFT,
            rig_move(0, 1, true),
            SECTION,
            "move the point up (coarse)",
            None,
        ),
        bind(
            KeyCode::Down,
            SHIFT,
            rig_move(0, -1, true),
            SECTION,
            "move the point down (coarse)",
            None,
        ),
        bind(
            ch('p'),
            NONE,
            Action::Rig(R::NextParam),
            SECTION,
            "next parameter: zone, falloff; semi-axes, bulge, frame angle; length, width; jaw degrees per unit, axis angle",
            Some("param"),
        ),
        bind(
            ch('l'),
            NONE,
            Action::Rig(R::Param {
                by: 1,
                coarse: false,
            }),
            SECTION,
            "increase the parameter, or turn it counter-clockwise (fine)",
            Some("change"),
        ),
        bind(
            ch('h'),
            NONE,
            Action::Rig(R::Param {
                by: -1,
                coarse: false,
            }),
            SECTION,
            "decrease the parameter (fine)",
            None,
        ),
        bind(
            ch('L'),
            NONE,
            Action::Rig(R::Param {
                by: 1,
                coarse: true,
            }),
            SECTION,
            "increase the parameter (coarse)",
            None,
        ),
        bind(
            ch('H'),
            NONE,
            Action::Rig(R::Param {
                by: -1,
                coarse: true,
            }),
            SECTION,
            "decrease the parameter (coarse)",
            None,
        ),
        bind(
            ch('>'),
            NONE,
            Action::Rig(R::Held(1)),
            SECTION,
            "hold the muscle at a higher activation",
            None,
        ),
        bind(
            ch('<'),
            NONE,
            Action::Rig(R::Held(-1)),
            SECTION,
            "hold the muscle at a lower activation",
            None,
        ),
        bind(
            ch('u'),
            NONE,
            Action::Undo,
            SECTION,
            "undo the last edit, a rig change or an activation, in the order made",
            Some("undo"),
        ),
        bind(
            ch('U'),
            NONE,
            Action::Redo,
            SECTION,
            "redo the last undone edit",
            None,
        ),
        bind(
            ch('r'),
            CTRL,
            Action::Redo,
            SECTION,
            "redo the last undone edit",
            None,
        ),
    ];
    TABLE
}

/// The keys of the input line, the help overlay and questions, for the help overlay.
pub const OTHER_KEYS: &[(&str, &str)] = &[
    (
        "Tab",
        "complete a muscle name, AU number or command (input line)",
    ),
    ("Enter / Esc", "accept / cancel the input line"),
    ("Ctrl-u", "clear the input line before the cursor"),
    ("y / n", "answer a question (Esc = no)"),
];

/// What the mouse does, for the help overlay.
pub const MOUSE: &[(&str, &str)] = &[
    ("click", "select a muscle row, AU or expression"),
    ("wheel on a muscle", "adjust it by a fine step"),
    ("wheel on the face", "zoom"),
    ("wheel on the table", "move the selection"),
    ("drag on the face", "turn and tilt the view"),
];

/// What a key does in `grimace play`'s viewer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlayKey {
    /// Leave the viewer.
    Quit,
    /// Pause or resume.
    Pause,
    /// Show the next frame and pause there.
    Step,
    /// Double the speed.
    Faster,
    /// Halve the speed.
    Slower,
}

/// One key of a viewer whose help is one list (the play viewer, the landmark picker): the
/// key, what it does, and what the help and the status line say about it.
#[derive(Debug, Clone, Copy)]
pub struct KeyBinding<A> {
    /// The key.
    pub code: KeyCode,
    /// Modifiers that must be held (Shift is part of upper-case letters).
    pub mods: KeyModifiers,
    /// What it does.
    pub action: A,
    /// Said in the help.
    pub description: &'static str,
    /// Said in the status line, for the first key of each action that has one.
    pub hint: Option<&'static str>,
}

/// A [`KeyBinding`], for writing key tables.
pub(crate) const fn key_binding<A>(
    code: KeyCode,
    mods: KeyModifiers,
    action: A,
    description: &'static str,
    hint: Option<&'static str>,
) -> KeyBinding<A> {
    KeyBinding {
        code,
        mods,
        action,
        description,
        hint,
    }
}

/// The action a table binds to a key press, if any.
pub(crate) fn find_action<A: Clone>(table: &[KeyBinding<A>], key: KeyEvent) -> Option<A> {
    let mods = significant(key);
    table
        .iter()
        .find(|b| b.code == key.code && b.mods == mods)
        .map(|b| b.action.clone())
}

/// A table's help: keys doing the same thing share a line.
pub(crate) fn list_help_lines<A>(table: &[KeyBinding<A>]) -> Vec<(String, &'static str)> {
    let mut lines: Vec<(String, &'static str)> = Vec::new();
    for b in table {
        let label = key_label(b.code, b.mods);
        match lines.iter_mut().find(|(_, d)| *d == b.description) {
            Some(line) => {
                line.0.push_str(" / ");
                line.0.push_str(&label);
            }
            None => lines.push((label, b.description)),
        }
    }
    lines
}

/// One key binding of the play viewer.
pub type PlayBinding = KeyBinding<PlayKey>;

use key_binding as play;

/// Every key of the play viewer, in help order.
pub const PLAY_BINDINGS: &[PlayBinding] = &[
    play(
        ch(' '),
        NONE,
        PlayKey::Pause,
        "pause / resume",
        Some("pause"),
    ),
    play(
        ch('.'),
        NONE,
        PlayKey::Step,
        "step one frame (pauses)",
        Some("step"),
    ),
    play(
        ch('n'),
        NONE,
        PlayKey::Step,
        "step one frame (pauses)",
        None,
    ),
    play(
        KeyCode::Right,
        NONE,
        PlayKey::Step,
        "step one frame (pauses)",
        None,
    ),
    play(ch('+'), NONE, PlayKey::Faster, "speed x2", Some("faster")),
    play(ch('='), NONE, PlayKey::Faster, "speed x2", None),
    play(KeyCode::Up, NONE, PlayKey::Faster, "speed x2", None),
    play(ch('-'), NONE, PlayKey::Slower, "speed /2", Some("slower")),
    play(ch('_'), NONE, PlayKey::Slower, "speed /2", None),
    play(KeyCode::Down, NONE, PlayKey::Slower, "speed /2", None),
    play(ch('q'), NONE, PlayKey::Quit, "quit", Some("quit")),
    play(KeyCode::Esc, NONE, PlayKey::Quit, "quit", None),
    play(ch('c'), CTRL, PlayKey::Quit, "quit", None),
];

/// The play viewer's action for a key press, if any.
pub fn play_dispatch(key: KeyEvent) -> Option<PlayKey> {
    find_action(PLAY_BINDINGS, key)
}

/// The play viewer's keys for `--help`: keys doing the same thing share a line.
pub fn play_help_lines() -> Vec<(String, &'static str)> {
    list_help_lines(PLAY_BINDINGS)
}

/// The play viewer's status line hints: `key hint` for the bindings that have one.
pub fn play_hints() -> String {
    PLAY_BINDINGS
        .iter()
        .filter_map(|b| b.hint.map(|h| format!("{} {h}", key_label(b.code, b.mods))))
        .collect::<Vec<_>>()
        .join("   ")
}

/// The action for a key press in the given mode, if any.
pub fn dispatch(mode: &Mode, key: KeyEvent) -> Option<Action> {
    match mode {
        Mode::Normal => normal(key),
        Mode::Input(_) => input(key),
        Mode::Help(_) => match key.code {
            KeyCode::Char('j') | KeyCode::Down => Some(Action::HelpScroll(1)),
            KeyCode::Char('k') | KeyCode::Up => Some(Action::HelpScroll(-1)),
            KeyCode::PageDown | KeyCode::Char(' ') => Some(Action::HelpScroll(10)),
            KeyCode::PageUp => Some(Action::HelpScroll(-10)),
            _ => Some(Action::Cancel),
        },
        Mode::Confirm(_) => match key.code {
            KeyCode::Char('y') | KeyCode::Char('Y') => Some(Action::Answer(true)),
            KeyCode::Char('n') | KeyCode::Char('N') | KeyCode::Esc => Some(Action::Answer(false)),
            _ => None,
        },
    }
}

/// The action for a key press in the editor's current mode: rig mode's keys first while it
/// is on, then [`dispatch`].
pub fn dispatch_for(app: &App, key: KeyEvent) -> Option<Action> {
    if app.rig_edit.on && app.mode == Mode::Normal {
        let mods = significant(key);
        if let Some(b) = rig_bindings()
            .iter()
            .find(|b| b.code == key.code && b.mods == mods)
        {
            return Some(b.action.clone());
        }
    }
    dispatch(&app.mode, key)
}

fn normal(key: KeyEvent) -> Option<Action> {
    let mods = significant(key);
    bindings()
        .iter()
        .find(|b| b.code == key.code && b.mods == mods)
        .map(|b| b.action.clone())
}

/// The modifiers that matter: Shift is part of the character for printable keys.
pub(crate) fn significant(key: KeyEvent) -> KeyModifiers {
    let mut mods =
        key.modifiers & (KeyModifiers::CONTROL | KeyModifiers::ALT | KeyModifiers::SHIFT);
    if matches!(key.code, KeyCode::Char(_)) {
        mods.remove(KeyModifiers::SHIFT);
    }
    mods
}

fn input(key: KeyEvent) -> Option<Action> {
    let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
    Some(match key.code {
        KeyCode::Enter => Action::InputSubmit,
        KeyCode::Esc => Action::Cancel,
        KeyCode::Char('c') if ctrl => Action::Cancel,
        KeyCode::Char('a') if ctrl => Action::InputHome,
        KeyCode::Char('e') if ctrl => Action::InputEnd,
        KeyCode::Char('u') if ctrl => Action::InputClear,
        KeyCode::Char('h') if ctrl => Action::InputBackspace,
        KeyCode::Char(c) if !ctrl => Action::InputChar(c),
        KeyCode::Backspace => Action::InputBackspace,
        KeyCode::Delete => Action::InputDelete,
        KeyCode::Left => Action::InputLeft,
        KeyCode::Right => Action::InputRight,
        KeyCode::Home => Action::InputHome,
        KeyCode::End => Action::InputEnd,
        KeyCode::Tab => Action::InputComplete,
        _ => return None,
    })
}

/// How a key is written in the help overlay.
pub fn key_label(code: KeyCode, mods: KeyModifiers) -> String {
    let base = match code {
        KeyCode::Char(' ') => "Space".to_string(),
        KeyCode::Char(c) => c.to_string(),
        KeyCode::Up => "Up".into(),
        KeyCode::Down => "Down".into(),
        KeyCode::Left => "Left".into(),
        KeyCode::Right => "Right".into(),
        KeyCode::Enter => "Enter".into(),
        KeyCode::Tab => "Tab".into(),
        KeyCode::Esc => "Esc".into(),
        other => format!("{other:?}"),
    };
    if mods.contains(KeyModifiers::CONTROL) {
        format!("Ctrl-{base}")
    } else if mods.contains(KeyModifiers::SHIFT) {
        format!("Shift-{base}")
    } else {
        base
    }
}

/// The help overlay's lines for the bindings: keys doing the same thing share a line.
pub fn help_lines() -> Vec<(String, String, &'static str)> {
    let mut lines: Vec<(String, String, &'static str)> = Vec::new();
    for b in bindings().iter().chain(rig_bindings()) {
        let label = key_label(b.code, b.mods);
        match lines
            .iter_mut()
            .find(|(_, desc, section)| desc == b.description && *section == b.section)
        {
            Some(line) => {
                line.0.push_str(" / ");
                line.0.push_str(&label);
            }
            None => lines.push((label, b.description.to_string(), b.section)),
        }
    }
    lines
}

/// The status line hints: `key hint` for the bindings that have one.
pub fn hints() -> Vec<(String, &'static str)> {
    hints_of(bindings())
}

/// The status line hints for the editor's state: rig mode's own while it is on.
pub fn hints_for(app: &App) -> Vec<(String, &'static str)> {
    if app.rig_edit.on {
        let mut hints = hints_of(rig_bindings());
        hints.push((":w".into(), "save rig"));
        hints
    } else {
        hints()
    }
}

fn hints_of(table: &[Binding]) -> Vec<(String, &'static str)> {
    table
        .iter()
        .filter_map(|b| b.hint.map(|h| (key_label(b.code, b.mods), h)))
        .collect()
}

#[cfg(test)]
mod tests;
