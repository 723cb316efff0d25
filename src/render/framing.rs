//! Framing: which way a face looks and which part of the mesh a view fits.
//!
//! A mesh may stand any way up (y up as glTF, z up as Blender and many scanners) and may be a
//! face, a head, a bust or a whole body. Views are defined in the face's own axes: across
//! (the subject's left), up, and out of the face. [`Framing::of_rig`] reads those axes from
//! the rig's sphincters (their frames lie in the face's plane, major axis across, minor axis
//! up; `fit-rig` sets them from the landmarks) and the face's extent from the rig's muscle
//! points, so a fitted bust is shown upright with its face filling the view. A mesh without a
//! rig ([`Framing::of_mesh`]) is stood up by its shape: the longer of its y and z extents is
//! taken for up.
//!
//! Axes within 20 degrees of the mesh's own are snapped to them exactly, so a face modelled
//! square to its axes is drawn square (the built-in face's front view is the mesh's xy plane
//! bit for bit), while a scan lying at an angle is turned upright.

use glam::{Mat3, Vec3};

use crate::model::{Mesh, MuscleKind, Rig};

/// Up to this angle between the face's axes and an axis-aligned frame, the aligned frame is
/// used.
const SNAP_DEGREES: f32 = 20.0;

/// A mesh whose face region spans at least this share of its extent, across and up, is
/// framed whole: it is a face, not a head or body around one.
const MOSTLY_FACE: f32 = 0.9;

/// How far beyond the rig's muscle points the face region reaches, as a fraction of their
/// extent on each side (the chin below the lowest muscle, the forehead above the frontalis).
const FACE_MARGIN: f32 = 0.12;

/// How a mesh is shown: its face's axes and the points a view is fitted to.
#[derive(Debug, Clone, PartialEq)]
pub struct Framing {
    /// Mesh to face coordinates (rows: across toward the subject's left, up, out of the
    /// face): the camera's [`super::Camera::basis`].
    pub basis: Mat3,
    /// The rest vertices of the face region, when the face is a small part of the mesh;
    /// `None` fits the whole mesh.
    pub focus: Option<Vec<Vec3>>,
    /// The extent of what a view fits, in face coordinates (measured once, so views that
    /// scale steps and pans with the face pay nothing per frame).
    extent: Vec3,
}

impl Framing {
    /// The framing of a rigged mesh: axes from the sphincters' frames (the mouth's first),
    /// the face region from the muscles' points.
    pub fn of_rig(rig: &Rig, mesh: &Mesh) -> Framing {
        Framing::of_rig_facing(rig, mesh, None)
    }

    /// [`Framing::of_rig`] with the face's axes given (`--up`, `--front`; see
    /// [`facing`]) instead of read from the rig.
    pub fn of_rig_facing(rig: &Rig, mesh: &Mesh, given: Option<Mat3>) -> Framing {
        match given.or_else(|| face_axes(rig).map(snap)) {
            Some(basis) => Framing::new(basis, face_region(rig, mesh, basis), mesh),
            None => Framing::of_mesh(mesh),
        }
    }

    /// The framing of a mesh alone: up is the longer of its y and z extents (y when equal),
    /// the face toward +z for y up and toward -y for z up (Blender's front view).
    pub fn of_mesh(mesh: &Mesh) -> Framing {
        let (lo, hi) = mesh.bounds();
        let size = hi - lo;
        let basis = if size.is_finite() && size.z > size.y * 1.05 {
            Mat3::from_cols(Vec3::X, Vec3::Z, -Vec3::Y).transpose()
        } else {
            Mat3::IDENTITY
        };
        Framing::new(basis, None, mesh)
    }

    fn new(basis: Mat3, focus: Option<Vec<Vec3>>, mesh: &Mesh) -> Framing {
        let points = focus.as_deref().unwrap_or(&mesh.positions);
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for p in points.iter().filter(|p| p.is_finite()) {
            let f = basis * *p;
            lo = lo.min(f);
            hi = hi.max(f);
        }
        let extent = hi - lo;
        Framing {
            basis,
            focus,
            extent: if extent.is_finite() {
                extent
            } else {
                Vec3::ONE
            },
        }
    }

    /// The size of what a view fits, for steps and pans that scale with the face: the larger
    /// of its extents across and up, in mesh units.
    pub fn size(&self) -> f32 {
        self.extent.truncate().max_element().max(f32::EPSILON)
    }

    /// The face's height (its extent along the face's up), for rig mode's steps.
    pub fn height(&self) -> f32 {
        if self.extent.y > 0.0 {
            self.extent.y
        } else {
            1.0
        }
    }
}

