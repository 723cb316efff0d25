//! Keeping the skin on the face: two rules applied after the muscles (they go beyond the
//! paper; `docs/model.md` describes them).
//!
//! - **Slide.** Waters' linear muscle pulls a vertex straight toward a bone attachment deep
//!   inside the head, so skin that travels far (a mouth corner at AU12) also sinks behind
//!   the rest surface. Each moved vertex gets, at bind time, the rest surface around it (a
//!   normal and a quadratic height field over a patch); after the muscles, the part of the
//!   displacement that ends below it is mostly removed, so the skin slides along the face
//!   instead of into it. Displacement out of the surface (a pout, a bulge) is kept.
//! - **Area bound.** After the jaw, each triangle whose area projected on its rest normal
//!   falls below a fraction of its rest area gets the scale of its displacements that would
//!   keep that fraction, and each vertex's displacement is scaled by the mean of its
//!   triangles' scales (one pass, no promise). Only triangles that could shrink that far
//!   are checked (found at bind time).
//!
//! Both rules are per-vertex or per-triangle functions of the positions before them, so a
//! partial update (`update_muscle`, `update_jaw`) recomputes the same numbers in the same
//! order as a full deformation and stays bit-identical to it.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::NO_ROW;
use crate::model::mesh::{Distance, Mesh};

/// How displaced skin is kept on the face, beyond the paper's equations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkinRules {
    /// Fraction of a vertex's sink below the rest surface that is removed: 0 keeps the
    /// paper's displacement, 1 keeps the vertex on the fitted rest surface.
    pub slide: f32,
    /// Smallest fraction of its rest area (projected on its rest normal) a triangle keeps;
    /// 0 bounds nothing.
    pub min_area: f32,
    /// Radius of the patch of rest surface fitted around each vertex, as a fraction of the
    /// diagonal of the mesh's bounding box.
    pub patch: f32,
    /// Length over which each muscle's pull is spread into the skin around it, as a
    /// fraction of the diagonal of the box around the rig's muscles (`spread.rs`); 0 keeps
    /// each muscle's own field.
    pub spread: f32,
}

impl SkinRules {
    /// The paper's deformation: no slide, no area bound.
    pub const PAPER: SkinRules = SkinRules {
        slide: 0.0,
        min_area: 0.0,
        patch: 0.05,
        spread: 0.0,
    };

    /// What the editor, `grimace play` and `grimace render` bind with: 85 % of the sink removed, every triangle keeps at
    /// least 20 % of its rest area, patches of 5 % of the face's diagonal (about 14 mm on
    /// the default face).
    pub const DEFAULT: SkinRules = SkinRules {
        slide: 0.85,
        min_area: 0.2,
        patch: 0.05,
        spread: 0.0,
    };

    /// [`SkinRules::DEFAULT`] with each linear and sheet muscle's pull spread into the skin around
    /// it over 2 % of the diagonal of the box around the rig's muscles (about 4 mm on the
    /// built-in face; `docs/model.md`, "The skin spread"). Fewer tears; not yet the default
    /// because it moves some AUs of the built-in table (AU17 pushes the lower lip through
    /// the upper).
    pub const TISSUE: SkinRules = SkinRules {
        spread: 0.02,
        ..SkinRules::DEFAULT
    };

    /// True when every rule is off.
    pub fn is_paper(&self) -> bool {
        self.slide == 0.0 && self.min_area == 0.0 && self.spread == 0.0
    }

    /// Checks the values: slide and min_area in 0..1 (min_area below 1), patch above 0.
    pub fn check(&self) -> Result<(), String> {
        if !(self.slide.is_finite() && (0.0..=1.0).contains(&self.slide)) {
            return Err(format!("skin slide {} is outside 0.0 to 1.0", self.slide));
        }
        if !(self.min_area.is_finite() && (0.0..1.0).contains(&self.min_area)) {
            return Err(format!(
                "skin min_area {} is outside 0.0 to below 1.0",
                self.min_area
            ));
        }
        if !(self.spread.is_finite() && (0.0..=0.5).contains(&self.spread)) {
            return Err(format!("skin spread {} is outside 0.0 to 0.5", self.spread));
        }
        if !(self.patch.is_finite() && self.patch > 0.0 && self.patch <= 1.0) {
            return Err(format!(
                "skin patch {} must be above 0.0 and at most 1.0",
                self.patch
            ));
        }
        Ok(())
    }
}

impl Default for SkinRules {
    fn default() -> SkinRules {
        SkinRules::DEFAULT
    }
}

