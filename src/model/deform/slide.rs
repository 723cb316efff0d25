//! The skin's slide (a rule of [`super::SkinRules`], beyond the paper; `docs/model.md`).
//!
//! Waters' linear muscle pulls a vertex straight toward a bone attachment deep inside the
//! head, so skin that travels far (a mouth corner at AU12) also sinks behind the rest
//! surface. Each moved vertex gets, at bind time, the rest surface around it (a normal and a
//! quadratic height field over a patch); after the muscles, the part of the displacement
//! that ends below it is mostly removed, so the skin slides along the face instead of into
//! it. Displacement out of the surface (a pout, a bulge) is kept.
//!
//! The slide is a per-vertex function of the positions before it, so a partial update
//! (`update_muscle`, `update_jaw`) recomputes the same numbers in the same order as a full
//! deformation and stays bit-identical to it.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::skin::Adjacency;
use crate::model::envelope::lower_envelope;
use crate::model::mesh::{Distance, Mesh};

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
    /// The longest lift the vertex takes, so that lifts within steep triangles' planes do
    /// not fold them (see [`set_lift_caps`]); [`NO_CAP`] where nothing caps it.
    lift_cap: f32,
}

/// The share of a triangle's smallest altitude its vertices' lifts may move them within its
/// plane, and the most neighbours' lift caps may differ per unit of distance between them
/// (`docs/model.md`, "The slide at folds"): three vertices each moved less than a third of
/// it cannot bring one across the opposite edge.
const LIFT_SHARE: f32 = 1.0 / 3.0;

/// The lift cap of a vertex nothing caps: finite, as the bind cache keeps only finite numbers.
const NO_CAP: f32 = f32::MAX;

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
            let lift = (depth * slide * self.grip).min(self.lift_cap);
            s + self.normal * lift
        } else {
            s
        }
    }
}

/// Most rest vertices a patch fit visits (the nearest ones), whatever their area: a bound on
/// the cost of a patch on a mesh many times finer than a face needs (32 times the 128 of
/// MakeHuman's base mesh or the built-in face). At 512 the patches of MediaPipe's face cut
/// in sixty-four (0.85 mm edges, finer still at the lips) shrank to 3 mm at the mouth
/// corners, where a smile then turned triangles over.
const PATCH_VERTICES: usize = 4096;

/// Fewest vertices a patch may be cut to by [`PATCH_VISITS`].
const PATCH_VERTICES_LEAST: usize = 512;

/// Most vertex visits of all the patches of one bind together: a mesh with more moved
/// vertices than this over [`PATCH_VERTICES`] (32 768, a head like MediaPipe's face cut in
/// sixty-four) has its patches cut to this over its moved vertices, but to no fewer than
/// [`PATCH_VERTICES_LEAST`]: whole patches' cost would grow with the square of the mesh's
/// size; this way it stays within the budget up to 262 144 moved vertices and grows as it
/// did beyond (`BENCHMARKS.md`: a head of 277 000 vertices binds in 1.75 times the time it
/// took with every patch cut to 512).
const PATCH_VISITS: usize = PATCH_VERTICES * 32_768;

/// The most vertices each patch of a bind fitting `moved` vertices visits.
fn patch_vertices(moved: usize) -> usize {
    (PATCH_VISITS / moved.max(1)).clamp(PATCH_VERTICES_LEAST, PATCH_VERTICES)
}

/// The most surface a patch gathers, as a share of the square of the face's size (the
/// diagonal of the box round the rig's muscles, about 210 mm on an adult face): about a
/// disc 20 mm across. A patch is gathered nearest first until it holds that much of the
/// mesh's area (each vertex a third of its triangles'), so a mesh four times finer fits its
/// patches over the same skin. Counted in vertices (128 before), a finer mesh's patches
/// shrank to a fold's own width at the mouth corners, and a smile turned its triangles over
/// there (MakeHuman cut in four: AU12 turned 2 over and stretched an edge 3.3x). 128
/// vertices of the built-in face or MakeHuman's base mesh hold 0.027 and 0.032 of it.
pub(super) const PATCH_AREA: f64 = 0.03;

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
    (radius, area): (f32, f64),
) -> Vec<Patch> {
    // Each vertex's patch depends on the rest mesh only, so chunks of vertices are fitted
    // on the rayon pool, each with its own search state: the same bits as one pass.
    let chunk = vertices.len().div_ceil(PATCH_CHUNKS).max(PATCH_CHUNK_MIN);
    let search = Search {
        mesh,
        adjacency,
        normals,
        radius,
        area,
        vertex_area: vertex_areas(mesh),
        most: patch_vertices(vertices.len()),
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
        let mut patches = vertices
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
            .collect::<Vec<Patch>>();
        set_lift_caps(mesh, &row, &mut patches);
        smooth_lift_caps(mesh, self.adjacency, vertices, &row, &mut patches);
        patches
    }
}

