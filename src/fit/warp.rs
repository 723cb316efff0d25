//! The map from a template face to a target face: a similarity (rotation, uniform scale,
//! translation) that best aligns the landmarks, then a thin-plate spline that takes each
//! aligned template landmark onto its target landmark and bends space smoothly in between.
//!
//! Everything is computed in `f64`. The spline uses the 3D biharmonic kernel `|r|` with a
//! small regularisation so repeated or nearly repeated landmarks do not make it singular.

use glam::{DMat3, DVec3, Vec3};
use nalgebra::{DMatrix, Matrix3};

use crate::landmarks::rms_spread;

/// A rotation, uniform scale and translation: `x -> scale * rotation * x + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Similarity {
    /// A proper rotation (determinant +1).
    pub rotation: DMat3,
    /// The uniform scale.
    pub scale: f64,
    /// The translation.
    pub translation: DVec3,
}

impl Similarity {
    /// Applies the similarity to a point.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * p * self.scale + self.translation
    }

    /// The least-squares similarity taking `from[i]` to `to[i]` (Umeyama 1991), restricted
    /// to proper rotations; `None` when either set has no spread.
    pub fn fit(from: &[DVec3], to: &[DVec3]) -> Option<Similarity> {
        let n = from.len().min(to.len());
        if n == 0 {
            return None;
        }
        let mean_from = from[..n].iter().copied().sum::<DVec3>() / n as f64;
        let mean_to = to[..n].iter().copied().sum::<DVec3>() / n as f64;
        let mut cov = DMat3::ZERO;
        let mut var_from = 0.0;
        for (a, b) in from[..n].iter().zip(&to[..n]) {
            let (a, b) = (*a - mean_from, *b - mean_to);
            cov += outer(b, a);
            var_from += a.length_squared();
        }
        cov *= 1.0 / n as f64;
        var_from /= n as f64;
        if var_from.is_nan() || var_from <= 0.0 {
            return None;
        }
        let (u, s, v) = svd3(cov);
        let mut d = DVec3::ONE;
        if (u.determinant() * v.determinant()) < 0.0 {
            d.z = -1.0;
        }
        let rotation = u * DMat3::from_diagonal(d) * v.transpose();
        let scale = s.dot(d) / var_from;
        if !(scale > 0.0 && scale.is_finite()) {
            return None;
        }
        let translation = mean_to - rotation * mean_from * scale;
        Some(Similarity {
            rotation,
            scale,
            translation,
        })
    }
}

/// The outer product `a b^T`.
pub(crate) fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

fn to_matrix(m: DMat3) -> Matrix3<f64> {
    Matrix3::from_column_slice(&m.to_cols_array())
}

fn to_dmat3(m: &Matrix3<f64>) -> DMat3 {
    DMat3::from_cols_slice(m.as_slice())
}

/// Singular value decomposition of a 3x3 matrix, `m = u diag(s) v^T`, singular values
/// sorted largest first (nalgebra's SVD; `u` and `v` are orthogonal).
fn svd3(m: DMat3) -> (DMat3, DVec3, DMat3) {
    let svd = to_matrix(m).svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        unreachable!("u and v were asked for");
    };
    let values = svd.singular_values;
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
    let (u, v) = (to_dmat3(&u), to_dmat3(&v_t.transpose()));
    (
        DMat3::from_cols(u.col(order[0]), u.col(order[1]), u.col(order[2])),
        DVec3::new(values[order[0]], values[order[1]], values[order[2]]),
        DMat3::from_cols(v.col(order[0]), v.col(order[1]), v.col(order[2])),
    )
}

/// Eigenvalues and unit eigenvectors (columns) of a symmetric 3x3 matrix (nalgebra's
/// symmetric eigen-decomposition), in no particular order.
pub(crate) fn symmetric_eigen(m: DMat3) -> ([f64; 3], DMat3) {
    let eigen = to_matrix(m).symmetric_eigen();
    let values = eigen.eigenvalues;
    (
        [values[0], values[1], values[2]],
        to_dmat3(&eigen.eigenvectors),
    )
}

