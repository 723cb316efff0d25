//! Rig mode (`R`): placing muscles. The selected muscle (or the jaw) is held at an activation
//! so its pull stays visible, its points move in the view plane and its parameters change by
//! steps; every change is checked by the model before it is kept, and can be undone.
//!
//! State lives in [`RigEdit`], changes in the pure [`update`]; the event loop writes the rig
//! file for [`Effect::SaveRig`].

use std::path::{Path, PathBuf};

use glam::{Mat3, Vec3};

use super::action::{Action, Effect};
use super::app::{App, FileStamp, Input, InputKind, Mode, Row};
use crate::io::rig_file::{check_rig, rig_to_ron};
use crate::model::muscle::mirror_x;
use crate::model::{Activations, MuscleKind, Rig};

/// Fine step of a point or a length, as a fraction of the face's height.
pub const FINE_FRACTION: f32 = 0.005;
/// Coarse step of a point or a length, as a fraction of the face's height.
pub const COARSE_FRACTION: f32 = 0.025;
/// Said when a command would leave with the rig's changes unsaved.
pub const UNSAVED_RIG: &str =
    "the rig has unsaved changes: :w in rig mode (R) saves it, :q! discards it";

/// Step of the held activation (`<` and `>`).
pub const HELD_STEP: f32 = 0.25;

/// What rig mode knows: whether it is on, the rig's file, the selected point and parameter,
/// the held activation and the rig's own undo history.
#[derive(Debug, Clone, PartialEq)]
pub struct RigEdit {
    /// Rig mode is on.
    pub on: bool,
    /// The rig file `:w` writes; `None` for a built-in rig (`:w` asks for a name).
    pub path: Option<PathBuf>,
    /// The rig file as loaded or last saved, to notice changes made by others.
    pub stamp: Option<FileStamp>,
    /// The rig as loaded or last saved, once it has been edited.
    pub saved: Option<Rig>,
    /// Index of the selected point of the selected muscle (`Tab` cycles).
    pub point: usize,
    /// Index of the selected parameter of the selected muscle (`p` cycles).
    pub param: usize,
    /// The activation the selected muscle is held at.
    pub held: f32,
    /// Rigs to go back to.
    pub undo: Vec<Rig>,
    /// Rigs undone.
    pub redo: Vec<Rig>,
    /// What the face shows: the row held, its activation and the scene generation after
    /// deforming, so a change made elsewhere is noticed and the hold applied again.
    shown: Option<(Row, f32, u64)>,
}

impl Default for RigEdit {
    fn default() -> RigEdit {
        RigEdit {
            on: false,
            path: None,
            stamp: None,
            saved: None,
            point: 0,
            param: 0,
            held: 1.0,
            undo: Vec::new(),
            redo: Vec::new(),
            shown: None,
        }
    }
}

impl RigEdit {
    /// Rig mode for a rig loaded from `path` (`None`: built in) with these file contents.
    pub fn for_file(path: Option<PathBuf>, contents: Option<&[u8]>) -> RigEdit {
        RigEdit {
            path,
            stamp: contents.map(FileStamp::of),
            ..RigEdit::default()
        }
    }

    /// True when the rig differs from its file.
    pub fn dirty(&self, rig: &Rig) -> bool {
        self.saved.as_ref().is_some_and(|saved| saved != rig)
    }
}

/// A rig-mode intent.
#[derive(Debug, Clone, PartialEq)]
pub enum RigAction {
    /// Enter or leave rig mode.
    Toggle,
    /// Select the next point of the selected muscle.
    NextPoint,
    /// Select the next parameter of the selected muscle.
    NextParam,
    /// Move the selected point in the view plane by steps (right, up).
    Move {
        /// Steps to the screen's right.
        right: i8,
        /// Steps up the screen.
        up: i8,
        /// Coarse steps.
        coarse: bool,
    },
    /// Change the selected parameter by steps.
    Param {
        /// Steps (negative: down).
        by: i8,
        /// Coarse steps.
        coarse: bool,
    },
    /// Change the held activation by steps of [`HELD_STEP`].
    Held(i8),
    /// Undo the last rig change.
    Undo,
    /// Redo the last undone rig change.
    Redo,
    /// The rig file was written.
    Saved {
        /// Where.
        path: PathBuf,
        /// Its new stamp.
        stamp: FileStamp,
    },
    /// Writing the rig file failed (or found it changed on disk).
    SaveFailed {
        /// The file.
        path: PathBuf,
        /// Why.
        error: String,
    },
}

