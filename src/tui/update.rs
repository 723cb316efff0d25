//! `update`: the only place the editor's state changes. Pure: no input or output; what needs
//! doing outside (saving, quitting, the recovery file) comes back as [`Effect`]s.

use std::path::PathBuf;

use crate::facs::AuKey;
use crate::model::Activations;

use super::action::{Action, Effect};
use super::app::{
    App, CellMode, Focus, Input, InputKind, Mode, Question, Row, Style, TableItem, ViewPreset,
    COARSE_STEP, FINE_STEP,
};
use super::keymap::COMMAND_NAMES;
use super::table_ops;

/// Applies one action to the state and returns the effects to run.
pub fn update(app: &mut App, action: Action) -> Vec<Effect> {
    let mut fx = Vec::new();
    if !matches!(action, Action::StepFine(_) | Action::StepCoarse(_)) {
        app.last_step = None;
    }
    match action {
        Action::SelectNext => move_selection(app, 1),
        Action::SelectPrev => move_selection(app, -1),
        Action::SelectFirst => move_selection(app, i64::MIN / 2),
        Action::SelectLast => move_selection(app, i64::MAX / 2),
        Action::SelectRow(row) => {
            if let Some(i) = app.rows.iter().position(|&r| r == row) {
                app.selected = i;
                app.focus = Focus::Muscles;
            }
        }
        Action::SelectTableItem(i) => {
            if i < app.table_items().len() {
                app.table_selected = i;
                app.focus = Focus::Table;
            }
        }
        Action::SwitchFocus => {
            app.focus = match app.focus {
                Focus::Muscles => Focus::Table,
                Focus::Table => Focus::Muscles,
            };
        }
        Action::StartFind => open(app, InputKind::Find, ""),
        Action::StepFine(n) => step(app, f32::from(n) * FINE_STEP, &mut fx),
        Action::StepCoarse(n) => step(app, f32::from(n) * COARSE_STEP, &mut fx),
        Action::StartSetValue => {
            let value = format_value(app.value(app.selected_row()));
            open(app, InputKind::Value, value);
        }
        Action::ZeroSelected => {
            let row = app.selected_row();
            set_rows(app, row, 0.0, &mut fx);
        }
        Action::ResetAll => {
            if app.activations.is_rest() {
                app.info("already at rest");
            } else {
                let rest = Activations::zero(app.rig());
                replace_activations(app, rest, None, &mut fx);
                app.info("every muscle and the jaw reset to zero");
            }
        }
        Action::ToggleMirror => {
            app.mirror = !app.mirror;
            let state = if app.mirror {
                "on: left/right pairs move together"
            } else {
                "off"
            };
            app.info(format!("mirror mode {state}"));
        }
        Action::StartRecord => {
            let suggestion = match selected_item(app) {
                Some(TableItem::Au(key)) if app.focus == Focus::Table => key.to_string(),
                _ => String::new(),
            };
            open(app, InputKind::RecordKey, suggestion);
        }
        Action::Activate => activate(app, &mut fx),
        Action::OverwriteSelected => match selected_item(app) {
            Some(TableItem::Au(key)) => {
                let name = app
                    .table
                    .aus
                    .get(&key)
                    .map(|e| e.name.clone())
                    .unwrap_or_default();
                app.mode = Mode::Confirm(Question::OverwriteAu { key, name });
            }
            _ => app.error("select an AU in the table first (Tab switches to the table)"),
        },
        Action::DeleteSelected => match selected_item(app) {
            Some(TableItem::Au(key)) => app.mode = Mode::Confirm(Question::DeleteAu(key)),
            Some(TableItem::Expression(name)) => delete_expression(app, &name, &mut fx),
            None => app.error("the table is empty: nothing to delete"),
        },
        Action::RenameSelected => match selected_item(app) {
            Some(TableItem::Au(key)) => {
                let name = app
                    .table
                    .aus
                    .get(&key)
                    .map(|e| e.name.clone())
                    .unwrap_or_default();
                open(app, InputKind::Rename(key), name);
            }
            Some(TableItem::Expression(_)) => {
                app.error("expressions are renamed by storing them again: :expr NAME COMBO")
            }
            None => app.error("select an AU in the table first (Tab switches to the table)"),
        },
        Action::StartAddAu => {
            let suggestion = match selected_item(app) {
                Some(TableItem::Au(key)) => format!("{key} "),
                _ => String::new(),
            };
            open(app, InputKind::AddAu, suggestion);
        }
        Action::StartExpression => open(app, InputKind::ExpressionName, ""),
        Action::Rotate(yaw, pitch) => {
            app.view.yaw = wrap_degrees(app.view.yaw + yaw);
            app.view.pitch = (app.view.pitch + pitch).clamp(-89.0, 89.0);
        }
        Action::Zoom(factor) => {
            if factor.is_finite() && factor > 0.0 {
                app.view.zoom = (app.view.zoom * factor).clamp(0.25, 8.0);
            }
        }
        Action::Pan(dx, dy) => {
            app.view.pan.0 = (app.view.pan.0 + dx).clamp(-1.0, 1.0);
            app.view.pan.1 = (app.view.pan.1 + dy).clamp(-1.0, 1.0);
        }
        Action::ResetView => app.view.preset(ViewPreset::Front),
        Action::Preset(preset) => app.view.preset(preset),
        Action::CycleStyle => {
            app.view.style = app.view.style.next();
            app.info(format!("style: {}", app.view.style.name()));
        }
        Action::CycleCells => {
            app.view.cells = super::app::next_cells(app.view.cells);
            app.info(format!("cells: {}", super::app::cells_name(app.view.cells)));
        }
        Action::ToggleAscii => {
            app.view.cells = if app.view.cells == CellMode::Ascii {
                CellMode::Braille
            } else {
                CellMode::Ascii
            };
            app.info(format!("cells: {}", super::app::cells_name(app.view.cells)));
        }
        Action::ToggleMuscles => {
            app.view.show_muscles = !app.view.show_muscles;
            app.info(on_off("muscle overlay", app.view.show_muscles));
        }
        Action::ToggleGhost => {
            app.view.show_ghost = !app.view.show_ghost;
            app.info(on_off("rest-pose ghost", app.view.show_ghost));
        }
        Action::ToggleDisplacement => {
            app.view.show_displacement = !app.view.show_displacement;
            app.info(on_off("displacement colours", app.view.show_displacement));
        }
        Action::Undo => undo(app, &mut fx),
        Action::Redo => redo(app, &mut fx),
        Action::Save => save(app, None, false, &mut fx),
        Action::Quit => quit(app, &mut fx),
        Action::StartCommand => open(app, InputKind::Command, ""),
        Action::ToggleHelp => {
            app.mode = match app.mode {
                Mode::Help(_) => Mode::Normal,
                _ => Mode::Help(0),
            }
        }
        Action::Command(line) => run_command(app, &line, &mut fx),
        Action::InputChar(c) => edit_input(app, |input| {
            let at = byte_index(&input.text, input.cursor);
            input.text.insert(at, c);
            input.cursor += 1;
        }),
        Action::InputBackspace => {
            let empty = matches!(&app.mode, Mode::Input(i) if i.text.is_empty());
            if empty {
                app.mode = Mode::Normal;
            } else {
                edit_input(app, |input| {
                    if input.cursor > 0 {
                        input.cursor -= 1;
                        let at = byte_index(&input.text, input.cursor);
                        input.text.remove(at);
                    }
                });
            }
        }
        Action::InputDelete => edit_input(app, |input| {
            if input.cursor < input.text.chars().count() {
                let at = byte_index(&input.text, input.cursor);
                input.text.remove(at);
            }
        }),
        Action::InputLeft => edit_input(app, |input| input.cursor = input.cursor.saturating_sub(1)),
        Action::InputRight => edit_input(app, |input| {
            input.cursor = (input.cursor + 1).min(input.text.chars().count())
        }),
        Action::InputHome => edit_input(app, |input| input.cursor = 0),
        Action::InputEnd => edit_input(app, |input| input.cursor = input.text.chars().count()),
        Action::InputComplete => complete(app),
        Action::InputSubmit => {
            if let Mode::Input(input) = std::mem::replace(&mut app.mode, Mode::Normal) {
                submit(app, input, &mut fx);
            }
        }
        Action::Cancel => {
            if matches!(app.mode, Mode::Confirm(_)) {
                return update(app, Action::Answer(false));
            }
            app.mode = Mode::Normal;
        }
        Action::Answer(yes) => {
            if let Mode::Confirm(question) = std::mem::replace(&mut app.mode, Mode::Normal) {
                answer(app, question, yes, &mut fx);
            }
        }
        Action::HelpScroll(by) => {
            if let Mode::Help(scroll) = &mut app.mode {
                *scroll = (i32::from(*scroll) + i32::from(by)).clamp(0, 500) as u16;
            }
        }
        Action::Resize(w, h) => app.size = (w, h),
        Action::Saved {
            path,
            stamp,
            quit_after,
        } => {
            app.info(format!("saved {}", path.display()));
            app.file = Some(path);
            app.file_stamp = Some(stamp);
            app.saved_table = app.table.clone();
            fx.push(Effect::RemoveRecovery);
            if quit_after {
                fx.push(Effect::Quit);
            }
        }
        Action::SaveFailed { path, error } => app.error(format!(
            "could not save {}: {error}; your edits are kept, nothing was lost",
            path.display()
        )),
        Action::SaveConflict { path, quit_after } => {
            app.mode = Mode::Confirm(Question::OverwriteFile { path, quit_after })
        }
    }
    fx
}

