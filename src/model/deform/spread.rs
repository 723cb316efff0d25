//! The skin spread: each muscle's pull carried into the skin around its zone, the way tissue
//! carries it, computed once at bind time (`docs/model.md`, "The skin spread").
//!
//! Waters' fields end where the muscle's zone ends, and inside it neighbouring vertices may
//! be pulled very differently (a cone's edge, an eye ring's band across the nose), which is
//! where skin tears. Each muscle's field `F` (displacement per unit activation) is replaced
//! by the solution `G` of one implicit heat step on the rest surface,
//!
//! ```text
//! (M + l^2 L) G = M F
//! ```
//!
//! with `M` the lumped (barycentric) vertex areas, `L` the cotangent Laplacian (weights
//! clamped at zero so the system stays positive definite on poor triangles) and `l` the
//! spread length. This is the finite-element form of `G - l^2 ΔG = F`: a smoothing whose
//! kernel dies out as `exp(-r / l)` along the surface, so its reach is set in face units and
//! not by the mesh's resolution. It runs along the mesh's edges only, so a lip or lid slit
//! that is open in the mesh is a cut, and vertices a muscle's mask holds at zero (the other
//! side of a joined mouth, the eyeballs) are kept out. The result is again a sparse field, so
//! a frame stays a linear blend.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::model::field::Field;
use crate::model::mesh::Distance;
use crate::model::mesh::Mesh;
use crate::model::muscle::MuscleKind;
use crate::model::Rig;

/// How far the spread is solved, in spread lengths: beyond it the kernel has fallen below
/// `exp(-4)` of its value and the field is taken as zero.
const REACH: f64 = 4.0;
/// Entries smaller than this fraction of the field's largest are left out (sparsity).
const KEEP: f64 = 1e-2;
/// Relative residual at which the conjugate gradients stop.
const TOLERANCE: f64 = 1e-7;
/// Most conjugate-gradient iterations (far more than a face needs).
const MAX_ITERATIONS: usize = 2000;

/// The rest surface's operators: vertex neighbours with cotangent weights, and vertex areas.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Surface {
    start: Vec<u32>,
    neighbour: Vec<u32>,
    /// Edge weight `(cot a + cot b) / 2`, clamped at zero, parallel to `neighbour`.
    weight: Vec<f64>,
    /// Edge length, parallel to `neighbour`.
    length: Vec<f64>,
    /// Lumped vertex area: a third of each triangle around it.
    mass: Vec<f64>,
}

