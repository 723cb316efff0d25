//! Fitting an AU entry to a target shape: the muscle activations (0 to 2) and jaw activation
//! (0 to 4) whose deformation best reproduces the target's displacement from rest.
//!
//! The fit is made on the deformation the rig was bound with ([`crate::model::Deformation`]).
//! For the paper's bare model and a fixed jaw activation the deformation is affine in the
//! muscle activations (each vertex's jaw blend is an affine map of its post-muscle position),
//! so the muscles come from a box-constrained linear least-squares problem solved exactly by
//! the active-set method of [`super::lsq`], and the jaw from a scan and a golden-section search over its range.
//! The skin rules make the deformation nonlinear: that linear solution is then the start of
//! projected Gauss-Newton iterations on the deformation itself (a forward-difference
//! Jacobian at the current estimate, the same bounded least squares for the step, a
//! backtracking line search on the true residual), which keep every activation in range.

use glam::{DMat3, DVec3, Vec3};
use thiserror::Error;

use super::lsq::{activation_bounds, box_least_squares};
use crate::model::{Activations, BoundRig, JAW_RANGE, MUSCLE_RANGE};

/// Why a target cannot be fitted.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolveError {
    /// The target has another vertex count than the rig's mesh.
    #[error("the target has {given} vertices but the rig's mesh has {expected}; a target must be the same mesh, vertex for vertex")]
    VertexCount {
        /// Vertices in the target.
        given: usize,
        /// Vertices in the rig's mesh.
        expected: usize,
    },
    /// The target does not differ from the rest shape.
    #[error("the target is the rest shape: nothing to fit")]
    NoDisplacement,
}

/// The result of fitting one target.
#[derive(Debug, Clone, PartialEq)]
pub struct AuFit {
    /// The best activations.
    pub activations: Activations,
    /// `1 - |residual|^2 / |target|^2` over all vertices.
    pub explained: f64,
}

/// Fits activations to a target shape of the bound rig's mesh.
pub fn fit_au(bound: &BoundRig, target: &[Vec3]) -> Result<AuFit, SolveError> {
    let rest = bound.rest();
    if target.len() != rest.len() {
        return Err(SolveError::VertexCount {
            given: target.len(),
            expected: rest.len(),
        });
    }
    let problem = Problem::new(bound, target);
    if problem.target_norm.is_nan() || problem.target_norm <= 0.0 {
        return Err(SolveError::NoDisplacement);
    }
    let (jaw, muscles, residual) = problem.best_jaw();
    let linear = to_activations(&muscles, jaw);
    if bound.skin().is_paper() {
        return Ok(AuFit {
            activations: linear,
            explained: 1.0 - residual / problem.target_norm,
        });
    }
    let (activations, residual) = Refine::new(bound, target).run(linear);
    Ok(AuFit {
        activations,
        explained: 1.0 - residual / problem.target_norm,
    })
}

/// Activations in range from a solution's values.
fn to_activations(muscles: &[f64], jaw: f64) -> Activations {
    Activations {
        muscles: muscles
            .iter()
            .map(|&a| clean(a, *MUSCLE_RANGE.end()))
            .collect(),
        jaw: clean(jaw, *JAW_RANGE.end()),
    }
}

/// Gauss-Newton iterations at most; each costs one deformation per variable.
const GAUSS_NEWTON_ITERATIONS: usize = 30;
/// The finite-difference step of an activation.
const DIFFERENCE_STEP: f64 = 1e-3;

/// The bounded nonlinear least squares of a target on the deformation as bound.
struct Refine<'a> {
    bound: &'a BoundRig,
    target: &'a [Vec3],
    /// Upper bound of each variable: the muscles, then the jaw when the rig has one.
    hi: Vec<f64>,
    muscles: usize,
}

/// One variable's column of the Jacobian: the vertices it moves and how far per unit.
type Column = Vec<(u32, DVec3)>;

