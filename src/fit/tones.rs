//! The lids' lash lines and the lips' vermilion on any head: skin found from the head's
//! landmarks and marked as vertex groups, so the `shaded` style draws the upper lids' margins
//! dark and the lips darker than the skin around them, as a photograph shows them.
//!
//! A face tracker places the lids on the lash line and the mouth on the lips' tone. On a
//! shaded render without them, a fitted MediaPipe mask's open eyes read half closed (the
//! tracker's eyeBlink 0.45 at rest, 0.04 on the built-in face), so a closed eye reads little
//! more; and its pale lips give the mouth no corners to find (`docs/gallery.md`).
//!
//! * `right_upper_lid_line`, `left_upper_lid_line` (and `*_lower_lid_line`, drawn lighter):
//!   the skin along each lid's free edge as a viewer sees it ([`super::lidedge`]: on a head
//!   whose lids have a thickness the landmarks lie on the lid's back, not on the edge), from
//!   the edge onto the lid by [`LINE_WIDTH`] of the eye's width;
//! * `vermilion`: the skin inside the lips' outer contour (landmarks 48-59) in the face's
//!   plane, near the lips in depth.
//!
//! The groups are per vertex, so the tones move with the skin when the lids close or the
//! lips part. Every head loaded with landmarks gets them (`io::load`, and the built-in face
//! from its own landmarks in `io::builtin`), so the editor, `render` and `export` draw the
//! same face. A head that names these groups itself keeps its own.

use std::collections::BTreeMap;

use glam::{DVec3, Vec3};

use super::lidedge::{lid_edges, EYE_MARKS};
use super::parts::{find_parts, Part, PartOverrides, Parts};
use crate::landmarks::FaceFrame;
use crate::model::Mesh;

/// How far onto the lid from its free edge the lash line reaches, in eye widths: about 1.5 mm
/// on an eye 30 mm wide, an upper lid's lashes and the lid margin's edge as a photograph
/// shows them.
pub const LINE_WIDTH: f64 = 0.05;
/// How far past the free edge (off the lid) a vertex may lie and still be on the line, in
/// eye widths: the edge is found by sampling, the margin's vertices lie within a sample of it.
const LINE_SLACK: f64 = 0.02;
/// How far in front of or behind the lid's edge, or the lips' contour, skin still counts,
/// in eye widths (the socket's lining and the back of the head do not).
const DEPTH_REACH: f64 = 0.33;
/// How far outside the lips' contour a vertex may lie and still be vermilion, in eye
/// widths: the contour's own vertices lie on it.
const LIP_SLACK: f64 = 0.02;

/// The group names, in the order the renderer looks them up.
pub const UPPER_LID_LINE: &str = "upper_lid_line";
/// See [`UPPER_LID_LINE`].
pub const LOWER_LID_LINE: &str = "lower_lid_line";
/// See [`UPPER_LID_LINE`].
pub const VERMILION: &str = "vermilion";

/// The subject's sides, in the order of [`EYE_MARKS`].
const SIDES: [&str; 2] = ["right", "left"];

/// Whether `mesh` already names tone groups of its own.
fn has_tones(mesh: &Mesh) -> bool {
    mesh.groups.keys().any(|name| {
        [UPPER_LID_LINE, LOWER_LID_LINE, VERMILION]
            .iter()
            .any(|word| name.contains(word))
    })
}

/// Adds the lid lines and the vermilion from the 68 landmarks (`marks` their vertices,
/// `points` their positions) to a mesh that names none of its own.
pub fn mark(mesh: &mut Mesh, marks: &[u32], points: &[Vec3]) {
    if has_tones(mesh) {
        return;
    }
    for (name, members) in find(mesh, marks, points) {
        mesh.groups.insert(name, members);
    }
}