/// The face's axes for a face whose up and front (out of the face) are the given mesh
/// directions; either may be left out, and is then taken as the usual partner of the other
/// (y up faces +z, z up faces -y, as glTF and Blender have it). `None` when the two are not
/// at right angles or not unit axes.
pub fn facing(up: Option<Vec3>, front: Option<Vec3>) -> Option<Mat3> {
    let first_across = |given: Vec3, choices: [Vec3; 3]| {
        choices
            .into_iter()
            .find(|c| c.dot(given).abs() < 1e-6)
            .unwrap_or(Vec3::ZERO)
    };
    let (up, front) = match (up, front) {
        (None, None) => return None,
        (Some(up), Some(front)) => (up, front),
        (Some(up), None) => (up, first_across(up, [Vec3::Z, -Vec3::Y, Vec3::X])),
        (None, Some(front)) => (first_across(front, [Vec3::Y, Vec3::Z, Vec3::X]), front),
    };
    let across = up.cross(front);
    (up.is_normalized() && front.is_normalized() && up.dot(front).abs() < 1e-6)
        .then(|| Mat3::from_cols(across, up, front).transpose())
}

/// The face's axes (rows across, up, out) from the rig's sphincters, the mouth's first;
/// `None` without a sphincter.
fn face_axes(rig: &Rig) -> Option<Mat3> {
    let mut frames = rig.muscles.iter().filter_map(|m| match &m.kind {
        MuscleKind::Sphincter(s) => Some((s.convergence, s.frame)),
        _ => None,
    });
    let first = frames
        .clone()
        .find(|(c, _)| *c == crate::model::Convergence::Centre);
    let (_, frame) = first.or_else(|| frames.next())?;
    let across = frame.x.normalize_or_zero();
    let out = across.cross(frame.y).normalize_or_zero();
    let up = out.cross(across);
    (across != Vec3::ZERO && out != Vec3::ZERO)
        .then(|| Mat3::from_cols(across, up, out).transpose())
}

/// `basis` replaced by the axis-aligned rotation nearest to it when that is within
/// [`SNAP_DEGREES`] of it.
fn snap(basis: Mat3) -> Mat3 {
    let aligned = |v: Vec3| {
        let a = v.abs();
        let axis = if a.x >= a.y && a.x >= a.z {
            Vec3::X * v.x.signum()
        } else if a.y >= a.z {
            Vec3::Y * v.y.signum()
        } else {
            Vec3::Z * v.z.signum()
        };
        (axis, v.dot(axis).clamp(-1.0, 1.0).acos().to_degrees())
    };
    let (across, a) = aligned(basis.row(0));
    let (up, b) = aligned(basis.row(1));
    let out = across.cross(up);
    let c = basis.row(2).dot(out).clamp(-1.0, 1.0).acos().to_degrees();
    if a.max(b).max(c) <= SNAP_DEGREES && out != Vec3::ZERO {
        Mat3::from_cols(across, up, out).transpose()
    } else {
        basis
    }
}

/// The muscles' points: where the face is.
fn muscle_points(rig: &Rig) -> Vec<Vec3> {
    let mut points = Vec::new();
    for muscle in &rig.muscles {
        match &muscle.kind {
            MuscleKind::Linear(l) => points.extend([l.attachment, l.insertion]),
            MuscleKind::Sphincter(s) => {
                let (x, y) = (s.frame.x.normalize_or_zero(), s.frame.y.normalize_or_zero());
                points.extend([
                    s.centre + x * s.semi_major,
                    s.centre - x * s.semi_major,
                    s.centre + y * s.semi_minor,
                    s.centre - y * s.semi_minor,
                ]);
            }
            MuscleKind::Sheet(s) => points.extend(s.attachment.iter().chain(&s.insertion)),
        }
    }
    if let Some(jaw) = &rig.jaw {
        points.push(jaw.pivot);
    }
    points.retain(|p| p.is_finite());
    points
}