/// The text of a question, for the view.
pub fn question_text(question: &Question) -> String {
    match question {
        Question::QuitUnsaved => {
            "There are unsaved changes. Quit and discard them? (y/n)".to_string()
        }
        Question::OverwriteAu { key, name } => {
            format!("AU {key} exists. Overwrite it with the current state as \"{name}\"? (y/n)")
        }
        Question::DeleteAu(key) => format!("Delete AU {key}? (y/n)"),
        Question::OverwriteFile { path, .. } => format!(
            "{} changed on disk since it was loaded (or is another file). Overwrite it? (y/n)",
            path.display()
        ),
        Question::Recover(found) => format!(
            "Recover unsaved changes from {}? (y = recover, n = discard)",
            found.when
        ),
    }
}

fn on_off(what: &str, on: bool) -> String {
    format!("{what} {}", if on { "on" } else { "off" })
}

fn wrap_degrees(deg: f32) -> f32 {
    let wrapped = (deg + 180.0).rem_euclid(360.0) - 180.0;
    if wrapped == -180.0 {
        180.0
    } else {
        wrapped
    }
}

/// Two decimals, as shown in the panel.
pub fn format_value(value: f32) -> String {
    format!("{value:.2}")
}

fn open(app: &mut App, kind: InputKind, text: impl Into<String>) {
    app.mode = Mode::Input(Input::new(kind, text));
}

fn edit_input(app: &mut App, f: impl FnOnce(&mut Input)) {
    if let Mode::Input(input) = &mut app.mode {
        f(input);
    }
}

fn byte_index(text: &str, chars: usize) -> usize {
    text.char_indices()
        .nth(chars)
        .map_or(text.len(), |(i, _)| i)
}

