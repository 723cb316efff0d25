//! What rig mode edits on each muscle kind and on the jaw: the points (`Tab`), the
//! parameters (`p`) and how they step, and one change applied to a muscle, its mirror
//! partner or the jaw's pose.

use glam::{Quat, Vec3};

use super::JawPose;
use crate::model::rig::reflect;
use crate::model::{MuscleKind, Rig};
use crate::tui::app::Row;

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
pub(super) enum Unit {
    /// A length: steps are fractions of the face's height.
    Length,
    /// A plain number with its fine and coarse steps.
    Fixed(f32, f32),
    /// A direction turned about the view axis by fine and coarse steps in degrees; its
    /// value is its angle in the view plane, counter-clockwise from the screen's right.
    Angle(f32, f32),
}

/// Name of the sphincter's frame parameter.
pub(super) const FRAME_ANGLE: &str = "frame angle";
/// Name of the jaw's axis parameter.
pub(super) const AXIS_ANGLE: &str = "axis angle";

/// The parameters of a muscle kind (or the jaw, `None`), in `p` order.
pub(super) fn params(kind: Option<&MuscleKind>) -> &'static [(&'static str, Unit)] {
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

pub(super) fn point_mut(kind: &mut MuscleKind, i: usize) -> Option<&mut Vec3> {
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
pub(super) fn param_mut(kind: &mut MuscleKind, i: usize) -> Option<&mut f32> {
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
pub(super) enum Change {
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
    pub(super) fn mirrored(self, normal: Vec3) -> Change {
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
    pub(super) fn to_kind(self, kind: &mut MuscleKind) -> bool {
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
    pub(super) fn to_jaw(self, pose: &mut JawPose) -> bool {
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

pub(super) fn kind_of(rig: &Rig, row: Row) -> Option<&MuscleKind> {
    match row {
        Row::Muscle(m) => rig.muscles.get(m).map(|m| &m.kind),
        Row::Jaw => None,
    }
}