/// The template-to-target map: a similarity followed by a thin-plate spline correction.
#[derive(Debug, Clone, PartialEq)]
pub struct Warp {
    /// The similarity that aligns the template landmarks with the target's.
    pub similarity: Similarity,
    /// The spline's centres: the template landmarks after the similarity.
    centres: Vec<DVec3>,
    /// One weight vector per centre.
    weights: Vec<DVec3>,
    /// Affine part of the correction: `affine * x + offset`.
    affine: DMat3,
    offset: DVec3,
    /// A length typical of the landmark set (RMS distance from their centroid, target units).
    pub spread: f64,
}

/// Regularisation of the spline relative to the landmark spread: small enough that the
/// landmarks are matched to a tiny fraction of the face, large enough that two landmarks on
/// one point do not make the system singular.
const SMOOTHING: f64 = 1e-4;

impl Warp {
    /// The warp taking `template[i]` to `target[i]`; `None` when a set has no spread or the
    /// spline's system cannot be solved.
    pub fn fit(template: &[Vec3], target: &[Vec3]) -> Option<Warp> {
        let from: Vec<DVec3> = template.iter().map(|p| p.as_dvec3()).collect();
        let to: Vec<DVec3> = target.iter().map(|p| p.as_dvec3()).collect();
        let similarity = Similarity::fit(&from, &to)?;
        let centres: Vec<DVec3> = from.iter().map(|&p| similarity.apply(p)).collect();
        let spread = rms_spread(&to);
        let n = centres.len();
        let size = n + 4;
        // [K + lambda I, P; P^T, 0] [w; a] = [y; 0], one right-hand side per coordinate.
        let mut a = vec![0.0; size * size];
        let lambda = SMOOTHING * spread;
        for i in 0..n {
            for j in 0..n {
                a[i * size + j] = centres[i].distance(centres[j]);
            }
            a[i * size + i] += lambda;
            let row = [1.0, centres[i].x, centres[i].y, centres[i].z];
            for (k, value) in row.iter().enumerate() {
                a[i * size + n + k] = *value;
                a[(n + k) * size + i] = *value;
            }
        }
        let mut rhs = vec![[0.0; 3]; size];
        for i in 0..n {
            let d = to[i] - centres[i];
            rhs[i] = [d.x, d.y, d.z];
        }
        let solution = solve_dense(a, rhs, size)?;
        let weights = solution[..n].iter().map(|r| DVec3::from(*r)).collect();
        let [c, x, y, z] = [
            solution[n],
            solution[n + 1],
            solution[n + 2],
            solution[n + 3],
        ]
        .map(DVec3::from);
        Some(Warp {
            similarity,
            centres,
            weights,
            affine: DMat3::from_cols(x, y, z),
            offset: c,
            spread,
        })
    }

    /// Maps a template point into the target's space.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        let q = self.similarity.apply(p);
        let mut d = self.affine * q + self.offset;
        for (c, w) in self.centres.iter().zip(&self.weights) {
            d += *w * q.distance(*c);
        }
        q + d
    }

    /// [`Warp::apply`] for `f32` points.
    pub fn apply_f32(&self, p: Vec3) -> Vec3 {
        self.apply(p.as_dvec3()).as_vec3()
    }

    /// The warp's Jacobian at template point `p` (central differences).
    pub fn jacobian(&self, p: DVec3) -> DMat3 {
        let h = 1e-4 * self.spread.max(1e-12) / self.similarity.scale;
        let col = |e: DVec3| (self.apply(p + e * h) - self.apply(p - e * h)) / (2.0 * h);
        DMat3::from_cols(col(DVec3::X), col(DVec3::Y), col(DVec3::Z))
    }

    /// The local scale at template point `p`: the cube root of the Jacobian's determinant.
    pub fn local_scale(&self, p: DVec3) -> f64 {
        self.jacobian(p).determinant().abs().cbrt()
    }

    /// How far the spline bends: the largest landmark correction after the similarity,
    /// relative to the landmark spread.
    pub fn bend(&self, target: &[Vec3]) -> f64 {
        self.centres
            .iter()
            .zip(target)
            .map(|(c, t)| c.distance(t.as_dvec3()))
            .fold(0.0, f64::max)
            / self.spread.max(1e-300)
    }
}