fn selected_item(app: &App) -> Option<TableItem> {
    let items = app.table_items();
    items
        .get(app.table_selected.min(items.len().saturating_sub(1)))
        .cloned()
}

fn move_selection(app: &mut App, by: i64) {
    let (current, len) = match app.focus {
        Focus::Muscles => (app.selected, app.rows.len()),
        Focus::Table => (app.table_selected, app.table_items().len()),
    };
    if len == 0 {
        return;
    }
    let next = (current as i64).saturating_add(by).clamp(0, len as i64 - 1) as usize;
    match app.focus {
        Focus::Muscles => app.selected = next,
        Focus::Table => app.table_selected = next,
    }
}

/// Remembers the state before an edit, for undo.
fn begin_edit(app: &mut App) {
    app.undo.push(app.snapshot());
    app.redo.clear();
}

fn edited(app: &mut App, fx: &mut Vec<Effect>) {
    app.edits += 1;
    fx.push(Effect::RecoveryDue);
}

fn step(app: &mut App, by: f32, fx: &mut Vec<Effect>) {
    let row = app.selected_row();
    let (lo, hi) = app.range(row);
    let old = app.value(row);
    let new = ((old + by) / 0.01).round() * 0.01;
    let new = new.clamp(lo, hi);
    if new == old {
        app.info(format!(
            "{} is at its {} ({})",
            app.row_name(row),
            if by > 0.0 { "maximum" } else { "minimum" },
            format_value(old)
        ));
        return;
    }
    let coalesce = app.last_step == Some(row) && !app.undo.is_empty();
    if !coalesce {
        begin_edit(app);
    }
    apply_rows(app, row, new);
    app.last_step = Some(row);
    edited(app, fx);
}

/// Sets a row (and its mirror partner in mirror mode) to `value`, as one undoable edit.
fn set_rows(app: &mut App, row: Row, value: f32, fx: &mut Vec<Effect>) {
    let (lo, hi) = app.range(row);
    if !value.is_finite() || value < lo || value > hi {
        app.error(format!(
            "{} must be between {} and {}; {value} rejected",
            app.row_name(row),
            format_value(lo),
            format_value(hi)
        ));
        return;
    }
    let partner_differs = app
        .partner(row)
        .filter(|_| app.mirror)
        .is_some_and(|p| app.value(p) != value);
    if app.value(row) == value && !partner_differs {
        return;
    }
    begin_edit(app);
    apply_rows(app, row, value);
    edited(app, fx);
}

/// `:set` and `:jaw`: like [`set_rows`], saying what was set (a typed command has no other
/// feedback when the row is scrolled out of sight).
fn set_from_command(app: &mut App, row: Row, value: f32, fx: &mut Vec<Effect>) {
    let (lo, hi) = app.range(row);
    set_rows(app, row, value, fx);
    if value.is_finite() && (lo..=hi).contains(&value) {
        let partner = app.partner(row).filter(|_| app.mirror);
        let also = partner.map_or(String::new(), |p| format!(" (and {})", app.row_name(p)));
        app.info(format!(
            "{} = {}{also}",
            app.row_name(row),
            format_value(value)
        ));
    }
}

fn apply_rows(app: &mut App, row: Row, value: f32) {
    set_one(app, row, value);
    if app.mirror {
        if let Some(partner) = app.partner(row) {
            set_one(app, partner, value);
        }
    }
}

fn set_one(app: &mut App, row: Row, value: f32) {
    match row {
        Row::Muscle(i) => {
            if let Some(slot) = app.activations.muscles.get_mut(i) {
                *slot = value;
            }
            app.scene.update_muscle(&app.activations, Some(i));
        }
        Row::Jaw => {
            app.activations.jaw = value;
            app.scene.update_muscle(&app.activations, None);
        }
    }
}

fn replace_activations(
    app: &mut App,
    activations: Activations,
    loaded: Option<AuKey>,
    fx: &mut Vec<Effect>,
) {
    begin_edit(app);
    app.activations = activations;
    app.loaded = loaded;
    app.scene.deform(&app.activations);
    edited(app, fx);
}

fn restore(app: &mut App, snapshot: super::app::Snapshot) {
    app.activations = snapshot.activations;
    app.table = snapshot.table;
    app.loaded = snapshot.loaded;
    app.scene.deform(&app.activations);
    let items = app.table_items().len();
    app.table_selected = app.table_selected.min(items.saturating_sub(1));
}

fn undo(app: &mut App, fx: &mut Vec<Effect>) {
    match app.undo.pop() {
        Some(snapshot) => {
            app.redo.push(app.snapshot());
            restore(app, snapshot);
            app.info(format!("undone ({} more to undo)", app.undo.len()));
            edited(app, fx);
        }
        None => app.error("nothing to undo"),
    }
}

fn redo(app: &mut App, fx: &mut Vec<Effect>) {
    match app.redo.pop() {
        Some(snapshot) => {
            app.undo.push(app.snapshot());
            restore(app, snapshot);
            app.info(format!("redone ({} more to redo)", app.redo.len()));
            edited(app, fx);
        }
        None => app.error("nothing to redo"),
    }
}

fn save(app: &mut App, to: Option<PathBuf>, quit_after: bool, fx: &mut Vec<Effect>) {
    let path = match to.or_else(|| app.file.clone()) {
        Some(path) => path,
        None => {
            app.error("the built-in table has no file: save it with :w FILE");
            return;
        }
    };
    let expected = if Some(&path) == app.file.as_ref() {
        app.file_stamp
    } else {
        None
    };
    fx.push(Effect::Save {
        path,
        contents: table_ops::to_ron(&app.table),
        expected,
        force: false,
        quit_after,
    });
}

