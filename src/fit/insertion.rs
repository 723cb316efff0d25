//! The muscles of the mouth's corners meet the skin at their insertion at the template's
//! angle.
//!
//! A linear muscle pulls the skin toward its attachment, along the chord from insertion to
//! attachment. The warp carries both ends, but the attachment lies far from any landmark and
//! a few millimetres under the skin, where the warp bends most: on MakeHuman's head the
//! depressor anguli oris's chord left the mouth corner 40 degrees back from the face's plane
//! (31 on the template), steeply into the skin, so at AU15 the corners went about 4.8 mm
//! down and 5.7 mm back into the face and the tracker read little frown at sadness. What a
//! muscle does to the skin is decided at its insertion: there its fibres run along the skin
//! on every face. So a fitted chord that leaves the skin more steeply inward than the
//! template's is turned about the insertion toward the face's front until its angle to the
//! skin's tangent plane is the template's. Its length (and so the falloff's distances), the
//! insertion and its direction as seen from the front (which the warp, fitted on landmarks
//! spread over the face's plane, gets right) stay, and its attachment stays behind the
//! insertion. A chord the warp left shallower is kept, and a template fitted to itself keeps
//! every muscle as it was.
//!
//! Only the muscles that insert at the mouth's corners (the modiolus: the angular depressor,
//! the zygomatic major, the risorius, the buccinator) are turned. Turned everywhere, the rule
//! also lifted MediaPipe's levator labii, whose AU10 then stretched an edge of the upper lip
//! 2.61x (2.39x before; over the 2.5x of a tear), and MakeHuman's frontalis, whose raised
//! attachments moved the render's framing (`docs/gallery.md`).

use glam::Vec3;

use super::parts::{Part, Parts};
use super::Template;
use crate::landmarks::{mm_per_unit, FaceFrame};
use crate::model::{Mesh, Muscle, MuscleKind};

/// Radius round the insertion over which the skin's normal is averaged, in mm (the face's
/// units from its outer canthal distance: [`mm_per_unit`]).
const NORMAL_MM: f32 = 6.0;
/// Skin facing away from the face's front by more than this (the cosine of the angle to the
/// front axis) is left out of the normal: the mouth's lining and the lips' inner faces lie
/// within the radius at a mouth corner and face inward.
const MIN_FRONT: f32 = 0.2;
/// A template muscle inserts at a mouth corner when its insertion lies this close to the
/// corner's landmark (iBUG 48 or 54), as a fraction of the mouth's width.
const CORNER_REACH: f32 = 0.15;
/// Angles this close (radians) are left as they are.
const SAME_ANGLE: f32 = 1e-4;

/// One face's skin triangles seen from the front, for the normals round an insertion.
pub(super) struct Skin {
    /// The face's front axis.
    front: Vec3,
    /// Skin triangles with their area-weighted normals, facing the front.
    triangles: Vec<(Vec3, Vec3)>,
    /// The radius of the normal's average (mesh units).
    radius: f32,
}

impl Skin {
    /// The skin of `mesh` (the vertices `is_skin` keeps) facing `front`, on a face with these
    /// 68 `landmarks` (its scale; no normal is found when they give none).
    fn new(mesh: &Mesh, is_skin: &dyn Fn(usize) -> bool, front: Vec3, landmarks: &[Vec3]) -> Self {
        let p = &mesh.positions;
        let triangles = mesh
            .triangles
            .iter()
            .filter(|t| t.iter().all(|&v| is_skin(v as usize)))
            .filter_map(|t| {
                let [a, b, c] = t.map(|v| p[v as usize]);
                let n = (b - a).cross(c - a);
                let unit = n.normalize_or_zero();
                (unit.dot(front) > MIN_FRONT).then_some(((a + b + c) / 3.0, n))
            })
            .collect();
        Skin {
            front,
            triangles,
            radius: mm_per_unit(landmarks).map_or(0.0, |mm| NORMAL_MM / mm),
        }
    }

    /// The template's skin: the connected pieces of its mesh that hold a landmark (its teeth,
    /// tongue and eyeballs are pieces of their own).
    pub(super) fn of_template(template: Template<'_>, front: Vec3) -> Self {
        let skin = super::parts::on_landmark_pieces(template.mesh, template.landmarks);
        let is_skin = |v: usize| skin[v];
        Skin::new(template.mesh, &is_skin, front, template.landmarks)
    }

    /// The fitted mesh's skin (the parts the fit calls skin).
    pub(super) fn of_mesh(mesh: &Mesh, parts: &Parts, landmarks: &[Vec3], front: Vec3) -> Self {
        let is_skin = |v: usize| parts.of_vertex[v] == Part::Skin;
        Skin::new(mesh, &is_skin, front, landmarks)
    }

    /// The skin's outward normal round `at`: the area-weighted mean of the front-facing
    /// triangles' normals within the radius; `None` where there are none.
    fn normal(&self, at: Vec3) -> Option<Vec3> {
        let r2 = self.radius * self.radius;
        let sum: Vec3 = self
            .triangles
            .iter()
            .filter(|(c, _)| c.distance_squared(at) <= r2)
            .map(|(_, n)| *n)
            .sum();
        let n = sum.normalize_or_zero();
        (n != Vec3::ZERO).then_some(n)
    }
}

/// Whether `p` lies at a mouth corner of a face with these 68 `landmarks`.
fn at_mouth_corner(landmarks: &[Vec3], p: Vec3) -> bool {
    let (Some(right), Some(left)) = (landmarks.get(48), landmarks.get(54)) else {
        return false;
    };
    let reach = CORNER_REACH * right.distance(*left);
    p.distance(*right).min(p.distance(*left)) <= reach
}

