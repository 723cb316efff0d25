//! Muscle descriptions: the three muscle kinds of the model and their parameters.
//!
//! A muscle here is pure data, placed in mesh coordinates. How it moves skin is computed in
//! [`crate::model::field`], once per rig and mesh.

use glam::{DMat3, Vec3};
use serde::{Deserialize, Serialize};

/// Which side of the face a muscle (or an AU) belongs to.
///
/// Left and right are the subject's: the subject's left lies at positive x, as in glTF's
/// convention (right-handed, y up, the face toward +z).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, Default,
)]
pub enum Side {
    /// The subject's left (x > 0).
    Left,
    /// The subject's right (x < 0).
    Right,
    /// On the midline, or acting on both sides at once.
    #[default]
    Centre,
}

impl Side {
    /// The other side (centre stays centre).
    pub fn mirrored(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
            Side::Centre => Side::Centre,
        }
    }

    /// One letter: `L`, `R` or `C`.
    pub fn letter(self) -> char {
        match self {
            Side::Left => 'L',
            Side::Right => 'R',
            Side::Centre => 'C',
        }
    }
}

/// A named muscle of a rig.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Muscle {
    /// Unique name within the rig, e.g. `L_Zygomatic_Major`.
    pub name: String,
    /// The side of the face the muscle lies on.
    #[serde(default)]
    pub side: Side,
    /// The name of the muscle that mirrors this one across x = 0, if any. Editors use it to
    /// move pairs together.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mirror: Option<String>,
    /// The muscle's kind and geometry.
    pub kind: MuscleKind,
}

/// The three muscle kinds of the model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum MuscleKind {
    /// Waters' linear (vector) muscle.
    Linear(Linear),
    /// An elliptical sphincter (mouth or eye).
    Sphincter(Sphincter),
    /// A rectangular sheet muscle (frontalis).
    Sheet(Sheet),
}

/// The point reflected across the plane x = 0.
pub fn mirror_x(p: Vec3) -> Vec3 {
    Vec3::new(-p.x, p.y, p.z)
}

impl MuscleKind {
    /// The same muscle reflected across the plane x = 0: every point (and direction) has its
    /// x negated, the order of points kept.
    pub fn mirrored_x(&self) -> MuscleKind {
        match self {
            MuscleKind::Linear(m) => MuscleKind::Linear(Linear {
                attachment: mirror_x(m.attachment),
                insertion: mirror_x(m.insertion),
                ..m.clone()
            }),
            MuscleKind::Sphincter(m) => MuscleKind::Sphincter(Sphincter {
                centre: mirror_x(m.centre),
                frame: m.frame.mirrored_x(),
                ..m.clone()
            }),
            MuscleKind::Sheet(m) => MuscleKind::Sheet(Sheet {
                attachment: m.attachment.map(mirror_x),
                insertion: m.insertion.map(mirror_x),
                ..m.clone()
            }),
        }
    }

    /// A short lower-case label: `linear`, `sphincter` or `sheet`.
    pub fn label(&self) -> &'static str {
        match self {
            MuscleKind::Linear(_) => "linear",
            MuscleKind::Sphincter(_) => "sphincter",
            MuscleKind::Sheet(_) => "sheet",
        }
    }
}

/// Waters' linear muscle: a cone of influence with its apex at the bone attachment, opening
/// toward the skin insertion (MODEL-NOTES section 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Linear {
    /// The fixed end on the bone: the cone's apex and the centre of the falloff distances.
    pub attachment: Vec3,
    /// The end in the skin; it only sets the muscle's direction.
    pub insertion: Vec3,
    /// Half-angle of the cone of influence, in degrees (0 < zone < 90).
    pub zone: f32,
    /// Distance from the attachment where the radial falloff starts.
    pub falloff_start: f32,
    /// Distance from the attachment where the radial falloff reaches zero.
    pub falloff_end: f32,
}

/// Where a sphincter pulls the skin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Convergence {
    /// Toward the ellipse's centre (mouth, eqs. 1-5).
    Centre,
    /// Straight toward the ellipse's major axis (eye, eqs. 6-9): closes the lids without
    /// pulling the eye corners in.
    MajorAxis,
}

/// An elliptical sphincter (MODEL-NOTES sections 2 and 3), in the plane of its [`Frame`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sphincter {
    /// Centre of the ellipse (its depth along the frame's z is not used by the in-plane pull).
    pub centre: Vec3,
    /// Semi-axis along the frame's x (`lx`).
    pub semi_major: f32,
    /// Semi-axis along the frame's y (`ly`).
    pub semi_minor: f32,
    /// Toward the centre (mouth) or toward the major axis (eye).
    pub convergence: Convergence,
    /// The bulge constant `Z` of eq. 5: the skin moves along the frame's z (out of the face)
    /// by at most activation / Z. The paper uses 10 for the mouth and 30 for the eyes.
    pub bulge: f32,
    /// The ellipse's orientation; the mesh's own axes unless set.
    #[serde(default, skip_serializing_if = "Frame::is_identity")]
    pub frame: Frame,
}

