//! `update`: the only place the editor's state changes. Pure: no input or output; what needs
//! doing outside (saving, quitting, the recovery file) comes back as [`Effect`]s.
//!
//! One file per concern: [`prompt`] (the input line, its completion and what a submitted line
//! does), [`table`] (the AU table, saving and quitting), [`edit`] (activations and undo) and
//! [`view`] (camera and drawing options). Each reaches the others' functions through this
//! module.

use std::path::PathBuf;

use crate::facs::AuKey;
use crate::model::Activations;

use crate::tui::action::{Action, Effect};
use crate::tui::app::{
    App, CellMode, Focus, Input, InputKind, Mode, Question, Row, TableItem, ViewPreset, FINE_STEP,
    STEP_RESOLUTION,
};

use crate::tui::table_ops;

pub(crate) mod command;
pub(crate) mod edit;
pub(crate) mod prompt;
pub(crate) mod table;
#[cfg(test)]
mod tests;
pub(crate) mod view;

use edit::*;
use prompt::*;
use table::*;

/// Applies one action to the state and returns the effects to run.
pub fn update(app: &mut App, action: Action) -> Vec<Effect> {
    let mut fx = Vec::new();
    if !matches!(action, Action::StepFine(_) | Action::StepCoarse(_)) {
        app.history.last_step = None;
    }
    match action {
        action @ (Action::SelectNext
        | Action::SelectPrev
        | Action::SelectFirst
        | Action::SelectLast
        | Action::SelectRow(_)
        | Action::SelectTableItem(_)
        | Action::SwitchFocus) => select(app, action),
        action @ (Action::StartFind
        | Action::StepFine(_)
        | Action::StepCoarse(_)
        | Action::StartSetValue
        | Action::ZeroSelected
        | Action::ResetAll
        | Action::ToggleMirror) => edit_values(app, action, &mut fx),
        action @ (Action::StartRecord
        | Action::Activate
        | Action::OverwriteSelected
        | Action::DeleteSelected
        | Action::RenameSelected
        | Action::StartAddAu
        | Action::StartExpression) => edit_table(app, action, &mut fx),
        action @ (Action::Rotate(..)
        | Action::Zoom(_)
        | Action::Pan(..)
        | Action::ResetView
        | Action::Preset(_)
        | Action::CycleStyle
        | Action::CycleCells
        | Action::ToggleAscii
        | Action::ToggleMuscles
        | Action::ToggleGhost
        | Action::ToggleDisplacement) => view::apply(app, action),
        Action::Undo => undo(app, &mut fx),
        Action::Redo => redo(app, &mut fx),
        Action::Save => save(app, None, false, &mut fx),
        Action::Quit => quit(app, &mut fx),
        Action::StartCommand => open(app, InputKind::Command, ""),
        Action::Command(line) => command::run(app, &line, &mut fx),
        action @ (Action::InputChar(_)
        | Action::InputBackspace
        | Action::InputDelete
        | Action::InputLeft
        | Action::InputRight
        | Action::InputHome
        | Action::InputEnd
        | Action::InputClear
        | Action::InputComplete) => prompt::edit(app, action),
        action @ (Action::ToggleHelp
        | Action::InputSubmit
        | Action::Cancel
        | Action::Answer(_)
        | Action::HelpScroll(_)) => leave_or_scroll(app, action, &mut fx),
        Action::Resize(w, h) => app.view.size = (w, h),
        Action::Rig(action) => crate::tui::rig::update(app, action, &mut fx),
        action @ (Action::Saved { .. }
        | Action::SaveFailed { .. }
        | Action::SaveConflict { .. }
        | Action::TableRead { .. }) => file_result(app, action, &mut fx),
    }
    crate::tui::rig::sync(app);
    fx
}

/// The keys that open, answer or leave a mode: help, the prompt, a question.
fn leave_or_scroll(app: &mut App, action: Action, fx: &mut Vec<Effect>) {
    match action {
        Action::ToggleHelp => {
            app.mode = match app.mode {
                Mode::Help(_) => Mode::Normal,
                _ => Mode::Help(0),
            }
        }
        Action::InputSubmit => {
            if let Mode::Input(input) = std::mem::replace(&mut app.mode, Mode::Normal) {
                submit(app, input, fx);
            }
        }
        // Leaving a question is answering no; leaving anything else goes back to normal.
        Action::Cancel => {
            if let Mode::Confirm(question) = std::mem::replace(&mut app.mode, Mode::Normal) {
                answer(app, question, false, fx);
            }
        }
        Action::Answer(yes) => {
            if let Mode::Confirm(question) = std::mem::replace(&mut app.mode, Mode::Normal) {
                answer(app, question, yes, fx);
            }
        }
        Action::HelpScroll(by) => {
            if let Mode::Help(scroll) = &mut app.mode {
                *scroll = (i32::from(*scroll) + i32::from(by)).clamp(0, 500) as u16;
            }
        }
        _ => {}
    }
}

/// The selection keys: which muscle row or table item, which panel.
fn select(app: &mut App, action: Action) {
    match action {
        Action::SelectNext => move_selection(app, 1),
        Action::SelectPrev => move_selection(app, -1),
        Action::SelectFirst => move_selection(app, i64::MIN / 2),
        Action::SelectLast => move_selection(app, i64::MAX / 2),
        Action::SelectRow(row) => {
            if let Some(i) = app.selection.rows.iter().position(|&r| r == row) {
                app.selection.selected = i;
                app.selection.focus = Focus::Muscles;
            }
        }
        Action::SelectTableItem(i) => {
            if i < app.table_items().len() {
                app.selection.table_selected = i;
                app.selection.focus = Focus::Table;
            }
        }
        Action::SwitchFocus => {
            app.selection.focus = match app.selection.focus {
                Focus::Muscles => Focus::Table,
                Focus::Table => Focus::Muscles,
            };
        }
        _ => unreachable!("not a selection action"),
    }
}