/// The front axis of a face frame, as `f32`.
pub(super) fn front(frame: &FaceFrame) -> Vec3 {
    frame.forward.as_vec3()
}

/// The angle (radians) of the chord from `insertion` to `attachment` over the skin's tangent
/// plane with normal `n` (negative: into the skin).
fn elevation(attachment: Vec3, insertion: Vec3, n: Vec3) -> Option<f32> {
    let u = (attachment - insertion).normalize_or_zero();
    (u != Vec3::ZERO).then(|| u.dot(n).clamp(-1.0, 1.0).asin())
}

/// `attachment` turned about `insertion` toward or away from the face's `front`, so that the
/// chord's angle over the tangent plane of normal `n` is `angle`; its length and its
/// direction as seen from the front are kept (the warp, fitted on landmarks spread over the
/// face's plane, gets that direction right; the depth is what it bends). Of the two turns
/// that reach the angle, the smaller, and no further than the face's plane (the attachment
/// stays behind the insertion); `None` when none does, when that would not lift the chord,
/// or when the chord runs along `front`.
fn turned(attachment: Vec3, insertion: Vec3, n: Vec3, front: Vec3, angle: f32) -> Option<Vec3> {
    let chord = attachment - insertion;
    let u = chord.normalize_or_zero();
    let f = front.normalize_or_zero();
    let p = (u - f * u.dot(f)).normalize_or_zero();
    if p == Vec3::ZERO || f == Vec3::ZERO {
        return None;
    }
    // u(t) = cos t p + sin t f, and u(t).n = r cos(t - phi)
    let (pn, fn_) = (p.dot(n), f.dot(n));
    let (r, phi) = ((pn * pn + fn_ * fn_).sqrt(), fn_.atan2(pn));
    let c = angle.sin() / r;
    if !(r > 0.0 && c.abs() <= 1.0) {
        return None;
    }
    let now = u.dot(f).atan2(u.dot(p));
    let t = [phi + c.acos(), phi - c.acos()]
        .into_iter()
        .min_by(|a, b| wrap(a - now).abs().total_cmp(&wrap(b - now).abs()))?;
    // the attachment is on bone, under the skin: never in front of the insertion; and the
    // chord is only ever lifted out of the skin
    let t = t.min(0.0);
    if t <= now {
        return None;
    }
    Some(insertion + (p * t.cos() + f * t.sin()) * chord.length())
}

/// An angle brought into (-pi, pi].
fn wrap(a: f32) -> f32 {
    let tau = std::f32::consts::TAU;
    a - tau * ((a + std::f32::consts::PI) / tau).floor()
}

/// Turns each linear muscle of `fitted` (carried from `template_muscles`, in the same order)
/// whose template insertion lies at a mouth corner of the template's 68 `corners_of`
/// landmarks about its insertion, so that it meets `skin[1]` at the angle the template's
/// meets `skin[0]`, where it dives into the skin more steeply than that. Muscles with no
/// front-facing skin round the insertion, on either face, are left as carried.
pub(super) fn keep_angles(
    template_muscles: &[Muscle],
    corners_of: &[Vec3],
    fitted: &mut [Muscle],
    skin: [&Skin; 2],
) {
    for (from, to) in template_muscles.iter().zip(fitted.iter_mut()) {
        let (MuscleKind::Linear(a), MuscleKind::Linear(b)) = (&from.kind, &mut to.kind) else {
            continue;
        };
        if !at_mouth_corner(corners_of, a.insertion) {
            continue;
        }
        let Some(want) = skin[0]
            .normal(a.insertion)
            .and_then(|n| elevation(a.attachment, a.insertion, n))
        else {
            continue;
        };
        let Some(n) = skin[1].normal(b.insertion) else {
            continue;
        };
        let Some(have) = elevation(b.attachment, b.insertion, n) else {
            continue;
        };
        // only a chord the warp sank is lifted: it is the attachment's depth, far from the
        // landmarks, that the warp gets wrong, and a chord left shallower is kept as carried
        if want - have <= SAME_ANGLE {
            continue;
        }
        if let Some(p) = turned(b.attachment, b.insertion, n, skin[1].front, want) {
            b.attachment = p;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turning_sets_the_angle_and_keeps_the_length_and_the_front_view() {
        // skin facing front and down, a chord down and back into it
        let n = Vec3::new(0.0, -0.5, 1.0).normalize();
        let (ins, att) = (Vec3::ZERO, Vec3::new(10.0, -30.0, -20.0));
        let p = turned(att, ins, n, Vec3::Z, -0.1).unwrap();
        assert!((p.length() - att.length()).abs() < 1e-3);
        assert!((elevation(p, ins, n).unwrap() + 0.1).abs() < 1e-4);
        // seen from the front it still points the same way
        assert!((p.x / p.y - att.x / att.y).abs() < 1e-4 && p.y < 0.0);
        assert!(p.z > att.z);
    }

    #[test]
    fn an_attachment_is_not_turned_in_front_of_its_insertion() {
        let n = Vec3::new(0.0, -0.5, 1.0).normalize();
        let att = Vec3::new(10.0, -30.0, -20.0);
        let p = turned(att, Vec3::ZERO, n, Vec3::Z, 0.5).unwrap();
        assert!(p.z.abs() < 1e-4, "{p}");
        // nor turned deeper into the skin
        assert!(turned(att, Vec3::ZERO, n, Vec3::Z, -0.5).is_none());
    }

    #[test]
    fn a_chord_along_the_front_is_not_turned() {
        assert!(turned(Vec3::Z, Vec3::ZERO, Vec3::Z, Vec3::Z, 0.2).is_none());
    }
}
