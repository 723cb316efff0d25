//! Rig mode (`R`): placing muscles. The selected muscle (or the jaw) is held at an activation
//! so its pull stays visible, its points move in the view plane and its parameters change by
//! steps; every change is checked by the model before it is kept, and can be undone.
//!
//! State lives in [`RigEdit`], changes in the pure [`update`]; the event loop writes the rig
//! file for [`Effect::SaveRig`].

use std::path::PathBuf;

use glam::{Quat, Vec3};

use super::action::{Action, Effect};
use super::app::{App, FileStamp, Input, InputKind, Mode, Row, Step};
use crate::io::rig_file::check_rig;
use crate::model::rig::reflect;
use crate::model::{Activations, Jaw, MuscleKind, Rig};

/// Fine step of a point or a length, as a fraction of the face's height.
pub const FINE_FRACTION: f32 = 0.005;
/// Coarse step of a point or a length, as a fraction of the face's height.
pub const COARSE_FRACTION: f32 = 0.025;
/// Said when a command would leave with the rig's changes unsaved.
pub const UNSAVED_RIG: &str =
    "the rig has unsaved changes: :w in rig mode (R) saves it, :q! discards it";

/// Step of the held activation (`<` and `>`).
pub const HELD_STEP: f32 = 0.25;

/// What rig mode knows: whether it is on, the rig's file, the selected point and parameter
/// and the held activation. Its changes are undone with the rest of the editor's edits
/// ([`crate::tui::app::History`]), each kept as a [`RigUndo`].
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
    /// Change the selected parameter by steps (an angle turns counter-clockwise on screen).
    Param {
        /// Steps (negative: down).
        by: i8,
        /// Coarse steps.
        coarse: bool,
    },
    /// Change the held activation by steps of [`HELD_STEP`].
    Held(i8),
    /// The rig file was written.
    Saved {
        /// Where, as the user gave it.
        path: PathBuf,
        /// The file written, absolute: what the table names from now on.
        file: PathBuf,
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

/// The jaw's pose: what rig mode changes of the jaw (its weights stay).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JawPose {
    /// The point the jaw turns about.
    pub pivot: Vec3,
    /// The axis it turns about.
    pub axis: Vec3,
    /// Degrees per unit of jaw activation.
    pub degrees_per_unit: f32,
}

impl JawPose {
    fn of(jaw: &Jaw) -> JawPose {
        JawPose {
            pivot: jaw.pivot,
            axis: jaw.axis,
            degrees_per_unit: jaw.degrees_per_unit,
        }
    }
}

/// Parts of a rig, as rig mode changes them and undo puts them back.
#[derive(Debug, Clone, PartialEq)]
pub enum RigParts {
    /// Muscles' kinds with their parameters, by index (a muscle and its mirror partner).
    Muscles(Vec<(usize, MuscleKind)>),
    /// The jaw's pose.
    Jaw(JawPose),
    /// A whole rig (one put back from a recovery file).
    Whole(Box<Rig>),
}

impl RigParts {
    /// The same parts as they are in `rig` now.
    fn current(&self, rig: &Rig) -> RigParts {
        match self {
            RigParts::Muscles(list) => RigParts::Muscles(
                list.iter()
                    .filter_map(|(i, _)| Some((*i, rig.muscles.get(*i)?.kind.clone())))
                    .collect(),
            ),
            RigParts::Jaw(pose) => RigParts::Jaw(rig.jaw.as_ref().map_or(*pose, JawPose::of)),
            RigParts::Whole(_) => RigParts::Whole(Box::new(rig.clone())),
        }
    }

    /// Puts the parts into the scene's rig, binding again only what they touch.
    fn apply(self, scene: &mut super::scene::Scene) -> Result<(), String> {
        match self {
            RigParts::Muscles(list) => scene.rebind_muscles(list),
            RigParts::Jaw(p) => scene.rebind_jaw(p.pivot, p.axis, p.degrees_per_unit),
            RigParts::Whole(rig) => scene.set_rig(*rig),
        }
    }
}

/// A rig change as the editor's history keeps it: what changed, and the parts to put back.
#[derive(Debug, Clone, PartialEq)]
pub struct RigUndo {
    /// What the change was to, for the message line (`L_Zygomatic_Major attachment`).
    pub what: String,
    /// The parts as they were before the change.
    pub parts: RigParts,
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

/// How a parameter steps: by lengths scaled to the face, by fixed amounts, or by turning.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Unit {
    /// A length: steps are fractions of the face's height.
    Length,
    /// A plain number with its fine and coarse steps.
    Fixed(f32, f32),
    /// A direction turned about the view axis by fine and coarse steps in degrees; its
    /// value is its angle in the view plane, counter-clockwise from the screen's right.
    Angle(f32, f32),
}