impl<'a> Refine<'a> {
    fn new(bound: &'a BoundRig, target: &'a [Vec3]) -> Refine<'a> {
        let muscles = bound.muscle_count();
        let (_, hi) = activation_bounds(muscles, bound.rig().jaw.is_some());
        Refine {
            bound,
            target,
            hi,
            muscles,
        }
    }

    fn activations(&self, x: &[f64]) -> Activations {
        let jaw = x.get(self.muscles).copied().unwrap_or(0.0);
        Activations {
            muscles: x[..self.muscles].iter().map(|&a| a as f32).collect(),
            jaw: jaw as f32,
        }
    }

    /// The deformed positions at `x` (the rest shape if the rig refuses them, which the
    /// bounds rule out).
    fn deform(&self, x: &[f64], out: &mut Vec<Vec3>) {
        if self.bound.deform(&self.activations(x), out).is_err() {
            out.clear();
            out.extend_from_slice(self.bound.rest());
        }
    }

    fn cost(&self, positions: &[Vec3]) -> f64 {
        positions
            .iter()
            .zip(self.target)
            .map(|(p, t)| (p.as_dvec3() - t.as_dvec3()).length_squared())
            .sum()
    }

    /// Iterates from `start`; returns the activations and their residual `|r|^2`.
    fn run(&self, start: Activations) -> (Activations, f64) {
        let mut x: Vec<f64> = start.muscles.iter().map(|&a| f64::from(a)).collect();
        if self.hi.len() > self.muscles {
            x.push(f64::from(start.jaw));
        }
        let mut now = Vec::new();
        self.deform(&x, &mut now);
        let mut cost = self.cost(&now);
        let mut trial = Vec::new();
        for _ in 0..GAUSS_NEWTON_ITERATIONS {
            if cost == 0.0 {
                break;
            }
            let proposal = self.step(&x, &now);
            let mut t = 1.0;
            let mut accepted = false;
            while t > 1e-4 {
                let candidate: Vec<f64> = x
                    .iter()
                    .zip(&proposal)
                    .map(|(a, b)| a + t * (b - a))
                    .collect();
                self.deform(&candidate, &mut trial);
                let c = self.cost(&trial);
                if c < cost {
                    let moved = candidate
                        .iter()
                        .zip(&x)
                        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                    x = candidate;
                    std::mem::swap(&mut now, &mut trial);
                    cost = c;
                    accepted = moved > 1e-7;
                    break;
                }
                t *= 0.5;
            }
            if !accepted {
                break;
            }
        }
        let jaw = x.get(self.muscles).copied().unwrap_or(0.0);
        (to_activations(&x[..self.muscles], jaw), cost)
    }

    /// The bounded Gauss-Newton point from `x`: minimises `|J (y - x) + r|^2` over the box.
    fn step(&self, x: &[f64], now: &[Vec3]) -> Vec<f64> {
        let columns = self.jacobian(x, now);
        let k = x.len();
        let residual: Vec<DVec3> = now
            .iter()
            .zip(self.target)
            .map(|(p, t)| p.as_dvec3() - t.as_dvec3())
            .collect();
        let mut gram = vec![0.0; k * k];
        let mut jr = vec![0.0; k];
        let mut dense = vec![DVec3::ZERO; now.len()];
        for i in 0..k {
            for &(v, d) in &columns[i] {
                dense[v as usize] = d;
                jr[i] += d.dot(residual[v as usize]);
            }
            for j in i..k {
                let dot: f64 = columns[j]
                    .iter()
                    .map(|&(v, d)| d.dot(dense[v as usize]))
                    .sum();
                gram[i * k + j] = dot;
                gram[j * k + i] = dot;
            }
            for &(v, _) in &columns[i] {
                dense[v as usize] = DVec3::ZERO;
            }
        }
        // |J y - (J x - r)|^2: the linear term is G x - J^T r.
        let c: Vec<f64> = (0..k)
            .map(|i| (0..k).map(|j| gram[i * k + j] * x[j]).sum::<f64>() - jr[i])
            .collect();
        box_least_squares(&gram, &c, &vec![0.0; k], &self.hi)
    }

    /// Forward differences of the deformation in each variable, stepping inward at a bound.
    fn jacobian(&self, x: &[f64], now: &[Vec3]) -> Vec<Column> {
        let mut moved = Vec::new();
        (0..x.len())
            .map(|i| {
                let h = if x[i] + DIFFERENCE_STEP <= self.hi[i] {
                    DIFFERENCE_STEP
                } else {
                    -DIFFERENCE_STEP
                };
                let mut y = x.to_vec();
                y[i] += h;
                self.deform(&y, &mut moved);
                // the step as the f32 activation really took it
                let taken = f64::from(y[i] as f32) - f64::from(x[i] as f32);
                moved
                    .iter()
                    .zip(now)
                    .enumerate()
                    .filter(|(_, (a, b))| a != b)
                    .map(|(v, (a, b))| (v as u32, (a.as_dvec3() - b.as_dvec3()) / taken))
                    .collect()
            })
            .collect()
    }
}

