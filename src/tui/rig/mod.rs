//! Rig mode (`R`): placing muscles. The selected muscle (or the jaw) is held at an activation
//! so its pull stays visible, its points move in the view plane and its parameters change by
//! steps; every change is checked by the model before it is kept, and can be undone.
//!
//! State lives in [`RigEdit`], changes in the pure [`update`]; the event loop writes the rig
//! file for [`Effect::SaveRig`].

use std::path::PathBuf;

use glam::Vec3;

use super::action::{Action, Effect, RigAction};
use super::app::{App, FileStamp, Input, InputKind, Mode, Row, Step};
use crate::io::rig_file::check_rig;
use crate::model::{Activations, MuscleKind, Rig};

mod params;
pub use super::app::{JawPose, RigEdit, RigParts, RigUndo};
use params::{kind_of, param_mut, params, Change, Unit};
pub use params::{param_names, point, point_names};

/// Fine step of a point or a length, as a fraction of the face's height.
pub const FINE_FRACTION: f32 = 0.005;
/// Coarse step of a point or a length, as a fraction of the face's height.
pub const COARSE_FRACTION: f32 = 0.025;
/// Said when a command would leave with the rig's changes unsaved.
pub const UNSAVED_RIG: &str =
    "the rig has unsaved changes: :w in rig mode (R) saves it, :q! discards it";

/// Step of the held activation (`<` and `>`).
pub const HELD_STEP: f32 = 0.25;

/// The face's height: the scale of point and length steps.
fn face_size(app: &App) -> f32 {
    app.doc.face.framing().height()
}

/// The screen's right and up directions in mesh coordinates, for the current view.
pub fn view_axes(app: &App) -> (Vec3, Vec3) {
    let back = app.camera().view_matrix().transpose();
    (back * Vec3::X, back * Vec3::Y)
}

/// The direction out of the screen toward the viewer, in mesh coordinates: the axis that
/// angle parameters turn about.
fn view_out(app: &App) -> Vec3 {
    let (right, up) = view_axes(app);
    right.cross(up)
}

/// The angle of `d` in the view plane in degrees, counter-clockwise from the screen's
/// right; `None` when `d` points (nearly) along the view.
pub fn view_angle(app: &App, d: Vec3) -> Option<f32> {
    let (right, up) = view_axes(app);
    let (x, y) = (d.dot(right), d.dot(up));
    (x.hypot(y) > 1e-3 * d.length()).then(|| y.atan2(x).to_degrees())
}

/// Applies one rig-mode action. Pure: saving comes back as [`Effect::SaveRig`].
pub fn update(app: &mut App, action: RigAction, fx: &mut Vec<Effect>) {
    match action {
        RigAction::Toggle => {
            app.rig_edit.on = !app.rig_edit.on;
            if app.rig_edit.on {
                app.info(format!("rig mode: {}", describe(app)));
            } else {
                app.info("rig mode off");
            }
        }
        RigAction::NextPoint => {
            let n = point_names(kind_of(app.rig(), app.selected_row())).len();
            // From the point shown (a muscle with fewer points shows its last one).
            app.rig_edit.point = (app.rig_edit.point.min(n.saturating_sub(1)) + 1) % n.max(1);
            app.info(describe(app));
        }
        RigAction::NextParam => {
            let n = params(kind_of(app.rig(), app.selected_row())).len();
            app.rig_edit.param = (app.rig_edit.param.min(n.saturating_sub(1)) + 1) % n.max(1);
            app.info(describe(app));
        }
        RigAction::Move { right, up, coarse } => move_point(app, (right, up), coarse, fx),
        RigAction::Param { by, coarse } => change_param(app, by, coarse, fx),
        RigAction::Held(by) => {
            let (lo, hi) = app.range(app.selected_row());
            let held = (app.rig_edit.held + f32::from(by) * HELD_STEP).clamp(lo.max(0.0), hi);
            app.rig_edit.held = held;
            app.info(format!("held at {held:.2}"));
        }
        RigAction::Saved { path, file, stamp } => saved(app, path, file, stamp, fx),
        RigAction::SaveFailed { path, error } => app.error(format!(
            "could not save the rig to {}: {error}; your edits are kept",
            path.display()
        )),
    }
    sync(app);
}