/// Name of the sphincter's frame parameter.
const FRAME_ANGLE: &str = "frame angle";
/// Name of the jaw's axis parameter.
const AXIS_ANGLE: &str = "axis angle";

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
            (FRAME_ANGLE, Unit::Angle(1.0, 5.0)),
        ],
        Some(MuscleKind::Sheet(_)) => &[("length", Unit::Length), ("width", Unit::Length)],
        None => &[
            ("degrees per unit", Unit::Fixed(0.1, 0.5)),
            (AXIS_ANGLE, Unit::Angle(1.0, 5.0)),
        ],
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
    match row {
        Row::Muscle(m) => point_mut(&mut rig.muscles.get(m)?.kind.clone(), i).copied(),
        Row::Jaw => rig.jaw.as_ref().map(|j| j.pivot).filter(|_| i == 0),
    }
}

/// The numeric (length or fixed) parameter `i` of a muscle kind.
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
    /// Add to the numeric parameter `i`.
    Param(usize, f32),
    /// Turn the direction parameter (a sphincter's frame, the jaw's axis) about `axis` by
    /// `radians` (right-hand rule).
    Turn {
        /// The unit axis of the turn.
        axis: Vec3,
        /// The angle.
        radians: f32,
    },
}

impl Change {
    /// The same change on the mirror partner: moves reflected across the face's mirror plane
    /// (unit normal `normal`), turns reflected too (the reflected axis, the opposite sense).
    fn mirrored(self, normal: Vec3) -> Change {
        match self {
            Change::Move(i, by) => Change::Move(i, reflect(by, normal)),
            Change::Turn { axis, radians } => Change::Turn {
                axis: reflect(axis, normal),
                radians: -radians,
            },
            other => other,
        }
    }

    /// Applies the change to a muscle kind; false if it has no such point or parameter.
    fn to_kind(self, kind: &mut MuscleKind) -> bool {
        match (self, kind) {
            (Change::Move(i, by), kind) => point_mut(kind, i).map(|p| *p += by).is_some(),
            (Change::Param(i, by), kind) => param_mut(kind, i).map(|v| *v += by).is_some(),
            (Change::Turn { axis, radians }, MuscleKind::Sphincter(m)) => {
                let turn = Quat::from_axis_angle(axis, radians);
                m.frame.x = turn * m.frame.x;
                m.frame.y = turn * m.frame.y;
                true
            }
            (Change::Turn { .. }, _) => false,
        }
    }