/// Sets each patch's [`Patch::lift_cap`]. The lift moves a vertex along its patch's normal;
/// in a triangle steeper than 45 degrees against that normal (a lip's underside beside a
/// mouth corner, whose patch faces out of the face) more of it runs within the triangle's
/// plane than out of it, and neighbours lifted by different lengths folded small triangles
/// over. Each such triangle caps its vertices' lift at [`LIFT_SHARE`] of its smallest
/// altitude over `sin - cos` of its angle to the patch's normal (the share itself for a lift
/// wholly within the plane). A triangle at 45 degrees or flatter (open face) caps nothing.
fn set_lift_caps(mesh: &Mesh, row: &[u32], patches: &mut [Patch]) {
    let rest = &mesh.positions;
    for p in patches.iter_mut() {
        p.lift_cap = NO_CAP;
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| rest[i as usize]);
        let cross = (b - a).cross(c - a);
        let longest = [b - a, c - b, a - c]
            .map(|e| e.length())
            .into_iter()
            .fold(0.0f32, f32::max);
        let Some(n) = cross.try_normalize() else {
            continue;
        };
        let altitude = cross.length() / longest;
        for &v in t {
            let r = row[v as usize];
            if r == u32::MAX {
                continue;
            }
            let patch = &mut patches[r as usize];
            let (sin, cos) = (patch.normal.cross(n).length(), patch.normal.dot(n).abs());
            let steep = sin - cos;
            if steep > 0.0 {
                patch.lift_cap = patch.lift_cap.min(LIFT_SHARE * altitude / steep);
            }
        }
    }
}

/// Lowers the lift caps until no two neighbours' caps differ by more than [`LIFT_SHARE`] of
/// the distance between them (each cap becomes the least over the moved vertices of their cap
/// plus that share of the distance along the mesh's edges, found nearest first): a capped
/// vertex beside an uncapped one would otherwise be left behind by its neighbour's whole lift.
fn smooth_lift_caps(
    mesh: &Mesh,
    adjacency: &Adjacency,
    vertices: &[u32],
    row: &[u32],
    patches: &mut [Patch],
) {
    let rest = &mesh.positions;
    let mut caps: Vec<f64> = patches.iter().map(|p| f64::from(p.lift_cap)).collect();
    let capped = (0..patches.len()).filter(|&r| patches[r].lift_cap < NO_CAP);
    let neighbours = |r: usize| {
        let v = vertices[r] as usize;
        adjacency.of_vertex(v).iter().filter_map(move |&w| {
            let q = row[w as usize];
            let length = (rest[w as usize] - rest[v]).length() as f64;
            (q != u32::MAX).then_some((q as usize, length))
        })
    };
    // Rounded to the caps' own precision, so the caps compared are the ones kept.
    let rise = |cap: f64, length: f64| (cap + f64::from(LIFT_SHARE) * length) as f32 as f64;
    lower_envelope(&mut caps, capped, neighbours, rise);
    for (patch, cap) in patches.iter_mut().zip(caps) {
        patch.lift_cap = cap as f32;
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
    /// The most surface a patch gathers ([`PATCH_AREA`]).
    area: f64,
    /// The most vertices a patch gathers ([`patch_vertices`]).
    most: usize,
    /// Each vertex's share of the surface: a third of each of its triangles.
    vertex_area: Vec<f64>,
}

/// Each vertex's share of the mesh's surface: a third of the area of each triangle it is a
/// corner of.
fn vertex_areas(mesh: &Mesh) -> Vec<f64> {
    let mut area = vec![0.0f64; mesh.vertex_count()];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
        let third = (b - a).cross(c - a).length() / 6.0;
        for &v in t {
            area[v as usize] += third;
        }
    }
    area
}

/// One vertex's patch: its points (vertex, distance), fitted extent and chosen normal.
struct Gathered {
    near: Vec<(usize, f64)>,
    reach: f64,
    normal: DVec3,
}