/// The rest surface around one vertex: an outward normal, two tangents and the quadratic
/// height `d x + e y + a x^2 + b x y + c y^2` along the normal at tangent offset `(x, y)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Patch {
    normal: Vec3,
    u: Vec3,
    v: Vec3,
    d: f32,
    e: f32,
    a: f32,
    b: f32,
    c: f32,
    radius: f32,
    grip: f32,
}

impl Patch {
    /// The displacement `s` with `slide` of its sink below the patch removed.
    #[inline(always)]
    pub(super) fn slide(&self, s: Vec3, slide: f32) -> Vec3 {
        let sn = s.dot(self.normal);
        let x = s.dot(self.u);
        let y = s.dot(self.v);
        let r2 = x * x + y * y;
        let mut h = self.a * x * x + self.b * x * y + self.c * y * y;
        if r2 > self.radius * self.radius {
            // beyond the fitted patch the height grows linearly from its value at the rim
            h *= self.radius / r2.sqrt();
        }
        h += self.d * x + self.e * y;
        // no steeper than 45 degrees from the tangent plane
        let r = r2.sqrt();
        let h = h.clamp(-r, r);
        let depth = h - sn;
        if depth > 0.0 {
            s + self.normal * (depth * slide * self.grip)
        } else {
            s
        }
    }
}

/// Vertex neighbours of a mesh (CSR).
pub(super) struct Adjacency {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Adjacency {
    pub(super) fn of(mesh: &Mesh) -> Adjacency {
        let n = mesh.positions.len();
        let edges = mesh.edges();
        let mut count = vec![0u32; n + 1];
        for [a, b] in &edges {
            count[*a as usize + 1] += 1;
            count[*b as usize + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut list = vec![0u32; count[n] as usize];
        for [a, b] in &edges {
            list[fill[*a as usize] as usize] = *b;
            fill[*a as usize] += 1;
            list[fill[*b as usize] as usize] = *a;
            fill[*b as usize] += 1;
        }
        Adjacency { start: count, list }
    }

    fn of_vertex(&self, v: usize) -> &[u32] {
        &self.list[self.start[v] as usize..self.start[v + 1] as usize]
    }
}

/// Most rest vertices a patch fit visits (the nearest ones).
const PATCH_VERTICES: usize = 128;

/// The outward rest normals: area-weighted vertex normals, turned round when the mesh's
/// triangles face into the head (their normals point toward the centroid on the whole).
pub(super) fn outward_normals(mesh: &Mesh) -> Vec<Vec3> {
    let rest = &mesh.positions;
    let mut normals = mesh.vertex_normals(rest);
    let centroid = rest.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / rest.len().max(1) as f64;
    let mut outward = 0.0f64;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| rest[i as usize].as_dvec3());
        outward += (b - a).cross(c - a).dot((a + b + c) / 3.0 - centroid);
    }
    if outward < 0.0 {
        normals.iter_mut().for_each(|n| *n = -*n);
    }
    normals
}

/// Fits the rest surface around each vertex of `vertices` (a patch of `radius`) in two
/// passes: each vertex's plane normal (weighted principal axes of its patch's points), then
/// the patch's normal, which is that plane's blended toward the mean of the first pass's
/// normals over the patch as far as the skin folds (1 - the plane's grip), and the height
/// field and grip in that frame. In a fold (a mouth corner) a vertex's own plane turns
/// quickly; lifted along it, neighbours moved apart and small triangles turned over.
pub(super) fn fit_patches(
    mesh: &Mesh,
    adjacency: &Adjacency,
    normals: &[Vec3],
    vertices: &[u32],
    radius: f32,
) -> Vec<Patch> {
    // Each vertex's patch depends on the rest mesh only, so chunks of vertices are fitted
    // on the rayon pool, each with its own search state: the same bits as one pass.
    let chunk = vertices.len().div_ceil(PATCH_CHUNKS).max(PATCH_CHUNK_MIN);
    let search = Search {
        mesh,
        adjacency,
        normals,
        radius,
    };
    search.fit_in_chunks(vertices, chunk)
}

impl Search<'_> {
    /// [`fit_patches`] with `vertices` split in chunks of `chunk`.
    fn fit_in_chunks(&self, vertices: &[u32], chunk: usize) -> Vec<Patch> {
        let (search, mesh, normals) = (self, self.mesh, self.normals);
        let planes: Vec<DVec3> = vertices
            .par_chunks(chunk)
            .flat_map_iter(|part| {
                search
                    .chunk(part, |near, weight, outward| {
                        plane_normal(&mesh.positions, near, weight, outward)
                    })
                    .into_iter()
                    .map(|(_, g)| g.normal)
            })
            .collect();
        let mut row = vec![u32::MAX; mesh.positions.len()];
        for (i, &v) in vertices.iter().enumerate() {
            row[v as usize] = i as u32;
        }
        vertices
            .par_chunks(chunk)
            .flat_map_iter(|part| {
                let fitted = search.chunk(part, |near, weight, outward| {
                    // the patch's own vertex comes first; on open skin (grip 1) its plane stays
                    let own = planes[row[near[0].0] as usize];
                    let fold = 1.0 - f64::from(grip(normals, near, weight, own));
                    let mean = near
                        .iter()
                        .filter(|&&(q, _)| row[q] != u32::MAX)
                        .map(|&(q, d)| planes[row[q] as usize] * weight(d))
                        .sum::<DVec3>()
                        .try_normalize()
                        .unwrap_or(outward);
                    (own * (1.0 - fold) + mean * fold)
                        .try_normalize()
                        .unwrap_or(outward)
                });
                fitted.into_iter().map(|(v, g)| search.patch(v, g))
            })
            .collect()
    }
}

