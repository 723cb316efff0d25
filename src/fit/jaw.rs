//! Jaw weights for a fitted mesh: the template's weights carried over by nearest point, then
//! split along the inner lip line so that a closed mouth opens.
//!
//! Each skin vertex takes the weight of the nearest template vertex after the warp, fading to
//! 0 where no template vertex is near (a neck or body beyond the template's face). Between
//! the mouth corners, a vertex above the inner lip line gets 0 (tapering back to the carried
//! weight at the corners), and one below takes its weight from the template's lower lip
//! only. Parts that turn with the jaw (lower teeth, tongue) get 1, still parts 0.

use glam::Vec3;
use rayon::prelude::*;

use super::nearest::Nearest;
use super::parts::{Part, Parts};
use super::regions::{smoothstep, Opening, Side};
use super::warp::Warp;
use super::Template;
use crate::model::{Jaw, Mesh};

/// Weights fade out between these distances from the nearest carried template vertex, as
/// fractions of the landmarks' spread.
const FADE: (f64, f64) = (0.08, 0.2);

/// The jaw's slide per degree on the fitted mesh: the template's slide carried by the warp's
/// local linear part `j` at the pivot (so a larger head slides further), kept in the plane
/// the jaw turns in (perpendicular to the carried axis `axis`): the condyles glide in the
/// sagittal plane, and a slide across it would make a symmetric jaw drop lopsided.
pub fn carried_slide(jaw: &Jaw, j: glam::DMat3, axis: Vec3) -> Vec3 {
    if jaw.slide == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let carried = j * jaw.slide.as_dvec3();
    let axis = axis.as_dvec3().normalize_or_zero();
    let planar = carried - axis * carried.dot(axis);
    let planar = planar.as_vec3();
    // an axis snapped to a coordinate axis leaves that coordinate exactly zero
    Vec3::select(axis.as_vec3().abs().cmpeq(Vec3::ONE), Vec3::ZERO, planar)
}

/// The jaw weights of `mesh`, sorted by vertex, zeros left out.
pub fn weights(
    template: Template<'_>,
    jaw: &Jaw,
    warp: &Warp,
    mesh: &Mesh,
    parts: &Parts,
    mouth_from: Option<&Opening>,
    mouth_to: Option<&Opening>,
) -> Vec<(u32, f32)> {
    let mut dense = vec![0.0f32; template.mesh.vertex_count()];
    for &(v, w) in &jaw.weights {
        if let Some(slot) = dense.get_mut(v as usize) {
            *slot = w;
        }
    }
    let carried: Vec<Vec3> = template
        .mesh
        .positions
        .iter()
        .map(|p| warp.apply_f32(*p))
        .collect();
    let all = Nearest::new(carried.clone(), (0..carried.len() as u32).collect());
    // each lip takes its weights from the same lip of the template (where the mesh's lips
    // are joined, a vertex of one lip may lie nearest the other lip of the template)
    let side_index = |side: Side| {
        let ids: Vec<u32> = match mouth_from {
            Some(m) => (0..carried.len() as u32)
                .filter(|&v| m.side_weight(template.mesh.positions[v as usize], side) > 0.0)
                .collect(),
            None => Vec::new(),
        };
        Nearest::new(ids.iter().map(|&v| carried[v as usize]).collect(), ids)
    };
    let (lower, upper) = (side_index(Side::Lower), side_index(Side::Upper));
    let (near, far) = (FADE.0 * warp.spread, FADE.1 * warp.spread);
    // each vertex's weight depends on the template and its own position only: found on
    // the rayon pool, listed in vertex order as one pass would
    let weight = |(v, p): (usize, &Vec3)| -> f32 {
        match parts.of_vertex[v] {
            Part::Still => 0.0,
            Part::Jaw => 1.0,
            Part::Skin => {
                let below = mouth_to.map_or(0.0, |m| m.side_weight(*p, Side::Lower));
                let above = mouth_to.map_or(0.0, |m| m.side_weight(*p, Side::Upper));
                let index = if below > 0.0 {
                    &lower
                } else if above > 0.0 {
                    &upper
                } else {
                    &all
                };
                let from_upper = above > 0.0 && below <= 0.0 && upper.nearest(*p).is_some();
                let (id, d) = index
                    .nearest(*p)
                    .or(all.nearest(*p))
                    .unwrap_or((0, f32::INFINITY));
                let fade = 1.0 - smoothstep(near, far, f64::from(d));
                let w = f64::from(dense.get(id as usize).copied().unwrap_or(0.0)) * fade;
                // the template's upper lip carries its own (small, by the corners) weights;
                // without one, the upper lip is split off the jaw
                if from_upper {
                    w as f32
                } else {
                    (w * (1.0 - above)) as f32
                }
            }
        }
    };
    let all_weights: Vec<f32> = mesh.positions.par_iter().enumerate().map(weight).collect();
    all_weights
        .into_iter()
        .enumerate()
        .filter(|&(_, w)| w > 0.0)
        .map(|(v, w)| (v as u32, w))
        .collect()
}