fn quit(app: &mut App, fx: &mut Vec<Effect>) {
    if app.dirty() {
        app.mode = Mode::Confirm(Question::QuitUnsaved);
    } else {
        fx.push(Effect::RemoveRecovery);
        fx.push(Effect::Quit);
    }
}

fn answer(app: &mut App, question: Question, yes: bool, fx: &mut Vec<Effect>) {
    match (question, yes) {
        (Question::QuitUnsaved, true) => {
            fx.push(Effect::RemoveRecovery);
            fx.push(Effect::Quit);
        }
        (Question::OverwriteAu { key, name }, true) => record(app, key, &name, fx),
        (Question::DeleteAu(key), true) => delete_au(app, key, fx),
        (Question::OverwriteFile { path, quit_after }, true) => fx.push(Effect::Save {
            path,
            contents: table_ops::to_ron(&app.table),
            expected: None,
            force: true,
            quit_after,
        }),
        (Question::Recover(found), true) => {
            begin_edit(app);
            app.activations = found.activations;
            app.table = found.table;
            app.file_stamp = found.base;
            app.scene.deform(&app.activations);
            app.info("recovered the unsaved changes; :w saves them");
            edited(app, fx);
        }
        (Question::Recover(_), false) => {
            fx.push(Effect::RemoveRecovery);
            app.info("discarded the recovered changes");
        }
        (_, false) => app.info("cancelled"),
    }
}

fn activate(app: &mut App, fx: &mut Vec<Effect>) {
    if app.focus == Focus::Muscles {
        update_into(app, Action::StartSetValue, fx);
        return;
    }
    match selected_item(app) {
        Some(TableItem::Au(key)) => load_au(app, key, fx),
        Some(TableItem::Expression(name)) => load_expression(app, &name, fx),
        None => app.error("the table is empty: record an AU with r"),
    }
}

fn update_into(app: &mut App, action: Action, fx: &mut Vec<Effect>) {
    let more = update(app, action);
    fx.extend(more);
}

fn load_au(app: &mut App, key: AuKey, fx: &mut Vec<Effect>) {
    match table_ops::activations_of(&app.table, key, app.rig()) {
        Ok(activations) => {
            replace_activations(app, activations, Some(key), fx);
            let name = app
                .table
                .aus
                .get(&key)
                .map(|e| e.name.clone())
                .unwrap_or_default();
            app.info(format!("loaded AU {key} {name}"));
        }
        Err(e) => app.error(e),
    }
}

fn load_expression(app: &mut App, name: &str, fx: &mut Vec<Effect>) {
    let Some(combo) = app.table.expressions.get(name).cloned() else {
        app.error(format!("the table has no expression named `{name}`"));
        return;
    };
    match table_ops::evaluate(&app.table, &combo, app.rig()) {
        Ok(activations) => {
            replace_activations(app, activations, None, fx);
            app.info(format!("loaded expression {name} = {combo}"));
        }
        Err(e) => app.error(e),
    }
}

fn record(app: &mut App, key: AuKey, name: &str, fx: &mut Vec<Effect>) {
    let mut table = app.table.clone();
    match table_ops::record(&mut table, key, name, app.rig(), &app.activations) {
        Ok(()) => {
            begin_edit(app);
            app.table = table;
            app.loaded = Some(key);
            if let Some(i) = app
                .table_items()
                .iter()
                .position(|it| *it == TableItem::Au(key))
            {
                app.table_selected = i;
            }
            app.info(format!("recorded AU {key} {name}"));
            edited(app, fx);
        }
        Err(e) => app.error(e),
    }
}

fn delete_au(app: &mut App, key: AuKey, fx: &mut Vec<Effect>) {
    let mut table = app.table.clone();
    if let Err(e) = table_ops::remove(&mut table, key) {
        app.error(e);
        return;
    }
    begin_edit(app);
    app.table = table;
    if app.loaded == Some(key) {
        app.loaded = None;
    }
    let items = app.table_items().len();
    app.table_selected = app.table_selected.min(items.saturating_sub(1));
    app.info(format!("deleted AU {key} (u undoes)"));
    edited(app, fx);
}

fn delete_expression(app: &mut App, name: &str, fx: &mut Vec<Effect>) {
    if !app.table.expressions.contains_key(name) {
        app.error(format!("the table has no expression named `{name}`"));
        return;
    }
    begin_edit(app);
    app.table.expressions.remove(name);
    let items = app.table_items().len();
    app.table_selected = app.table_selected.min(items.saturating_sub(1));
    app.info(format!("deleted expression {name} (u undoes)"));
    edited(app, fx);
}

fn rename(app: &mut App, key: AuKey, name: &str, fx: &mut Vec<Effect>) {
    let name = name.trim();
    if name.is_empty() {
        app.error("an AU's name cannot be empty");
        return;
    }
    if !app.table.aus.contains_key(&key) {
        app.error(format!("the table has no AU {key}"));
        return;
    }
    begin_edit(app);
    if let Some(entry) = app.table.aus.get_mut(&key) {
        entry.name = name.to_string();
    }
    app.info(format!("AU {key} renamed to {name}"));
    edited(app, fx);
}

/// Adds an AU (`12`) or a combination with FACS intensities (`12C`, `6+12B`) at `intensity`
/// to the current state.
fn add_au(app: &mut App, what: &str, intensity: f32, fx: &mut Vec<Effect>) {
    if !intensity.is_finite() || !(0.0..=2.0).contains(&intensity) {
        app.error(format!(
            "intensity must be between 0 and 2; {intensity} rejected"
        ));
        return;
    }
    let add = match what.parse::<AuKey>() {
        Ok(key) => table_ops::activations_of(&app.table, key, app.rig()),
        Err(_) => table_ops::evaluate(&app.table, what, app.rig()),
    };
    match add {
        Ok(add) => {
            let sum = table_ops::add_scaled(&app.activations, &add, intensity);
            replace_activations(app, sum, None, fx);
            app.info(format!("added {what} at {}", format_value(intensity)));
        }
        Err(e) => app.error(e),
    }
}

