//! One frame's muscles: the activations (0-2) and jaw (0-4) whose deformation of the rig's
//! landmark vertices best matches the observed motion.
//!
//! The problem is `min |J (y - x) - r|^2_W + temporal |y - previous|^2 + sum s_i y_i` over the
//! box, with `J` the landmark Jacobian ([`LandmarkModel`]: the muscles' secant columns and the
//! jaw's slope where it stands), `r` the motion the bound deformation at `x` leaves
//! unexplained, and `W` the landmark weights. It is solved by [`crate::fit::lsq`], then
//! refined: the deformation is evaluated at the new point (skin rules, jaw turn and all), the
//! jaw relinearised there, and the step taken again while the true objective falls. Every
//! muscle is its own variable, so the left and right sides are solved separately.

use glam::{DVec3, Vec3};

use super::pose::landmark_weight;
use super::rig_model::LandmarkModel;
use crate::fit::lsq::{activation_bounds, box_least_squares, Penalties};
use crate::model::{Activations, BoundRig};

/// How strongly the solve is held to its neighbours and to few muscles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Regularisation {
    /// The temporal weight as a fraction of the mean muscle's own weight (`J_i W J_i`).
    pub temporal: f64,
    /// The sparsity term's pull, in activation units: a muscle of average strength acting
    /// alone comes out this much lower than it would without the term, so noise does not
    /// wake it; the price per unit is the same for every muscle.
    pub sparsity: f64,
    /// The ridge of the signed reading ([`FrameSolver::signed`]) as a fraction of each
    /// variable's own weight (`J_i W J_i`): a muscle acting alone reads `1 / (1 + ridge)` of
    /// its activation, whatever its strength.
    pub signed_ridge: f64,
}

impl Default for Regularisation {
    fn default() -> Regularisation {
        Regularisation {
            temporal: 0.02,
            sparsity: 0.01,
            signed_ridge: 0.2,
        }
    }
}

/// Refinement steps on the deformation itself after the first linear solve.
pub const REFINEMENTS: usize = 2;

/// One frame's answer.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// The activations, in range.
    pub activations: Activations,
    /// `|residual|^2_W`: the motion the solution leaves unexplained.
    pub residual: f64,
    /// `|motion|^2_W`: the frame's non-rigid motion.
    pub motion: f64,
    /// The landmarks' motion the activations make (rig space).
    pub predicted: Vec<DVec3>,
}

impl Solution {
    /// `1 - |residual|^2 / |motion|^2`.
    pub fn explained(&self) -> f64 {
        if self.motion > 0.0 {
            1.0 - self.residual / self.motion
        } else {
            1.0
        }
    }
}

/// Solves frames in order, each near the one before.
#[derive(Debug)]
pub struct FrameSolver<'a> {
    bound: &'a BoundRig,
    model: &'a LandmarkModel,
    weights: Vec<DVec3>,
    /// `J_m W J_n` over the muscles (row-major, muscles x muscles).
    muscle_gram: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    sparsity: Vec<f64>,
    temporal: f64,
    previous: Option<Vec<f64>>,
    scratch: Vec<Vec3>,
    /// `(J^T W J + ridge diag(J^T W J))^-1` at rest (row-major): [`FrameSolver::signed`]'s
    /// solve.
    signed_inverse: Vec<f64>,
}

