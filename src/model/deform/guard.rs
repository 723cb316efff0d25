//! The skin's area bound (a rule of [`super::SkinRules`], beyond the paper; `docs/model.md`).
//!
//! After the muscles and the slide, before the jaw, each triangle whose area projected on its
//! rest normal falls below a fraction of its rest area gets the scale of its displacements
//! that would keep that fraction, and each vertex's displacement is scaled by the mean of its
//! triangles' scales (one pass, no promise), lowered no further than keeps the vertex within
//! a third of its shortest edge of where it would be unscaled ([`SCALE_SHARE`]); the jaw then
//! turns the result, so its travel is never scaled. Only triangles that could shrink that far
//! are checked (found at bind time).
//!
//! The bound is a per-triangle function of the positions before it, so a partial update
//! (`update_muscle`, `update_jaw`) recomputes the same numbers in the same order as a full
//! deformation and stays bit-identical to it.

use glam::Vec3;

use super::NO_ROW;
use crate::model::mesh::Mesh;

/// The most a vertex's scaled displacement may move it against a neighbour that keeps its
/// whole displacement, as a share of its shortest edge in a checked triangle (as the slide's
/// lift caps: three vertices each moved less than a third of an edge seldom bring one across
/// the opposite edge). The scale multiplies the vertex's whole travel, and neighbours' scales
/// (the means of their triangles') differ within one ring: on a mesh much finer than the
/// face's features a few hundredths of scale on a 10 mm travel turned triangles the muscles
/// alone left standing (MediaPipe's face cut in sixty-four: AU9 62 triangles, none without
/// the bound).
const SCALE_SHARE: f32 = 1.0 / 3.0;

/// The triangles that could shrink below the bound, and what a partial update touches.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct Guard {
    /// The checked triangles.
    pub triangles: Vec<[u32; 3]>,
    /// Each checked triangle's rest shape, prepared for [`Guard::triangle_scale`].
    shapes: Vec<TriangleShape>,
    /// The vertices of the checked triangles, sorted.
    pub vertices: Vec<u32>,
    /// Per mesh vertex: its index in `vertices`, or [`NO_ROW`].
    index: Vec<u32>,
    /// CSR from a guarded vertex to its checked triangles.
    tri_start: Vec<u32>,
    tri_list: Vec<u32>,
    /// Per muscle, then the jaw: the guarded vertices whose scale may change.
    pub settle: Vec<Vec<u32>>,
    /// Per muscle, then the jaw: the vertices whose positions those scales read.
    pub recompute: Vec<Vec<u32>>,
    /// Per muscle, then the jaw: the checked triangles of the `settle` vertices.
    pub rescale: Vec<Vec<u32>>,
    /// Per guarded vertex: its shortest rest edge in a checked triangle.
    shortest: Vec<f32>,
}