fn store_expression(app: &mut App, name: &str, combo: &str, fx: &mut Vec<Effect>) {
    let mut table = app.table.clone();
    if let Err(e) = table_ops::set_expression(&mut table, name, combo) {
        app.error(e);
        return;
    }
    begin_edit(app);
    app.table = table;
    app.info(format!("expression {name} = {combo} stored"));
    edited(app, fx);
}

fn set_combo(app: &mut App, combo: &str, fx: &mut Vec<Effect>) {
    match table_ops::evaluate(&app.table, combo, app.rig()) {
        Ok(activations) => {
            replace_activations(app, activations, None, fx);
            app.info(format!("state set from {combo}"));
        }
        Err(e) => app.error(e),
    }
}

fn parse_key(app: &mut App, text: &str) -> Option<AuKey> {
    match text.parse::<AuKey>() {
        Ok(key) => Some(key),
        Err(e) => {
            app.error(e.to_string());
            None
        }
    }
}

fn parse_value(app: &mut App, text: &str) -> Option<f32> {
    match text.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Some(v),
        _ => {
            app.error(format!("`{}` is not a number", text.trim()));
            None
        }
    }
}

/// The name an AU is recorded under when none is typed: its current name, else the FACS name.
fn suggested_name(app: &App, key: AuKey) -> String {
    app.table
        .aus
        .get(&key)
        .map(|e| e.name.clone())
        .or_else(|| table_ops::facs_name(key.number).map(str::to_string))
        .unwrap_or_else(|| format!("AU {key}"))
}

fn record_or_ask(app: &mut App, key: AuKey, name: &str, fx: &mut Vec<Effect>) {
    if app.table.aus.contains_key(&key) {
        app.mode = Mode::Confirm(Question::OverwriteAu {
            key,
            name: name.to_string(),
        });
    } else {
        record(app, key, name, fx);
    }
}

fn submit(app: &mut App, input: Input, fx: &mut Vec<Effect>) {
    let text = input.text.trim().to_string();
    match input.kind {
        InputKind::Command => run_command(app, &text, fx),
        InputKind::Find => find(app, &text),
        InputKind::Value => {
            if let Some(v) = parse_value(app, &text) {
                let row = app.selected_row();
                set_rows(app, row, v, fx);
            }
        }
        InputKind::RecordKey => {
            if let Some(key) = parse_key(app, &text) {
                let name = suggested_name(app, key);
                open(app, InputKind::RecordName(key), name);
            }
        }
        InputKind::RecordName(key) => {
            let name = if text.is_empty() {
                suggested_name(app, key)
            } else {
                text
            };
            record_or_ask(app, key, &name, fx);
        }
        InputKind::Rename(key) => rename(app, key, &text, fx),
        InputKind::AddAu => {
            let mut words = text.split_whitespace();
            match words.next() {
                None => app.error("type an AU number, e.g. 12 0.5"),
                Some(what) => {
                    let intensity = words.next().map_or(Some(1.0), |w| parse_value(app, w));
                    if let Some(i) = intensity {
                        add_au(app, what, i, fx);
                    }
                }
            }
        }
        InputKind::ExpressionName => {
            let text = text.replacen('=', " ", 1);
            let mut words = text.split_whitespace();
            match (words.next(), words.next()) {
                (Some(name), Some(combo)) => store_expression(app, name, combo, fx),
                _ => app.error("type a name and a combination, e.g. smile 6+12"),
            }
        }
    }
}

/// Normalises a name for matching: lower case, spaces and underscores alike.
fn fold(name: &str) -> String {
    name.to_lowercase().replace(' ', "_")
}

fn find(app: &mut App, text: &str) {
    if text.is_empty() {
        return;
    }
    let wanted = fold(text);
    let start = app.selected + 1;
    let n = app.rows.len();
    let hit = (0..n)
        .map(|k| (start + k) % n)
        .find(|&i| fold(app.row_name(app.rows[i])).contains(&wanted));
    match hit {
        Some(i) => {
            app.selected = i;
            app.focus = Focus::Muscles;
            app.info(format!("found {}", app.row_name(app.rows[i])));
        }
        None => app.error(format!("no muscle matches `{text}`")),
    }
}

fn row_by_name(app: &App, name: &str) -> Option<Row> {
    if fold(name) == "jaw" {
        return app.rows.iter().copied().find(|r| *r == Row::Jaw);
    }
    let wanted = fold(name);
    app.rig()
        .muscles
        .iter()
        .position(|m| fold(&m.name) == wanted)
        .map(Row::Muscle)
}