impl Surface {
    /// The operators of `mesh`'s rest surface.
    pub(super) fn of(mesh: &Mesh) -> Surface {
        let p: Vec<DVec3> = mesh.positions.iter().map(|p| p.as_dvec3()).collect();
        let n = p.len();
        let mut mass = vec![0.0f64; n];
        // half-edge weights gathered per vertex pair, merged below
        let mut pairs: Vec<(u32, u32, f64)> = Vec::with_capacity(mesh.triangles.len() * 6);
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| p[i as usize]);
            let area = (b - a).cross(c - a).length() / 2.0;
            for i in 0..3 {
                mass[t[i] as usize] += area / 3.0;
                // the angle at corner i is opposite edge (j, k)
                let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                let (o, e1, e2) = (p[t[i] as usize], p[t[j] as usize], p[t[k] as usize]);
                let (u, v) = (e1 - o, e2 - o);
                let sin = u.cross(v).length();
                let cot = if sin > 0.0 { u.dot(v) / sin } else { 0.0 };
                let (lo, hi) = (t[j].min(t[k]), t[j].max(t[k]));
                pairs.push((lo, hi, cot / 2.0));
            }
        }
        pairs.sort_unstable_by_key(|&(a, b, _)| (a, b));
        let mut merged: Vec<(u32, u32, f64)> = Vec::with_capacity(pairs.len());
        for (a, b, w) in pairs {
            match merged.last_mut() {
                Some(last) if last.0 == a && last.1 == b => last.2 += w,
                _ => merged.push((a, b, w)),
            }
        }
        let mut start = vec![0u32; n + 1];
        for &(a, b, _) in &merged {
            start[a as usize + 1] += 1;
            start[b as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let total = start[n] as usize;
        let (mut neighbour, mut weight, mut length) =
            (vec![0u32; total], vec![0.0; total], vec![0.0; total]);
        for &(a, b, w) in &merged {
            let l = (p[a as usize] - p[b as usize]).length();
            for (from, to) in [(a, b), (b, a)] {
                let slot = fill[from as usize] as usize;
                fill[from as usize] += 1;
                neighbour[slot] = to;
                weight[slot] = w.max(0.0);
                length[slot] = l;
            }
        }
        Surface {
            start,
            neighbour,
            weight,
            length,
            mass,
        }
    }

    fn around(&self, v: usize) -> std::ops::Range<usize> {
        self.start[v] as usize..self.start[v + 1] as usize
    }

    /// Whether vertex `v` has an edge: a vertex in no triangle (a seam's copy, moved with
    /// its lead) is not on the surface, and its row of the system would be empty.
    fn on_surface(&self, v: usize) -> bool {
        !self.around(v).is_empty()
    }

    /// The vertices within `reach` of the field's vertices along the surface (never through
    /// a vertex where `open` is false), nearest first.
    fn region(&self, field: &Field, open: &dyn Fn(usize) -> bool, reach: f64) -> Vec<u32> {
        let n = self.mass.len();
        let mut distance = vec![f64::INFINITY; n];
        let mut queue = std::collections::BinaryHeap::new();
        for &v in &field.vertices {
            distance[v as usize] = 0.0;
            queue.push(std::cmp::Reverse((Distance(0.0), v)));
        }
        let mut region = Vec::new();
        let mut done = vec![false; n];
        while let Some(std::cmp::Reverse((Distance(d), v))) = queue.pop() {
            let vi = v as usize;
            if done[vi] {
                continue;
            }
            done[vi] = true;
            if !self.on_surface(vi) {
                continue;
            }
            region.push(v);
            for slot in self.around(vi) {
                let w = self.neighbour[slot] as usize;
                let next = d + self.length[slot];
                if next <= reach && next < distance[w] && open(w) {
                    distance[w] = next;
                    queue.push(std::cmp::Reverse((Distance(next), w as u32)));
                }
            }
        }
        region
    }

    /// The field spread over the surface by `length` (see the module's doc). `open(v)` is
    /// false where the muscle may not move the skin (its mask is zero there).
    pub(super) fn spread(&self, field: &Field, open: &dyn Fn(usize) -> bool, length: f64) -> Field {
        if field.is_empty() || length <= 0.0 {
            return field.clone();
        }
        let mut region = self.region(field, open, REACH * length);
        region.sort_unstable();
        let n = self.mass.len();
        let mut local = vec![u32::MAX; n];
        for (i, &v) in region.iter().enumerate() {
            local[v as usize] = i as u32;
        }
        let mut rhs = vec![DVec3::ZERO; region.len()];
        for (&v, d) in field.vertices.iter().zip(&field.displacements) {
            // (a field vertex off the surface is in no row)
            if let Some(slot) = rhs.get_mut(local[v as usize] as usize) {
                *slot = d.as_dvec3() * self.mass[v as usize];
            }
        }
        let system = System {
            surface: self,
            region: &region,
            local: &local,
            t: length * length,
        };
        let solved = system.solve(&rhs);
        // over the surface's vertices only, as the spread field's
        let largest = field
            .vertices
            .iter()
            .zip(&field.displacements)
            .filter(|(&v, _)| self.on_surface(v as usize))
            .map(|(_, d)| d.as_dvec3().length())
            .fold(0.0, f64::max);
        // the muscle keeps its strength: the spread field's largest travel is the muscle's own
        let spread_largest = solved.iter().map(|g| g.length()).fold(0.0, f64::max);
        let gain = if spread_largest > 0.0 {
            largest / spread_largest
        } else {
            1.0
        };
        let mut out = Field::default();
        for (&v, g) in region.iter().zip(&solved) {
            let g = *g * gain;
            if g.length() > KEEP * largest {
                out.vertices.push(v);
                out.displacements.push(g.as_vec3());
            }
        }
        out
    }
}

/// `(M + t L)` restricted to a region, with the field held at zero outside it.
struct System<'a> {
    surface: &'a Surface,
    region: &'a [u32],
    local: &'a [u32],
    t: f64,
}