/// The lid lines and the vermilion of a face with these landmarks (none when they give no
/// face frame).
pub fn find(mesh: &Mesh, marks: &[u32], points: &[Vec3]) -> BTreeMap<String, Vec<u32>> {
    let mut groups = BTreeMap::new();
    let Some(frame) = FaceFrame::of(points) else {
        return groups;
    };
    let eye = 0.5 * (points[36].distance(points[39]) + points[42].distance(points[45])) as f64;
    if eye <= 0.0 || marks.len() != points.len() {
        return groups;
    }
    let parts = find_parts(mesh, marks, points, &PartOverrides::default());
    let plane = Plane { frame, eye };
    for (side, marks_of) in SIDES.iter().zip(&EYE_MARKS) {
        let fallback = |ids: &[usize; 4]| ids.iter().map(|&i| points[i]).collect::<Vec<_>>();
        let (upper, lower) = match lid_edges(mesh, &parts, marks, marks_of) {
            Some(edges) => (edges.upper, edges.lower),
            None => (fallback(&marks_of.upper), fallback(&marks_of.lower)),
        };
        for (name, edge, onto) in [(UPPER_LID_LINE, upper, 1.0), (LOWER_LID_LINE, lower, -1.0)] {
            let members = plane.along_edge(mesh, &parts, &edge, onto);
            if !members.is_empty() {
                groups.insert(format!("{side}_{name}"), members);
            }
        }
    }
    let contour: Vec<Vec3> = (48..60).map(|i| points[i]).collect();
    let lips = plane.inside(mesh, &parts, &contour);
    if !lips.is_empty() {
        groups.insert(VERMILION.to_string(), lips);
    }
    groups
}

/// The face's plane and the eye's width, to place skin against the landmarks.
struct Plane {
    frame: FaceFrame,
    eye: f64,
}

impl Plane {
    /// `p` across the face, up it and out of it.
    fn local(&self, p: Vec3) -> DVec3 {
        self.frame.local(DVec3::ZERO, p.as_dvec3())
    }

    /// The skin vertices within [`LINE_WIDTH`] of a lid's free `edge` on the lid's side
    /// (`onto` +1 above the edge, -1 below), between the eye's corners.
    fn along_edge(&self, mesh: &Mesh, parts: &Parts, edge: &[Vec3], onto: f64) -> Vec<u32> {
        let mut line: Vec<DVec3> = edge.iter().map(|&p| self.local(p)).collect();
        line.sort_by(|a, b| a.x.total_cmp(&b.x));
        let (width, slack, reach) = (
            LINE_WIDTH * self.eye,
            LINE_SLACK * self.eye,
            DEPTH_REACH * self.eye,
        );
        skin(mesh, parts)
            .filter(|&v| {
                let q = self.local(mesh.positions[v as usize]);
                let Some(e) = super::lidedge::polyline_at(&line, q.x) else {
                    return false;
                };
                let off = (q.y - e.y) * onto;
                (-slack..=width).contains(&off) && (q.z - e.z).abs() <= reach
            })
            .collect()
    }

    /// The skin vertices inside the closed `contour` in the face's plane (or within
    /// [`LIP_SLACK`] of it), near it in depth.
    fn inside(&self, mesh: &Mesh, parts: &Parts, contour: &[Vec3]) -> Vec<u32> {
        let ring: Vec<DVec3> = contour.iter().map(|&p| self.local(p)).collect();
        let depth = ring.iter().map(|q| q.z).sum::<f64>() / ring.len() as f64;
        let (slack, reach) = (LIP_SLACK * self.eye, DEPTH_REACH * self.eye);
        skin(mesh, parts)
            .filter(|&v| {
                let q = self.local(mesh.positions[v as usize]);
                (q.z - depth).abs() <= reach
                    && (winds_around(&ring, q) || distance_to_ring(&ring, q) <= slack)
            })
            .collect()
    }
}

/// The skin vertices of `mesh`.
fn skin<'a>(mesh: &'a Mesh, parts: &'a Parts) -> impl Iterator<Item = u32> + 'a {
    (0..mesh.vertex_count() as u32).filter(|&v| parts.of_vertex[v as usize] == Part::Skin)
}

/// Whether the closed polygon `ring` (its `x`, `y`) winds around `q` (even-odd rule).
fn winds_around(ring: &[DVec3], q: DVec3) -> bool {
    let mut inside = false;
    for (k, a) in ring.iter().enumerate() {
        let b = ring[(k + 1) % ring.len()];
        if (a.y > q.y) != (b.y > q.y) {
            let x = a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if q.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The distance in the plane (`x`, `y`) from `q` to the closed polygon `ring`.
fn distance_to_ring(ring: &[DVec3], q: DVec3) -> f64 {
    let flat = |p: DVec3| glam::DVec2::new(p.x, p.y);
    let q = flat(q);
    (0..ring.len())
        .map(|k| {
            let (a, b) = (flat(ring[k]), flat(ring[(k + 1) % ring.len()]));
            let ab = b - a;
            let t = ((q - a).dot(ab) / ab.length_squared().max(f64::EPSILON)).clamp(0.0, 1.0);
            q.distance(a + ab * t)
        })
        .fold(f64::INFINITY, f64::min)
}