/// Moves the selected point of the selected muscle along the view's right and up.
fn move_point(app: &mut App, (right, up): (i8, i8), coarse: bool, fx: &mut Vec<Effect>) {
    let step = face_size(app)
        * if coarse {
            COARSE_FRACTION
        } else {
            FINE_FRACTION
        };
    let (r, u) = view_axes(app);
    let by = (r * f32::from(right) + u * f32::from(up)) * step;
    let points = point_names(kind_of(app.rig(), app.selected_row()));
    let i = app.rig_edit.point.min(points.len().saturating_sub(1));
    edit(app, Change::Move(i, by), points.get(i).copied(), fx);
}

/// Steps the selected parameter of the selected muscle (a length, a number or a turn).
fn change_param(app: &mut App, by: i8, coarse: bool, fx: &mut Vec<Effect>) {
    let list = params(kind_of(app.rig(), app.selected_row()));
    let i = app.rig_edit.param.min(list.len().saturating_sub(1));
    let Some(&(name, unit)) = list.get(i) else {
        return;
    };
    let pick = |fine: f32, coarse_step: f32| if coarse { coarse_step } else { fine };
    let change = match unit {
        Unit::Length => Change::Param(
            i,
            f32::from(by) * face_size(app) * pick(FINE_FRACTION, COARSE_FRACTION),
        ),
        Unit::Fixed(fine, coarse_step) => Change::Param(i, f32::from(by) * pick(fine, coarse_step)),
        Unit::Angle(fine, coarse_step) => {
            if let Some(reason) = cannot_turn(app) {
                return app.error(reason);
            }
            Change::Turn {
                axis: view_out(app),
                radians: (f32::from(by) * pick(fine, coarse_step)).to_radians(),
            }
        }
    };
    edit(app, change, Some(name), fx);
}

/// Records a finished rig save: the table names the rig file, the recovery file shrinks.
fn saved(app: &mut App, path: PathBuf, file: PathBuf, stamp: FileStamp, fx: &mut Vec<Effect>) {
    if app.doc.table.rig == file {
        app.info(format!("saved the rig to {}", path.display()));
    } else {
        // The table goes with the rig shown: reopened, it must load this rig.
        app.doc.table.rig = file;
        app.info(format!(
            "saved the rig to {}; the table now names it (:w saves the table)",
            path.display()
        ));
    }
    app.rig_edit.path = Some(path);
    app.rig_edit.stamp = Some(stamp);
    app.rig_edit.saved = Some(app.rig().clone());
    // The recovery file now holds only what is still unsaved, if anything.
    fx.push(if app.dirty() {
        Effect::RecoveryDue
    } else {
        Effect::RemoveRecovery
    });
}

/// Why the selected direction cannot be turned in this view, if it cannot: the jaw's axis
/// pointing along the view would not move.
fn cannot_turn(app: &App) -> Option<String> {
    let axis = match app.selected_row() {
        Row::Jaw => app.rig().jaw.as_ref()?.axis,
        Row::Muscle(_) => return None,
    };
    view_angle(app, axis).is_none().then(|| {
        "the jaw's axis points along the view, so turning it about the view changes nothing: \
         turn the view first (e.g. 1 for the front)"
            .to_string()
    })
}

