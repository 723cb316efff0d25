//! Activations: steps, exact values and mirror partners, whole states, and undo and redo.

use super::*;
use crate::tui::app::Step;

/// Remembers the state before an edit, for undo.
pub(crate) fn begin_edit(app: &mut App) {
    app.history.undo.push(Step::State(app.snapshot()));
    app.history.redo.clear();
}

pub(crate) fn edited(app: &mut App, fx: &mut Vec<Effect>) {
    app.history.edits += 1;
    fx.push(Effect::RecoveryDue);
}

/// `value` rounded to hundredths, as the nearest `f32` to the decimal (dividing the whole
/// number of hundredths rounds once; multiplying by 0.01 would round twice).
pub(crate) fn round_to_step(value: f32) -> f32 {
    (value * STEP_RESOLUTION).round() / STEP_RESOLUTION
}

pub(crate) fn step(app: &mut App, by: f32, fx: &mut Vec<Effect>) {
    let row = app.selected_row();
    let (lo, hi) = app.range(row);
    let old = app.value(row);
    let new = round_to_step(old + by).clamp(lo, hi);
    if new == old {
        app.info(format!(
            "{} is at its {} ({})",
            app.row_name(row),
            if by > 0.0 { "maximum" } else { "minimum" },
            format_value(old)
        ));
        return;
    }
    let coalesce = app.history.last_step == Some(row)
        && matches!(app.history.undo.last(), Some(Step::State(_)));
    if !coalesce {
        begin_edit(app);
    }
    apply_rows(app, row, new);
    app.history.last_step = Some(row);
    edited(app, fx);
}

/// Sets a row (and its mirror partner in mirror mode) to `value`, as one undoable edit.
pub(crate) fn set_rows(app: &mut App, row: Row, value: f32, fx: &mut Vec<Effect>) {
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
        .filter(|_| app.selection.mirror)
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
pub(crate) fn set_from_command(app: &mut App, row: Row, value: f32, fx: &mut Vec<Effect>) {
    let (lo, hi) = app.range(row);
    set_rows(app, row, value, fx);
    if value.is_finite() && (lo..=hi).contains(&value) {
        let partner = app.partner(row).filter(|_| app.selection.mirror);
        let also = partner.map_or(String::new(), |p| format!(" (and {})", app.row_name(p)));
        app.info(format!(
            "{} = {}{also}",
            app.row_name(row),
            format_value(value)
        ));
    }
}

pub(crate) fn apply_rows(app: &mut App, row: Row, value: f32) {
    set_one(app, row, value);
    if app.selection.mirror {
        if let Some(partner) = app.partner(row) {
            set_one(app, partner, value);
        }
    }
}

pub(crate) fn set_one(app: &mut App, row: Row, value: f32) {
    match row {
        Row::Muscle(i) => {
            if let Some(slot) = app.doc.activations.muscles.get_mut(i) {
                *slot = value;
            }
            app.doc.face.update_muscle(&app.doc.activations, Some(i));
        }
        Row::Jaw => {
            app.doc.activations.jaw = value;
            app.doc.face.update_muscle(&app.doc.activations, None);
        }
    }
}

pub(crate) fn replace_activations(
    app: &mut App,
    activations: Activations,
    loaded: Option<AuKey>,
    fx: &mut Vec<Effect>,
) {
    begin_edit(app);
    app.doc.activations = activations;
    app.doc.loaded = loaded;
    app.doc.face.deform(&app.doc.activations);
    edited(app, fx);
}

pub(crate) fn restore(app: &mut App, snapshot: crate::tui::app::Snapshot) {
    app.doc.activations = snapshot.activations;
    app.doc.table = snapshot.table;
    app.doc.loaded = snapshot.loaded;
    app.doc.face.deform(&app.doc.activations);
    let items = app.table_items().len();
    app.selection.table_selected = app.selection.table_selected.min(items.saturating_sub(1));
}

/// Takes back the last edit, of activations, the table or the rig, whichever came last.
pub(crate) fn undo(app: &mut App, fx: &mut Vec<Effect>) {
    back(app, true, fx)
}

/// Makes the last undone edit again.
pub(crate) fn redo(app: &mut App, fx: &mut Vec<Effect>) {
    back(app, false, fx)
}

/// Moves one step from the undo list to the redo list (`undo`) or back, saying what moved.
fn back(app: &mut App, undo: bool, fx: &mut Vec<Effect>) {
    let (done, word) = if undo {
        ("undone", "undo")
    } else {
        ("redone", "redo")
    };
    let popped = if undo {
        app.history.undo.pop()
    } else {
        app.history.redo.pop()
    };
    let step = match popped {
        None => return app.error(format!("nothing to {word}")),
        Some(Step::State(snapshot)) => {
            let current = Step::State(app.snapshot());
            restore(app, snapshot);
            current
        }
        Some(Step::Rig(change)) => match crate::tui::rig::put_back(app, change) {
            Ok(inverse) => Step::Rig(inverse),
            Err((change, reason)) => {
                let list = if undo {
                    &mut app.history.undo
                } else {
                    &mut app.history.redo
                };
                list.push(Step::Rig(change));
                return app.error(format!("cannot {word} the rig change: {reason}"));
            }
        },
    };
    let what = match &step {
        Step::Rig(change) => format!(" the rig change to {}", change.what),
        Step::State(_) => String::new(),
    };
    let (to, left) = if undo {
        (&mut app.history.redo, app.history.undo.len())
    } else {
        (&mut app.history.undo, app.history.redo.len())
    };
    to.push(step);
    let shown = if app.rig_edit.on && !what.is_empty() {
        format!("; {}", crate::tui::rig::describe(app))
    } else {
        String::new()
    };
    app.info(format!("{done}{what} ({left} more to {word}){shown}"));
    edited(app, fx);
}