/// The rest vertices inside the face region (the muscles' extent across and up, with a
/// margin), or `None` when that is most of the mesh.
fn face_region(rig: &Rig, mesh: &Mesh, basis: Mat3) -> Option<Vec<Vec3>> {
    let points = muscle_points(rig);
    if points.len() < 3 {
        return None;
    }
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for p in &points {
        let f = basis * *p;
        lo = lo.min(f);
        hi = hi.max(f);
    }
    let margin = (hi - lo) * FACE_MARGIN;
    let (lo, hi) = (lo - margin, hi + margin);
    let (mut mlo, mut mhi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for p in mesh.positions.iter().filter(|p| p.is_finite()) {
        let f = basis * *p;
        mlo = mlo.min(f);
        mhi = mhi.max(f);
    }
    // The share of the mesh's extent, across and up, that the face region covers.
    let covered = (hi.min(mhi) - lo.max(mlo)) / (mhi - mlo).max(Vec3::splat(f32::EPSILON));
    if covered.x >= MOSTLY_FACE && covered.y >= MOSTLY_FACE {
        return None;
    }
    let inside: Vec<Vec3> = mesh
        .positions
        .iter()
        .copied()
        .filter(|p| {
            let f = basis * *p;
            f.x >= lo.x && f.x <= hi.x && f.y >= lo.y && f.y <= hi.y
        })
        .collect();
    (inside.len() >= 3).then_some(inside)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::builtin;

    #[test]
    fn the_built_in_face_is_framed_as_it_is() {
        let mesh = builtin::default_mesh();
        let framing = Framing::of_rig(&builtin::default_rig(), &mesh);
        assert_eq!((framing.basis, &framing.focus), (Mat3::IDENTITY, &None));
        let (lo, hi) = mesh.bounds();
        assert_eq!(framing.height(), (hi - lo).y);
    }

    #[test]
    fn a_z_up_face_is_stood_up_and_a_face_on_a_bigger_mesh_is_framed_alone() {
        // The built-in face turned to z up (front toward -y), on a mesh with a body below.
        let turn = Mat3::from_rotation_x(std::f32::consts::FRAC_PI_2);
        let mut mesh = builtin::default_mesh();
        let mut rig = builtin::default_rig();
        let face = mesh.positions.len();
        let (lo, hi) = mesh.bounds();
        let body: Vec<Vec3> = (0..4 * face)
            .map(|i| {
                let t = i as f32 / (4 * face) as f32;
                Vec3::new(
                    lo.x * 3.0 * (1.0 - t) + hi.x * 3.0 * t,
                    lo.y - 40.0 * t,
                    lo.z,
                )
            })
            .collect();
        mesh.positions.extend(body);
        for p in &mut mesh.positions {
            *p = turn * *p;
        }
        for muscle in &mut rig.muscles {
            match &mut muscle.kind {
                MuscleKind::Linear(l) => {
                    l.attachment = turn * l.attachment;
                    l.insertion = turn * l.insertion;
                }
                MuscleKind::Sphincter(s) => {
                    s.centre = turn * s.centre;
                    s.frame.x = turn * s.frame.x;
                    s.frame.y = turn * s.frame.y;
                }
                MuscleKind::Sheet(s) => {
                    for p in s.attachment.iter_mut().chain(&mut s.insertion) {
                        *p = turn * *p;
                    }
                }
            }
        }
        if let Some(jaw) = &mut rig.jaw {
            jaw.pivot = turn * jaw.pivot;
        }
        let framing = Framing::of_rig(&rig, &mesh);
        // Mesh z is the face's up, mesh -y is out of the face.
        assert_eq!(framing.basis.row(1), Vec3::Z);
        assert_eq!(framing.basis.row(2), -Vec3::Y);
        let focus = framing.focus.expect("the face is a small part of the mesh");
        assert!(
            focus.len() >= face * 9 / 10 && focus.len() < face + face / 4,
            "{}",
            focus.len()
        );
        assert_eq!(Framing::of_mesh(&mesh).basis, framing.basis);
    }

    #[test]
    fn given_axes_turn_the_view_as_asked() {
        assert_eq!(facing(None, None), None);
        assert_eq!(facing(Some(Vec3::Y), None), Some(Mat3::IDENTITY));
        let z_up = facing(Some(Vec3::Z), None).unwrap();
        assert_eq!(z_up, Framing::of_mesh(&tall_in_z()).basis);
        assert_eq!(facing(None, Some(-Vec3::Y)), Some(z_up));
        assert_eq!(
            facing(Some(Vec3::Z), Some(Vec3::Z)),
            None,
            "not at right angles"
        );
        let rig = builtin::default_rig();
        let mesh = builtin::default_mesh();
        let turned = Framing::of_rig_facing(&rig, &mesh, Some(z_up));
        assert_eq!(turned.basis, z_up);
    }

    fn tall_in_z() -> Mesh {
        let mut mesh = builtin::default_mesh();
        for p in &mut mesh.positions {
            *p = Vec3::new(p.x, -p.z, p.y);
        }
        mesh
    }
}
