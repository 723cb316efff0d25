//! Feature lines: which edges and contours a style draws, with their colour and depth bias.

use glam::Vec3;

use super::depth::depth_slope;
use super::{Edge, Renderer, Segment, NONE};
use crate::model::mesh::bounds_of as finite_bounds;
use crate::render::canvas::Rgb;
use crate::render::scene::{displacement_ramp, Scene, Style};

/// Depth bias (in dot heights) that lets a line lying on a surface pass the depth test.
const BASE_BIAS: f32 = 1.0;
/// Extra bias per unit of the adjacent faces' depth slope (dots of depth per dot).
const SLOPE_BIAS: f32 = 0.8;
/// Cap on the slope part of the bias, so steep faces do not let hidden lines through.
const MAX_SLOPE_BIAS: f32 = 6.0;

/// Displacements below this fraction of the full colour keep the mesh's own colour.
pub(super) const HEAT_FLOOR: f32 = 0.02;

impl Renderer {
    /// How far each vertex moved from rest, as a fraction of the full-colour displacement.
    #[inline(never)]
    pub(super) fn compute_heat(&mut self, scene: &Scene) {
        self.vertex_heat.clear();
        if !scene.displacement {
            return;
        }
        let rest = scene.rest_positions();
        let (lo, hi) = finite_bounds(rest);
        let full = (scene.displacement_full * (hi - lo).length()).max(f32::EPSILON);
        self.vertex_heat.extend(
            scene
                .positions
                .iter()
                .zip(rest)
                .map(|(p, r)| (*p - *r).length() / full),
        );
    }

    fn edge_color(&self, scene: &Scene, e: &Edge) -> Rgb {
        let heat = |i: u32| self.vertex_heat.get(i as usize).copied().unwrap_or(0.0);
        let h = heat(e.a).max(heat(e.b));
        if self.vertex_heat.is_empty() || h.is_nan() || h < HEAT_FLOOR {
            scene.palette.mesh
        } else {
            displacement_ramp(h)
        }
    }

    /// The depth bias for a line lying on the given triangles (the steeper, the larger).
    fn bias(&mut self, tris: [u32; 2]) -> f32 {
        let mut slope = 0.0f32;
        for t in tris {
            if t != NONE && self.facing.get(t as usize) == Some(&true) {
                slope = slope.max(self.slope(t as usize));
            }
        }
        BASE_BIAS + (SLOPE_BIAS * slope).min(MAX_SLOPE_BIAS)
    }

    /// The depth slope of front-facing triangle `t`, computed once per frame.
    #[inline]
    fn slope(&mut self, t: usize) -> f32 {
        let cached = self.slopes[t];
        // A slope is never NaN (`depth_slope` turns NaN into f32::MAX): NaN means not yet.
        if !cached.is_nan() {
            return cached;
        }
        let slope = depth_slope(self.triangles[t].map(|i| self.vert(i)));
        self.slopes[t] = slope;
        slope
    }

    /// Whether an edge belongs to the style's line set.
    fn wanted(&self, style: Style, e: &Edge, cos_crease: f32) -> bool {
        let f0 = self.facing[e.t0 as usize];
        let f1 = e.t1 != NONE && self.facing[e.t1 as usize];
        match style {
            Style::Wireframe => f0 || f1,
            Style::Shaded => false,
            Style::Lines => {
                if e.t1 == NONE {
                    return true;
                }
                if f0 != f1 {
                    return true;
                }
                f0 && f1 && {
                    let n0 = self.face_normals[e.t0 as usize];
                    let n1 = self.face_normals[e.t1 as usize];
                    n0.dot(n1) < cos_crease * (n0.length_squared() * n1.length_squared()).sqrt()
                }
            }
        }
    }

    /// Gathers the style's edges.
    #[inline(never)]
    pub(super) fn collect_edges(&mut self, scene: &Scene, style: Style) {
        if style == Style::Lines {
            self.compute_face_normals(scene);
        }
        let cos_crease = scene.crease_degrees.to_radians().cos();
        for k in 0..self.edges.len() {
            let e = self.edges[k];
            if !self.wanted(style, &e, cos_crease) {
                continue;
            }
            let (a, b) = (self.vert(e.a), self.vert(e.b));
            let bias = self.bias([e.t0, e.t1]);
            let color = self.edge_color(scene, &e);
            self.segments.push(Segment { a, b, bias, color });
        }
    }

    /// Gathers lines where the surface turns away from the viewer by a given amount: iso-lines of
    /// (vertex normal . direction to the viewer), drawn across front-facing triangles. They
    /// outline the sides of the nose, the eye sockets and the lips, which are smooth (no
    /// crease) and not on the silhouette.
    #[inline(never)]
    pub(super) fn collect_facing_contours(&mut self, scene: &Scene) {
        self.compute_normals(scene);
        self.vertex_facing.clear();
        let viewer = self.viewer_mesh;
        self.vertex_facing
            .extend(self.normals.iter().map(|n| n.dot(viewer)));
        let sign = self.sign(scene.orientation);
        let cos_crease = scene.crease_degrees.to_radians().cos();
        let color = scene.palette.contour;
        for t in 0..self.triangles.len() {
            if !self.facing[t] {
                continue;
            }
            let tri = self.triangles[t];
            let f = tri.map(|i| self.vertex_facing[i as usize]);
            // Most faces cross no level: test that first, smoothness only when one does.
            let mut smooth = None;
            for &level in scene.facing_contours {
                if !crosses(f, level) {
                    continue;
                }
                let Some((a, b)) = iso_crossing(tri.map(|i| self.vert(i)), f, level) else {
                    continue;
                };
                // Next to a crease the smoothed vertex normals say nothing about this face
                // (a box's corner normals would draw a line across a flat side): skip it.
                if !*smooth.get_or_insert_with(|| {
                    let face = self.face_normals[t].normalize_or_zero() * sign;
                    tri.iter()
                        .all(|&i| self.normals[i as usize].dot(face) >= cos_crease)
                }) {
                    break;
                }
                let bias = self.bias([t as u32, NONE]);
                self.segments.push(Segment { a, b, bias, color });
            }
        }
    }

