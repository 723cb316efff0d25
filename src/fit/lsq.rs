//! The one bounded least-squares solver: `fit-au` fits AU entries with it and `capture`
//! solves each video frame's muscles with it.
//!
//! The problem is a quadratic `x G x / 2 - c x` over a box `lo <= x <= hi` (muscles 0 to 2,
//! the jaw 0 to 4: [`activation_bounds`]), `G` the Gram matrix `J^T J` of a Jacobian and `c`
//! its `J^T d` for the target displacement `d`. [`Penalties`] adds what a sequence of frames
//! needs: a temporal term that keeps a frame near the previous one, and a sparsity term (an
//! L1 norm, linear because every variable is non-negative) so two antagonists do not both
//! rise and cancel.

use crate::model::{JAW_RANGE, MUSCLE_RANGE};

/// The bounds of a rig's variables: `muscles` muscles (0 to 2), then the jaw (0 to 4) when
/// `jaw` is set.
pub fn activation_bounds(muscles: usize, jaw: bool) -> (Vec<f64>, Vec<f64>) {
    let mut hi = vec![f64::from(*MUSCLE_RANGE.end()); muscles];
    if jaw {
        hi.push(f64::from(*JAW_RANGE.end()));
    }
    (vec![0.0; hi.len()], hi)
}

/// Terms added to a least-squares problem `|J x - d|^2` over a sequence of frames:
/// `temporal |x - previous|^2 + sparsity * sum(x)` (the sum is the L1 norm on the box).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Penalties<'a> {
    /// Weight of the squared distance to the previous frame's solution.
    pub temporal: f64,
    /// The previous frame's solution, when there is one.
    pub previous: Option<&'a [f64]>,
    /// Weight of the sum of the variables, per variable (a scale of `J^T d`'s units).
    pub sparsity: &'a [f64],
}

impl Penalties<'_> {
    /// Adds the terms to `G` (row-major, `n` x `n`) and `c` of `x G x / 2 - c x`, the
    /// half-scaled form of `|J x - d|^2`.
    pub fn apply(&self, gram: &mut [f64], c: &mut [f64]) {
        let n = c.len();
        if let Some(previous) = self.previous.filter(|_| self.temporal > 0.0) {
            for i in 0..n {
                gram[i * n + i] += self.temporal;
                c[i] += self.temporal * previous.get(i).copied().unwrap_or(0.0);
            }
        }
        for (ci, s) in c.iter_mut().zip(self.sparsity) {
            *ci -= 0.5 * s;
        }
    }
}

/// Minimises `x G x / 2 - c x` over `lo <= x <= hi` (per variable; G symmetric positive
/// semi-definite) by a primal active-set method; a tiny ridge makes indistinguishable
/// muscles share.
pub fn box_least_squares(gram: &[f64], c: &[f64], lo: &[f64], hi: &[f64]) -> Vec<f64> {
    let m = c.len();
    let trace: f64 = (0..m).map(|i| gram[i * m + i]).sum();
    let ridge = 1e-10 * trace.max(1e-300) / m.max(1) as f64;
    let g = |i: usize, j: usize| gram[i * m + j] + if i == j { ridge } else { 0.0 };
    // Muscles that move nothing stay at 0.
    let live: Vec<bool> = (0..m).map(|i| gram[i * m + i] > 0.0).collect();
    let mut x = lo.to_vec();
    // free[i]: not held at a bound.
    let mut free: Vec<bool> = vec![false; m];
    for _ in 0..(4 * m + 20) {
        // Release the bound variable whose gradient most wants to move inward.
        let grad: Vec<f64> = (0..m)
            .map(|i| (0..m).map(|j| g(i, j) * x[j]).sum::<f64>() - c[i])
            .collect();
        let scale = 1e-12 * (1.0 + c.iter().fold(0.0f64, |a, v| a.max(v.abs())));
        let release = (0..m)
            .filter(|&i| live[i] && !free[i])
            .filter(|&i| (x[i] <= lo[i] && grad[i] < -scale) || (x[i] >= hi[i] && grad[i] > scale))
            .max_by(|&a, &b| grad[a].abs().total_cmp(&grad[b].abs()));
        let Some(i) = release else {
            if free.iter().any(|&f| f) && !inner(&g, c, &mut x, &mut free, lo, hi) {
                continue;
            }
            return x;
        };
        free[i] = true;
        while !inner(&g, c, &mut x, &mut free, lo, hi) {}
    }
    x
}