impl<'a> FrameSolver<'a> {
    /// A solver for `bound`'s landmarks as `model` describes them.
    pub fn new(
        bound: &'a BoundRig,
        model: &'a LandmarkModel,
        regularisation: Regularisation,
    ) -> FrameSolver<'a> {
        let weights: Vec<DVec3> = (0..model.rest().len()).map(landmark_weight).collect();
        let m = model.muscle_count();
        let mut muscle_gram = vec![0.0; m * m];
        for i in 0..m {
            for j in i..m {
                let g = weighted_dot(&weights, model.column(i), model.column(j));
                muscle_gram[i * m + j] = g;
                muscle_gram[j * m + i] = g;
            }
        }
        let (lo, hi) = activation_bounds(m, model.has_jaw());
        let diagonal: Vec<f64> = (0..m).map(|i| muscle_gram[i * m + i]).collect();
        let live = diagonal.iter().filter(|&&g| g > 0.0).count().max(1);
        let mean = diagonal.iter().sum::<f64>() / live as f64;
        // One price per unit of activation for every variable, set from the mean muscle:
        // a muscle that moves the landmarks little is not a cheaper way to explain them.
        let sparsity = vec![2.0 * regularisation.sparsity * mean; lo.len()];
        let temporal = regularisation.temporal * mean;
        let signed_inverse = signed_inverse(
            model,
            &weights,
            &muscle_gram,
            regularisation.signed_ridge,
            mean,
        );
        FrameSolver {
            bound,
            model,
            weights,
            muscle_gram,
            lo,
            hi,
            sparsity,
            temporal,
            previous: None,
            scratch: Vec::new(),
            signed_inverse,
        }
    }

    /// Forgets the previous frame (after a gap in the recording).
    pub fn reset(&mut self) {
        self.previous = None;
    }

    /// The landmark weights per axis of the rig (see [`landmark_weight`]).
    pub fn weights(&self) -> &[DVec3] {
        &self.weights
    }

    /// Solves one frame's motion (one vector per landmark, in the rig's space).
    pub fn solve(&mut self, motion: &[DVec3]) -> Solution {
        let n = self.model.variable_count();
        let mut x = self.previous.clone().unwrap_or_else(|| vec![0.0; n]);
        let mut predicted = self.predict(&x);
        let mut cost = self.objective(&x, motion, &predicted);
        for _ in 0..=REFINEMENTS {
            let y = self.step(&x, motion, &predicted);
            let mut accepted = false;
            for t in [1.0, 0.5] {
                let z: Vec<f64> = x.iter().zip(&y).map(|(a, b)| a + t * (b - a)).collect();
                let p = self.predict(&z);
                let c = self.objective(&z, motion, &p);
                if c < cost {
                    (x, predicted, cost, accepted) = (z, p, c, true);
                    break;
                }
            }
            if !accepted {
                break;
            }
        }
        let residual = weighted_distance(&self.weights, motion, &predicted);
        let total = weighted_dot(&self.weights, motion, motion);
        self.previous = Some(x.clone());
        Solution {
            activations: self.activations(&x),
            residual,
            motion: total,
            predicted,
        }
    }

    fn activations(&self, x: &[f64]) -> Activations {
        let m = self.model.muscle_count();
        Activations {
            muscles: x[..m]
                .iter()
                .zip(&self.hi)
                .map(|(&a, &hi)| a.clamp(0.0, hi) as f32)
                .collect(),
            jaw: x.get(m).map_or(0.0, |&k| k.clamp(0.0, self.hi[m]) as f32),
        }
    }

    /// The landmarks' displacement on the bound deformation at `x`.
    fn predict(&mut self, x: &[f64]) -> Vec<DVec3> {
        let act = self.activations(x);
        self.model.displacement(self.bound, &act, &mut self.scratch)
    }

    /// The objective at `x`: weighted residual plus the penalties.
    fn objective(&self, x: &[f64], motion: &[DVec3], predicted: &[DVec3]) -> f64 {
        let mut cost = weighted_distance(&self.weights, motion, predicted);
        cost += x
            .iter()
            .zip(&self.sparsity)
            .map(|(a, s)| a * s)
            .sum::<f64>();
        if let Some(previous) = &self.previous {
            cost += self.temporal
                * x.iter()
                    .zip(previous)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>();
        }
        cost
    }

    /// Signed activations for a motion measured from a neutral that may itself carry
    /// muscle work: the linear least-squares answer on the Jacobian at rest (the jaw's slope
    /// at rest), every variable free to go below 0 as far as above it (below 0, a muscle
    /// works less than in the neutral), held near 0 by a ridge on each variable scaled by its
    /// own weight ([`Regularisation::signed_ridge`]) rather than by the sparsity term (an L1
    /// price would favour going below 0). The bounds are applied after the solve, not in
    /// it: this reads how far a frame is from the neutral in muscle units, it does not
    /// explain the frame.
    pub fn signed(&self, motion: &[DVec3]) -> Vec<f64> {
        let n = self.model.variable_count();
        let jaw = self.model.has_jaw().then(|| self.model.jaw_slope(0.0));
        let c: Vec<f64> = (0..n)
            .map(|i| match (i < self.model.muscle_count(), &jaw) {
                (true, _) => weighted_dot(&self.weights, self.model.column(i), motion),
                (false, Some(jaw)) => weighted_dot(&self.weights, jaw, motion),
                (false, None) => 0.0,
            })
            .collect();
        (0..n)
            .map(|i| {
                let x: f64 = (0..n).map(|j| self.signed_inverse[i * n + j] * c[j]).sum();
                x.clamp(-self.hi[i], self.hi[i])
            })
            .collect()
    }

    /// The bounded linearised step from `x`: the minimiser of the linear model there.
    fn step(&self, x: &[f64], motion: &[DVec3], predicted: &[DVec3]) -> Vec<f64> {
        let m = self.model.muscle_count();
        let n = self.model.variable_count();
        let residual: Vec<DVec3> = motion.iter().zip(predicted).map(|(a, b)| *a - *b).collect();
        let mut gram = vec![0.0; n * n];
        for i in 0..m {
            gram[i * n..i * n + m].copy_from_slice(&self.muscle_gram[i * m..i * m + m]);
        }
        let jaw = self.model.has_jaw().then(|| self.model.jaw_slope(x[m]));
        if let Some(jaw) = &jaw {
            for i in 0..m {
                let g = weighted_dot(&self.weights, self.model.column(i), jaw);
                gram[i * n + m] = g;
                gram[m * n + i] = g;
            }
            gram[m * n + m] = weighted_dot(&self.weights, jaw, jaw);
        }
        // |J (y - x) - r|^2: the linear term is J^T r + G x.
        let mut c: Vec<f64> = (0..n)
            .map(|i| {
                let column = if i < m {
                    self.model.column(i)
                } else {
                    jaw.as_deref().unwrap_or_default()
                };
                weighted_dot(&self.weights, column, &residual)
                    + (0..n).map(|j| gram[i * n + j] * x[j]).sum::<f64>()
            })
            .collect();
        Penalties {
            temporal: self.temporal,
            previous: self.previous.as_deref(),
            sparsity: &self.sparsity,
        }
        .apply(&mut gram, &mut c);
        box_least_squares(&gram, &c, &self.lo, &self.hi)
    }
}

