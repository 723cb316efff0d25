//! Jaw weights for a fitted mesh: the template's weights carried over by nearest point, then
//! split along the inner lip line so that a closed mouth opens.
//!
//! Each skin vertex takes the weight of the nearest template vertex after the warp; where the
//! template's skin is not near (under the chin, down the neck, a mouth's lining) the weights
//! are a harmonic map along the mesh from those carried to 0 (`super::jawfade`). Between
//! the mouth corners, a vertex of the upper lip gets 0 (tapering back to the carried weight
//! at the corners), and one of the lower lip takes its weight from the template's lower lip
//! only. Which lip a vertex is on goes by connectivity ([`LipSides`]: the lip it is reached
//! from along the mesh without crossing the slit), not by height: a full upper lip curls
//! below the line between the inner lip landmarks. Parts that turn with the jaw (lower teeth, tongue) get 1, still parts 0.

use glam::Vec3;
use rayon::prelude::*;

use super::lipsides::{side_weight, LipSides};
use super::nearest::Nearest;
use super::parts::{Part, Parts};
use super::regions::{smoothstep, Opening, Side};
use super::warp::Warp;
use super::Template;
use crate::model::{Jaw, Mesh};

/// Carried weights fade out between these distances from the nearest carried template
/// vertex, as fractions of the landmarks' spread; skin further than the first from the
/// template's skin takes its weight along the mesh instead (`super::jawfade`).
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

/// The jaw weights of `mesh`, sorted by vertex, zeros left out; the template's mouth and
/// lips, then the mesh's, say which lip each vertex is on.
pub fn weights(
    template: Template<'_>,
    jaw: &Jaw,
    warp: &Warp,
    mesh: &Mesh,
    parts: &Parts,
    [(mouth_from, lips_from), (mouth_to, lips)]: [(Option<&Opening>, Option<&LipSides>); 2],
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
                .filter(|&v| {
                    let p = template.mesh.positions[v as usize];
                    side_weight(lips_from, m, v as usize, p, side) > 0.0
                })
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
                let side = |s: Side| mouth_to.map_or(0.0, |m| side_weight(lips, m, v, *p, s));
                let (below, above) = (side(Side::Lower), side(Side::Upper));
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
    let mut all_weights: Vec<f32> = mesh.positions.par_iter().enumerate().map(weight).collect();
    // carried by nearest point, a fade beyond the template's face is a cliff across the
    // neck and the mouth's lining (a vertex 5 mm from the template's jaw line against one
    // 11 mm away); there the weights are found along the mesh instead
    let skin_index = template_skin(template, &carried);
    let held: Vec<bool> = mesh
        .positions
        .par_iter()
        .zip(&parts.of_vertex)
        .map(|(p, part)| {
            *part == Part::Skin
                && skin_index
                    .nearest(*p)
                    .is_some_and(|(_, d)| f64::from(d) <= near)
        })
        .collect();
    super::jawfade::relax_beyond(
        mesh,
        parts,
        &mut all_weights,
        &held,
        super::jawfade::FADE_ALONG * warp.spread,
    );
    if let Some(lips) = lips {
        let limit = steepest(template.mesh, &dense) / warp.similarity.scale;
        ease_corners(mesh, parts, &mut all_weights, lips, limit);
    }
    all_weights
        .into_iter()
        .enumerate()
        .filter(|&(_, w)| w > 0.0)
        .map(|(v, w)| (v as u32, w))
        .collect()
}

/// The template's skin at its `carried` places, as a nearest-point index: the connected pieces
/// of the template mesh that hold a landmark (its teeth, gums and tongue, each weighted 0 or 1 as a
/// whole, say nothing about the skin lining a mouth).
fn template_skin(template: Template<'_>, carried: &[Vec3]) -> Nearest {
    let component = super::parts::components(template.mesh);
    let positions = &template.mesh.positions;
    let mut skin_pieces: Vec<u32> = template
        .landmarks
        .iter()
        .filter_map(|l| {
            (0..positions.len())
                .min_by(|&a, &b| {
                    positions[a]
                        .distance_squared(*l)
                        .total_cmp(&positions[b].distance_squared(*l))
                })
                .map(|v| component[v])
        })
        .collect();
    skin_pieces.sort_unstable();
    skin_pieces.dedup();
    let ids: Vec<u32> = (0..positions.len() as u32)
        .filter(|&v| skin_pieces.binary_search(&component[v as usize]).is_ok())
        .collect();
    Nearest::new(ids.iter().map(|&v| carried[v as usize]).collect(), ids)
}