/// An activation in range, with values within rounding of a bound set to it.
fn clean(a: f64, hi: f32) -> f32 {
    let a = a.clamp(0.0, f64::from(hi)) as f32;
    if a < 1e-6 {
        0.0
    } else if (hi - a).abs() < 1e-6 {
        hi
    } else {
        a
    }
}

/// One vertex the rig moves: its rest position, target displacement, jaw weight and muscle
/// entries.
struct Row {
    rest: DVec3,
    target: DVec3,
    jaw: f64,
    entries: Vec<(usize, DVec3)>,
}

struct Problem {
    rows: Vec<Row>,
    muscles: usize,
    /// `|target - rest|^2` over all vertices.
    target_norm: f64,
    /// `|target - rest|^2` over the vertices no muscle or jaw moves (always residual).
    fixed_residual: f64,
    pivot: DVec3,
    axis: DVec3,
    radians_per_unit: f64,
    /// The jaw's slide per unit of activation (`Jaw::slide` times its degrees per unit).
    slide_per_unit: DVec3,
}

impl Problem {
    fn new(bound: &BoundRig, target: &[Vec3]) -> Problem {
        let rest = bound.rest();
        let rig = bound.rig();
        let n = rest.len();
        let mut entries: Vec<Vec<(usize, DVec3)>> = vec![Vec::new(); n];
        for m in 0..bound.muscle_count() {
            if let Some(field) = bound.field(m) {
                for (&v, d) in field.vertices.iter().zip(&field.displacements) {
                    entries[v as usize].push((m, d.as_dvec3()));
                }
            }
        }
        let mut jaw = vec![0.0; n];
        if let Some(j) = &rig.jaw {
            for &(v, w) in &j.weights {
                if let Some(slot) = jaw.get_mut(v as usize) {
                    *slot = f64::from(w);
                }
            }
        }
        let mut rows = Vec::new();
        let mut target_norm = 0.0;
        let mut fixed_residual = 0.0;
        for (v, row_entries) in entries.into_iter().enumerate() {
            let d = target[v].as_dvec3() - rest[v].as_dvec3();
            target_norm += d.length_squared();
            if row_entries.is_empty() && jaw[v] == 0.0 {
                fixed_residual += d.length_squared();
                continue;
            }
            rows.push(Row {
                rest: rest[v].as_dvec3(),
                target: d,
                jaw: jaw[v],
                entries: row_entries,
            });
        }
        let (pivot, axis, radians_per_unit, slide_per_unit) = match &rig.jaw {
            Some(j) => (
                j.pivot.as_dvec3(),
                j.axis.as_dvec3().normalize_or(DVec3::X),
                f64::from(j.degrees_per_unit).to_radians(),
                j.slide.as_dvec3() * f64::from(j.degrees_per_unit),
            ),
            None => (DVec3::ZERO, DVec3::X, 0.0, DVec3::ZERO),
        };
        Problem {
            rows,
            muscles: bound.muscle_count(),
            target_norm,
            fixed_residual,
            pivot,
            axis,
            radians_per_unit,
            slide_per_unit,
        }
    }