/// The points of a muscle kind (or the jaw, `None`), in `Tab` order.
pub fn point_names(kind: Option<&MuscleKind>) -> &'static [&'static str] {
    match kind {
        Some(MuscleKind::Linear(_)) => &["attachment", "insertion"],
        Some(MuscleKind::Sphincter(_)) => &["centre"],
        Some(MuscleKind::Sheet(_)) => &[
            "attachment end 1",
            "attachment end 2",
            "insertion end 1",
            "insertion end 2",
        ],
        None => &["pivot"],
    }
}

/// How a parameter steps: by lengths scaled to the face, or by fixed amounts.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Unit {
    /// A length: steps are fractions of the face's height.
    Length,
    /// A plain number with its fine and coarse steps.
    Fixed(f32, f32),
}

/// The parameters of a muscle kind (or the jaw, `None`), in `p` order.
fn params(kind: Option<&MuscleKind>) -> &'static [(&'static str, Unit)] {
    match kind {
        Some(MuscleKind::Linear(_)) => &[
            ("zone", Unit::Fixed(1.0, 5.0)),
            ("falloff start", Unit::Length),
            ("falloff end", Unit::Length),
        ],
        Some(MuscleKind::Sphincter(_)) => &[
            ("semi-major", Unit::Length),
            ("semi-minor", Unit::Length),
            ("bulge", Unit::Fixed(1.0, 5.0)),
        ],
        Some(MuscleKind::Sheet(_)) => &[("length", Unit::Length), ("width", Unit::Length)],
        None => &[("degrees per unit", Unit::Fixed(0.1, 0.5))],
    }
}

/// The parameter names of a muscle kind (or the jaw), in `p` order.
pub fn param_names(kind: Option<&MuscleKind>) -> Vec<&'static str> {
    params(kind).iter().map(|(name, _)| *name).collect()
}

fn point_mut(kind: &mut MuscleKind, i: usize) -> Option<&mut Vec3> {
    match kind {
        MuscleKind::Linear(m) => [&mut m.attachment, &mut m.insertion].into_iter().nth(i),
        MuscleKind::Sphincter(m) => (i == 0).then_some(&mut m.centre),
        MuscleKind::Sheet(m) => {
            let [a0, a1] = &mut m.attachment;
            let [i0, i1] = &mut m.insertion;
            [a0, a1, i0, i1].into_iter().nth(i)
        }
    }
}

/// The point `i` of a muscle kind (or the jaw's pivot for `None`), as stored.
pub fn point(rig: &Rig, row: Row, i: usize) -> Option<Vec3> {
    let mut rig = rig.clone();
    match row {
        Row::Muscle(m) => point_mut(&mut rig.muscles.get_mut(m)?.kind, i).copied(),
        Row::Jaw => rig.jaw.map(|j| j.pivot).filter(|_| i == 0),
    }
}

fn param_mut(kind: &mut MuscleKind, i: usize) -> Option<&mut f32> {
    match kind {
        MuscleKind::Linear(m) => [&mut m.zone, &mut m.falloff_start, &mut m.falloff_end]
            .into_iter()
            .nth(i),
        MuscleKind::Sphincter(m) => [&mut m.semi_major, &mut m.semi_minor, &mut m.bulge]
            .into_iter()
            .nth(i),
        MuscleKind::Sheet(m) => [&mut m.length, &mut m.width].into_iter().nth(i),
    }
}

/// One change to a muscle or the jaw.
#[derive(Debug, Clone, Copy)]
enum Change {
    /// Move point `i` by a vector.
    Move(usize, Vec3),
    /// Add to parameter `i`.
    Param(usize, f32),
}

impl Change {
    /// The same change on the mirror partner: moves reflected across x = 0.
    fn mirrored(self) -> Change {
        match self {
            Change::Move(i, by) => Change::Move(i, mirror_x(by)),
            other => other,
        }
    }
}

/// Applies a change to row `row` of `rig`; false if the row has no such point or parameter.
fn apply_change(rig: &mut Rig, row: Row, change: Change) -> bool {
    match row {
        Row::Muscle(m) => {
            let Some(muscle) = rig.muscles.get_mut(m) else {
                return false;
            };
            match change {
                Change::Move(i, by) => point_mut(&mut muscle.kind, i).map(|p| *p += by),
                Change::Param(i, by) => param_mut(&mut muscle.kind, i).map(|v| *v += by),
            }
            .is_some()
        }
        Row::Jaw => match (&mut rig.jaw, change) {
            (Some(jaw), Change::Move(0, by)) => {
                jaw.pivot += by;
                true
            }
            (Some(jaw), Change::Param(0, by)) => {
                jaw.degrees_per_unit += by;
                true
            }
            _ => false,
        },
    }
}

