//! The one table of `:` commands. Each entry has its name, aliases, usage, a one-line
//! description, the function that runs it and what completes its argument; running a command
//! line, the `?` help overlay and `Tab` completion all read it, so the three never disagree.

use std::path::PathBuf;

use super::{self as up, edit, prompt, table};
use crate::tui::action::{Action, Effect};
use crate::tui::app::{App, Mode, Row, Style, ViewPreset};

/// A command line split after its command word.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Args<'a> {
    /// Everything after the command word, trimmed (names may contain spaces).
    pub rest: &'a str,
    /// `rest` split at whitespace.
    pub words: Vec<&'a str>,
}

impl<'a> Args<'a> {
    /// The arguments in `rest`.
    pub fn new(rest: &'a str) -> Args<'a> {
        let rest = rest.trim();
        Args {
            rest,
            words: rest.split_whitespace().collect(),
        }
    }

    /// The text after the first word, trimmed (an AU's name after its key).
    fn after_first(&self) -> &'a str {
        match self.words.first() {
            Some(first) => self.rest[first.len()..].trim(),
            None => "",
        }
    }
}

/// What completes a command's first argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Completer {
    /// Nothing (no argument, or a free one: a file name, a number).
    Nothing,
    /// The rig's muscle names and `jaw`.
    Muscles,
    /// The AUs of the table.
    AuKeys,
    /// The expressions of the table.
    Expressions,
    /// A fixed set of words.
    Words(&'static [&'static str]),
}

impl Completer {
    /// The candidates for the argument.
    pub fn candidates(self, app: &App) -> Vec<String> {
        match self {
            Completer::Nothing => Vec::new(),
            Completer::Muscles => muscle_names(app),
            Completer::AuKeys => au_keys(app),
            Completer::Expressions => app.doc.table.expressions.keys().cloned().collect(),
            Completer::Words(words) => words.iter().map(|w| w.to_string()).collect(),
        }
    }
}

/// The rig's muscle names, and `jaw` when it has one.
pub fn muscle_names(app: &App) -> Vec<String> {
    let mut names: Vec<String> = app.rig().muscles.iter().map(|m| m.name.clone()).collect();
    if app.rig().jaw.is_some() {
        names.push("jaw".into());
    }
    names
}

/// The keys of the table's AUs.
pub fn au_keys(app: &App) -> Vec<String> {
    app.doc.table.aus.keys().map(|k| k.to_string()).collect()
}

/// Runs a command with its arguments, pushing the effects it asks for.
pub type Run = fn(&mut App, &Args, &mut Vec<Effect>);

/// One `:` command.
#[derive(Debug, Clone, Copy)]
pub struct Command {
    /// The name typed after `:`.
    pub name: &'static str,
    /// Other names for the same command.
    pub aliases: &'static [&'static str],
    /// The arguments, as shown in help (`N [NAME]`); empty when there are none.
    pub usage: &'static str,
    /// What it does, in one line.
    pub description: &'static str,
    /// Runs it.
    pub run: Run,
    /// What completes its first argument.
    pub completer: Completer,
}

impl Command {
    /// The command's name and its aliases.
    pub fn names(&self) -> impl Iterator<Item = &'static str> {
        std::iter::once(self.name).chain(self.aliases.iter().copied())
    }
}

const VIEWS: &[&str] = &["front", "side", "three-quarter"];
const STYLES: &[&str] = &["lines", "shaded", "wireframe"];