    /// Gathers iso-depth contours across the front-facing triangles.
    #[inline(never)]
    pub(super) fn collect_contours(&mut self, scene: &Scene) {
        let (zmin, zmax) = self
            .projected
            .iter()
            .filter(|p| p.is_finite())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.z), hi.max(p.z))
            });
        if zmin >= zmax {
            return;
        }
        let step = (zmax - zmin) / (scene.contours + 1) as f32;
        let color = scene.palette.contour;
        for t in 0..self.triangles.len() {
            if !self.facing[t] {
                continue;
            }
            let p = self.triangles[t].map(|i| self.vert(i));
            let lo = p[0].z.min(p[1].z).min(p[2].z);
            let hi = p[0].z.max(p[1].z).max(p[2].z);
            let first = (((lo - zmin) / step).floor() as i64 + 1).max(1);
            let last = (((hi - zmin) / step).ceil() as i64 - 1).min(scene.contours as i64);
            for k in first..=last {
                let level = zmin + step * k as f32;
                if let Some((a, b)) = level_crossing(p, level) {
                    let bias = self.bias([t as u32, NONE]);
                    self.segments.push(Segment { a, b, bias, color });
                }
            }
        }
    }
}

/// Where the plane `z = level` cuts a triangle, as a segment (depth included).
fn level_crossing(p: [Vec3; 3], level: f32) -> Option<(Vec3, Vec3)> {
    iso_crossing(p, [p[0].z, p[1].z, p[2].z], level)
}

/// Whether [`iso_crossing`] finds a segment: the corners are not all on one side of
/// `level` (NaN counts as not below, as there). Cheap and branch-free, for the many faces
/// no line crosses.
#[inline]
pub(super) fn crosses(f: [f32; 3], level: f32) -> bool {
    let below = (f[0] < level) as u8 + (f[1] < level) as u8 + (f[2] < level) as u8;
    below % 3 != 0
}

/// Where a per-corner scalar `f` crosses `level` inside a triangle, as a segment between
/// points interpolated on its edges.
pub(super) fn iso_crossing(p: [Vec3; 3], f: [f32; 3], level: f32) -> Option<(Vec3, Vec3)> {
    let mut hits = [Vec3::ZERO; 2];
    let mut n = 0;
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        if (f[i] < level) != (f[j] < level) && n < 2 {
            let t = (level - f[i]) / (f[j] - f[i]);
            hits[n] = p[i] + (p[j] - p[i]) * t;
            n += 1;
        }
    }
    (n == 2).then_some((hits[0], hits[1]))
}

/// The sorted unique edges of `triangles` with the triangles on each side.
///
/// The half edges are bucketed by their smaller vertex (a counting sort: linear in the
/// mesh, where sorting all of them was most of a big mesh's first frame), then each
/// vertex's few are sorted by the other vertex and the triangle: the order of a sort by
/// (smaller vertex, larger vertex, triangle).
pub(super) fn build_edges(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<Edge> {
    let halves = |tri: [u32; 3]| {
        let valid = tri.iter().all(|&i| (i as usize) < vertex_count);
        [(0, 1), (1, 2), (2, 0)]
            .into_iter()
            .map(move |(i, j)| (tri[i].min(tri[j]), tri[i].max(tri[j])))
            .filter(move |&(a, b)| valid && a != b)
    };
    let mut start = vec![0u32; vertex_count + 1];
    for &tri in triangles {
        for (a, _) in halves(tri) {
            start[a as usize + 1] += 1;
        }
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut next = start.clone();
    let mut half = vec![(0u32, 0u32); start[vertex_count] as usize];
    for (t, &tri) in triangles.iter().enumerate() {
        for (a, b) in halves(tri) {
            half[next[a as usize] as usize] = (b, t as u32);
            next[a as usize] += 1;
        }
    }
    let mut edges: Vec<Edge> = Vec::with_capacity(half.len() / 2 + 1);
    for a in 0..vertex_count {
        let bucket = &mut half[start[a] as usize..start[a + 1] as usize];
        bucket.sort_unstable();
        for &(b, t) in bucket.iter() {
            match edges.last_mut() {
                Some(e) if e.a == a as u32 && e.b == b => {
                    // A third triangle on one edge (non-manifold) is ignored.
                    if e.t1 == NONE {
                        e.t1 = t;
                    }
                }
                _ => edges.push(Edge {
                    a: a as u32,
                    b,
                    t0: t,
                    t1: NONE,
                }),
            }
        }
    }
    edges
}
