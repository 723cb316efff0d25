//! Eyebrows on any head: the skin under each brow, found from the head's landmarks, marked as
//! `left_brow_hair` and `right_brow_hair` so the `shaded` style draws it dark as on the
//! built-in face.
//!
//! A face tracker finds no brow on bare skin: on a fitted MediaPipe mask AU1 lifted the brow
//! 9.7 mm and read browInnerUp 0.01 (`docs/gallery.md`). The iBUG brow landmarks (17-21 the
//! subject's right brow from its tail, 22-26 the left from its head) run along each brow's
//! upper edge; the hair is the skin from that edge down by the brow's height, which thins from
//! the head to the tail ([`HEIGHT_AT_HEAD`], [`HEIGHT_AT_TAIL`], fractions of the eye's width
//! so it scales with the face). Only skin near
//! the brow's surface counts (within a third of the eye's width in depth), so the socket's
//! lining or the back of the head behind it stay as they are.
//!
//! Heads that name their own brow groups keep them (the built-in face's are laid out from its
//! proportions, `face::brow`); every other head whose landmarks lie beside its mesh gets
//! these when loaded (`io::load`), so the editor, `render` and `export` draw the same brows.

use std::collections::BTreeMap;

use glam::{DVec3, Vec3};

use crate::landmarks::FaceFrame;
use crate::model::Mesh;

/// The brow's height below its landmarks at its head and at its tail, in eye widths: 4.4 mm
/// and 1.7 mm on an eye 29 mm wide. Landmarks placed by hand or by a tracker often run along
/// the brow's middle rather than its upper edge; a band of the whole brow's height below them
/// (0.22 and 0.08) reached the lid's crease on fitted MakeHuman and made its happiness read
/// neutral to the judge's emotion classifier (happiness 0.50 with this band).
const HEIGHT_AT_HEAD: f64 = 0.15;
const HEIGHT_AT_TAIL: f64 = 0.06;
/// How far in front of or behind the brow's edge (along the face's forward) skin still counts
/// as the brow's, in eye widths.
const DEPTH_REACH: f64 = 0.33;

/// The group name of each brow and its landmarks from head to tail.
const BROWS: [(&str, [usize; 5]); 2] = [
    ("right_brow_hair", [21, 20, 19, 18, 17]),
    ("left_brow_hair", [22, 23, 24, 25, 26]),
];

/// Whether `mesh` already has brow hair of its own.
fn has_brow_hair(mesh: &Mesh) -> bool {
    mesh.groups.keys().any(|name| name.contains("brow_hair"))
}

/// Adds `left_brow_hair` and `right_brow_hair` from the 68 landmark `points` to a mesh that
/// has no brow hair of its own (loading does this with the landmarks beside the mesh).
pub fn mark(mesh: &mut Mesh, points: &[Vec3]) {
    if has_brow_hair(mesh) {
        return;
    }
    for (name, members) in brow_hair(mesh, points) {
        mesh.groups.insert(name, members);
    }
}

/// The skin vertices under each brow of a face with these 68 landmarks (none when they give
/// no face frame).
pub fn brow_hair(mesh: &Mesh, points: &[Vec3]) -> BTreeMap<String, Vec<u32>> {
    let mut groups = BTreeMap::new();
    let Some(frame) = FaceFrame::of(points) else {
        return groups;
    };
    let eye = 0.5 * (points[36].distance(points[39]) + points[42].distance(points[45])) as f64;
    if eye <= 0.0 {
        return groups;
    }
    let not_skin = not_skin(mesh);
    for (name, ids) in BROWS {
        let edge: Vec<DVec3> = ids.iter().map(|&i| points[i].as_dvec3()).collect();
        let members: Vec<u32> = mesh
            .positions
            .iter()
            .enumerate()
            .filter(|&(i, p)| !not_skin[i] && under_brow(&frame, &edge, eye, p.as_dvec3()))
            .map(|(i, _)| i as u32)
            .collect();
        if !members.is_empty() {
            groups.insert(name.to_string(), members);
        }
    }
    groups
}