/// `(J^T W J + ridge D)^-1` (row-major) over every variable, `D` the diagonal of each
/// variable's own weight `J_i W J_i` (at least [`SILENT_FLOOR`] of the mean muscle's, `mean`,
/// so a muscle that moves no landmark still has a ridge), the jaw's column its slope at rest;
/// the identity scaled by the inverse of the smallest ridge if it cannot be inverted.
///
/// The ridge is each variable's own: one of the whole (a multiple of the mean muscle's weight)
/// shrinks a weak muscle's reading far more than a strong one's, and on a real recording
/// (docs/capture.md) the jaw's reading with it; scaled by each variable's weight, every
/// reading shrinks alike, and a muscle's reading does not depend on the units of its column.
fn signed_inverse(
    model: &LandmarkModel,
    weights: &[DVec3],
    muscle_gram: &[f64],
    ridge: f64,
    mean: f64,
) -> Vec<f64> {
    let m = model.muscle_count();
    let n = model.variable_count();
    let jaw = model.jaw_slope(0.0);
    let column = |i: usize| if i < m { model.column(i) } else { &jaw };
    let gram = nalgebra::DMatrix::from_fn(n, n, |i, j| {
        let g = if i < m && j < m {
            muscle_gram[i * m + j]
        } else {
            weighted_dot(weights, column(i), column(j))
        };
        g + if i == j {
            ridge * g.max(SILENT_FLOOR * mean)
        } else {
            0.0
        }
    });
    match gram.cholesky() {
        Some(c) => c.inverse().transpose().iter().copied().collect(),
        None => nalgebra::DMatrix::from_diagonal_element(
            n,
            n,
            1.0 / (ridge * SILENT_FLOOR * mean).max(1e-300),
        )
        .iter()
        .copied()
        .collect(),
    }
}

/// The least weight, as a fraction of the mean muscle's, a variable's ridge in the signed
/// reading is scaled by: a muscle that moves no landmark (the orbital orbicularis oculi on
/// the default rig) reads 0 rather than making the matrix singular.
pub const SILENT_FLOOR: f64 = 1e-3;

/// `sum_i w_i . (a_i * b_i)`: each axis weighted.
pub fn weighted_dot(weights: &[DVec3], a: &[DVec3], b: &[DVec3]) -> f64 {
    weights
        .iter()
        .zip(a.iter().zip(b))
        .map(|(w, (a, b))| w.dot(*a * *b))
        .sum()
}

/// `sum_i w_i . (a_i - b_i)^2`.
fn weighted_distance(weights: &[DVec3], a: &[DVec3], b: &[DVec3]) -> f64 {
    weights
        .iter()
        .zip(a.iter().zip(b))
        .map(|(w, (a, b))| w.dot((*a - *b) * (*a - *b)))
        .sum()
}
