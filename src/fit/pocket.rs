//! The mouth pocket appended behind cut lips: a closed bag of triangles from the inner lip
//! contour back into the head, in the group `mouth_interior` (drawn nearly black by
//! `shaded`, kept still by the muscles).
//!
//! A face mask such as MediaPipe's has no inside: once its lips are cut ([`super::lipcut`]),
//! an opened mouth shows whatever lies behind the mask. The pocket gives it an inside. It has
//! two sheets, one behind each lip, joined at the corners and along a back row: each sheet
//! runs from a rim just behind its lip's inner edge (the cut line for the upper lip, the
//! copies for the lower) back to the back row, bulging away from the other sheet (up for the
//! upper, down for the lower) in the middle and closing at the corners. The sheets are the
//! pocket's own vertices: the lips stay skin, and the pocket is a separate piece that the
//! jaw turns. Its jaw weights ([`Pocket::jaw_weights`]) follow the lips at the rim (each rim
//! vertex the weight of the lip vertex it sits behind) and meet halfway between the lips'
//! weights at the back row, so the lower sheet turns with the jaw and the upper stays.

use std::f32::consts::PI;

use glam::Vec3;

use crate::landmarks::FaceFrame;
use crate::model::Mesh;

/// The pocket's group name: the renderer's dark tone for the inside of the mouth, a rigid
/// part for `fit-rig`.
pub const GROUP: &str = "mouth_interior";

/// How deep the pocket reaches behind the lips, in outer mouth widths.
const DEPTH: f32 = 0.45;
/// How far each sheet bulges away from the lip line halfway back, in outer mouth widths.
const BULGE: f32 = 0.2;
/// How far behind its lip edge the rim sits, in outer mouth widths: behind the lip's own
/// surface, so the closed mouth hides it.
const INSET: f32 = 0.02;
/// Rows of each sheet from the rim to the back row.
const ROWS: usize = 4;

/// A mouth pocket appended to an opened mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Pocket {
    /// The pocket's first vertex in the mesh; it holds the vertices from there on.
    pub first: u32,
    /// Per pocket vertex, where its jaw weight comes from: the upper lip vertex and the
    /// lower lip vertex it lies between, and the lower one's share.
    pub sources: Vec<(u32, u32, f32)>,
    /// The pocket's triangles' number in the mesh: they are the last ones.
    pub triangles: usize,
}