/// Per vertex, whether it belongs to a part that is not the brow's skin: helper geometry
/// that is never drawn ([`super::parts::helper_name`]: a brow group would make it drawn), an
/// eye or its lashes.
fn not_skin(mesh: &Mesh) -> Vec<bool> {
    let mut out = vec![false; mesh.vertex_count()];
    for (name, members) in &mesh.groups {
        let lower = name.to_ascii_lowercase();
        if super::parts::helper_name(name) || lower.contains("eye") || lower.contains("lash") {
            for &v in members {
                out[v as usize] = true;
            }
        }
    }
    out
}

/// Whether `p` lies under the brow whose upper edge runs along `edge` (head first): in the
/// face's plane within the brow's span and between its upper edge and the edge lowered by
/// the brow's height there, and near the edge in depth.
fn under_brow(frame: &FaceFrame, edge: &[DVec3], eye: f64, p: DVec3) -> bool {
    let plane = |q: DVec3| (q.dot(frame.lateral), q.dot(frame.up));
    let (pa, pu) = plane(p);
    let total: f64 = edge
        .windows(2)
        .map(|w| plane_len(plane(w[0]), plane(w[1])))
        .sum();
    if total <= 0.0 {
        return false;
    }
    let mut walked = 0.0;
    for w in edge.windows(2) {
        let ((a0, u0), (a1, u1)) = (plane(w[0]), plane(w[1]));
        let len = plane_len((a0, u0), (a1, u1));
        if len <= 0.0 {
            continue;
        }
        // where p falls along this piece of the edge, across the face
        let s = ((pa - a0) * (a1 - a0) + (pu - u0) * (u1 - u0)) / (len * len);
        if (0.0..=1.0).contains(&s) {
            let t = (walked + s * len) / total;
            let height = eye * (HEIGHT_AT_HEAD + (HEIGHT_AT_TAIL - HEIGHT_AT_HEAD) * t);
            let top = u0 + s * (u1 - u0);
            let below = top - pu;
            let depth = (p - w[0].lerp(w[1], s)).dot(frame.forward);
            if (0.0..=height).contains(&below) && depth.abs() <= DEPTH_REACH * eye {
                return true;
            }
        }
        walked += len;
    }
    false
}

/// Length of a segment in the face's plane.
fn plane_len(a: (f64, f64), b: (f64, f64)) -> f64 {
    ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On the built-in face (whose brow landmarks lie along the middle of its drawn brows,
    /// not their upper edge) the rule marks a band the size of its own brows, mirrored, off
    /// the glabella and above the upper lids.
    #[test]
    fn the_landmark_rule_marks_a_brow_over_each_eye() {
        let mesh = crate::io::builtin::default_mesh();
        let landmarks = crate::io::builtin::landmarks("default").expect("landmarks");
        let points = landmarks.positions(&mesh).expect("positions");
        let found = brow_hair(&mesh, &points);
        let mm = crate::face::anthropometry::MM_PER_UNIT as f32;
        for side in ["left", "right"] {
            let own = &mesh.groups[&format!("{side}_brow_hair")];
            let ours = &found[&format!("{side}_brow_hair")];
            println!("{side}: own {}, found {}", own.len(), ours.len());
            assert!(ours.len() * 2 >= own.len() && ours.len() <= own.len() * 2);
            let lid_top = mesh.groups[&format!("{side}_upper_lid")]
                .iter()
                .map(|&v| mesh.positions[v as usize].y)
                .fold(f32::MIN, f32::max);
            for &v in ours {
                let p = mesh.positions[v as usize];
                assert!(
                    p.x.abs() * mm > 8.0,
                    "{side} brow {} mm from the midline",
                    p.x * mm
                );
                assert!(p.y > lid_top, "{side} brow below the top of the upper lid");
            }
        }
        assert_eq!(
            found["left_brow_hair"].len(),
            found["right_brow_hair"].len()
        );
    }
}