/// Every command, in help order.
pub const COMMANDS: &[Command] = &[
    Command {
        name: "w",
        aliases: &["write"],
        usage: "[FILE]",
        description: "save (to FILE: save as)",
        run: write,
        completer: Completer::Nothing,
    },
    Command {
        name: "wq",
        aliases: &["x"],
        usage: "[FILE]",
        description: "save and quit",
        run: write_quit,
        completer: Completer::Nothing,
    },
    Command {
        name: "q",
        aliases: &["quit"],
        usage: "",
        description: "quit (asks when there are unsaved changes)",
        run: quit,
        completer: Completer::Nothing,
    },
    Command {
        name: "q!",
        aliases: &["quit!"],
        usage: "",
        description: "quit, discarding unsaved changes",
        run: quit_discarding,
        completer: Completer::Nothing,
    },
    Command {
        name: "record",
        aliases: &[],
        usage: "N [NAME]",
        description: "record the current state as AU N (e.g. 12, R12)",
        run: record,
        completer: Completer::AuKeys,
    },
    Command {
        name: "load",
        aliases: &[],
        usage: "N",
        description: "load AU N",
        run: load,
        completer: Completer::AuKeys,
    },
    Command {
        name: "delete",
        aliases: &[],
        usage: "N",
        description: "delete AU N",
        run: delete,
        completer: Completer::AuKeys,
    },
    Command {
        name: "rename",
        aliases: &[],
        usage: "N NAME",
        description: "rename AU N",
        run: rename,
        completer: Completer::AuKeys,
    },
    Command {
        name: "add",
        aliases: &[],
        usage: "N [INTENSITY]",
        description: "add AU N at an intensity (default 1) to the current state",
        run: add,
        completer: Completer::AuKeys,
    },
    Command {
        name: "combo",
        aliases: &[],
        usage: "STR",
        description: "set the state from an AU combination, e.g. 1+2+5B+26",
        run: combo,
        completer: Completer::Nothing,
    },
    Command {
        name: "expr",
        aliases: &[],
        usage: "NAME [COMBO]",
        description: "store an expression, or load it when no combination is given",
        run: expr,
        completer: Completer::Expressions,
    },
    Command {
        name: "import",
        aliases: &[],
        usage: "TABLE",
        description: "add the AUs this table lacks from another (a file, or builtin:default)",
        run: import,
        completer: Completer::Words(&["builtin:default"]),
    },
    Command {
        name: "set",
        aliases: &[],
        usage: "MUSCLE VALUE",
        description: "set a muscle's activation (0-2)",
        run: set,
        completer: Completer::Muscles,
    },
    Command {
        name: "jaw",
        aliases: &[],
        usage: "VALUE",
        description: "set the jaw (0-4)",
        run: jaw,
        completer: Completer::Nothing,
    },
    Command {
        name: "zero",
        aliases: &["reset"],
        usage: "",
        description: "reset every muscle and the jaw",
        run: zero,
        completer: Completer::Nothing,
    },
    Command {
        name: "undo",
        aliases: &[],
        usage: "",
        description: "undo the last edit",
        run: undo,
        completer: Completer::Nothing,
    },
    Command {
        name: "redo",
        aliases: &[],
        usage: "",
        description: "redo the last undone edit",
        run: redo,
        completer: Completer::Nothing,
    },
    Command {
        name: "view",
        aliases: &[],
        usage: "front|side|three-quarter",
        description: "preset views",
        run: view,
        completer: Completer::Words(VIEWS),
    },
    Command {
        name: "style",
        aliases: &[],
        usage: "lines|shaded|wireframe",
        description: "drawing style",
        run: style,
        completer: Completer::Words(STYLES),
    },
    Command {
        name: "help",
        aliases: &[],
        usage: "",
        description: "this help",
        run: help,
        completer: Completer::Nothing,
    },
];

/// The command a name or alias stands for.
pub fn find(name: &str) -> Option<&'static Command> {
    COMMANDS.iter().find(|c| c.names().any(|n| n == name))
}

/// Every name and alias, for completing the command word.
pub fn names() -> Vec<&'static str> {
    COMMANDS.iter().flat_map(Command::names).collect()
}

/// The help overlay's lines for the commands: `:name USAGE` and the description, naming the
/// aliases.
pub fn help_lines() -> Vec<(String, String)> {
    COMMANDS
        .iter()
        .map(|c| {
            let keys = if c.usage.is_empty() {
                format!(":{}", c.name)
            } else {
                format!(":{} {}", c.name, c.usage)
            };
            let description = if c.aliases.is_empty() {
                c.description.to_string()
            } else {
                let aliases: Vec<String> = c.aliases.iter().map(|a| format!(":{a}")).collect();
                format!("{} (also {})", c.description, aliases.join(", "))
            };
            (keys, description)
        })
        .collect()
}

/// Runs a command line (without the `:`).
pub fn run(app: &mut App, line: &str, fx: &mut Vec<Effect>) {
    let line = line.trim();
    let (name, rest) = line.split_once(char::is_whitespace).unwrap_or((line, ""));
    if name.is_empty() {
        return;
    }
    match find(name) {
        Some(command) => (command.run)(app, &Args::new(rest), fx),
        None => app.error(format!("unknown command `{name}` (? lists the commands)")),
    }
}

/// The completions of the word being typed on a command line: command names for the first
/// word, the command's completer for the second.
pub fn candidates(app: &App, before: &str) -> Vec<String> {
    let words: Vec<&str> = before.split(' ').collect();
    match words.as_slice() {
        [_] => names().into_iter().map(str::to_string).collect(),
        [command, _] => find(command).map_or(Vec::new(), |c| c.completer.candidates(app)),
        _ => Vec::new(),
    }
}