/// Vertices per parallel chunk of [`fit_patches`] at least (each clears a mark per mesh
/// vertex), and the number of chunks it aims at (a few per core, for balance).
const PATCH_CHUNK_MIN: usize = 2048;
const PATCH_CHUNKS: usize = 64;

/// What one patch search reads.
struct Search<'a> {
    mesh: &'a Mesh,
    adjacency: &'a Adjacency,
    normals: &'a [Vec3],
    radius: f32,
}

/// One vertex's patch: its points (vertex, distance), fitted extent and chosen normal.
struct Gathered {
    near: Vec<(usize, f64)>,
    reach: f64,
    normal: DVec3,
}

impl Search<'_> {
    /// Gathers the patch of each vertex of `vertices` in order and gives each the normal
    /// `choose(points, weight, outward)` picks.
    fn chunk(
        &self,
        vertices: &[u32],
        choose: impl Fn(&[(usize, f64)], &dyn Fn(f64) -> f64, DVec3) -> DVec3,
    ) -> Vec<(usize, Gathered)> {
        let rest = &self.mesh.positions;
        let mut seen = vec![u32::MAX; rest.len()];
        let mut queue = BinaryHeap::new();
        let r = self.radius as f64;
        vertices
            .iter()
            .enumerate()
            .map(|(stamp, &v)| {
                let v = v as usize;
                let p = rest[v].as_dvec3();
                let mut near: Vec<(usize, f64)> = Vec::new();
                queue.clear();
                // nearest first (ties by vertex number), so that mirrored vertices of a
                // symmetric mesh gather mirrored patches
                queue.push(Reverse((Distance(0.0), v)));
                seen[v] = stamp as u32;
                while let Some(Reverse((Distance(d), q))) = queue.pop() {
                    near.push((q, d));
                    if near.len() >= PATCH_VERTICES {
                        break;
                    }
                    for &w in self.adjacency.of_vertex(q) {
                        let w = w as usize;
                        let d = (rest[w].as_dvec3() - p).length();
                        if seen[w] != stamp as u32 && d <= r {
                            seen[w] = stamp as u32;
                            queue.push(Reverse((Distance(d), w)));
                        }
                    }
                }
                // the fitted extent: the patch radius, or less where the nearest vertices end
                let reach = near.last().map_or(0.0, |&(_, d)| d).min(r).max(r * 0.25);
                let weight = |d: f64| (1.0 - d / (reach * 1.01)).max(0.0);
                let outward = near
                    .iter()
                    .map(|&(q, d)| self.normals[q].as_dvec3() * weight(d))
                    .sum::<DVec3>()
                    .normalize_or_zero();
                let normal = choose(&near, &weight, outward);
                (
                    v,
                    Gathered {
                        near,
                        reach,
                        normal,
                    },
                )
            })
            .collect()
    }

    /// The patch of vertex `v` from its gathered points, in the frame of their normal.
    fn patch(&self, v: usize, g: Gathered) -> Patch {
        let weight = |d: f64| (1.0 - d / (g.reach * 1.01)).max(0.0);
        let n = g.normal;
        let u = n.any_orthonormal_vector() * n.length(); // zero normal: a flat patch
        let (w, p) = (n.cross(u), self.mesh.positions[v].as_dvec3());
        let fit = surface_field(&self.mesh.positions, &g.near, p, [u, w, n]);
        Patch {
            normal: n.as_vec3(),
            u: u.as_vec3(),
            v: w.as_vec3(),
            d: fit[0] as f32,
            e: fit[1] as f32,
            a: fit[2] as f32,
            b: fit[3] as f32,
            c: fit[4] as f32,
            radius: g.reach as f32,
            grip: grip(self.normals, &g.near, weight, n),
        }
    }
}