/// Applies a change (and its mirror on the partner in mirror mode) if the model accepts the
/// result, binding again only the muscles changed (or the jaw); otherwise says why on the
/// status line and keeps the rig as it was. The change joins the editor's undo history.
fn edit(app: &mut App, change: Change, part: Option<&str>, fx: &mut Vec<Effect>) {
    let row = app.selected_row();
    let partner = app.partner(row).filter(|_| app.selection.mirror);
    let nothing = || format!("{} has nothing to change there", app.row_name(row));
    let (before, after) = match row {
        Row::Muscle(m) => {
            let rig = app.rig();
            let Some(muscle) = rig.muscles.get(m) else {
                return app.error(nothing());
            };
            let mut before = vec![(m, muscle.kind.clone())];
            if let Some(Row::Muscle(p)) = partner {
                if let Some(other) = rig.muscles.get(p) {
                    before.push((p, other.kind.clone()));
                }
            }
            let mut after = before.clone();
            if !change.to_kind(&mut after[0].1) {
                return app.error(nothing());
            }
            if let Some((_, kind)) = after.get_mut(1) {
                // The face's own plane: a head fitted turned is not mirrored across x = 0.
                let normal = rig.mirror_normal().unwrap_or(Vec3::X);
                change.mirrored(normal).to_kind(kind);
            }
            (RigParts::Muscles(before), RigParts::Muscles(after))
        }
        Row::Jaw => {
            let Some(jaw) = &app.rig().jaw else {
                return app.error("the rig has no jaw");
            };
            let before = JawPose::of(jaw);
            let mut after = before;
            if !change.to_jaw(&mut after) {
                return app.error(nothing());
            }
            (RigParts::Jaw(before), RigParts::Jaw(after))
        }
    };
    let first = app.rig_edit.saved.is_none().then(|| app.rig().clone());
    if let Err(reason) = after.apply(&mut app.doc.face) {
        return app.error(format!("refused: {reason}"));
    }
    if let Some(rig) = first {
        app.rig_edit.saved = Some(rig);
    }
    let also = partner.map_or(String::new(), |p| format!(" (and {})", app.row_name(p)));
    let what = format!("{} {}{also}", app.row_name(row), part.unwrap_or("-"));
    app.history.undo.push(Step::Rig(RigUndo {
        what,
        parts: before,
    }));
    app.history.redo.clear();
    app.history.last_step = None;
    app.rig_edit.shown = None;
    app.history.edits += 1;
    fx.push(Effect::RecoveryDue);
    app.info(format!("{}{also}", describe(app)));
}

/// Puts back the parts of a rig change (undo or redo), returning the change that takes them
/// back again; a change the model now refuses comes back unchanged with the reason.
pub fn put_back(app: &mut App, change: RigUndo) -> Result<RigUndo, (RigUndo, String)> {
    let current = change.parts.current(app.rig());
    if let Err(reason) = change.parts.clone().apply(&mut app.doc.face) {
        return Err((change, reason));
    }
    app.rig_edit.shown = None;
    if !app.rig_edit.on {
        let activations = app.doc.activations.clone();
        app.doc.face.deform(&activations);
    }
    Ok(RigUndo {
        what: change.what,
        parts: current,
    })
}

/// Puts back a rig found in a recovery file, as an unsaved (and undoable) change of the rig
/// as loaded; a rig that no longer fits the mesh is left out, with the reason.
pub fn recover(app: &mut App, rig: Rig) {
    let before = app.rig().clone();
    match app.doc.face.set_rig(rig) {
        Ok(()) => {
            app.rig_edit.saved.get_or_insert_with(|| before.clone());
            app.history.undo.push(Step::Rig(RigUndo {
                what: "the recovered rig".into(),
                parts: RigParts::Whole(Box::new(before)),
            }));
            app.history.redo.clear();
            app.rig_edit.shown = None;
            if !app.rig_edit.on {
                let activations = app.doc.activations.clone();
                app.doc.face.deform(&activations);
            }
        }
        Err(reason) => app.warn(format!("the recovered rig is left out: {reason}")),
    }
}

/// Shows the selected muscle at the held activation while rig mode is on, and the edited
/// activations otherwise. Runs after every action; deforms only when something changed.
pub fn sync(app: &mut App) {
    let generation = app.doc.face.generation();
    if !app.rig_edit.on {
        if let Some((_, _, shown)) = app.rig_edit.shown.take() {
            if shown == generation {
                let activations = app.doc.activations.clone();
                app.doc.face.deform(&activations);
            }
        }
        return;
    }
    let row = app.selected_row();
    let want = (row, app.rig_edit.held);
    if app
        .rig_edit
        .shown
        .is_some_and(|(r, h, g)| (r, h) == want && g == generation)
    {
        return;
    }
    let activations = held_activations(app, row, app.rig_edit.held);
    app.doc.face.deform(&activations);
    app.rig_edit.shown = Some((row, app.rig_edit.held, app.doc.face.generation()));
}