    /// Applies the change to the jaw's pose; false if it has no such point or parameter.
    fn to_jaw(self, pose: &mut JawPose) -> bool {
        match self {
            Change::Move(0, by) => pose.pivot += by,
            Change::Param(0, by) => pose.degrees_per_unit += by,
            Change::Turn { axis, radians } => {
                pose.axis = Quat::from_axis_angle(axis, radians) * pose.axis;
            }
            _ => return false,
        }
        true
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
    app.doc.scene.framing().height()
}

/// The screen's right and up directions in mesh coordinates, for the current view.
pub fn view_axes(app: &App) -> (Vec3, Vec3) {
    let back = super::view::viewport::camera(app).view_matrix().transpose();
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
        RigAction::Move { right, up, coarse } => {
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
        RigAction::Param { by, coarse } => {
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
                Unit::Fixed(fine, coarse_step) => {
                    Change::Param(i, f32::from(by) * pick(fine, coarse_step))
                }
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
        RigAction::Held(by) => {
            let (lo, hi) = app.range(app.selected_row());
            let held = (app.rig_edit.held + f32::from(by) * HELD_STEP).clamp(lo.max(0.0), hi);
            app.rig_edit.held = held;
            app.info(format!("held at {held:.2}"));
        }
        RigAction::Saved { path, file, stamp } => {
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
        RigAction::SaveFailed { path, error } => app.error(format!(
            "could not save the rig to {}: {error}; your edits are kept",
            path.display()
        )),
    }
    sync(app);
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
    if let Err(reason) = after.apply(&mut app.doc.scene) {
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
    if let Err(reason) = change.parts.clone().apply(&mut app.doc.scene) {
        return Err((change, reason));
    }
    app.rig_edit.shown = None;
    if !app.rig_edit.on {
        let activations = app.doc.activations.clone();
        app.doc.scene.deform(&activations);
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
    match app.doc.scene.set_rig(rig) {
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
                app.doc.scene.deform(&activations);
            }
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
        run(&mut app, Action::Undo);
        assert_eq!(linear(&app, i), before);
        run(&mut app, Action::Redo);
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
        // One coloured mark per weighted vertex, the axis line and the pivot's mark.
        assert_eq!(out.len(), jaw.weights.len() + 2);
    }

    fn select(app: &mut App, name: &str) -> usize {
        let i = app.rig().muscle_index(name).expect("the muscle");
        run(app, Action::SelectRow(Row::Muscle(i)));
        assert_eq!(app.selected_row(), Row::Muscle(i));
        i
    }

    fn param(app: &mut App, by: i8, coarse: bool) {
        run(app, Action::Rig(RigAction::Param { by, coarse }));
    }

    fn sphincter(app: &App, i: usize) -> crate::model::Sphincter {
        match &app.rig().muscles[i].kind {
            MuscleKind::Sphincter(s) => s.clone(),
            other => panic!("{other:?}"),
        }
    }

    /// The default face in an editor, rig mode on.
    fn default_app() -> App {
        let (rig, mesh, table) = crate::cli::edit::default_face().expect("the built-in face");
        let scene = crate::tui::scene::Scene::new(rig, mesh).expect("binds");
        let mut app = App::new(scene, table, None);
        run(&mut app, Action::Rig(RigAction::Toggle));
        app
    }

    /// The rig as bound from scratch deforms the held face exactly as the rebound one.
    fn assert_bound_as_from_scratch(app: &App) {
        let scratch = crate::model::Deformation::default()
            .bind(app.rig(), app.doc.scene.mesh())
            .unwrap();
        let activations = held_activations(app, app.selected_row(), app.rig_edit.held);
        let mut out = Vec::new();
        scratch.deform(&activations, &mut out).unwrap();
        let bits = |p: &[Vec3]| -> Vec<[u32; 3]> {
            p.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
        };
        assert_eq!(bits(app.doc.scene.positions()), bits(&out));
    }

    #[test]
    fn the_sphincter_frame_turns_about_the_view_and_mirrors_and_undoes() {
        let mut app = default_app();
        let l = select(&mut app, "L_Orbicularis_Oculi");
        let r = app.rig().mirror_of(l).expect("the eyes are a pair");
        let (l0, r0) = (sphincter(&app, l), sphincter(&app, r));
        run(&mut app, Action::ToggleMirror);
        run(&mut app, Action::Rig(RigAction::NextParam));
        run(&mut app, Action::Rig(RigAction::NextParam));
        run(&mut app, Action::Rig(RigAction::NextParam));
        assert!(describe(&app).contains("frame angle"), "{}", describe(&app));
        let angle_l = view_angle(&app, l0.frame.axis_x()).unwrap();
        let angle_r = view_angle(&app, r0.frame.axis_x()).unwrap();
        param(&mut app, 1, true);
        let (l1, r1) = (sphincter(&app, l), sphincter(&app, r));
        // Counter-clockwise on screen by 5 degrees; the partner clockwise by as much.
        let turned_l = view_angle(&app, l1.frame.axis_x()).unwrap();
        let turned_r = view_angle(&app, r1.frame.axis_x()).unwrap();
        assert!(
            (turned_l - angle_l - 5.0).abs() < 1e-3,
            "{angle_l} -> {turned_l}"
        );
        assert!(
            (turned_r - angle_r + 5.0).abs() < 1e-3,
            "{angle_r} -> {turned_r}"
        );
        assert!(app.message.as_ref().unwrap().text.contains("deg"));
        // The frame stays a frame: the ellipse keeps its plane's normal facing the viewer.
        assert!(l1.frame.check().is_ok());
        assert_eq!((l1.centre, l1.semi_major), (l0.centre, l0.semi_major));
        assert_bound_as_from_scratch(&app);
        run(&mut app, Action::Undo);
        assert_eq!((sphincter(&app, l), sphincter(&app, r)), (l0, r0));
        assert_bound_as_from_scratch(&app);
        run(&mut app, Action::Redo);
        assert_eq!((sphincter(&app, l), sphincter(&app, r)), (l1, r1));
    }

    #[test]
    fn the_jaw_pivot_axis_and_degrees_change_and_undo_in_order() {
        let mut app = rig_app();
        run(&mut app, Action::SelectRow(Row::Jaw));
        let jaw0 = app.rig().jaw.clone().unwrap();
        // The side view looks along the axis: turning it is refused with the reason.
        run(&mut app, Action::Preset(crate::tui::app::ViewPreset::Side));
        run(&mut app, Action::Rig(RigAction::NextParam));
        assert!(
            describe(&app).contains("axis angle along the view"),
            "{}",
            describe(&app)
        );
        param(&mut app, 1, false);
        assert_eq!(app.rig().jaw.as_ref(), Some(&jaw0));
        assert!(app
            .message
            .as_ref()
            .unwrap()
            .text
            .contains("along the view"));
        assert!(app.history.undo.is_empty());
        run(&mut app, Action::Preset(crate::tui::app::ViewPreset::Front));
        run(
            &mut app,
            Action::Rig(RigAction::Move {
                right: 0,
                up: 1,
                coarse: false,
            }),
        );
        let step = face_size(&app) * FINE_FRACTION;
        let jaw1 = app.rig().jaw.clone().unwrap();
        assert!((jaw1.pivot.y - jaw0.pivot.y - step).abs() < 1e-6);
        run(&mut app, Action::Rig(RigAction::NextParam));
        param(&mut app, 1, false); // degrees per unit, by 0.1
        let jaw2 = app.rig().jaw.clone().unwrap();
        assert!((jaw2.degrees_per_unit - jaw0.degrees_per_unit - 0.1).abs() < 1e-6);
        run(&mut app, Action::Rig(RigAction::NextParam));
        assert!(
            describe(&app).contains("axis angle 0.0 deg"),
            "{}",
            describe(&app)
        );
        param(&mut app, -2, false); // the axis, 2 degrees clockwise in the front view
        let jaw3 = app.rig().jaw.clone().unwrap();
        let tilt = jaw3.axis.y.atan2(jaw3.axis.x).to_degrees();
        assert!((tilt + 2.0).abs() < 1e-4, "{tilt}");
        assert_eq!(jaw3.weights, jaw0.weights);
        assert_bound_as_from_scratch(&app);
        // Undo goes back through the three jaw changes in the order made.
        for want in [&jaw2, &jaw1, &jaw0] {
            run(&mut app, Action::Undo);
            assert_eq!(app.rig().jaw.as_ref(), Some(want));
        }
        assert_bound_as_from_scratch(&app);
    }

    #[test]
    fn one_history_undoes_rig_and_activation_edits_in_the_order_made() {
        let mut app = rig_app();
        let Row::Muscle(i) = app.selected_row() else {
            panic!()
        };
        let rig0 = app.rig().clone();
        let act0 = app.doc.activations.clone();
        run(&mut app, Action::StepCoarse(1)); // an activation edit of the selected muscle
        let act1 = app.doc.activations.clone();
        assert_ne!(act1, act0);
        run(
            &mut app,
            Action::Rig(RigAction::Move {
                right: 1,
                up: 0,
                coarse: false,
            }),
        );
        let rig1 = app.rig().clone();
        run(&mut app, Action::StepCoarse(1)); // a second activation edit, after the rig's
        let act2 = app.doc.activations.clone();
        assert_ne!(act2, act1);
        run(&mut app, Action::Undo);
        assert_eq!((app.rig(), &app.doc.activations), (&rig1, &act1));
        run(&mut app, Action::Undo);
        assert_eq!((app.rig(), &app.doc.activations), (&rig0, &act1));
        let text = &app.message.as_ref().unwrap().text;
        assert!(
            text.starts_with(&format!(
                "undone the rig change to {} attachment",
                app.row_name(Row::Muscle(i))
            )),
            "{text}"
        );
        run(&mut app, Action::Undo);
        assert_eq!((app.rig(), &app.doc.activations), (&rig0, &act0));
        run(&mut app, Action::Undo);
        assert_eq!(app.message.as_ref().unwrap().text, "nothing to undo");
        for (rig, act) in [(&rig0, &act1), (&rig1, &act1), (&rig1, &act2)] {
            run(&mut app, Action::Redo);
            assert_eq!((app.rig(), &app.doc.activations), (rig, act));
        }
        // Leaving rig mode and undoing a rig change shows the face with the rig as it was.
        run(&mut app, Action::Undo);
        run(&mut app, Action::Undo);
        run(&mut app, Action::Rig(RigAction::Toggle));
        run(&mut app, Action::Undo);
        assert_eq!(app.rig(), &rig0);
        let scratch = crate::model::Deformation::default()
            .bind(&rig0, app.doc.scene.mesh())
            .unwrap();
        let mut out = Vec::new();
        scratch.deform(&app.doc.activations, &mut out).unwrap();
        assert_eq!(app.doc.scene.positions(), out.as_slice());
    }

    #[test]
    fn every_kind_of_change_rebinds_as_binding_from_scratch() {
        let mut app = default_app();
        run(&mut app, Action::ToggleMirror);
        for name in [
            "L_Zygomatic_Major",
            "L_Orbicularis_Oculi",
            "L_Frontalis_Sheet",
        ] {
            select(&mut app, name);
            for _ in 0..4 {
                run(&mut app, Action::Rig(RigAction::NextPoint));
                run(
                    &mut app,
                    Action::Rig(RigAction::Move {
                        right: 1,
                        up: -1,
                        coarse: false,
                    }),
                );
                run(&mut app, Action::Rig(RigAction::NextParam));
                param(&mut app, 1, false);
                assert_bound_as_from_scratch(&app);
            }
        }
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