/// Editing the activations: steps, typed values, zero, reset, mirror mode, find.
fn edit_values(app: &mut App, action: Action, fx: &mut Vec<Effect>) {
    match action {
        Action::StartFind => open(app, InputKind::Find, ""),
        Action::StepFine(n) => step(app, f32::from(n) * FINE_STEP, fx),
        Action::StepCoarse(n) => {
            let size = app.coarse_step(app.selected_row());
            step(app, f32::from(n) * size, fx)
        }
        Action::StartSetValue => {
            let row = app.selected_row();
            let (lo, hi) = app.range(row);
            let now = format!(
                "{} {}, {}-{}",
                app.row_name(row),
                format_value(app.value(row)),
                lo,
                hi
            );
            open(app, InputKind::Value(now), "");
        }
        Action::ZeroSelected => {
            let row = app.selected_row();
            set_rows(app, row, 0.0, fx);
        }
        Action::ResetAll => {
            if app.doc.activations.is_rest() {
                app.info("already at rest");
            } else {
                let rest = Activations::zero(app.rig());
                replace_activations(app, rest, None, fx);
                app.info("every muscle and the jaw reset to zero");
            }
        }
        Action::ToggleMirror => {
            app.selection.mirror = !app.selection.mirror;
            let state = if app.selection.mirror {
                "on: left/right pairs move together"
            } else {
                "off"
            };
            app.info(format!("mirror mode {state}"));
        }
        _ => unreachable!("not a value action"),
    }
}

/// Editing the AU table: record, load, overwrite, delete, rename, add, expressions.
/// The name AU `key` is recorded under in the table (empty when it is not recorded).
pub(crate) fn au_name(app: &App, key: AuKey) -> String {
    app.doc
        .table
        .aus
        .get(&key)
        .map(|e| e.name.clone())
        .unwrap_or_default()
}

fn edit_table(app: &mut App, action: Action, fx: &mut Vec<Effect>) {
    match action {
        Action::StartRecord => {
            let suggestion = match selected_item(app) {
                Some(TableItem::Au(key)) if app.selection.focus == Focus::Table => key.to_string(),
                _ => String::new(),
            };
            open(app, InputKind::RecordKey, suggestion);
        }
        Action::Activate => activate(app, fx),
        Action::OverwriteSelected => match selected_item(app) {
            Some(TableItem::Au(key)) => {
                let name = au_name(app, key);
                app.mode = Mode::Confirm(Question::OverwriteAu { key, name });
            }
            _ => app.error("select an AU in the table first (Tab switches to the table)"),
        },
        Action::DeleteSelected => match selected_item(app) {
            Some(TableItem::Au(key)) => app.mode = Mode::Confirm(Question::DeleteAu(key)),
            Some(TableItem::Expression(name)) => delete_expression(app, &name, fx),
            None => app.error("the table is empty: nothing to delete"),
        },
        Action::RenameSelected => match selected_item(app) {
            Some(TableItem::Au(key)) => {
                let name = au_name(app, key);
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
        _ => unreachable!("not a table action"),
    }
}

/// What the event loop reports back from a save or an import.
fn file_result(app: &mut App, action: Action, fx: &mut Vec<Effect>) {
    match action {
        Action::Saved {
            path,
            stamp,
            quit_after,
        } => {
            app.info(format!("saved {}", path.display()));
            app.doc.file = Some(path);
            app.doc.file_stamp = Some(stamp);
            app.doc.saved_table = app.doc.table.clone();
            fx.push(Effect::RemoveRecovery);
            if app.dirty() {
                // Rig edits are still unsaved: keep them for recovery.
                fx.push(Effect::RecoveryDue);
            }
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
        Action::TableRead { source, table } => match table {
            Ok(from) => table::import(app, &source, &from, fx),
            Err(e) => app.error(format!("could not import {source}: {e}")),
        },
        _ => unreachable!("not a file result"),
    }
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
        Question::AddMissingAus { name, missing, .. } => {
            let named: Vec<String> = missing
                .iter()
                .map(|k| match crate::facs::catalogue::name_of(k.number) {
                    Some(facs) => format!("{k} {facs}"),
                    None => k.to_string(),
                })
                .collect();
            format!(
                "{name} needs AUs the table lacks: {}. Add them from the built-in table? (y/n)",
                named.join(", ")
            )
        }
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

/// Two decimals, as shown in the panel.
pub fn format_value(value: f32) -> String {
    format!("{value:.2}")
}

fn move_selection(app: &mut App, by: i64) {
    let (current, len) = match app.selection.focus {
        Focus::Muscles => (app.selection.selected, app.selection.rows.len()),
        Focus::Table => (app.selection.table_selected, app.table_items().len()),
    };
    if len == 0 {
        return;
    }
    let next = (current as i64).saturating_add(by).clamp(0, len as i64 - 1) as usize;
    match app.selection.focus {
        Focus::Muscles => app.selection.selected = next,
        Focus::Table => app.selection.table_selected = next,
    }
}

fn update_into(app: &mut App, action: Action, fx: &mut Vec<Effect>) {
    let more = update(app, action);
    fx.extend(more);
}