/// How far round each mouth corner the jaw's weights are eased, in outer mouth widths.
const CORNER_REACH: f32 = 0.25;
/// Relaxation rounds at most.
const EASE_ROUNDS: usize = 400;

/// The steepest change of the template's jaw weights along any of its edges, per unit
/// length: how fast the template's own corners let the weight change.
fn steepest(mesh: &Mesh, weights: &[f32]) -> f64 {
    mesh.edges()
        .into_iter()
        .filter_map(|[a, b]| {
            let len = f64::from(mesh.positions[a as usize].distance(mesh.positions[b as usize]));
            let jump = f64::from(weights[a as usize] - weights[b as usize]).abs();
            (len > 0.0).then_some(jump / len)
        })
        .fold(0.0, f64::max)
}

/// Eases the jaw weights round the mouth corners, where the skin joins the lips and the
/// weight changes from the upper lip's (still) to the lower lip's (the jaw's). Carried by
/// nearest point from a template whose slit runs further into the corner, or split by lip
/// onto a mesh whose lips join a little sooner, two vertices a fraction of a millimetre apart
/// can take weights a third apart (MakeHuman's corners: 0.19 and 0.46 across a 0.6 mm edge,
/// a 7x stretch at AU26). Within [`CORNER_REACH`] of a corner, wherever an edge's weights
/// change faster than anywhere on the template (`limit`, per mesh unit), its ends and their
/// neighbours take the mean of their neighbours (weighted by `1 / length^2`), round after
/// round, until no edge there is steeper: the jump across the corner then grows from the
/// corner as on the template. A fit to the template itself has no steeper edge and changes
/// nothing; the open slit has no edges across it, so the lips stay split.
fn ease_corners(
    mesh: &Mesh,
    parts: &Parts,
    w: &mut [f32],
    lips: &super::lipsides::LipSides,
    limit: f64,
) {
    let reach = CORNER_REACH * lips.width();
    let near: Vec<bool> = mesh
        .positions
        .iter()
        .zip(&parts.of_vertex)
        .map(|(p, part)| *part == Part::Skin && lips.corner_distance(*p) <= reach)
        .collect();
    let edges: Vec<(usize, usize, f64)> = mesh
        .edges()
        .into_iter()
        .map(|[a, b]| (a as usize, b as usize))
        .filter(|&(a, b)| near[a] || near[b])
        .filter(|&(a, b)| parts.of_vertex[a] == Part::Skin && parts.of_vertex[b] == Part::Skin)
        .map(|(a, b)| {
            (
                a,
                b,
                f64::from(mesh.positions[a].distance(mesh.positions[b])),
            )
        })
        .filter(|&(_, _, len)| len > 0.0)
        .collect();
    let mut neighbours: std::collections::HashMap<usize, Vec<(usize, f64)>> = Default::default();
    for &(a, b, len) in &edges {
        neighbours
            .entry(a)
            .or_default()
            .push((b, 1.0 / (len * len)));
        neighbours
            .entry(b)
            .or_default()
            .push((a, 1.0 / (len * len)));
    }
    for _ in 0..EASE_ROUNDS {
        let mut free: Vec<usize> = Vec::new();
        for &(a, b, len) in &edges {
            if f64::from(w[a] - w[b]).abs() > limit * len * (1.0 + 1e-3) {
                for v in [a, b] {
                    free.push(v);
                    free.extend(neighbours[&v].iter().map(|&(n, _)| n));
                }
            }
        }
        free.retain(|&v| near[v]);
        free.sort_unstable();
        free.dedup();
        if free.is_empty() {
            break;
        }
        for v in free {
            let (sum, total) = neighbours[&v].iter().fold((0.0, 0.0), |(s, t), &(n, k)| {
                (s + k * f64::from(w[n]), t + k)
            });
            if total > 0.0 {
                w[v] = (sum / total) as f32;
            }
        }
    }
}