/// The orientation of a sphincter's ellipse: `x` is its major axis, `y` its up direction
/// (the minor axis, toward which an eye's upper lid closes from below), and `z = x × y`
/// points out of the face, the way the skin bulges.
///
/// The two directions need not be unit or exactly perpendicular: the frame used is `x`
/// normalised and `y` made perpendicular to it (Gram-Schmidt, `x` kept). Non-finite, zero or
/// (nearly) parallel directions are refused by [`Frame::check`]. The default is the mesh's
/// own axes, the model of the paper: `x = (1, 0, 0)`, `y = (0, 1, 0)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// The direction of the ellipse's major axis.
    pub x: Vec3,
    /// The ellipse's up direction (its minor axis).
    pub y: Vec3,
}

impl Default for Frame {
    fn default() -> Frame {
        Frame::IDENTITY
    }
}

/// Directions whose angle has a sine below this are taken as parallel.
const MIN_SINE: f64 = 1e-3;

impl Frame {
    /// The mesh's own axes: the ellipse in the x-y plane, bulging toward +z.
    pub const IDENTITY: Frame = Frame {
        x: Vec3::X,
        y: Vec3::Y,
    };

    /// True for the mesh's own axes (exactly), where the frame changes nothing.
    pub fn is_identity(&self) -> bool {
        *self == Frame::IDENTITY
    }

    /// The rotation taking the ellipse's own axes to the mesh's: its columns are the unit
    /// `x`, the unit `y` made perpendicular to `x`, and their cross product. `None` when the
    /// frame does not pass [`Frame::check`].
    pub fn rotation(&self) -> Option<DMat3> {
        self.check().ok()?;
        let x = self.x.as_dvec3().normalize();
        let y = self.y.as_dvec3().normalize();
        let y = (y - x * x.dot(y)).normalize();
        Some(DMat3::from_cols(x, y, x.cross(y)))
    }

    /// Checks that both directions are finite and non-zero and that they are not parallel.
    /// The error says what is wrong, for a message naming the muscle's `frame`.
    pub fn check(&self) -> Result<(), String> {
        for (axis, v) in [("x", self.x), ("y", self.y)] {
            if !v.is_finite() {
                return Err(format!("{axis} {v} is not finite"));
            }
            if v.as_dvec3().length() == 0.0 {
                return Err(format!("{axis} is zero, which is no direction"));
            }
        }
        let (x, y) = (self.x.as_dvec3().normalize(), self.y.as_dvec3().normalize());
        if x.cross(y).length() < MIN_SINE {
            return Err(format!(
                "x {} and y {} are parallel; y must point across the ellipse's major axis",
                self.x, self.y
            ));
        }
        Ok(())
    }

    /// The unit major axis in mesh coordinates (the mesh's x for a bad frame).
    pub fn axis_x(&self) -> Vec3 {
        self.rotation().map_or(Vec3::X, |r| r.x_axis.as_vec3())
    }

    /// The unit up direction, perpendicular to the major axis (the mesh's y for a bad frame).
    pub fn axis_y(&self) -> Vec3 {
        self.rotation().map_or(Vec3::Y, |r| r.y_axis.as_vec3())
    }

    /// The frame of the sphincter reflected across the plane x = 0. The major axis is also
    /// reversed so that `z` still points out of the face (an ellipse's pull does not change
    /// when its major axis is reversed); the mesh's own axes map to themselves.
    pub fn mirrored_x(&self) -> Frame {
        // Adding zero turns the -0.0 of negated zeros into 0.0.
        Frame {
            x: -mirror_x(self.x) + Vec3::ZERO,
            y: mirror_x(self.y) + Vec3::ZERO,
        }
    }
}

/// A rectangular sheet muscle (MODEL-NOTES section 4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sheet {
    /// The two ends of the attachment line on the bone (A1, A2).
    pub attachment: [Vec3; 2],
    /// The two ends of the insertion line in the skin (l1, l2).
    pub insertion: [Vec3; 2],
    /// Length `L` of the zone of influence, measured from the attachment line along the axis;
    /// at least the attachment-to-insertion distance.
    pub length: f32,
    /// Width `W` of the zone of influence across the axis.
    pub width: f32,
}