fn kind_of(rig: &Rig, row: Row) -> Option<&MuscleKind> {
    match row {
        Row::Muscle(m) => rig.muscles.get(m).map(|m| &m.kind),
        Row::Jaw => None,
    }
}

/// The face's height: the scale of point and length steps.
fn face_size(app: &App) -> f32 {
    let (lo, hi) = app.doc.scene.mesh().bounds();
    (hi - lo).y.max(f32::EPSILON)
}

/// The screen's right and up directions in mesh coordinates, for the current view.
pub fn view_axes(app: &App) -> (Vec3, Vec3) {
    let view = Mat3::from_rotation_x(app.view.pitch.to_radians())
        * Mat3::from_rotation_y(-app.view.yaw.to_radians());
    let back = view.transpose();
    (back * Vec3::X, back * Vec3::Y)
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
            app.rig_edit.point = (app.rig_edit.point + 1) % n.max(1);
            app.info(describe(app));
        }
        RigAction::NextParam => {
            let n = params(kind_of(app.rig(), app.selected_row())).len();
            app.rig_edit.param = (app.rig_edit.param + 1) % n.max(1);
            app.info(describe(app));
        }
        RigAction::Move { right, up, coarse } => {
            let step = face_size(app)
                * if coarse {
                    COARSE_FRACTION
                } else {
                    FINE_FRACTION
                };
            let (r, u) = view_axes(app);
            let by = (r * f32::from(right) + u * f32::from(up)) * step;
            let n = point_names(kind_of(app.rig(), app.selected_row())).len();
            let change = Change::Move(app.rig_edit.point.min(n.saturating_sub(1)), by);
            edit(app, change, fx);
        }
        RigAction::Param { by, coarse } => {
            let list = params(kind_of(app.rig(), app.selected_row()));
            let i = app.rig_edit.param.min(list.len().saturating_sub(1));
            let step = match list.get(i).map(|p| p.1) {
                Some(Unit::Length) => {
                    face_size(app)
                        * if coarse {
                            COARSE_FRACTION
                        } else {
                            FINE_FRACTION
                        }
                }
                Some(Unit::Fixed(fine, coarse_step)) => {
                    if coarse {
                        coarse_step
                    } else {
                        fine
                    }
                }
                None => return,
            };
            edit(app, Change::Param(i, f32::from(by) * step), fx);
        }
        RigAction::Held(by) => {
            let (lo, hi) = app.range(app.selected_row());
            let held = (app.rig_edit.held + f32::from(by) * HELD_STEP).clamp(lo.max(0.0), hi);
            app.rig_edit.held = held;
            app.info(format!("held at {held:.2}"));
        }
        RigAction::Undo => back(app, true, fx),
        RigAction::Redo => back(app, false, fx),
        RigAction::Saved { path, stamp } => {
            app.info(format!("saved the rig to {}", path.display()));
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
        RigAction::SaveFailed { path, error } => app.error(format!(
            "could not save the rig to {}: {error}; your edits are kept",
            path.display()
        )),
    }
    sync(app);
}

/// Applies a change (and its mirror on the partner in mirror mode) if the model accepts the
/// result; otherwise says why on the status line and keeps the rig as it was.
fn edit(app: &mut App, change: Change, fx: &mut Vec<Effect>) {
    let row = app.selected_row();
    let mut rig = app.rig().clone();
    if !apply_change(&mut rig, row, change) {
        return app.error(format!("{} has nothing to change there", app.row_name(row)));
    }
    let partner = app.partner(row).filter(|_| app.selection.mirror);
    if let Some(p) = partner {
        apply_change(&mut rig, p, change.mirrored());
    }
    if let Err(reason) = check_rig(&rig)
        .map_err(|issue| issue.to_string())
        .and_then(|()| app.doc.scene.check_rig(&rig))
    {
        return app.error(format!("refused: {reason}"));
    }
    let before = app.rig().clone();
    if let Err(reason) = app.doc.scene.set_rig(rig) {
        return app.error(format!("refused: {reason}"));
    }
    app.rig_edit.saved.get_or_insert_with(|| before.clone());
    app.rig_edit.undo.push(before);
    app.rig_edit.redo.clear();
    app.rig_edit.shown = None;
    app.history.edits += 1;
    fx.push(Effect::RecoveryDue);
    let also = partner.map_or(String::new(), |p| format!(" (and {})", app.row_name(p)));
    app.info(format!("{}{also}", describe(app)));
}