/// Where, as a share of the patch radius, a patch point's distance along the mesh's edges
/// starts to lower its weight (see [`weighed_distance`]).
const FADE_ALONG: f64 = 0.75;

/// The distance a patch point is weighed by: its straight distance `d` from the patch's
/// vertex, raised toward the radius `r` as its distance along the mesh's edges `path`
/// goes from [`FADE_ALONG`] of the radius to the radius itself, where a point no longer
/// joins the patch. Skin that is near in space but far along the surface (the other side
/// of a fold, the skin round an eye's opening) reached through a rim of the patch then
/// joins it with no weight instead of a large one: weighed by the straight distance alone,
/// the patches of neighbouring vertices a few tenths of a millimetre apart on a fine mesh's
/// upper lid differed by a region of 400 vertices below the eye and their normals by 11
/// degrees, and the lids' slide turned their triangles over. On open skin the path is
/// within a few percent of the straight distance, and nearer than that share of the radius
/// nothing changes.
fn weighed_distance(d: f64, path: f64, r: f64) -> f64 {
    d.max((path - FADE_ALONG * r) / (1.0 - FADE_ALONG))
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
        // each seen vertex's distance from the patch's vertex along the mesh's edges
        let mut along = vec![0.0f64; rest.len()];
        let mut queue = BinaryHeap::new();
        let r = self.radius as f64;
        vertices
            .iter()
            .enumerate()
            .map(|(stamp, &v)| {
                let v = v as usize;
                let p = rest[v].as_dvec3();
                let mut near: Vec<(usize, f64)> = Vec::new();
                let mut gathered = 0.0;
                queue.clear();
                // nearest first (ties by vertex number), so that mirrored vertices of a
                // symmetric mesh gather mirrored patches
                queue.push(Reverse((Distance(0.0), v)));
                seen[v] = stamp as u32;
                along[v] = 0.0;
                let mut farthest = 0.0f64;
                while let Some(Reverse((Distance(d), q))) = queue.pop() {
                    near.push((q, weighed_distance(d, along[q], r)));
                    farthest = d;
                    gathered += self.vertex_area[q];
                    if near.len() >= self.most || gathered >= self.area {
                        break;
                    }
                    let at = rest[q].as_dvec3();
                    for &w in self.adjacency.of_vertex(q) {
                        let w = w as usize;
                        let path = along[q] + (rest[w].as_dvec3() - at).length();
                        if seen[w] == stamp as u32 {
                            along[w] = along[w].min(path);
                            continue;
                        }
                        let d = (rest[w].as_dvec3() - p).length();
                        if d <= r && path <= r {
                            seen[w] = stamp as u32;
                            along[w] = path;
                            queue.push(Reverse((Distance(d), w)));
                        }
                    }
                }
                // the fitted extent: the patch radius, or less where the nearest vertices end
                let reach = farthest.min(r).max(r * 0.25);
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
            lift_cap: NO_CAP,
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

/// The numbers of a [`Patch`] in a fixed order, for the bind cache (`deform/cache.rs`),
/// which keeps fitted patches so that a cached bind need not fit them again.
pub(super) const PATCH_FLOATS: usize = 17;

impl Patch {
    /// The patch as [`PATCH_FLOATS`] numbers: normal, u, v, then d, e, a, b, c, radius, grip,
    /// lift cap.
    pub(super) fn to_floats(self) -> [f32; PATCH_FLOATS] {
        let [n, u, v] = [self.normal, self.u, self.v].map(|x| x.to_array());
        let (d, e, a, b, c, r) = (self.d, self.e, self.a, self.b, self.c, self.radius);
        let rest = [d, e, a, b, c, r, self.grip, self.lift_cap];
        let mut floats = [0.0; PATCH_FLOATS];
        for (slot, x) in floats
            .iter_mut()
            .zip(n.into_iter().chain(u).chain(v).chain(rest))
        {
            *slot = x;
        }
        floats
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
            lift_cap: f[16],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::model::deform::skin::outward_normals;

    /// A point reached along a path no longer than three quarters of the radius is weighed
    /// by its straight distance; beyond, its weight's distance rises to the radius (no
    /// weight) as the path reaches the radius, continuously and never below the straight
    /// distance.
    #[test]
    fn a_point_far_along_the_surface_is_weighed_as_far() {
        let r = 4.0;
        assert_eq!(weighed_distance(1.0, 2.9, r), 1.0);
        assert_eq!(weighed_distance(1.0, 3.0, r), 1.0);
        assert_eq!(weighed_distance(1.0, 4.0, r), r);
        assert!((weighed_distance(1.0, 3.5, r) - 2.0).abs() < 1e-12);
        assert_eq!(weighed_distance(3.0, 3.2, r), 3.0);
        let mut last = 0.5;
        for k in 0..=100 {
            let w = weighed_distance(0.5, 3.0 + k as f64 * 0.01, r);
            assert!(w >= last && w - last < 0.05, "{w} after {last}");
            last = w;
        }
    }

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
        let area = f64::from(radius * radius);
        let parallel = fit_patches(&mesh, &adjacency, &normals, &vertices, (radius, area));
        let search = Search {
            mesh: &mesh,
            adjacency: &adjacency,
            normals: &normals,
            radius,
            area,
            vertex_area: vertex_areas(&mesh),
            most: patch_vertices(vertices.len()),
        };
        let one_pass = search.fit_in_chunks(&vertices, vertices.len());
        assert_eq!(parallel, one_pass);
    }

    /// A flat patch in the plane z = 0 (normal +z), full grip, no cap on its lift.
    fn flat_patch(radius: f32) -> Patch {
        Patch {
            normal: Vec3::Z,
            u: Vec3::X,
            v: Vec3::Y,
            a: 0.0,
            b: 0.0,
            c: 0.0,
            d: 0.0,
            e: 0.0,
            radius,
            grip: 1.0,
            lift_cap: NO_CAP,
        }
    }

    #[test]
    fn slide_lifts_a_sinking_displacement_toward_the_patch() {
        // a flat patch: a displacement straight into it loses `slide` of its depth,
        // one out of it is kept
        let patch = flat_patch(1.0);
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

    #[test]
    fn a_steep_triangle_caps_the_lift_and_the_caps_grow_slowly_across_the_skin() {
        // a strip along x in the plane z = 0 whose first triangle stands up out of it: the
        // patch normals are +z, so a lift in that triangle runs within its plane
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-0.5, 0.5, 1.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(6.0, 0.0, 0.0),
            Vec3::new(6.0, 1.0, 0.0),
        ];
        let triangles = vec![
            [0, 1, 2],
            [0, 3, 1],
            [1, 3, 4],
            [3, 5, 4],
            [4, 5, 6],
            [5, 7, 6],
            [6, 7, 8],
        ];
        let mesh = Mesh::new(positions, triangles).expect("a mesh");
        let flat = flat_patch(10.0);
        let vertices: Vec<u32> = (0..9).filter(|&v| v != 2).collect();
        let mut row = vec![u32::MAX; 9];
        for (r, &v) in vertices.iter().enumerate() {
            row[v as usize] = r as u32;
        }
        let mut patches = vec![flat; vertices.len()];
        set_lift_caps(&mesh, &row, &mut patches);
        let cap = |patches: &[Patch], v: usize| patches[row[v] as usize].lift_cap;
        // the standing triangle: twice its area sqrt(1.25) over its longest edge sqrt(1.5),
        // at sin^2 = 0.8 to the patch normal; the flat ones cap nothing
        let expected = LIFT_SHARE * (1.25f32 / 1.5).sqrt() / (0.8f32.sqrt() - 0.2f32.sqrt());
        for v in [0, 1] {
            assert!(
                (cap(&patches, v) - expected).abs() < 1e-5,
                "{v}: {}",
                cap(&patches, v)
            );
        }
        assert_eq!(cap(&patches, 3), NO_CAP);
        smooth_lift_caps(&mesh, &Adjacency::of(&mesh), &vertices, &row, &mut patches);
        for v in [3, 5, 7] {
            let grown = cap(&patches, v) - cap(&patches, 0);
            let far = mesh.positions[v].x;
            assert!(
                grown > 0.0 && grown <= LIFT_SHARE * far * 1.0001,
                "{v}: {grown}"
            );
        }
        // the lift is no longer than the cap; a sink on open skin far away is lifted more
        let sink = Vec3::new(0.5, 0.0, -2.0);
        let near = patches[row[0] as usize].slide(sink, 1.0);
        let far = patches[row[7] as usize].slide(sink, 1.0);
        assert!((near.z - sink.z - cap(&patches, 0)).abs() < 1e-6, "{near}");
        assert!(far.z > near.z, "{far} {near}");
    }
}
