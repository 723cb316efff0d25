//! The built-in jaw's skin weights relaxed over the cheeks and chin (`face::rigs`,
//! `docs/face.md`).

use glam::Vec3;

use super::anthropometry::{units, y_units, GNATHION_Y, GONION_X};
use super::round3;
use super::surface;
use crate::model::Mesh;

/// How far (mm) beyond the skin that the analytic jaw weights move the relaxed weights may
/// reach: the cheek and chin around the mouth carry an opening jaw's pull.
pub(super) const JAW_CARRY_MM: f64 = 25.0;

/// Radius (mm) round each mouth corner within which the mandible's skin is held at less than
/// the jaw's full weight, easing in from the corner's weight.
pub(super) const JAW_CORNER_EASE_MM: f64 = 30.0;

/// The mouth slit as the jaw's weights see it: found from the mesh's boundary between the
/// corners and the mouth line (both from the landmarks).
pub(super) struct MouthSlit {
    /// The left mouth corner (the right one is its mirror in x).
    pub(super) corner: Vec3,
    /// Height of the mouth line.
    pub(super) mouth_y: f32,
    /// Jaw weight at the corners.
    pub(super) corner_weight: f64,
    /// Distance (mesh units) from a corner over which the upper lip's weight falls to 0.
    pub(super) corner_reach: f64,
}

impl MouthSlit {
    /// True for a point between the corners, within 3 mm of the mouth line and not behind
    /// the corners: the lips along the slit.
    fn on_lips(&self, p: Vec3) -> bool {
        let band = units(3.0) as f32;
        p.x.abs() < self.corner.x
            && (p.y - self.mouth_y).abs() <= band
            && p.z >= self.corner.z - band
    }

    /// Distance from `p` to the nearer mouth corner.
    fn corner_distance(&self, p: Vec3) -> f32 {
        Vec3::new(p.x.abs(), p.y, p.z).distance(self.corner)
    }

    /// The slit's margin vertices (skin vertices on the mesh's boundary between the corners,
    /// within 3 mm of the mouth line and not behind the corners) with their held weights: at
    /// distance `s` from the nearer corner along x, the upper lip's `c (1 - s / reach)` (not
    /// below 0) and the lower lip's `c + (1 - c) (1 - (1 - t)^1.5)` with `t = s / x_corner`
    /// (1 at the midline), `c` the corner's weight. The jump across the slit so grows in
    /// proportion to the distance from the corner instead of as its square root, and the
    /// lower lip still rises fast enough for an oval opening (three quarters of the way at
    /// half the way to the corner).
    fn margin_weights(&self, mesh: &Mesh, skin: usize) -> Vec<(u32, f64)> {
        let mut uses: std::collections::BTreeMap<(u32, u32), u32> = Default::default();
        for t in &mesh.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *uses.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let on_slit = |v: u32| (v as usize) < skin && self.on_lips(mesh.positions[v as usize]);
        let mut margin: Vec<u32> = uses
            .iter()
            .filter(|&(&(a, b), &n)| n == 1 && on_slit(a) && on_slit(b))
            .flat_map(|(&(a, b), _)| [a, b])
            .collect();
        margin.sort_unstable();
        margin.dedup();
        let (c, x_corner) = (self.corner_weight, f64::from(self.corner.x));
        margin
            .into_iter()
            .map(|v| {
                let p = mesh.positions[v as usize];
                let s = x_corner - f64::from(p.x.abs());
                let w = if p.y >= self.mouth_y {
                    c * (1.0 - s / self.corner_reach).max(0.0)
                } else {
                    let t = (s / x_corner).clamp(0.0, 1.0);
                    c + (1.0 - c) * (1.0 - (1.0 - t).powf(1.5))
                };
                (v, w)
            })
            .collect()
    }
}

