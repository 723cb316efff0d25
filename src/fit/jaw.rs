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
use super::parts::{Part, Parts, SkinGraph};
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
    // whether a vertex of the template, or of the mesh, lies on `side` of its mouth
    let template_side = |v: u32, side: Side| {
        let p = template.mesh.positions[v as usize];
        mouth_from.is_some_and(|m| side_weight(lips_from, m, v as usize, p, side) > 0.0)
    };
    let mesh_side = |v: u32, side: Side| {
        let p = mesh.positions[v as usize];
        mouth_to.is_some_and(|m| side_weight(lips, m, v as usize, p, side) > 0.0)
    };
    let side_index = |side: Side| {
        let ids: Vec<u32> = (0..carried.len() as u32)
            .filter(|&v| template_side(v, side))
            .collect();
        Nearest::new(ids.iter().map(|&v| carried[v as usize]).collect(), ids)
    };
    let (lower, upper) = (side_index(Side::Lower), side_index(Side::Upper));
    let margin = LowerMargin::find(
        template,
        &carried,
        mesh,
        parts,
        [lips_from, lips],
        [&|u| template_side(u, Side::Lower), &|v| {
            mesh_side(v, Side::Lower)
        }],
    );
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
                // (a margin was found only where the template's lower lip has vertices, so
                // the lower lip's index above was not left for all)
                let read = match &margin {
                    Some(margin) if below > 0.0 => margin.read(v, *p, carried),
                    _ => index.blend(*p, carried),
                };
                let w = read.unwrap_or(0.0) * fade;
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
        // the lips part between the corners: where they are joined (a mesh fitted without
        // its lips cut), the edges from one lip to the other there are not eased across
        let apart = |a: usize, b: usize| {
            let (a32, b32) = (a as u32, b as u32);
            let across = (mesh_side(a32, Side::Upper) && mesh_side(b32, Side::Lower))
                || (mesh_side(a32, Side::Lower) && mesh_side(b32, Side::Upper));
            let by_corner = |v: usize| super::ease::by_corner(lips, mesh.positions[v]);
            across && !(by_corner(a) && by_corner(b))
        };
        super::ease::ease(
            mesh,
            parts,
            &mut all_weights,
            (&|p| super::ease::near_corner(lips, p), &apart),
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

/// The lower lip's margin along the slit, on the template and on the mesh. The template
/// holds its lower lip's margin back from the jaw (`face::jaw_skin`: the weights along the
/// slit are lower than the lip's body), a step over one template edge; carried by place,
/// that row lands a few rows onto a finer lip's front instead of on the lip's own margin, and
/// the jaw's weight dipped there (MediaPipe's face cut in sixty-four: 0.905, 0.854, 0.904
/// within a millimetre; AU27 turned 16 triangles over). So a vertex of the lower lip reads the
/// template's margin and the template's body apart, and blends them by its distance along the
/// surface from the mesh's own margin, over the template's distance from its margin to its
/// body at that place along the slit.
struct LowerMargin {
    margin: Nearest,
    body: Nearest,
    /// Per template margin vertex, the distance (after the warp) to the nearest body vertex.
    reach: Vec<f64>,
    /// Per mesh vertex, the distance along the skin from the mesh's lower-lip margin.
    distance: Vec<f64>,
}

impl LowerMargin {
    /// `None` when either face's lower lip has no margin (an open slit's boundary) or no
    /// body. `lower` says which template vertices, then which mesh vertices, are the lower
    /// lip's (as the weights' lower-lip index takes them).
    fn find(
        template: Template<'_>,
        carried: &[Vec3],
        mesh: &Mesh,
        parts: &Parts,
        [lips_from, lips]: [Option<&LipSides>; 2],
        lower: [&dyn Fn(u32) -> bool; 2],
    ) -> Option<LowerMargin> {
        let (lips_from, lips) = (lips_from?, lips?);
        // a lower lip's vertex on an edge of one triangle only: the slit's boundary
        let on_margin = |lips: &LipSides, m: &Mesh| {
            let mut on = vec![false; m.vertex_count()];
            for (a, b) in m.boundary_edges() {
                for v in [a, b] {
                    on[v as usize] |= lips.side(v as usize) == Some(Side::Lower);
                }
            }
            on
        };
        let from_margin = on_margin(lips_from, template.mesh);
        let ids = |margin: bool| -> Vec<u32> {
            (0..carried.len() as u32)
                .filter(|&u| lower[0](u) && from_margin[u as usize] == margin)
                .collect()
        };
        let (margin_ids, body_ids) = (ids(true), ids(false));
        let to_margin: Vec<u32> = on_margin(lips, mesh)
            .iter()
            .enumerate()
            .filter(|&(v, &m)| m && parts.of_vertex[v] == Part::Skin && lower[1](v as u32))
            .map(|(v, _)| v as u32)
            .collect();
        if margin_ids.is_empty() || body_ids.is_empty() || to_margin.is_empty() {
            return None;
        }
        let index = |ids: &[u32]| {
            Nearest::new(
                ids.iter().map(|&u| carried[u as usize]).collect(),
                ids.to_vec(),
            )
        };
        let body = index(&body_ids);
        let mut reach = vec![0.0; carried.len()];
        for &u in &margin_ids {
            let d = body
                .nearest(carried[u as usize])
                .map_or(0.0, |(_, d)| f64::from(d));
            reach[u as usize] = d;
        }
        Some(LowerMargin {
            margin: index(&margin_ids),
            body,
            reach,
            distance: SkinGraph::new(mesh, parts).distances(&to_margin, f64::INFINITY),
        })
    }

    /// The weight of lower-lip vertex `v` at `p`: the template margin's on the mesh's margin,
    /// its body's from the template's margin-to-body distance there on, smoothly between; a
    /// vertex on a template body vertex reads it exactly (the template fitted to itself).
    fn read(&self, v: usize, p: Vec3, value: impl Fn(u32) -> f64 + Copy) -> Option<f64> {
        let body = self.body.blend(p, value)?;
        let reach = self.margin.blend(p, |u| self.reach[u as usize])?;
        let on_body = self.body.nearest(p).is_some_and(|(_, d)| d == 0.0);
        if on_body || reach <= 0.0 || self.distance[v] >= reach {
            return Some(body);
        }
        let t = smoothstep(0.0, reach, self.distance[v]);
        Some((1.0 - t) * self.margin.blend(p, value)? + t * body)
    }
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
