//! Feature lines: which edges and contours a style draws, with their colour and depth bias.

use glam::Vec3;

use super::bands::join;
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

    /// The depth bias for a line lying on the given triangles (the steeper, the larger),
    /// with `slope(t)` the depth slope of front-facing triangle `t`.
    fn bias(&self, tris: [u32; 2], mut slope: impl FnMut(usize) -> f32) -> f32 {
        let mut steepest = 0.0f32;
        for t in tris {
            if t != NONE && self.facing.get(t as usize) == Some(&true) {
                steepest = steepest.max(slope(t as usize));
            }
        }
        BASE_BIAS + (SLOPE_BIAS * steepest).min(MAX_SLOPE_BIAS)
    }

    /// The depth slope of triangle `t` in this frame.
    #[inline]
    fn slope_of(&self, t: usize) -> f32 {
        depth_slope(self.triangles[t].map(|i| self.vert(i)))
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

    /// Gathers the style's lines into `segments`, in drawing order: the edges, then (the
    /// `lines` style) the iso-depth contours and the facing contours. On a big mesh the
    /// edges are gathered beside the contours, each into its own list, joined in that
    /// order (the same lines as one after the other).
    #[inline(never)]
    pub(super) fn collect_lines(&mut self, scene: &Scene, style: Style) {
        if style == Style::Lines {
            self.compute_face_normals(scene);
        }
        let contours = style == Style::Lines && scene.contours > 0;
        let facing = style == Style::Lines && !scene.facing_contours.is_empty();
        let mut edges = std::mem::take(&mut self.segments);
        let mut slopes = std::mem::take(&mut self.slopes);
        let mut late = std::mem::take(&mut self.late_segments);
        let mut normals = std::mem::take(&mut self.normals);
        let mut toward = std::mem::take(&mut self.vertex_facing);
        late.clear();
        let this = &*self;
        join(
            self.parallel(),
            || this.collect_edges(scene, style, &mut slopes, &mut edges),
            || {
                if contours {
                    this.collect_contours(scene, &mut late);
                }
                if facing {
                    this.vertex_normals(scene, &mut normals);
                    this.collect_facing_contours(scene, (&normals, &mut toward), &mut late);
                }
            },
        );
        edges.append(&mut late);
        (self.segments, self.slopes, self.late_segments) = (edges, slopes, late);
        (self.normals, self.vertex_facing) = (normals, toward);
    }

    /// Gathers the style's edges into `out`, with `slopes` the per-triangle depth slopes of
    /// this frame computed once (NaN until needed).
    fn collect_edges(
        &self,
        scene: &Scene,
        style: Style,
        slopes: &mut [f32],
        out: &mut Vec<Segment>,
    ) {
        let cos_crease = scene.crease_degrees.to_radians().cos();
        let mut slope = |t: usize| {
            // A slope is never NaN (`depth_slope` turns NaN into f32::MAX): NaN means not yet.
            if slopes[t].is_nan() {
                slopes[t] = self.slope_of(t);
            }
            slopes[t]
        };
        for e in &self.edges {
            if !self.wanted(style, e, cos_crease) {
                continue;
            }
            let (a, b) = (self.vert(e.a), self.vert(e.b));
            let bias = self.bias([e.t0, e.t1], &mut slope);
            let color = self.edge_color(scene, e);
            out.push(Segment { a, b, bias, color });
        }
    }

    /// Gathers lines where the surface turns away from the viewer by a given amount: iso-lines of
    /// (vertex normal . direction to the viewer), drawn across front-facing triangles. They
    /// outline the sides of the nose, the eye sockets and the lips, which are smooth (no
    /// crease) and not on the silhouette. `normals` are this frame's vertex normals;
    /// `toward` receives how much each faces the viewer.
    fn collect_facing_contours(
        &self,
        scene: &Scene,
        (normals, toward): (&[Vec3], &mut Vec<f32>),
        out: &mut Vec<Segment>,
    ) {
        toward.clear();
        let viewer = self.viewer_mesh;
        toward.extend(normals.iter().map(|n| n.dot(viewer)));
        let sign = self.sign(scene.orientation);
        let cos_crease = scene.crease_degrees.to_radians().cos();
        let color = scene.palette.contour;
        for t in 0..self.triangles.len() {
            if !self.facing[t] {
                continue;
            }
            let tri = self.triangles[t];
            let f = tri.map(|i| toward[i as usize]);
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
                        .all(|&i| normals[i as usize].dot(face) >= cos_crease)
                }) {
                    break;
                }
                let bias = self.bias([t as u32, NONE], |t| self.slope_of(t));
                out.push(Segment { a, b, bias, color });
            }
        }
    }

    /// Gathers iso-depth contours across the front-facing triangles into `out`.
    fn collect_contours(&self, scene: &Scene, out: &mut Vec<Segment>) {
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
                    let bias = self.bias([t as u32, NONE], |t| self.slope_of(t));
                    out.push(Segment { a, b, bias, color });
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