fn run_command(app: &mut App, line: &str, fx: &mut Vec<Effect>) {
    let line = line.trim();
    let (command, rest) = match line.split_once(char::is_whitespace) {
        Some((c, r)) => (c, r.trim()),
        None => (line, ""),
    };
    let args: Vec<&str> = rest.split_whitespace().collect();
    match command {
        "" => {}
        "w" | "write" => save(
            app,
            (!rest.is_empty()).then(|| PathBuf::from(rest)),
            false,
            fx,
        ),
        "wq" | "x" => save(
            app,
            (!rest.is_empty()).then(|| PathBuf::from(rest)),
            true,
            fx,
        ),
        "q" | "quit" => quit(app, fx),
        "q!" | "quit!" => {
            fx.push(Effect::RemoveRecovery);
            fx.push(Effect::Quit);
        }
        "record" => match args.first() {
            None => app.error("usage: :record N [NAME], e.g. :record 12 or :record R12"),
            Some(k) => {
                if let Some(key) = parse_key(app, k) {
                    let name = rest[k.len()..].trim();
                    let name = if name.is_empty() {
                        suggested_name(app, key)
                    } else {
                        name.to_string()
                    };
                    record_or_ask(app, key, &name, fx);
                }
            }
        },
        "load" => match args.as_slice() {
            [k] => {
                if let Some(key) = parse_key(app, k) {
                    load_au(app, key, fx);
                }
            }
            _ => app.error("usage: :load N"),
        },
        "delete" => match args.as_slice() {
            [k] => {
                if let Some(key) = parse_key(app, k) {
                    delete_au(app, key, fx);
                }
            }
            _ => app.error("usage: :delete N"),
        },
        "rename" => match args.first() {
            Some(k) if args.len() >= 2 => {
                if let Some(key) = parse_key(app, k) {
                    rename(app, key, rest[k.len()..].trim(), fx);
                }
            }
            _ => app.error("usage: :rename N NAME"),
        },
        "add" => match args.as_slice() {
            [what] | [what, _] => {
                let intensity = args.get(1).map_or(Some(1.0), |w| parse_value(app, w));
                if let Some(i) = intensity {
                    add_au(app, what, i, fx);
                }
            }
            _ => app.error("usage: :add N [INTENSITY], e.g. :add 12 0.5"),
        },
        "combo" => match args.as_slice() {
            [combo] => set_combo(app, combo, fx),
            _ => app.error("usage: :combo STR, e.g. :combo 1+2+5B+26"),
        },
        "expr" => match args.as_slice() {
            [name] => load_expression(app, name, fx),
            [name, combo] => store_expression(app, name, combo, fx),
            _ => app.error("usage: :expr NAME [COMBO], e.g. :expr smile 6+12"),
        },
        "set" => match args.as_slice() {
            [name, value] => match row_by_name(app, name) {
                Some(row) => {
                    if let Some(v) = parse_value(app, value) {
                        set_from_command(app, row, v, fx);
                    }
                }
                None => app.error(format!(
                    "the rig has no muscle named `{name}` (Tab completes)"
                )),
            },
            _ => app.error("usage: :set MUSCLE VALUE, e.g. :set L_Zygomatic_Major 0.8"),
        },
        "jaw" => match args.as_slice() {
            [value] if app.rows.contains(&Row::Jaw) => {
                if let Some(v) = parse_value(app, value) {
                    set_from_command(app, Row::Jaw, v, fx);
                }
            }
            [_] => app.error("this rig has no jaw"),
            _ => app.error("usage: :jaw VALUE (0 to 4)"),
        },
        "zero" | "reset" => update_into(app, Action::ResetAll, fx),
        "undo" => undo(app, fx),
        "redo" => redo(app, fx),
        "help" => app.mode = Mode::Help(0),
        "view" => {
            match rest {
                "front" => app.view.preset(ViewPreset::Front),
                "side" => app.view.preset(ViewPreset::Side),
                "three-quarter" | "3/4" => app.view.preset(ViewPreset::ThreeQuarter),
                _ => return app.error("usage: :view front|side|three-quarter"),
            }
            app.info(format!("view: {rest}"));
        }
        "style" => {
            match rest {
                "lines" => app.view.style = Style::Lines,
                "shaded" => app.view.style = Style::Shaded,
                "wireframe" => app.view.style = Style::Wireframe,
                _ => return app.error("usage: :style lines|shaded|wireframe"),
            }
            app.info(format!("style: {rest}"));
        }
        other => app.error(format!("unknown command `{other}` (? lists the commands)")),
    }
}

/// The completions of the word being typed.
fn candidates(app: &App, kind: &InputKind, before: &str) -> Vec<String> {
    let words: Vec<&str> = before.split(' ').collect();
    let au_keys = || {
        app.table
            .aus
            .keys()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
    };
    let muscles = || {
        let mut names: Vec<String> = app.rig().muscles.iter().map(|m| m.name.clone()).collect();
        if app.rig().jaw.is_some() {
            names.push("jaw".into());
        }
        names
    };
    match kind {
        InputKind::Find => muscles(),
        InputKind::RecordKey | InputKind::AddAu if words.len() == 1 => au_keys(),
        InputKind::Command if words.len() == 1 => {
            COMMAND_NAMES.iter().map(|s| s.to_string()).collect()
        }
        InputKind::Command if words.len() == 2 => match words[0] {
            "set" => muscles(),
            "record" | "load" | "delete" | "rename" | "add" => au_keys(),
            "expr" => app.table.expressions.keys().cloned().collect(),
            "view" => vec!["front".into(), "side".into(), "three-quarter".into()],
            "style" => vec!["lines".into(), "shaded".into(), "wireframe".into()],
            _ => Vec::new(),
        },
        _ => Vec::new(),
    }
}

fn complete(app: &mut App) {
    let Mode::Input(input) = &app.mode else {
        return;
    };
    let at = byte_index(&input.text, input.cursor);
    let before = input.text[..at].to_string();
    let word_start = before.rfind(' ').map_or(0, |i| i + 1);
    let word = &before[word_start..];
    let folded = fold(word);
    let matches: Vec<String> = candidates(app, &input.kind, &before)
        .into_iter()
        .filter(|c| fold(c).starts_with(&folded))
        .collect();
    if matches.is_empty() {
        app.error(format!("nothing completes `{word}`"));
        return;
    }
    let common = common_prefix(&matches);
    let replacement = if common.len() >= word.len() {
        common
    } else {
        word.to_string()
    };
    let suffix = if matches.len() == 1 { " " } else { "" };
    let many = (matches.len() > 1).then(|| matches.join("  "));
    if let Mode::Input(input) = &mut app.mode {
        let rest = input.text[at..].to_string();
        input.text = format!("{}{}{}{}", &before[..word_start], replacement, suffix, rest);
        input.cursor = before[..word_start].chars().count()
            + replacement.chars().count()
            + suffix.chars().count();
    }
    match many {
        Some(list) => app.info(list),
        None => app.message = None,
    }
}

