//! The built-in jaw's skin weights relaxed over the cheeks and chin (`face::rigs`,
//! `docs/face.md`).

use glam::Vec3;

use super::anthropometry::units;
use super::rigs::round3;
use crate::model::Mesh;

/// How far (mm) beyond the skin that the analytic jaw weights move the relaxed weights may
/// reach: the cheek and chin around the mouth carry an opening jaw's pull.
pub(super) const JAW_CARRY_MM: f64 = 15.0;

/// Relaxes the jaw's skin weights to a harmonic map, so that the opening jaw's pull falls off
/// as evenly as the skin allows instead of in the analytic map's steep bands (beside the mouth
/// corners an edge stretched 4x at AU26 and 6x at AU27). Held: the weights of 1 (the mandible
/// and the middle of the lower lip and chin), and 0 on the upper lip (`held_still`) and beyond
/// [`JAW_CARRY_MM`] of every moving vertex; free: every other skin vertex, which takes the
/// mean of its neighbours weighted by `1 / length^2` (the discrete Laplace equation, solved by
/// Gauss-Seidel sweeps in a fixed order, so the result is deterministic). The upper lip is
/// held only beyond the corners' reach (`face::rigs::JAW_CORNER_REACH_MM`): held up to the corner, the
/// map's slope grows without bound at the corner, the tip of the slit between a lower lip
/// that drops and an upper lip that stays. (A biharmonic map was tried: with the mandible
/// held at 1 it overshoots below the corners and stretches more.)
pub(super) fn relax_jaw_weights(
    mesh: &Mesh,
    skin: usize,
    weights: &[(u32, f32)],
    held_still: impl Fn(Vec3) -> bool,
) -> Vec<(u32, f32)> {
    let positions = &mesh.positions[..skin];
    let mut w = vec![0.0f64; skin];
    for &(v, x) in weights {
        w[v as usize] = f64::from(x);
    }
    let moving: Vec<Vec3> = weights
        .iter()
        .map(|&(v, _)| positions[v as usize])
        .collect();
    let reach = units(JAW_CARRY_MM) as f32;
    let free: Vec<bool> = (0..skin)
        .map(|v| {
            let p = positions[v];
            w[v] < 1.0
                && !(w[v] == 0.0 && held_still(p))
                && moving.iter().any(|q| q.distance(p) <= reach)
        })
        .collect();
    let mut neighbours: Vec<Vec<(usize, f64)>> = vec![Vec::new(); skin];
    for [a, b] in mesh.edges() {
        let (a, b) = (a as usize, b as usize);
        if a < skin && b < skin {
            let d = f64::from(positions[a].distance(positions[b]));
            if d > 0.0 {
                neighbours[a].push((b, 1.0 / (d * d)));
                neighbours[b].push((a, 1.0 / (d * d)));
            }
        }
    }
    for _ in 0..4000 {
        let mut change = 0.0f64;
        for v in (0..skin).filter(|&v| free[v]) {
            let (sum, total) = neighbours[v]
                .iter()
                .fold((0.0, 0.0), |(s, t), &(n, k)| (s + k * w[n], t + k));
            if total > 0.0 {
                let next = sum / total;
                change = change.max((next - w[v]).abs());
                w[v] = next;
            }
        }
        if change < 1e-6 {
            break;
        }
    }
    w.iter()
        .enumerate()
        .filter_map(|(v, &x)| {
            let x = round3((x as f32).clamp(0.0, 1.0));
            (x > 0.0).then_some((v as u32, x))
        })
        .collect()
}