fn back(app: &mut App, undo: bool, fx: &mut Vec<Effect>) {
    let (from, to) = if undo {
        (&mut app.rig_edit.undo, "undo")
    } else {
        (&mut app.rig_edit.redo, "redo")
    };
    let Some(rig) = from.pop() else {
        return app.info(format!("nothing to {to} in the rig"));
    };
    let current = app.rig().clone();
    match app.doc.scene.set_rig(rig) {
        Ok(()) => {
            if undo {
                app.rig_edit.redo.push(current);
            } else {
                app.rig_edit.undo.push(current);
            }
            app.rig_edit.shown = None;
            app.history.edits += 1;
            fx.push(Effect::RecoveryDue);
            app.info(format!("{to}: {}", describe(app)));
        }
        Err(reason) => app.error(format!("cannot {to}: {reason}")),
    }
}

/// Puts back a rig found in a recovery file, as an unsaved (and undoable) change of the rig
/// as loaded; a rig that no longer fits the mesh is left out, with the reason.
pub fn recover(app: &mut App, rig: Rig) {
    let before = app.rig().clone();
    match app.doc.scene.set_rig(rig) {
        Ok(()) => {
            app.rig_edit.saved.get_or_insert_with(|| before.clone());
            app.rig_edit.undo.push(before);
            app.rig_edit.redo.clear();
            app.rig_edit.shown = None;
        }
        Err(reason) => app.warn(format!("the recovered rig is left out: {reason}")),
    }
}