impl Pocket {
    /// Appends a pocket to `mesh` behind the inner lip edges `upper` and `lower` (vertex
    /// numbers from the right inner corner to the left, corners shared, as long as each
    /// other), in a face whose landmark positions are `points`; `None` when the landmarks
    /// have no frame or the edges are too short.
    pub fn append(
        mesh: &mut Mesh,
        upper: &[u32],
        lower: &[u32],
        points: &[Vec3],
    ) -> Option<Pocket> {
        let frame = FaceFrame::of(points)?;
        let m = upper.len();
        if m < 3 || lower.len() != m {
            return None;
        }
        let (fwd, up) = (frame.forward.as_vec3(), frame.up.as_vec3());
        let width = points[48].distance(points[54]);
        let at = |v: u32| mesh.positions[v as usize];
        let first = mesh.vertex_count() as u32;
        let mut positions: Vec<Vec3> = Vec::new();
        let mut sources: Vec<(u32, u32, f32)> = Vec::new();
        let mut add = |p: Vec3, source: (u32, u32, f32)| {
            positions.push(p);
            sources.push(source);
            first + positions.len() as u32 - 1
        };
        let back_of = |i: usize| {
            let mid = 0.5 * (at(upper[i]) + at(lower[i]));
            mid - fwd * (INSET + DEPTH * arc_share(i, m)) * width
        };
        // the corners: one vertex each, shared by every row of both sheets
        let corners = [0, m - 1].map(|k| add(back_of(k), (upper[k], lower[k], 0.5)));
        let row_of = |add: &mut dyn FnMut(Vec3, (u32, u32, f32)) -> u32,
                      place: &dyn Fn(usize) -> (Vec3, f32)| {
            (0..m)
                .map(|i| match i {
                    0 => corners[0],
                    i if i == m - 1 => corners[1],
                    i => {
                        let (p, share) = place(i);
                        add(p, (upper[i], lower[i], share))
                    }
                })
                .collect::<Vec<u32>>()
        };
        let back = row_of(&mut add, &|i| (back_of(i), 0.5));
        // rows[sheet][row][column]: the vertex there; both sheets end on the back row
        let mut rows: Vec<Vec<Vec<u32>>> = Vec::new();
        for (edge, sign, rim_share) in [(upper, 1.0f32, 0.0f32), (lower, -1.0, 1.0)] {
            let mut sheet: Vec<Vec<u32>> = (0..ROWS)
                .map(|row| {
                    let s = row as f32 / ROWS as f32;
                    let place = |i: usize| {
                        let rim = at(edge[i]) - fwd * INSET * width;
                        let lift = sign * BULGE * width * arc_share(i, m) * (PI * s).sin();
                        let share = rim_share + (0.5 - rim_share) * s;
                        (rim.lerp(back_of(i), s) + up * lift, share)
                    };
                    row_of(&mut add, &place)
                })
                .collect();
            sheet.push(back.clone());
            rows.push(sheet);
        }
        let centre = (0..m).map(&back_of).sum::<Vec3>() / m as f32;
        let front = centre + fwd * 2.0 * DEPTH * width;
        let before = mesh.triangles.len();
        mesh.positions.extend(positions);
        for sheet in &rows {
            stitch(mesh, sheet, front);
        }
        let members: Vec<u32> = (first..mesh.vertex_count() as u32).collect();
        mesh.groups.insert(GROUP.to_string(), members);
        Some(Pocket {
            first,
            sources,
            triangles: mesh.triangles.len() - before,
        })
    }

    /// The pocket vertices' jaw weights from the lips' (`weight(v)` for a lip vertex `v`):
    /// each the blend of the upper and lower lip vertex it lies between by its share.
    pub fn jaw_weights(&self, weight: impl Fn(u32) -> f32) -> Vec<(u32, f32)> {
        self.sources
            .iter()
            .enumerate()
            .map(|(k, &(a, b, share))| {
                let w = (1.0 - share) * weight(a) + share * weight(b);
                (self.first + k as u32, w)
            })
            .collect()
    }
}

/// Joins each row of a sheet to the next by two triangles per column, facing `front`; the
/// triangles at the shared corner vertices (two of whose corners are one vertex) are left out.
fn stitch(mesh: &mut Mesh, sheet: &[Vec<u32>], front: Vec3) {
    for (near, far) in sheet.iter().zip(&sheet[1..]) {
        for (i, pair) in near.windows(2).enumerate() {
            let [a, b, c, d] = [pair[0], pair[1], far[i + 1], far[i]];
            for tri in [[a, b, c], [a, c, d]] {
                if tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2] {
                    mesh.triangles.push(facing(&mesh.positions, tri, front));
                }
            }
        }
    }
}

/// How far column `i` of `m` lies from the nearer corner, as `sqrt(1 - t^2)` of its place
/// `t` from the middle (-1 and 1 at the corners): the pocket is deepest in the middle and
/// closes at the corners.
fn arc_share(i: usize, m: usize) -> f32 {
    let t = 2.0 * i as f32 / (m - 1) as f32 - 1.0;
    (1.0 - t * t).max(0.0).sqrt()
}

/// The triangle wound so that its normal faces `toward` (the inside of the pocket is seen
/// from in front of the mouth).
fn facing(positions: &[Vec3], tri: [u32; 3], toward: Vec3) -> [u32; 3] {
    let [a, b, c] = tri.map(|v| positions[v as usize]);
    let normal = (b - a).cross(c - a);
    if normal.dot(toward - (a + b + c) / 3.0) < 0.0 {
        [tri[0], tri[2], tri[1]]
    } else {
        tri
    }
}