    /// The best jaw activation with its muscles and residual: a scan of the jaw's range, then
    /// a golden-section search around the best sample.
    fn best_jaw(&self) -> (f64, Vec<f64>, f64) {
        let hi = f64::from(*JAW_RANGE.end());
        if self.radians_per_unit == 0.0 || self.rows.iter().all(|r| r.jaw == 0.0) {
            let (m, r) = self.muscles_at(0.0);
            return (0.0, m, r);
        }
        let steps = 16;
        let samples: Vec<(f64, f64)> = (0..=steps)
            .map(|i| {
                let k = hi * i as f64 / steps as f64;
                (k, self.muscles_at(k).1)
            })
            .collect();
        let best = (0..samples.len())
            .min_by(|&a, &b| samples[a].1.total_cmp(&samples[b].1))
            .unwrap_or(0);
        let step = hi / steps as f64;
        let (mut a, mut b) = (
            (samples[best].0 - step).max(0.0),
            (samples[best].0 + step).min(hi),
        );
        let ratio = 0.5 * (5f64.sqrt() - 1.0);
        let mut c = b - ratio * (b - a);
        let mut d = a + ratio * (b - a);
        let (mut fc, mut fd) = (self.muscles_at(c).1, self.muscles_at(d).1);
        for _ in 0..60 {
            if (b - a) < 1e-9 {
                break;
            }
            if fc < fd {
                b = d;
                d = c;
                fd = fc;
                c = b - ratio * (b - a);
                fc = self.muscles_at(c).1;
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + ratio * (b - a);
                fd = self.muscles_at(d).1;
            }
        }
        let mut candidates = vec![0.5 * (a + b), samples[best].0];
        candidates.extend([0.0, hi]);
        candidates
            .into_iter()
            .map(|k| {
                let (m, r) = self.muscles_at(k);
                (k, m, r)
            })
            .min_by(|x, y| x.2.total_cmp(&y.2))
            .unwrap_or((0.0, vec![0.0; self.muscles], self.target_norm))
    }

    /// The best muscle activations for jaw activation `k`, and the residual `|r|^2`.
    fn muscles_at(&self, k: f64) -> (Vec<f64>, f64) {
        let rotation = DMat3::from_axis_angle(self.axis, k * self.radians_per_unit);
        let m = self.muscles;
        let mut gram = vec![0.0; m * m];
        let mut rhs = vec![0.0; m];
        let mut constant = self.fixed_residual;
        // Per vertex: deformed = B (rest + sum a_i f_i) + (1 - B)-part, with
        // B = w R + (1 - w) I about the pivot; displacement = B f . a + (B rest + c - rest).
        let mut columns: Vec<(usize, DVec3)> = Vec::new();
        for row in &self.rows {
            let w = row.jaw;
            let blend = |p: DVec3| p + (rotation * p - p) * w;
            let slide = self.slide_per_unit * (k * w);
            let base = self.pivot + blend(row.rest - self.pivot) + slide - row.rest;
            let r0 = row.target - base;
            constant += r0.length_squared();
            columns.clear();
            columns.extend(row.entries.iter().map(|&(i, f)| (i, blend(f))));
            for &(i, fi) in &columns {
                rhs[i] += fi.dot(r0);
                for &(j, fj) in &columns {
                    gram[i * m + j] += fi.dot(fj);
                }
            }
        }
        let (lo, hi) = activation_bounds(m, false);
        let x = box_least_squares(&gram, &rhs, &lo, &hi);
        // |r|^2 = constant - 2 x.rhs + x G x
        let mut quad = 0.0;
        for i in 0..m {
            for j in 0..m {
                quad += x[i] * gram[i * m + j] * x[j];
            }
        }
        let lin: f64 = x.iter().zip(&rhs).map(|(a, b)| a * b).sum();
        (x, (constant - 2.0 * lin + quad).max(0.0))
    }
}