/// The quadratic height field `z = d x + e y + a x^2 + b x y + c y^2` of the surface around
/// `p` in the frame `[u, v, normal]`, fitted by least squares to the patch's points with a
/// constant term (the vertex's own offset, dropped): so a vertex in a fold keeps its depth
/// below the surface around it instead of being lifted out past the rows around it (forced
/// through the vertex, the field was a bowl as steep as the fold). All zero if singular.
fn surface_field(rest: &[Vec3], near: &[(usize, f64)], p: DVec3, frame: [DVec3; 3]) -> [f64; 5] {
    let [u, w, n] = frame;
    let mut m = [[0.0f64; 6]; 6];
    let mut rhs = [0.0f64; 6];
    for &(q, _) in near {
        let d = rest[q].as_dvec3() - p;
        let (x, y, z) = (d.dot(u), d.dot(w), d.dot(n));
        let row = [1.0, x, y, x * x, x * y, y * y];
        for i in 0..6 {
            for j in 0..6 {
                m[i][j] += row[i] * row[j];
            }
            rhs[i] += row[i] * z;
        }
    }
    match solve(m, rhs) {
        Some([_, d, e, a, b, c]) => [d, e, a, b, c],
        None => [0.0; 5],
    }
}

/// The cosine of the steepest the slide lets a surface be against its patch's plane (45
/// degrees, as [`Patch::slide`] caps the height).
const STEEPEST: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// How much of the slide a vertex takes: the share of its patch's skin facing the way the
/// patch does (outward normals' components along it over [`STEEPEST`], clamped to 0..1,
/// weighted toward the vertex), squared. 1 on open face; less in a slit or round a corner,
/// where the skin faces across and neighbouring rows, each lifted onto its own side, crossed.
fn grip(normals: &[Vec3], near: &[(usize, f64)], weight: impl Fn(f64) -> f64, n: DVec3) -> f32 {
    let (mut facing, mut total) = (0.0f64, 0.0f64);
    for &(q, d) in near {
        let k = weight(d);
        facing += k * (normals[q].as_dvec3().dot(n) / STEEPEST).clamp(0.0, 1.0);
        total += k;
    }
    if total > 0.0 {
        let share = facing / total;
        (share * share) as f32
    } else {
        1.0
    }
}

/// The normal of the plane fitted to the patch's points (weighted principal axes, the
/// smallest one), turned to agree with `outward`; `outward` itself when the points span no
/// plane. It depends on the points only, not on how the mesh is triangulated, so mirrored
/// vertices of a mirrored set of points get mirrored normals.
fn plane_normal(
    rest: &[Vec3],
    near: &[(usize, f64)],
    weight: impl Fn(f64) -> f64,
    outward: DVec3,
) -> DVec3 {
    if outward == DVec3::ZERO || near.len() < 3 {
        return outward;
    }
    let total: f64 = near.iter().map(|&(_, d)| weight(d)).sum();
    if total <= 0.0 {
        return outward;
    }
    let centre = near
        .iter()
        .map(|&(q, d)| rest[q].as_dvec3() * weight(d))
        .sum::<DVec3>()
        / total;
    let mut c = glam::DMat3::ZERO;
    for &(q, d) in near {
        let r = rest[q].as_dvec3() - centre;
        let w = weight(d);
        c += glam::DMat3::from_cols(r * (r.x * w), r * (r.y * w), r * (r.z * w));
    }
    // power iteration on trace(C) I - C converges to C's smallest axis
    let trace = c.x_axis.x + c.y_axis.y + c.z_axis.z;
    let flipped = glam::DMat3::from_diagonal(DVec3::splat(trace)) - c;
    let mut n = outward;
    for _ in 0..64 {
        n = (flipped * n).normalize_or_zero();
        if n == DVec3::ZERO {
            return outward;
        }
    }
    if n.dot(outward) < 0.0 {
        -n
    } else {
        n
    }
}

