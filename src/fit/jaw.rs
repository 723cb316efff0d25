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
                // the lip's own template vertices, or all where the lip has none
                let (index, d) = match index.nearest(*p) {
                    Some((_, d)) => (index, d),
                    None => (&all, all.nearest(*p).map_or(f32::INFINITY, |(_, d)| d)),
                };
                let fade = 1.0 - smoothstep(near, far, f64::from(d));
                let carried = |id: u32| f64::from(dense.get(id as usize).copied().unwrap_or(0.0));
                let w = index.blend(*p, carried).unwrap_or(0.0) * fade;
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
        // how fast the template's own corners let the weight change, anywhere on it
        let one = |_: usize| 1.0;
        let limit = super::ease::steepest(template.mesh, &dense, &one, &|_, _| true)
            / warp.similarity.scale;
        super::ease::ease(
            mesh,
            parts,
            &mut all_weights,
            &|p| super::ease::near_corner(lips, p),
            (limit, &one),
        );
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
    let skin = super::parts::on_landmark_pieces(template.mesh, template.landmarks);
    let ids: Vec<u32> = (0..skin.len() as u32)
        .filter(|&v| skin[v as usize])
        .collect();
    Nearest::new(ids.iter().map(|&v| carried[v as usize]).collect(), ids)
}