/// Solves `a x = rhs` (row-major `size` x `size`, three right-hand sides) by LU with partial
/// pivoting; `None` when singular (a pivot under 1e-13 of the largest entry) or not finite.
fn solve_dense(a: Vec<f64>, rhs: Vec<[f64; 3]>, size: usize) -> Option<Vec<[f64; 3]>> {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let lu = DMatrix::from_row_slice(size, size, &a).lu();
    let smallest = lu
        .u()
        .diagonal()
        .iter()
        .fold(f64::INFINITY, |m, v| m.min(v.abs()));
    if smallest.is_nan() || smallest <= 1e-13 * scale {
        return None;
    }
    let b = DMatrix::from_row_iterator(size, 3, rhs.iter().flatten().copied());
    let x = lu.solve(&b)?;
    let rows: Vec<[f64; 3]> = (0..size)
        .map(|i| [x[(i, 0)], x[(i, 1)], x[(i, 2)]])
        .collect();
    rows.iter()
        .all(|r| r.iter().all(|v| v.is_finite()))
        .then_some(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud() -> Vec<Vec3> {
        (0..30)
            .map(|i| {
                let t = i as f32;
                Vec3::new(
                    (t * 1.7).sin() * 3.0,
                    (t * 0.9).cos() * 2.0,
                    (t * 0.37).sin(),
                )
            })
            .collect()
    }

    #[test]
    fn eigen_vectors_of_a_diagonal_matrix_are_the_axes() {
        let m = DMat3::from_diagonal(DVec3::new(3.0, 1.0, 2.0));
        let (values, vectors) = symmetric_eigen(m);
        assert_eq!(values, [3.0, 1.0, 2.0]);
        assert_eq!(vectors.col(1).abs(), DVec3::Y);
    }

    #[test]
    fn similarity_is_recovered_exactly() {
        let from = cloud();
        let rotation = glam::Quat::from_euler(glam::EulerRot::XYZ, 0.7, -1.2, 2.1);
        let to: Vec<Vec3> = from
            .iter()
            .map(|p| rotation * *p * 25.4 + Vec3::new(100.0, -3.0, 7.0))
            .collect();
        let warp = Warp::fit(&from, &to).unwrap();
        assert!((warp.similarity.scale - 25.4).abs() < 1e-4);
        for (a, b) in from.iter().zip(&to) {
            assert!(warp.apply_f32(*a).distance(*b) < 1e-3);
        }
        let probe = Vec3::new(0.3, -0.2, 0.5);
        let want = rotation * probe * 25.4 + Vec3::new(100.0, -3.0, 7.0);
        assert!(warp.apply_f32(probe).distance(want) < 1e-3);
        assert!((warp.local_scale(probe.as_dvec3()) - 25.4).abs() < 1e-3);
    }

    #[test]
    fn spline_matches_landmarks_after_a_bend() {
        let from = cloud();
        let to: Vec<Vec3> = from
            .iter()
            .map(|p| *p + Vec3::new(0.1 * p.y * p.y, 0.05 * p.x, 0.0))
            .collect();
        let warp = Warp::fit(&from, &to).unwrap();
        for (a, b) in from.iter().zip(&to) {
            assert!(warp.apply_f32(*a).distance(*b) < 2e-3, "{a} -> {b}");
        }
    }

    #[test]
    fn no_spread_means_no_warp() {
        let from = vec![Vec3::ONE; 10];
        assert!(Warp::fit(&from, &cloud()[..10]).is_none());
        assert!(Warp::fit(&cloud()[..10], &from).is_none());
    }
}