/// Solves a small linear system by Gaussian elimination with partial pivoting; `None` when
/// it is (nearly) singular.
fn solve<const N: usize>(mut m: [[f64; N]; N], mut r: [f64; N]) -> Option<[f64; N]> {
    let scale = m.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    for col in 0..N {
        let pivot = (col..N).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col].abs() <= 1e-12 * scale {
            return None;
        }
        m.swap(col, pivot);
        r.swap(col, pivot);
        let (top, below) = m.split_at_mut(col + 1);
        let pivot_row = &top[col];
        for (offset, row) in below.iter_mut().enumerate() {
            let f = row[col] / pivot_row[col];
            for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= f * p;
            }
            r[col + 1 + offset] -= f * r[col];
        }
    }
    let mut out = [0.0; N];
    for row in (0..N).rev() {
        let mut acc = r[row];
        for k in row + 1..N {
            acc -= m[row][k] * out[k];
        }
        out[row] = acc / m[row][row];
    }
    out.iter().all(|x| x.is_finite()).then_some(out)
}

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
        guard
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

/// The numbers of a [`Patch`] in a fixed order, for the bind cache (`deform/cache.rs`),
/// which keeps fitted patches so that a cached bind need not fit them again.
pub(super) const PATCH_FLOATS: usize = 16;

impl Patch {
    /// The patch as [`PATCH_FLOATS`] numbers: normal, u, v, then d, e, a, b, c, radius, grip.
    pub(super) fn to_floats(self) -> [f32; PATCH_FLOATS] {
        let [n, u, v] = [self.normal, self.u, self.v].map(|x| x.to_array());
        let (d, e, a, b, c, r) = (self.d, self.e, self.a, self.b, self.c, self.radius);
        [
            n[0], n[1], n[2], u[0], u[1], u[2], v[0], v[1], v[2], d, e, a, b, c, r, self.grip,
        ]
    }

    /// The patch [`Patch::to_floats`] gave.
    pub(super) fn from_floats(f: [f32; PATCH_FLOATS]) -> Patch {
        Patch {
            normal: Vec3::new(f[0], f[1], f[2]),
            u: Vec3::new(f[3], f[4], f[5]),
            v: Vec3::new(f[6], f[7], f[8]),
            d: f[9],
            e: f[10],
            a: f[11],
            b: f[12],
            c: f[13],
            radius: f[14],
            grip: f[15],
        }
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
    fn patches_fitted_in_parallel_chunks_are_those_of_one_pass() {
        let mesh = crate::io::builtin::default_mesh();
        // every vertex, in a scrambled order, so that several chunks are made
        let n = mesh.vertex_count() as u32;
        let vertices: Vec<u32> = (0..n).map(|i| (i * 7919) % n).collect();
        assert!(
            vertices.len() > 2 * PATCH_CHUNK_MIN,
            "too few vertices for two chunks"
        );
        let adjacency = Adjacency::of(&mesh);
        let normals = outward_normals(&mesh);
        let (lo, hi) = mesh.bounds();
        let radius = (hi - lo).length() * 0.05;
        let parallel = fit_patches(&mesh, &adjacency, &normals, &vertices, radius);
        let search = Search {
            mesh: &mesh,
            adjacency: &adjacency,
            normals: &normals,
            radius,
        };
        let one_pass = search.fit_in_chunks(&vertices, vertices.len());
        assert_eq!(parallel, one_pass);
    }

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

    #[test]
    fn slide_lifts_a_sinking_displacement_toward_the_patch() {
        // a flat patch: a displacement straight into it loses `slide` of its depth,
        // one out of it is kept
        let patch = Patch {
            normal: Vec3::Z,
            u: Vec3::X,
            v: Vec3::Y,
            a: 0.0,
            b: 0.0,
            c: 0.0,
            d: 0.0,
            e: 0.0,
            radius: 1.0,
            grip: 1.0,
        };
        let s = patch.slide(Vec3::new(0.5, 0.0, -0.4), 0.75);
        assert!((s - Vec3::new(0.5, 0.0, -0.1)).length() < 1e-6, "{s}");
        assert_eq!(patch.slide(Vec3::new(0.5, 0.0, 0.4), 0.75).z, 0.4);
        // a dome curving away (height -x^2): sliding 0.5 along x may end 0.25 lower
        let dome = Patch {
            a: -1.0,
            c: -1.0,
            ..patch
        };
        let s = dome.slide(Vec3::new(0.5, 0.0, -0.25), 1.0);
        assert_eq!(s.z, -0.25);
        let s = dome.slide(Vec3::new(0.5, 0.0, -1.25), 1.0);
        assert!((s.z + 0.25).abs() < 1e-6, "{s}");
    }
}