impl System<'_> {
    /// `(M + t L) x` and the diagonal, row `i` of the region.
    fn row(&self, i: usize, x: &[DVec3]) -> DVec3 {
        let s = self.surface;
        let v = self.region[i] as usize;
        let mut sum = DVec3::ZERO;
        let mut diagonal = s.mass[v];
        for slot in s.around(v) {
            let w = s.weight[slot] * self.t;
            diagonal += w;
            let j = self.local[s.neighbour[slot] as usize];
            if j != u32::MAX {
                sum += x[j as usize] * w;
            }
        }
        x[i] * diagonal - sum
    }

    fn diagonal(&self, i: usize) -> f64 {
        let s = self.surface;
        let v = self.region[i] as usize;
        s.mass[v] + s.around(v).map(|slot| s.weight[slot]).sum::<f64>() * self.t
    }

    /// Jacobi-preconditioned conjugate gradients, the three coordinates side by side (each
    /// its own step sizes).
    fn solve(&self, b: &[DVec3]) -> Vec<DVec3> {
        let n = b.len();
        let inverse: Vec<f64> = (0..n).map(|i| 1.0 / self.diagonal(i)).collect();
        let mut x = vec![DVec3::ZERO; n];
        let mut r = b.to_vec();
        let mut z: Vec<DVec3> = r.iter().zip(&inverse).map(|(r, d)| *r * *d).collect();
        let mut p = z.clone();
        let dot =
            |a: &[DVec3], b: &[DVec3]| -> DVec3 { a.iter().zip(b).map(|(a, b)| *a * *b).sum() };
        let mut rz = dot(&r, &z);
        let b2 = dot(b, b);
        let mut ap = vec![DVec3::ZERO; n];
        for _ in 0..MAX_ITERATIONS {
            let r2 = dot(&r, &r);
            if r2.cmple(b2 * TOLERANCE * TOLERANCE).all() {
                break;
            }
            for (i, out) in ap.iter_mut().enumerate() {
                *out = self.row(i, &p);
            }
            let pap = dot(&p, &ap);
            let alpha = DVec3::select(pap.cmpgt(DVec3::ZERO), rz / pap, DVec3::ZERO);
            for i in 0..n {
                x[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
                z[i] = r[i] * inverse[i];
            }
            let next = dot(&r, &z);
            let beta = DVec3::select(rz.cmpgt(DVec3::ZERO), next / rz, DVec3::ZERO);
            rz = next;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
        }
        x
    }
}

/// The spread length of a rig: `fraction` of the diagonal of the box around its muscles'
/// anchor points (attachments, insertions, ring centres), so it scales with the face the
/// rig is placed on and not with the mesh it belongs to (a whole body) or its resolution.
pub(super) fn spread_length(rig: &Rig, fraction: f32) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    let mut add = |p: Vec3| {
        lo = lo.min(p.as_dvec3());
        hi = hi.max(p.as_dvec3());
    };
    for muscle in &rig.muscles {
        match &muscle.kind {
            MuscleKind::Linear(m) => {
                add(m.attachment);
                add(m.insertion);
            }
            MuscleKind::Sphincter(m) => add(m.centre),
            MuscleKind::Sheet(m) => m
                .attachment
                .iter()
                .chain(&m.insertion)
                .for_each(|p| add(*p)),
        }
    }
    if rig.muscles.is_empty() {
        return 0.0;
    }
    (hi - lo).length() * fraction as f64
}

/// Every field spread (in parallel, one muscle per task); `open[m]` says where muscle `m`
/// may move the skin (`None`: everywhere).
pub(super) fn spread_all(
    surface: &Surface,
    rig: &Rig,
    fields: Vec<Field>,
    scales: &[Option<Vec<f32>>],
    length: f64,
) -> Vec<Field> {
    fields
        .into_par_iter()
        .zip(scales.par_iter())
        .zip(rig.muscles.par_iter())
        .map(|((field, scale), muscle)| {
            spread_one(surface, &muscle.kind, field, scale.as_deref(), length)
        })
        .collect()
}

/// One muscle's field spread, kept off the vertices its mask scale holds at zero. A
/// sphincter's field is kept as it is: it already falls to zero on its ring, and spreading
/// an eye's ring would carry the lid's pull round the eye's corners into the other lid.
pub(super) fn spread_one(
    surface: &Surface,
    kind: &MuscleKind,
    field: Field,
    scale: Option<&[f32]>,
    length: f64,
) -> Field {
    if matches!(kind, MuscleKind::Sphincter(_)) {
        return field;
    }
    let field = &field;
    match scale {
        Some(scale) => surface.spread(field, &|v| scale[v] > 0.0, length),
        None => surface.spread(field, &|_| true, length),
    }
}