/// The edited activations with `row` set to `held`.
pub fn held_activations(app: &App, row: Row, held: f32) -> Activations {
    let mut activations = app.doc.activations.clone();
    match row {
        Row::Muscle(i) => {
            if let Some(a) = activations.muscles.get_mut(i) {
                *a = held;
            }
        }
        Row::Jaw => activations.jaw = held,
    }
    activations
}

/// The value of parameter `i` of `row`, as shown on the message line.
fn param_value(app: &App, row: Row, i: usize) -> Option<String> {
    let rig = app.rig();
    let angle = |d: Vec3| {
        Some(view_angle(app, d).map_or("along the view".to_string(), |a| format!("{a:.1} deg")))
    };
    match row {
        Row::Muscle(m) => {
            let mut kind = rig.muscles.get(m)?.kind.clone();
            match (&kind, params(Some(&kind)).get(i)?.1) {
                (MuscleKind::Sphincter(s), Unit::Angle(..)) => angle(s.frame.axis_x()),
                _ => param_mut(&mut kind, i).map(|v| format!("{v:.4}")),
            }
        }
        Row::Jaw => {
            let jaw = rig.jaw.as_ref()?;
            match i {
                0 => Some(format!("{:.4}", jaw.degrees_per_unit)),
                _ => angle(jaw.axis),
            }
        }
    }
}

/// The selected muscle, point and parameter with their values, for the message line.
pub fn describe(app: &App) -> String {
    let row = app.selected_row();
    let kind = kind_of(app.rig(), row);
    let points = point_names(kind);
    let pi = app.rig_edit.point.min(points.len().saturating_sub(1));
    let at = point(app.rig(), row, pi).map_or(String::new(), |p| {
        format!(" ({:.4}, {:.4}, {:.4})", p.x, p.y, p.z)
    });
    let list = params(kind);
    let ki = app.rig_edit.param.min(list.len().saturating_sub(1));
    let param = match (list.get(ki), param_value(app, row, ki)) {
        (Some((name, _)), Some(v)) => format!("  {name} {v}"),
        _ => String::new(),
    };
    format!(
        "{} held at {:.2}: {}{at}{param}",
        app.row_name(row),
        app.rig_edit.held,
        points.get(pi).copied().unwrap_or("-"),
    )
}

/// `:w` in rig mode: writes the rig to `to`, or to its own file. A built-in rig has none, so
/// the command line opens again asking for one.
pub fn save(app: &mut App, to: Option<PathBuf>, fx: &mut Vec<Effect>) {
    let Some(path) = to.clone().or_else(|| app.rig_edit.path.clone()) else {
        app.mode = Mode::Input(Input::new(InputKind::Command, "w "));
        app.warn("the built-in rig has no file: type a file name to save it as (e.g. my.rig.ron)");
        return;
    };
    let rig = app.rig().clone();
    if let Err(issue) = check_rig(&rig) {
        return app.error(format!("the rig is not saved: {issue}"));
    }
    let expected = if Some(&path) == app.rig_edit.path.as_ref() {
        app.rig_edit.stamp
    } else {
        None
    };
    fx.push(Effect::SaveRig {
        path,
        rig: Box::new(rig),
        expected,
    });
}

/// The rig-mode action for the outcome of a rig save (run by the event loop: it reads
/// where the file really is).
pub fn saved_action(outcome: Action) -> Action {
    Action::Rig(match outcome {
        Action::Saved { path, stamp, .. } => RigAction::Saved {
            file: crate::io::reference::real_path(&path),
            path,
            stamp,
        },
        Action::SaveFailed { path, error } => RigAction::SaveFailed { path, error },
        Action::SaveConflict { path, .. } => RigAction::SaveFailed {
            error: "it changed on disk since it was loaded; save under another name with :w FILE"
                .into(),
            path,
        },
        other => return other,
    })
}

#[cfg(test)]
mod tests;