/// Relaxes the jaw's skin weights to a harmonic map, so that the opening jaw's pull falls off
/// as evenly as the skin allows instead of in the analytic map's steep bands (beside the mouth
/// corners an edge stretched 4x at AU26 and 6x at AU27). Held: the weights of 1 (the mandible
/// and the middle of the lower lip and chin), and 0 on the upper lip (`held_still`) and beyond
/// [`JAW_CARRY_MM`] of every moving vertex; free: every other skin vertex, which takes the
/// mean of its neighbours weighted by `1 / length^2` (the discrete Laplace equation, solved by
/// Gauss-Seidel sweeps in a fixed order, so the result is deterministic). The upper lip is
/// held only beyond the corners' reach ([`JAW_CORNER_REACH_MM`]): held up to the corner, the
/// map's slope grows without bound at the corner, the tip of the slit between a lower lip
/// that drops and an upper lip that stays. (A biharmonic map was tried: with the mandible
/// held at 1 it overshoots below the corners and stretches more.)
///
/// Round the mouth corners two more things are held, since a harmonic map is singular at
/// the tip of a slit across which the weight jumps (at AU27 the edge below each corner
/// stretched 3.15x): the slit's margins get weights whose jump grows in proportion to the
/// distance from the corner ([`MouthSlit`]: the corner's weight at the corner, the upper
/// lip's falling to 0 within the corner's reach, the lower lip's rising to 1 at the
/// midline), and the mandible's weights of 1 within [`JAW_CORNER_EASE_MM`] of a corner
/// (the lips' own excepted) ease in from the corner's weight in proportion to the
/// distance, so the skin below
/// the corners is carried by the cheek and chin over a wide area rather than pinned to the
/// mandible.
pub(super) fn relax_jaw_weights(
    mesh: &Mesh,
    skin: usize,
    weights: &[(u32, f32)],
    slit: &MouthSlit,
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
    let mut held_margin = vec![false; skin];
    for (v, x) in slit.margin_weights(mesh, skin) {
        w[v as usize] = x;
        held_margin[v as usize] = true;
    }
    // the mandible's weights of 1 ease in from the corner's weight with the distance from
    // the corner
    let held_one: Vec<bool> = w.iter().map(|&x| x >= 1.0).collect();
    let ease_radius = units(JAW_CORNER_EASE_MM);
    for (v, x) in w.iter_mut().enumerate() {
        let from_corner = f64::from(slit.corner_distance(positions[v]));
        if held_one[v] && !slit.on_lips(positions[v]) && from_corner < ease_radius {
            let ease = super::surface::smoothstep(0.0, ease_radius, from_corner);
            *x = slit.corner_weight + (1.0 - slit.corner_weight) * ease;
        }
    }
    let free: Vec<bool> = (0..skin)
        .map(|v| {
            let p = positions[v];
            let held = held_margin[v] || held_one[v] || (w[v] == 0.0 && held_still(p));
            !held && moving.iter().any(|q| q.distance(p) <= reach)
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

/// Jaw weight at the mouth corners: a dropped jaw pulls the corners down (they are part of
/// both lips), 0.4 of the lower lip's drop. At 0.3 the corners stayed wide and high above the
/// dropped lip, a crescent that a face tracker reads as a smile (AU26 read mouthSmile 0.10 to
/// 0.17, surprise 0.18); at 0.4 the opening is an oval and neither reads as one.
pub const JAW_CORNER_WEIGHT: f64 = 0.4;

/// Radius (mm) of the skin round each mouth corner that follows the corner down (12 mm, was
/// 9: with the heavier corner the cheek beside it stretched 2.50x at the jaw's 4.0, now 2.38x).
pub(super) const JAW_CORNER_REACH_MM: f64 = 12.0;

/// Jaw weights. Below the mouth line: 1 across the middle of the lower lip and chin, falling
/// along a quarter ellipse (`sqrt(1 - u^2)`, steep only near the corner) to
/// [`JAW_CORNER_WEIGHT`] at the mouth corners, so the opening is an oval rather than a
/// crescent whose sides barely part; lower down the band that moves widens to the whole
/// mandible. On and above the mouth line only the skin beside each corner moves (not the
/// upper lip), with the corner's weight fading to 0 within [`JAW_CORNER_REACH_MM`]: the
/// corners sink a little and the upper lip stays.
pub fn jaw_weights(positions: &[Vec3], mouth_y: f32, corner_x: f32) -> Vec<(u32, f32)> {
    let chin_y = y_units(GNATHION_Y) as f32;
    let corner = (f64::from(corner_x), f64::from(mouth_y));
    let reach = units(JAW_CORNER_REACH_MM);
    let mut weights = Vec::new();
    for (i, p) in positions.iter().enumerate() {
        let (x, y) = (f64::from(p.x.abs()), f64::from(p.y));
        let w = if p.y >= mouth_y && x < corner.0 {
            // the upper lip: parts from the lower lip (a fitted rig splits it off the same way)
            0.0
        } else if p.y >= mouth_y {
            let from_corner = ((x - corner.0).powi(2) + (y - corner.1).powi(2)).sqrt();
            JAW_CORNER_WEIGHT * (1.0 - surface::smoothstep(0.0, reach, from_corner))
        } else {
            let depth = f64::from(((mouth_y - p.y) / (mouth_y - chin_y)).clamp(0.0, 1.0));
            let ease = surface::smoothstep(0.0, 0.6, depth);
            let inner = ease * units(GONION_X - 8.0);
            let outer = corner.0 + ease * (units(GONION_X + 16.0) - corner.0);
            let u = ((x - inner) / (outer - inner)).clamp(0.0, 1.0);
            // near the lips: a quarter ellipse down to the corner's weight, which fades
            // beyond the corner as it does above the mouth line; lower down the smoothstep
            // across the mandible, whose edge stays soft
            let tail = JAW_CORNER_WEIGHT * (1.0 - surface::smoothstep(outer, outer + reach, x));
            let oval = (1.0 - JAW_CORNER_WEIGHT) * (1.0 - u * u).sqrt() + tail;
            let soft = 1.0 - surface::smoothstep(0.0, 1.0, u);
            oval * (1.0 - ease) + soft * ease
        };
        let w = round3(w as f32);
        if w > 0.0 {
            weights.push((i as u32, w));
        }
    }
    weights
}