fn common_prefix(words: &[String]) -> String {
    let first = &words[0];
    let mut len = first.len();
    for w in &words[1..] {
        len = first
            .char_indices()
            .zip(w.chars())
            .take_while(|((_, a), b)| a.eq_ignore_ascii_case(b))
            .map(|((i, a), _)| i + a.len_utf8())
            .last()
            .unwrap_or(0)
            .min(len);
    }
    first[..len].to_string()
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;
    use std::path::PathBuf;

    use super::*;
    use crate::facs::AuTable;
    use crate::model::Side;
    use crate::tui::app::{FileStamp, Message, Severity};

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
        app.activations.muscles[app.rig().muscle_index(name).unwrap()]
    }

    #[test]
    fn rows_are_grouped_linear_sheet_sphincter_jaw() {
        let app = app();
        assert_eq!(
            app.rows,
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
        assert_eq!(app.selected, 0);
        run(&mut app, &[Action::SelectNext, Action::SelectNext]);
        assert_eq!(app.selected, 2);
        run(&mut app, &[Action::SelectLast]);
        assert_eq!(app.selected_row(), Row::Jaw);
        run(&mut app, &[Action::SelectNext]);
        assert_eq!(app.selected_row(), Row::Jaw);
        run(&mut app, &[Action::SelectFirst]);
        assert_eq!(app.selected, 0);
        run(&mut app, &[Action::SelectRow(Row::Muscle(0))]);
        assert_eq!(app.selected, 3);
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
        assert_eq!(app.activations.jaw, 4.0);
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
        assert_eq!(app.undo.len(), 1);
        run(&mut app, &[Action::SelectNext, Action::StepFine(1)]);
        assert_eq!(app.undo.len(), 2);
        run(&mut app, &[Action::Undo]);
        assert_eq!(muscle(&app, "R_Zygomatic_Major"), 0.0);
        assert!((muscle(&app, "L_Zygomatic_Major") - 0.15).abs() < 1e-6);
        run(&mut app, &[Action::Undo]);
        assert!(app.activations.is_rest());
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
        assert_eq!(app.redo.len(), 1);
        run(&mut app, &[Action::ZeroSelected, Action::StepCoarse(1)]);
        assert!(app.redo.is_empty());
    }

    #[test]
    fn edits_deform_the_face_and_undo_restores_it() {
        let mut app = app();
        let rest = app.scene.mesh().positions.clone();
        run(
            &mut app,
            &[
                Action::ToggleMirror,
                Action::StepCoarse(1),
                Action::StepCoarse(1),
            ],
        );
        assert_ne!(
            app.scene.positions(),
            &rest[..],
            "the zygomatics move the grid"
        );
        // The incremental update matches a full deformation.
        let mut full = app.scene.clone();
        full.deform(&app.activations);
        assert_eq!(app.scene.positions(), full.positions());
        command(&mut app, "jaw 2");
        let mut full = app.scene.clone();
        full.deform(&app.activations);
        assert_eq!(app.scene.positions(), full.positions());
        run(&mut app, &[Action::Undo, Action::Undo]);
        assert_eq!(app.scene.positions(), &rest[..]);
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
        assert!(matches!(&app.mode, Mode::Input(i) if i.text == "0.00"));
        update(&mut app, Action::InputHome);
        run(
            &mut app,
            &[
                Action::InputDelete,
                Action::InputDelete,
                Action::InputDelete,
                Action::InputDelete,
            ],
        );
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
        assert!(app.activations.is_rest());
        update(&mut app, Action::Undo);
        assert_eq!(app.activations.jaw, 3.0);
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
        assert_eq!(app.activations.jaw, 2.0);
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
        let entry = &app.table.aus[&AuKey::new(1)];
        assert_eq!(entry.name, "Brow raiser");
        assert_eq!(
            entry.muscles,
            BTreeMap::from([("Frontalis".to_string(), 0.8)])
        );
        assert!(app.dirty());
        assert_eq!(app.loaded, Some(AuKey::new(1)));
        // Recording over AU 12 asks first; "no" keeps the old entry.
        command(&mut app, "record 12 Smile");
        assert!(matches!(
            app.mode,
            Mode::Confirm(Question::OverwriteAu { .. })
        ));
        update(&mut app, Action::Answer(false));
        assert_eq!(app.table.aus[&AuKey::new(12)].name, "Lip Corner Puller");
        command(&mut app, "record 12 Smile");
        update(&mut app, Action::Answer(true));
        assert_eq!(app.table.aus[&AuKey::new(12)].name, "Smile");
        assert_eq!(
            app.table.aus[&AuKey::new(12)].muscles,
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
        assert_eq!(app.table.aus.len(), 64);
        command(&mut app, &format!("record {} x", codes[40]));
        assert!(error(&app).contains("full"), "{}", error(&app));
        assert_eq!(app.table.aus.len(), 64);
    }

    #[test]
    fn load_delete_rename_and_add() {
        let mut app = app();
        command(&mut app, "load 12");
        assert_eq!(muscle(&app, "L_Zygomatic_Major"), 1.0);
        assert_eq!(app.loaded, Some(AuKey::new(12)));
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
        assert!((muscle(&app, "L_Zygomatic_Major") - 0.6).abs() < 1e-6);
        command(&mut app, "add 12A 0.5");
        assert!((muscle(&app, "L_Zygomatic_Major") - 0.7).abs() < 1e-6);
        command(&mut app, "add 12Z");
        assert!(error(&app).starts_with("`12Z`"), "{}", error(&app));
        command(&mut app, "rename 12 Smile wide");
        assert_eq!(app.table.aus[&AuKey::new(12)].name, "Smile wide");
        command(&mut app, "load 4");
        assert_eq!(error(&app), "the table has no AU 4");
        command(&mut app, "delete 12");
        assert!(app.table.aus.is_empty());
        assert_eq!(app.loaded, None);
        update(&mut app, Action::Undo);
        assert_eq!(app.table.aus[&AuKey::new(12)].name, "Smile wide");
    }

    #[test]
    fn table_panel_keys_act_on_the_selected_au() {
        let mut app = app();
        command(&mut app, "record 1 Brow");
        run(
            &mut app,
            &[Action::SwitchFocus, Action::SelectLast, Action::Activate],
        );
        assert_eq!(app.loaded, Some(AuKey::new(12)));
        assert_eq!(muscle(&app, "L_Zygomatic_Major"), 1.0);
        update(&mut app, Action::DeleteSelected);
        assert_eq!(app.mode, Mode::Confirm(Question::DeleteAu(AuKey::new(12))));
        update(&mut app, Action::Answer(true));
        assert!(!app.table.aus.contains_key(&AuKey::new(12)));
        update(&mut app, Action::RenameSelected);
        assert!(
            matches!(&app.mode, Mode::Input(i) if i.kind == InputKind::Rename(AuKey::new(1)) && i.text == "Brow")
        );
        typed(&mut app, " raiser");
        update(&mut app, Action::InputSubmit);
        assert_eq!(app.table.aus[&AuKey::new(1)].name, "Brow raiser");
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
            contents,
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
        let back: AuTable = ron::from_str(&contents).unwrap();
        assert_eq!(back, app.table);
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
        app.file = None;
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
        assert!(
            error(&app).contains("could not save t.au.ron: Permission denied; your edits are kept")
        );
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
        let mut activations = app.activations.clone();
        activations.muscles[3] = 1.5;
        let mut table = app.table.clone();
        table.aus.clear();
        let question = Question::Recover(Box::new(crate::tui::app::Recovered {
            activations: activations.clone(),
            table: table.clone(),
            when: "5 s ago".into(),
            base: None,
        }));
        app.mode = Mode::Confirm(question.clone());
        assert!(question_text(&question).contains("recover"));
        let fx = update(&mut app, Action::Answer(true));
        assert_eq!(fx, vec![Effect::RecoveryDue]);
        assert_eq!(app.activations, activations);
        assert_eq!(app.table, table);
        assert!(app.dirty());
        let mut app2 = self::app();
        app2.mode = Mode::Confirm(question);
        assert_eq!(
            update(&mut app2, Action::Answer(false)),
            vec![Effect::RemoveRecovery]
        );
        assert!(app2.activations.is_rest());
    }

    #[test]
    fn view_actions_move_the_camera_within_limits() {
        let mut app = app();
        run(&mut app, &[Action::Rotate(200.0, 100.0)]);
        assert_eq!(app.view.yaw, -160.0);
        assert_eq!(app.view.pitch, 89.0);
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
        assert!(app.undo.is_empty());
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
        assert!(app.table.expressions.is_empty());
        command(&mut app, "expr smile 12C");
        assert_eq!(app.table.expressions["smile"], "12C");
        assert!(app.dirty());
        command(&mut app, "expr smile");
        assert!((muscle(&app, "L_Zygomatic_Major") - 0.6).abs() < 1e-6);
        command(&mut app, "zero");
        command(&mut app, "combo 12B");
        assert!((muscle(&app, "R_Zygomatic_Major") - 0.4).abs() < 1e-6);
        command(&mut app, "combo 12+");
        assert!(error(&app).starts_with("`12+`"), "{}", error(&app));
        // An AU an expression uses cannot be deleted.
        command(&mut app, "delete 12");
        assert!(error(&app).contains("smile"), "{}", error(&app));
        // Expressions are listed after the AUs; Enter loads, d deletes.
        run(&mut app, &[Action::SwitchFocus, Action::SelectLast]);
        update(&mut app, Action::Activate);
        assert!((muscle(&app, "L_Zygomatic_Major") - 0.6).abs() < 1e-6);
        update(&mut app, Action::DeleteSelected);
        assert!(app.table.expressions.is_empty());
        update(&mut app, Action::StartExpression);
        typed(&mut app, "grin = 12E");
        update(&mut app, Action::InputSubmit);
        assert_eq!(app.table.expressions["grin"], "12E");
    }

    #[test]
    fn table_selection_record_suggestion_and_enter_on_a_muscle() {
        let mut app = app();
        command(&mut app, "record 1 Brow");
        update(&mut app, Action::SelectTableItem(1));
        assert_eq!((app.focus, app.table_selected), (Focus::Table, 1));
        update(&mut app, Action::SelectTableItem(9));
        assert_eq!(app.table_selected, 1, "no such line: the selection stays");
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
        assert!(matches!(&app.mode, Mode::Input(i) if i.kind == InputKind::Value));
        update(&mut app, Action::Cancel);
        update(&mut app, Action::StartFind);
        assert!(matches!(&app.mode, Mode::Input(i) if i.kind == InputKind::Find));
    }

    #[test]
    fn resize_records_the_size() {
        let mut app = app();
        update(&mut app, Action::Resize(200, 60));
        assert_eq!(app.size, (200, 60));
    }
}