fn path_arg(args: &Args) -> Option<PathBuf> {
    (!args.rest.is_empty()).then(|| PathBuf::from(args.rest))
}

fn write(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    if app.rig_edit.on {
        return crate::tui::rig::save(app, path_arg(args), fx);
    }
    table::save(app, path_arg(args), false, fx);
}

fn write_quit(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    if app.rig_edit.dirty(app.rig()) {
        return app.error(crate::tui::rig::UNSAVED_RIG);
    }
    table::save(app, path_arg(args), true, fx);
}

fn quit(app: &mut App, _: &Args, fx: &mut Vec<Effect>) {
    table::quit(app, fx);
}

fn quit_discarding(_: &mut App, _: &Args, fx: &mut Vec<Effect>) {
    fx.push(Effect::RemoveRecovery);
    fx.push(Effect::Quit);
}

fn record(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    let Some(k) = args.words.first() else {
        return app.error("usage: :record N [NAME], e.g. :record 12 or :record R12");
    };
    if let Some(key) = prompt::parse_key(app, k) {
        let name = match args.after_first() {
            "" => table::suggested_name(app, key),
            name => name.to_string(),
        };
        table::record_or_ask(app, key, &name, fx);
    }
}

fn load(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    match args.words.as_slice() {
        [k] => {
            if let Some(key) = prompt::parse_key(app, k) {
                table::load_au(app, key, fx);
            }
        }
        _ => app.error("usage: :load N"),
    }
}

fn delete(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    match args.words.as_slice() {
        [k] => {
            if let Some(key) = prompt::parse_key(app, k) {
                table::delete_au(app, key, fx);
            }
        }
        _ => app.error("usage: :delete N"),
    }
}

fn rename(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    match args.words.first() {
        Some(k) if args.words.len() >= 2 => {
            if let Some(key) = prompt::parse_key(app, k) {
                table::rename(app, key, args.after_first(), fx);
            }
        }
        _ => app.error("usage: :rename N NAME"),
    }
}

fn add(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    match args.words.as_slice() {
        [what] | [what, _] => {
            let intensity = args
                .words
                .get(1)
                .map_or(Some(1.0), |w| prompt::parse_value(app, w));
            if let Some(i) = intensity {
                table::add_au(app, what, i, fx);
            }
        }
        _ => app.error("usage: :add N [INTENSITY], e.g. :add 12 0.5"),
    }
}

fn combo(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    match args.words.as_slice() {
        [combo] => table::set_combo(app, combo, fx),
        _ => app.error("usage: :combo STR, e.g. :combo 1+2+5B+26"),
    }
}

fn expr(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    match args.words.as_slice() {
        [name] => table::load_expression(app, name, fx),
        [name, combo] => table::store_expression(app, name, combo, fx),
        _ => app.error("usage: :expr NAME [COMBO], e.g. :expr smile 6+12"),
    }
}

fn import(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    if args.rest.is_empty() {
        return app.error("usage: :import TABLE, e.g. :import builtin:default");
    }
    fx.push(Effect::ReadTable(PathBuf::from(args.rest)));
}

fn set(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    match args.words.as_slice() {
        [name, value] => match prompt::row_by_name(app, name) {
            Some(row) => {
                if let Some(v) = prompt::parse_value(app, value) {
                    edit::set_from_command(app, row, v, fx);
                }
            }
            None => app.error(format!(
                "the rig has no muscle named `{name}` (Tab completes)"
            )),
        },
        _ => app.error("usage: :set MUSCLE VALUE, e.g. :set L_Zygomatic_Major 0.8"),
    }
}

fn jaw(app: &mut App, args: &Args, fx: &mut Vec<Effect>) {
    match args.words.as_slice() {
        [value] if app.selection.rows.contains(&Row::Jaw) => {
            if let Some(v) = prompt::parse_value(app, value) {
                edit::set_from_command(app, Row::Jaw, v, fx);
            }
        }
        [_] => app.error("this rig has no jaw"),
        _ => app.error("usage: :jaw VALUE (0 to 4)"),
    }
}

fn zero(app: &mut App, _: &Args, fx: &mut Vec<Effect>) {
    fx.extend(up::update(app, Action::ResetAll));
}

fn undo(app: &mut App, _: &Args, fx: &mut Vec<Effect>) {
    edit::undo(app, fx);
}

