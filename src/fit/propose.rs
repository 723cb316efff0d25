//! Proposing landmarks from some of them: the template's 68 landmarks carried onto a face
//! through a warp fitted on the ones known there, and a face's mirror plane from its
//! midline landmarks, for proposing one side from the other.
//!
//! The classic face's landmarks ([`crate::face::classic::ibug_landmarks`]) and the landmark
//! picker both propose this way; each snaps the carried points to vertices its own way.

use glam::{DMat3, DVec3, Vec3};

use super::warp::{outer, symmetric_eigen, Warp};
use crate::landmarks::COUNT;

/// The template's landmarks carried onto a target known at some of them: `template` holds
/// the template's 68 landmark points, `known` pairs landmark numbers with their points on
/// the target. A [`Warp`] (similarity and thin-plate spline) fitted on the known pairs takes
/// every template landmark across; known landmarks keep their given point exactly.
///
/// `None` when `template` does not hold 68 points, a number is out of range, or the known
/// points do not fix a warp (fewer than four, or all on a line).
pub fn carry(template: &[Vec3], known: &[(usize, Vec3)]) -> Option<Vec<Vec3>> {
    if template.len() != COUNT || known.len() < 4 || known.iter().any(|&(i, _)| i >= COUNT) {
        return None;
    }
    let from: Vec<Vec3> = known.iter().map(|&(i, _)| template[i]).collect();
    let to: Vec<Vec3> = known.iter().map(|&(_, p)| p).collect();
    let warp = Warp::fit(&from, &to)?;
    let mut out: Vec<Vec3> = template.iter().map(|&p| warp.apply_f32(p)).collect();
    if out.iter().any(|p| !p.is_finite()) {
        return None;
    }
    for &(i, p) in known {
        out[i] = p;
    }
    Some(out)
}

/// A plane of mirror symmetry: a point on it and its unit normal, which points toward the
/// subject's left.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MirrorPlane {
    /// A point on the plane (the centroid of the midline points it was fitted to).
    pub origin: DVec3,
    /// The unit normal, toward the subject's left.
    pub normal: DVec3,
}

impl MirrorPlane {
    /// The plane through midline points (at least three, not on one line), its normal
    /// turned toward `left` (points on the subject's left side). The plane is the
    /// least-squares fit: its normal is the direction in which the midline points spread
    /// least. `None` when the points do not fix a plane or `left` lies on it.
    pub fn fit(midline: &[Vec3], left: &[Vec3]) -> Option<MirrorPlane> {
        if midline.len() < 3 {
            return None;
        }
        let points: Vec<DVec3> = midline.iter().map(|p| p.as_dvec3()).collect();
        let origin = points.iter().copied().sum::<DVec3>() / points.len() as f64;
        let cov = points.iter().fold(DMat3::ZERO, |cov, p| {
            let d = *p - origin;
            cov + outer(d, d)
        });
        let (values, vectors) = symmetric_eigen(cov);
        // Ascending: the plane needs two clear directions of spread; its normal is the third.
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| values[i].total_cmp(&values[j]));
        let spread = values[order[2]].max(0.0);
        if spread <= 0.0 || values[order[1]] < 1e-6 * spread {
            return None;
        }
        let mut normal = vectors.col(order[0]).normalize_or_zero();
        if normal == DVec3::ZERO {
            return None;
        }
        let side: f64 = left
            .iter()
            .map(|p| (p.as_dvec3() - origin).dot(normal))
            .sum();
        let size = (spread / points.len() as f64).sqrt();
        if !side.is_finite() || side.abs() <= 1e-6 * size * left.len().max(1) as f64 {
            return None;
        }
        if side < 0.0 {
            normal = -normal;
        }
        Some(MirrorPlane { origin, normal })
    }

    /// The mirror image of `p` in the plane.
    pub fn reflect(&self, p: Vec3) -> Vec3 {
        let p = p.as_dvec3();
        (p - 2.0 * (p - self.origin).dot(self.normal) * self.normal).as_vec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn template() -> Vec<Vec3> {
        // A bumpy, non-planar set of 68 points.
        (0..COUNT)
            .map(|i| {
                let t = i as f32;
                Vec3::new(
                    (t * 0.7).sin() * 3.0,
                    (t * 0.31).cos() * 4.0,
                    (t * 0.13).sin(),
                )
            })
            .collect()
    }

    #[test]
    fn carrying_onto_a_moved_copy_gives_the_moved_template() {
        let template = template();
        let moved = |p: Vec3| Vec3::new(-p.y, p.x, p.z) * 2.0 + Vec3::new(1.0, -3.0, 0.5);
        let known: Vec<(usize, Vec3)> = [0, 9, 20, 33, 47, 60]
            .iter()
            .map(|&i| (i, moved(template[i])))
            .collect();
        let carried = carry(&template, &known).unwrap();
        for (i, p) in carried.iter().enumerate() {
            assert!(p.distance(moved(template[i])) < 1e-3, "landmark {i}: {p}");
        }
        assert_eq!(carried[20], known[2].1, "known points are kept exactly");
        assert!(
            carry(&template, &known[..3]).is_none(),
            "three points fix no warp"
        );
        assert!(carry(&template[..10], &known).is_none());
    }

    #[test]
    fn the_mirror_plane_comes_from_the_midline_not_from_x_zero() {
        // A face whose midline is the plane x = 2 turned 30 degrees about y.
        let turn = glam::Quat::from_rotation_y(30f32.to_radians());
        let at = |p: Vec3| turn * (p + Vec3::new(2.0, 0.0, 0.0));
        let midline: Vec<Vec3> = [(0.0, 3.0, 0.5), (0.0, 0.0, 2.0), (0.0, -3.0, 0.2)]
            .iter()
            .map(|&(x, y, z)| at(Vec3::new(x, y, z)))
            .collect();
        let left = [at(Vec3::new(1.5, 1.0, 0.0))];
        let plane = MirrorPlane::fit(&midline, &left).unwrap();
        let mirrored = plane.reflect(left[0]);
        assert!(
            mirrored.distance(at(Vec3::new(-1.5, 1.0, 0.0))) < 1e-4,
            "{mirrored}"
        );
        // The normal points to the subject's left whichever way the points were given.
        assert!((plane.normal.as_vec3() - turn * Vec3::X).length() < 1e-4);
        // Points on one line fix no plane; a left point on the plane gives no side.
        let line = [Vec3::ZERO, Vec3::Y, Vec3::Y * 2.0];
        assert!(MirrorPlane::fit(&line, &left).is_none());
        assert!(MirrorPlane::fit(&midline, &[midline[0]]).is_none());
    }
}