impl Guard {
    /// Finds the triangles that can shrink below `min_area` of their rest area when each
    /// vertex moves at most `reach[v]`; `moved[k]` lists what muscle `k` (the last entry:
    /// the jaw) moves.
    pub(super) fn new(mesh: &Mesh, min_area: f32, reach: &[f32], moved: &[&[u32]]) -> Guard {
        let mut guard = Guard::default();
        if min_area <= 0.0 {
            return guard;
        }
        guard.check_triangles(mesh, min_area, reach);
        guard.index_vertices(mesh.positions.len());
        guard.plan_updates(moved, mesh.positions.len());
        guard.shortest = vec![f32::INFINITY; guard.vertices.len()];
        for t in &guard.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let length = mesh.positions[a as usize].distance(mesh.positions[b as usize]);
                for v in [a, b] {
                    let g = guard.index[v as usize] as usize;
                    guard.shortest[g] = guard.shortest[g].min(length);
                }
            }
        }
        guard
    }

    /// The least scale guarded vertex `g` may take for a displacement of `travel`: a scale
    /// lowered by `1 - s` moves the vertex `(1 - s) travel` against a neighbour that keeps
    /// its own, and that is kept within [`SCALE_SHARE`] of its shortest edge.
    #[inline]
    pub(super) fn least_scale(&self, g: usize, travel: f32) -> f32 {
        if travel <= 0.0 {
            return 0.0;
        }
        1.0 - SCALE_SHARE * self.shortest[g] / travel
    }

    /// Keeps the triangles that could shrink below `min_area` of their rest area, with their
    /// rest shapes.
    fn check_triangles(&mut self, mesh: &Mesh, min_area: f32, reach: &[f32]) {
        let rest = &mesh.positions;
        for t in &mesh.triangles {
            let [p0, p1, p2] = t.map(|i| rest[i as usize].as_dvec3());
            let [b0, b1, b2] = t.map(|i| reach[i as usize] as f64);
            let (e1, e2) = (p1 - p0, p2 - p0);
            let n = e1.cross(e2);
            let a0 = n.length();
            if a0 == 0.0 || !a0.is_finite() {
                continue;
            }
            let (d1, d2) = (b1 + b0, b2 + b0);
            let worst = a0 - e1.length() * d2 - d1 * e2.length() - d1 * d2;
            if worst >= min_area as f64 * a0 {
                continue;
            }
            self.triangles.push(*t);
            let unit = n / a0;
            self.shapes.push(TriangleShape {
                across_e1: unit.cross(e1).as_vec3(),
                across_e2: e2.cross(unit).as_vec3(),
                normal: unit.as_vec3(),
                a0: a0 as f32,
                floor: (min_area as f64 * a0) as f32,
            });
        }
    }

    /// Lists the checked triangles' vertices and, per vertex, its checked triangles (CSR).
    fn index_vertices(&mut self, n: usize) {
        let mut count = vec![0u32; n];
        for t in &self.triangles {
            for &v in t {
                count[v as usize] += 1;
            }
        }
        self.index = vec![NO_ROW; n];
        self.tri_start.push(0);
        for (v, &c) in count.iter().enumerate() {
            if c > 0 {
                self.index[v] = self.vertices.len() as u32;
                self.vertices.push(v as u32);
                let last = *self.tri_start.last().unwrap_or(&0);
                self.tri_start.push(last + c);
            }
        }
        let mut fill: Vec<u32> = self.tri_start[..self.vertices.len()].to_vec();
        self.tri_list = vec![0; *self.tri_start.last().unwrap_or(&0) as usize];
        for (k, t) in self.triangles.iter().enumerate() {
            for &v in t {
                let g = self.index[v as usize] as usize;
                self.tri_list[fill[g] as usize] = k as u32;
                fill[g] += 1;
            }
        }
    }

    /// Per muscle (then the jaw), what its change can alter: the vertices whose scale may
    /// change, the vertices those scales read and the triangles to rescale.
    fn plan_updates(&mut self, moved: &[&[u32]], n: usize) {
        let mut stamp = vec![u32::MAX; n];
        let mut tri_stamp = vec![u32::MAX; self.triangles.len()];
        for (k, vertices) in moved.iter().enumerate() {
            let k32 = k as u32;
            // checked triangles with a moved vertex; their vertices' scales may change
            let mut settle = Vec::new();
            for &v in vertices.iter() {
                let g = self.index[v as usize];
                if g == NO_ROW {
                    continue;
                }
                for &t in self.triangles_of(g as usize) {
                    if tri_stamp[t as usize] == k32 {
                        continue;
                    }
                    tri_stamp[t as usize] = k32;
                    for &w in &self.triangles[t as usize] {
                        if stamp[w as usize] != k32 {
                            stamp[w as usize] = k32;
                            settle.push(w);
                        }
                    }
                }
            }
            settle.sort_unstable();
            // every vertex of every checked triangle of those vertices
            let mut recompute = Vec::new();
            let mut rescale = Vec::new();
            let second = k32 + moved.len() as u32;
            let third = second + moved.len() as u32;
            for &v in &settle {
                let g = self.index[v as usize] as usize;
                for &t in self.triangles_of(g) {
                    if tri_stamp[t as usize] != third {
                        tri_stamp[t as usize] = third;
                        rescale.push(t);
                    }
                    for &w in &self.triangles[t as usize] {
                        if stamp[w as usize] != second {
                            stamp[w as usize] = second;
                            recompute.push(w);
                        }
                    }
                }
            }
            recompute.sort_unstable();
            rescale.sort_unstable();
            self.settle.push(settle);
            self.recompute.push(recompute);
            self.rescale.push(rescale);
        }
    }

    /// True when no triangle needs checking.
    pub(super) fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The index of mesh vertex `v` among the guarded vertices, or [`NO_ROW`].
    #[inline]
    pub(super) fn index_of(&self, v: usize) -> u32 {
        self.index.get(v).copied().unwrap_or(NO_ROW)
    }

    pub(super) fn triangles_of(&self, g: usize) -> &[u32] {
        &self.tri_list[self.tri_start[g] as usize..self.tri_start[g + 1] as usize]
    }

    /// The scale of each checked triangle `t` (`scales[t]`, for the triangles listed, or all
    /// of them) from the positions `at` before the bound: the largest scale in 0..1 of its
    /// vertices' displacements that keeps it at its floor.
    #[inline]
    pub(super) fn triangle_scales(
        &self,
        which: Option<&[u32]>,
        rest: &[Vec3],
        at: &[Vec3],
        scales: &mut [f32],
    ) {
        let one = |t: usize| {
            let [i0, i1, i2] = self.triangles[t].map(|i| i as usize);
            let p0 = at[i0] - rest[i0];
            let d1 = at[i1] - rest[i1] - p0;
            let d2 = at[i2] - rest[i2] - p0;
            self.shapes[t].scale(d1, d2)
        };
        match which {
            Some(list) => {
                for &t in list {
                    scales[t as usize] = one(t as usize);
                }
            }
            None => {
                for (t, s) in scales[..self.triangles.len()].iter_mut().enumerate() {
                    *s = one(t);
                }
            }
        }
    }

    /// The scale of checked triangle `t` for displacements of its second and third vertices
    /// differing by `d1`, `d2` from its first's (what [`Guard::triangle_scales`] computes).
    #[inline]
    pub(super) fn triangle_scale(&self, t: usize, d1: Vec3, d2: Vec3) -> f32 {
        self.shapes[t].scale(d1, d2)
    }

    /// The scale of guarded vertex `g`'s displacement: the mean of its checked triangles'
    /// scales. (The smallest instead of the mean scales neighbouring vertices so differently
    /// that other triangles collapse.)
    #[inline]
    pub(super) fn vertex_scale(&self, g: usize, triangle_scales: &[f32]) -> f32 {
        let tris = self.triangles_of(g);
        let mut sum = 0.0f32;
        for &t in tris {
            sum += triangle_scales[t as usize];
        }
        sum / tris.len() as f32
    }
}