fn redo(app: &mut App, _: &Args, fx: &mut Vec<Effect>) {
    edit::redo(app, fx);
}

fn view(app: &mut App, args: &Args, _: &mut Vec<Effect>) {
    let preset = match args.rest {
        "front" => ViewPreset::Front,
        "side" => ViewPreset::Side,
        "three-quarter" | "3/4" => ViewPreset::ThreeQuarter,
        _ => return app.error("usage: :view front|side|three-quarter"),
    };
    app.view.preset(preset);
    app.info(format!("view: {}", args.rest));
}

fn style(app: &mut App, args: &Args, _: &mut Vec<Effect>) {
    app.view.style = match args.rest {
        "lines" => Style::Lines,
        "shaded" => Style::Shaded,
        "wireframe" => Style::Wireframe,
        _ => return app.error("usage: :style lines|shaded|wireframe"),
    };
    app.info(format!("style: {}", args.rest));
}

fn help(app: &mut App, _: &Args, _: &mut Vec<Effect>) {
    app.mode = Mode::Help(0);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tui::app::{InputKind, Message, Severity};
    use crate::tui::view::help;

    /// Every name and alias users can type, written out independently of the table.
    const EXPECTED: &[&str] = &[
        "w", "write", "wq", "x", "q", "quit", "q!", "quit!", "record", "load", "delete", "rename",
        "add", "combo", "expr", "set", "jaw", "zero", "reset", "undo", "redo", "view", "style",
        "help", "import",
    ];

    fn app() -> App {
        crate::tui::fixture::app()
    }

    /// The text on the command line after typing `text` and pressing Tab.
    fn completed(text: &str) -> String {
        let mut app = app();
        up::update(&mut app, Action::StartCommand);
        for c in text.chars() {
            up::update(&mut app, Action::InputChar(c));
        }
        up::update(&mut app, Action::InputComplete);
        match &app.mode {
            Mode::Input(input) if input.kind == InputKind::Command => input.text.clone(),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn the_table_holds_exactly_the_expected_names_once_each() {
        let names = names();
        for name in EXPECTED {
            assert_eq!(
                names.iter().filter(|n| *n == name).count(),
                1,
                ":{name} should be in the table once"
            );
        }
        for name in &names {
            assert!(EXPECTED.contains(name), ":{name} is not in EXPECTED");
        }
    }

    #[test]
    fn every_command_runs_shows_in_help_and_completes() {
        let help: Vec<(String, String)> = help::lines()
            .into_iter()
            .filter(|(_, _, heading)| !heading)
            .map(|(keys, description, _)| (keys, description))
            .collect();
        for &name in EXPECTED {
            // Runs: anything but "unknown command".
            let mut app = app();
            up::update(&mut app, Action::Command(name.into()));
            if let Some(Message {
                text,
                severity: Severity::Error,
            }) = &app.message
            {
                assert!(!text.starts_with("unknown command"), ":{name}: {text}");
            }
            // Shown in the help overlay, as the command or as an alias of one.
            let key = format!(":{name}");
            let shown = help.iter().any(|(keys, description)| {
                keys.split(' ').next() == Some(key.as_str())
                    || description.split([' ', ',', ')']).any(|w| w == key)
            });
            assert!(shown, ":{name} missing from the help overlay");
            // Completed from its first letters.
            let prefix: String = name.chars().take(name.chars().count() - 1).collect();
            assert!(
                candidates(&app, &prefix).iter().any(|c| c == name),
                ":{name} does not complete from `{prefix}`"
            );
        }
        assert_eq!(completed("wri"), "write ");
        assert_eq!(completed("res"), "reset ");
        assert_eq!(completed("quit"), "quit");
    }

    #[test]
    fn arguments_complete_from_the_commands_completer() {
        let app = app();
        assert_eq!(
            candidates(&app, "view "),
            ["front", "side", "three-quarter"]
        );
        assert_eq!(candidates(&app, "load "), au_keys(&app));
        assert_eq!(candidates(&app, "set "), muscle_names(&app));
        assert!(candidates(&app, "jaw ").is_empty());
        assert!(candidates(&app, "nosuch ").is_empty());
        assert!(candidates(&app, "set a b").is_empty());
    }

    #[test]
    fn unknown_commands_are_named() {
        let mut app = app();
        up::update(&mut app, Action::Command("frobnicate 3".into()));
        assert_eq!(
            app.message.unwrap().text,
            "unknown command `frobnicate` (? lists the commands)"
        );
    }
}