/// Shows the selected muscle at the held activation while rig mode is on, and the edited
/// activations otherwise. Runs after every action; deforms only when something changed.
pub fn sync(app: &mut App) {
    let generation = app.doc.scene.generation();
    if !app.rig_edit.on {
        if let Some((_, _, shown)) = app.rig_edit.shown.take() {
            if shown == generation {
                let activations = app.doc.activations.clone();
                app.doc.scene.deform(&activations);
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
    app.doc.scene.deform(&activations);
    app.rig_edit.shown = Some((row, app.rig_edit.held, app.doc.scene.generation()));
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
    let value = {
        let mut rig = app.rig().clone();
        match row {
            Row::Muscle(m) => rig
                .muscles
                .get_mut(m)
                .and_then(|m| param_mut(&mut m.kind, ki).copied()),
            Row::Jaw => rig.jaw.map(|j| j.degrees_per_unit),
        }
    };
    let param = match (list.get(ki), value) {
        (Some((name, _)), Some(v)) => format!("  {name} {v:.4}"),
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
    let mut rig = app.rig().clone();
    rig.mesh = mesh_for(&rig.mesh, app.rig_edit.path.as_deref(), &path);
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
        contents: rig_to_ron(&rig),
        expected,
    });
}

/// The rig's mesh reference as seen from a rig file at `to`: built-in and absolute
/// references stay; a relative one is resolved against the rig's old folder and written
/// relative to the new one when the folder is the same, absolute otherwise.
fn mesh_for(mesh: &Path, from: Option<&Path>, to: &Path) -> PathBuf {
    let text = mesh.to_string_lossy();
    if text.starts_with("builtin:") || mesh.is_absolute() {
        return mesh.to_path_buf();
    }
    let old_dir = from.and_then(Path::parent).unwrap_or(Path::new(""));
    let new_dir = to.parent().unwrap_or(Path::new(""));
    if old_dir == new_dir {
        return mesh.to_path_buf();
    }
    let joined = old_dir.join(mesh);
    std::path::absolute(&joined).unwrap_or(joined)
}

/// The rig-mode action for the outcome of a rig save.
pub fn saved_action(outcome: Action) -> Action {
    Action::Rig(match outcome {
        Action::Saved { path, stamp, .. } => RigAction::Saved { path, stamp },
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
mod tests {
    use super::*;
    use crate::tui::fixture;
    use crate::tui::update::update as run;

    fn rig_app() -> App {
        let mut app = fixture::app();
        run(&mut app, Action::Rig(RigAction::Toggle));
        app
    }

    fn linear(app: &App, i: usize) -> crate::model::Linear {
        match &app.rig().muscles[i].kind {
            MuscleKind::Linear(l) => l.clone(),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn the_selected_muscle_is_held_and_released() {
        let mut app = fixture::app();
        let rest = app.doc.scene.positions().to_vec();
        run(&mut app, Action::Rig(RigAction::Toggle));
        assert_ne!(app.doc.scene.positions(), rest.as_slice());
        assert!(app.doc.activations.is_rest(), "holding is not an edit");
        run(&mut app, Action::Rig(RigAction::Toggle));
        assert_eq!(app.doc.scene.positions(), rest.as_slice());
    }

    #[test]
    fn moving_a_point_goes_right_in_the_front_view_and_undoes() {
        let mut app = rig_app();
        let Row::Muscle(i) = app.selected_row() else {
            panic!("a muscle is selected first")
        };
        let before = linear(&app, i);
        run(
            &mut app,
            Action::Rig(RigAction::Move {
                right: 1,
                up: 0,
                coarse: true,
            }),
        );
        let after = linear(&app, i);
        let step = face_size(&app) * COARSE_FRACTION;
        assert_ne!(after, before, "{:?}", app.message);
        assert!((after.attachment.x - before.attachment.x - step).abs() < 1e-6);
        assert_eq!(after.attachment.y, before.attachment.y);
        assert_eq!(after.insertion, before.insertion);
        assert!(app.rig_edit.dirty(app.rig()));
        run(&mut app, Action::Rig(RigAction::Undo));
        assert_eq!(linear(&app, i), before);
        run(&mut app, Action::Rig(RigAction::Redo));
        assert_eq!(linear(&app, i), after);
    }

    #[test]
    fn mirror_mode_moves_the_partner_the_other_way() {
        let mut app = rig_app();
        let Row::Muscle(i) = app.selected_row() else {
            panic!()
        };
        let p = app.rig().mirror_of(i).expect("fixture pair");
        let before = linear(&app, p);
        run(&mut app, Action::ToggleMirror);
        run(
            &mut app,
            Action::Rig(RigAction::Move {
                right: 1,
                up: 1,
                coarse: false,
            }),
        );
        let step = face_size(&app) * FINE_FRACTION;
        let after = linear(&app, p);
        assert!((after.attachment.x - (before.attachment.x - step)).abs() < 1e-6);
        assert!((after.attachment.y - (before.attachment.y + step)).abs() < 1e-6);
    }

    #[test]
    fn an_invalid_value_is_refused_with_the_reason() {
        let mut app = rig_app();
        let Row::Muscle(i) = app.selected_row() else {
            panic!()
        };
        let before = app.rig().clone();
        // The zone must stay below 90 degrees.
        for _ in 0..20 {
            run(
                &mut app,
                Action::Rig(RigAction::Param {
                    by: 1,
                    coarse: true,
                }),
            );
        }
        let zone = linear(&app, i).zone;
        assert!((85.0..90.0).contains(&zone), "{zone}");
        let message = app.message.clone().unwrap();
        assert_eq!(message.severity, crate::tui::app::Severity::Error);
        assert!(message.text.contains("zone"), "{}", message.text);
        assert_ne!(app.rig(), &before);
    }

    #[test]
    fn write_and_quit_does_not_leave_an_unsaved_rig_behind() {
        let mut app = rig_app();
        let step = Action::Rig(RigAction::Move {
            right: 0,
            up: 1,
            coarse: false,
        });
        run(&mut app, step);
        let fx = run(&mut app, Action::Command("wq".into()));
        assert!(!fx.contains(&Effect::Quit), "{fx:?}");
        assert_eq!(app.message.as_ref().unwrap().text, UNSAVED_RIG);
        // Plain quit asks.
        run(&mut app, Action::Quit);
        assert!(matches!(app.mode, Mode::Confirm(_)));
    }

    #[test]
    fn the_zone_overlay_follows_the_kind() {
        use crate::render::Shape;
        let mut app = rig_app();
        let mut out = Vec::new();
        crate::tui::view::rig::zone_overlays(&app, &mut out);
        // A linear muscle: two cone edges, two arcs of segments, and the point's mark.
        assert!(out.len() > 5, "{}", out.len());
        assert!(matches!(out.last().unwrap().shape, Shape::Point { .. }));
        let last = app.selection.rows.len() - 1;
        app.selection.selected = last; // the jaw
        out.clear();
        crate::tui::view::rig::zone_overlays(&app, &mut out);
        let jaw = app.rig().jaw.as_ref().unwrap();
        // One coloured mark per weighted vertex, plus the pivot's.
        assert_eq!(out.len(), jaw.weights.len() + 1);
    }

    #[test]
    fn a_built_in_rig_asks_for_a_file_name() {
        let mut app = rig_app();
        let mut fx = Vec::new();
        save(&mut app, None, &mut fx);
        assert!(fx.is_empty());
        assert!(matches!(&app.mode, Mode::Input(i) if i.text == "w "));
        save(&mut app, Some(PathBuf::from("a.rig.ron")), &mut fx);
        assert!(matches!(&fx[..], [Effect::SaveRig { expected: None, .. }]));
    }
}