/// Solves for the free variables with the others held; if the solution leaves the box, steps
/// toward it until the first variable hits a bound, holds that one and returns `false`.
fn inner(
    g: &dyn Fn(usize, usize) -> f64,
    c: &[f64],
    x: &mut [f64],
    free: &mut [bool],
    lo: &[f64],
    hi: &[f64],
) -> bool {
    let ids: Vec<usize> = (0..x.len()).filter(|&i| free[i]).collect();
    if ids.is_empty() {
        return true;
    }
    let k = ids.len();
    let mut a = vec![0.0; k * k];
    let mut b = vec![0.0; k];
    for (r, &i) in ids.iter().enumerate() {
        b[r] = c[i]
            - (0..x.len())
                .filter(|&j| !free[j])
                .map(|j| g(i, j) * x[j])
                .sum::<f64>();
        for (s, &j) in ids.iter().enumerate() {
            a[r * k + s] = g(i, j);
        }
    }
    let Some(solution) = cholesky_solve(a, b, k) else {
        // Singular even with the ridge: hold the last released variable where it is.
        if let Some(&last) = ids.last() {
            free[last] = false;
        }
        return true;
    };
    let mut step = 1.0f64;
    let mut blocking = None;
    for (r, &i) in ids.iter().enumerate() {
        let target = solution[r];
        let delta = target - x[i];
        if target < lo[i] && delta < 0.0 {
            let t = (lo[i] - x[i]) / delta;
            if t < step {
                step = t;
                blocking = Some((i, lo[i]));
            }
        } else if target > hi[i] && delta > 0.0 {
            let t = (hi[i] - x[i]) / delta;
            if t < step {
                step = t;
                blocking = Some((i, hi[i]));
            }
        }
    }
    for (r, &i) in ids.iter().enumerate() {
        x[i] += step.max(0.0) * (solution[r] - x[i]);
    }
    match blocking {
        Some((i, bound)) => {
            x[i] = bound;
            free[i] = false;
            false
        }
        None => true,
    }
}

/// Solves a symmetric positive definite system (row-major `n` x `n`) by Cholesky
/// (nalgebra's); `None` when it is not definite.
fn cholesky_solve(a: Vec<f64>, b: Vec<f64>, n: usize) -> Option<Vec<f64>> {
    let factor = nalgebra::DMatrix::from_row_slice(n, n, &a).cholesky()?;
    let x = factor.solve(&nalgebra::DVector::from_vec(b));
    x.iter().all(|v| v.is_finite()).then(|| x.data.into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_least_squares_clamps_and_solves() {
        // G = I: the solution is c clamped to the box.
        let g = vec![1.0, 0.0, 0.0, 1.0];
        let (lo, hi) = ([0.0; 2], [2.0; 2]);
        let x = box_least_squares(&g, &[0.5, 3.0], &lo, &hi);
        assert!(
            (x[0] - 0.5).abs() < 1e-9 && (x[1] - 2.0).abs() < 1e-9,
            "{x:?}"
        );
        let x = box_least_squares(&g, &[-1.0, 1.0], &lo, &hi);
        assert!(x[0].abs() < 1e-9 && (x[1] - 1.0).abs() < 1e-9, "{x:?}");
        // Coupled: G = [[2,1],[1,2]], c = [3, 0]: unconstrained (2,-1); with x2 >= 0: x1 = 1.5.
        let g = vec![2.0, 1.0, 1.0, 2.0];
        let x = box_least_squares(&g, &[3.0, 0.0], &lo, &hi);
        assert!((x[0] - 1.5).abs() < 1e-9 && x[1].abs() < 1e-9, "{x:?}");
    }

    #[test]
    fn sparsity_keeps_antagonists_from_cancelling() {
        // Two opposite columns and no motion: any x1 = x2 explains it; the L1 term picks 0.
        let g = vec![1.0, -1.0, -1.0, 1.0];
        let (lo, hi) = activation_bounds(2, false);
        let mut gram = g.clone();
        let mut c = vec![0.0, 0.0];
        Penalties {
            temporal: 0.0,
            previous: None,
            sparsity: &[0.1, 0.1],
        }
        .apply(&mut gram, &mut c);
        let x = box_least_squares(&gram, &c, &lo, &hi);
        assert_eq!(x, vec![0.0, 0.0]);
        // A motion along the first column is still explained (less the small shrink).
        let mut c = vec![1.0, -1.0];
        let mut gram = g;
        Penalties {
            temporal: 0.0,
            previous: None,
            sparsity: &[0.1, 0.1],
        }
        .apply(&mut gram, &mut c);
        let x = box_least_squares(&gram, &c, &lo, &hi);
        assert!((x[0] - 0.95).abs() < 1e-6 && x[1] == 0.0, "{x:?}");
    }

    #[test]
    fn the_temporal_term_pulls_toward_the_previous_frame() {
        let (lo, hi) = activation_bounds(1, true);
        assert_eq!(hi, vec![2.0, 4.0]);
        let mut gram = vec![1.0, 0.0, 0.0, 1.0];
        let mut c = vec![1.0, 3.0];
        Penalties {
            temporal: 1.0,
            previous: Some(&[0.0, 1.0]),
            sparsity: &[0.0, 0.0],
        }
        .apply(&mut gram, &mut c);
        let x = box_least_squares(&gram, &c, &lo, &hi);
        assert!(
            (x[0] - 0.5).abs() < 1e-9 && (x[1] - 2.0).abs() < 1e-9,
            "{x:?}"
        );
    }
}