/// A checked triangle's rest shape: with `e1`, `e2` its rest edges from its first vertex and
/// `n` its unit normal, twice its projected area after displacements differing by `d1`,
/// `d2` from the first vertex's is `a0 + d2 . (n x e1) + d1 . (e2 x n) + n . (d1 x d2)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct TriangleShape {
    across_e1: Vec3,
    across_e2: Vec3,
    normal: Vec3,
    a0: f32,
    floor: f32,
}

impl TriangleShape {
    /// The largest `k` in 0..1 such that the displacements scaled by `k` keep twice the
    /// projected area at the floor or above (1 when the unscaled ones already do).
    #[inline]
    fn scale(&self, d1: Vec3, d2: Vec3) -> f32 {
        let a1 = d2.dot(self.across_e1) + d1.dot(self.across_e2);
        let a2 = self.normal.dot(d1.cross(d2));
        if self.a0 + a1 + a2 >= self.floor {
            return 1.0;
        }
        smaller_root(a2, a1, self.a0 - self.floor)
    }
}

/// The root in 0..1 of `a k^2 + b k + c` (positive at 0, negative at 1); 0 when there is
/// none (only by rounding).
fn smaller_root(a: f32, b: f32, c: f32) -> f32 {
    let (a, b, c) = (a as f64, b as f64, c as f64);
    let root = if a.abs() <= 1e-12 * (b.abs() + c.abs()) {
        -c / b
    } else {
        let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
        // the numerically stable pair of roots
        let q = -0.5 * (b + b.signum() * disc);
        let (r1, r2) = (q / a, c / q);
        let inside = |r: f64| r.is_finite() && (0.0..=1.0).contains(&r);
        match (inside(r1), inside(r2)) {
            (true, true) => r1.min(r2),
            (true, false) => r1,
            (false, true) => r2,
            (false, false) => 0.0,
        }
    };
    if root.is_finite() {
        root.clamp(0.0, 1.0) as f32
    } else {
        0.0
    }
}

#[cfg(test)]
/// The largest `k` in 0..1 such that the triangle `rest + k (moved - rest)` keeps twice its
/// area projected on `normal` at `floor` or above (1 when the moved triangle already does).
fn keep_area(rest: [Vec3; 3], moved: [Vec3; 3], normal: Vec3, floor: f32) -> f32 {
    let (e1, e2) = (rest[1] - rest[0], rest[2] - rest[0]);
    let shape = TriangleShape {
        across_e1: normal.cross(e1),
        across_e2: e2.cross(normal),
        normal,
        a0: normal.dot(e1.cross(e2)),
        floor,
    };
    let p0 = moved[0] - rest[0];
    shape.scale(moved[1] - rest[1] - p0, moved[2] - rest[2] - p0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keep_area_finds_the_scale_of_the_floor() {
        let rest = [Vec3::ZERO, Vec3::X, Vec3::Y];
        // vertex 1 pulled onto vertex 0: the area goes linearly from 1 to 0
        let moved = [Vec3::ZERO, Vec3::ZERO, Vec3::Y];
        let k = keep_area(rest, moved, Vec3::Z, 0.3);
        assert!((k - 0.7).abs() < 1e-6, "{k}");
        // a triangle that keeps its area keeps its whole displacement
        let shifted = rest.map(|p| p + Vec3::new(0.4, 0.2, 0.0));
        assert_eq!(keep_area(rest, shifted, Vec3::Z, 0.3), 1.0);
        // turned over: the floor is met before it flips
        let flipped = [Vec3::ZERO, -Vec3::X, Vec3::Y];
        let k = keep_area(rest, flipped, Vec3::Z, 0.3);
        assert!((k - 0.35).abs() < 1e-6, "{k}");
    }
}
