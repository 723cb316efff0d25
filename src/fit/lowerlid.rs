//! The lower lid's own ring (AU7, the lid tightener) on a fitted head, faded along the skin.
//!
//! The template's lower lid ring (`Orbicularis_Oculi_Lower` in the default rig) carries a
//! mask that is 1 below its axis and 0 above it: made for the template's lids, which meet
//! only at a corner vertex. Carried by nearest point to a head whose canthus is a fold of
//! several close rows (MakeHuman's, rows 0.6 mm apart), the step falls between two rows: one
//! is pulled up a millimetre, the next is not, and the rows between turn over.
//!
//! The palpebral fibres of the lower lid run from the medial to the lateral palpebral
//! ligament, which hold the canthi: the lid rises most in its middle and not at all at its
//! corners, and the skin round a canthus carries the pull from one lid to the other with no
//! seam. So the ring's carried mask is replaced by one made from distances along the skin
//! (Dijkstra on the mesh's edges, skin only), scaled by the eye's size:
//!
//! - **Lower side**: `d_up` and `d_low`, the distances to the upper and to the lower lid
//!   landmarks, and `g`, the distance from the lower lid's landmarks to the upper lid's
//!   (round a corner, or across the skin of a covered eye). The side is
//!   `smoothstep(0, 1, 0.5 + (d_up - d_low) / g)`: 1 on the lower lid and the cheek below,
//!   0 on the upper lid and above, a half at the canthi, and since both distances change by
//!   no more than the length walked, it changes by at most `3 / g` per unit of skin however
//!   close the mesh's rows lie.
//! - **Corners**: times `smoothstep(0, CORNER_FADE * w, d_corner)`, `d_corner` the distance
//!   to the nearer canthus landmark and `w` the eye's width: the pull fades to nothing at
//!   the palpebral ligaments.
//!
//! Skin on a piece of its own inside the ring (lashes) takes the weight of the nearest skin
//! vertex of the face. The other masks of the ring (its gain, the still parts, its depth and
//! reach) are kept; only the masks it shares with other muscles, carried from the template,
//! are left for it. Where the mesh is the template's own (the template fitted to itself) the
//! caller keeps the carried mask.

use glam::{DMat3, Vec3};

use super::parts::{Part, Parts, SkinGraph};
use super::regions::smoothstep;
use crate::model::{Mask, Mesh, Rig, Sphincter};

/// The pull fades out toward each canthus over this share of the eye's width (about 9 mm
/// on an adult eye): the lateral palpebral ligament and raphe, the medial ligament.
pub const CORNER_FADE: f64 = 0.3;

/// Weights this close to 1 are left out of the mask.
const EPSILON: f64 = 1e-6;

/// An eye's landmark vertices: its two corners, the upper lid's and the lower lid's
/// landmarks between them.
#[derive(Debug, Clone, Copy)]
pub(super) struct EyeVertices {
    /// The inner and outer corners.
    pub corners: [u32; 2],
    /// The upper lid's landmarks between the corners.
    pub upper: [u32; 2],
    /// The lower lid's landmarks between the corners.
    pub lower: [u32; 2],
}

/// The ellipse factor of ring `s` at `p` (1 at the centre, 0 on the rim, negative outside).
fn ellipse_factor(s: &Sphincter, p: Vec3) -> f64 {
    let rotation = s.frame.rotation().unwrap_or(DMat3::IDENTITY);
    let local = rotation.transpose() * (p.as_dvec3() - s.centre.as_dvec3());
    1.0 - (local.x / f64::from(s.semi_major)).hypot(local.y / f64::from(s.semi_minor))
}

/// The lower lid ring's weight at every skin vertex inside ring `s` (module docs), `None`
/// elsewhere; `None` altogether when the lids' landmarks are not joined by skin.
fn weights(
    s: &Sphincter,
    mesh: &Mesh,
    parts: &Parts,
    eye: EyeVertices,
) -> Option<Vec<Option<f64>>> {
    let at = |v: u32| mesh.positions[v as usize];
    let width = f64::from(at(eye.corners[0]).distance(at(eye.corners[1])));
    if width.is_nan() || width <= 0.0 {
        return None;
    }
    let graph = SkinGraph::new(mesh, parts);
    let limit = 4.0 * width;
    let up = graph.distances(&eye.upper, limit);
    let low = graph.distances(&eye.lower, limit);
    let corner = graph.distances(&eye.corners, limit);
    let gap = eye
        .lower
        .iter()
        .map(|&v| up[v as usize])
        .fold(0.0, f64::max);
    if !(gap.is_finite() && gap > 0.0) {
        return None;
    }
    let inside: Vec<bool> = (0..mesh.vertex_count())
        .map(|v| parts.of_vertex[v] == Part::Skin && ellipse_factor(s, mesh.positions[v]) > 0.0)
        .collect();
    let reached = |v: usize| up[v].is_finite() && low[v].is_finite();
    let own = |v: usize| {
        let side = smoothstep(0.0, 1.0, 0.5 + (up[v] - low[v]) / gap);
        side * smoothstep(0.0, CORNER_FADE * width, corner[v])
    };
    let face: Vec<usize> = (0..inside.len())
        .filter(|&v| inside[v] && reached(v))
        .collect();
    let weights = (0..inside.len())
        .map(|v| {
            if !inside[v] {
                return None;
            }
            if reached(v) {
                return Some(own(v));
            }
            // a piece of its own (lashes): the weight of the face's nearest skin vertex
            let p = mesh.positions[v];
            let nearest = face.iter().min_by(|&&a, &&b| {
                at(a as u32)
                    .distance_squared(p)
                    .total_cmp(&at(b as u32).distance_squared(p))
            })?;
            Some(own(*nearest))
        })
        .collect();
    Some(weights)
}

/// The mask of the lower lid ring `name` (its ring `s`) faded along the skin (module
/// docs); `None` when the lids' landmarks are not joined by skin.
pub(super) fn lower_lid_mask(
    name: &str,
    s: &Sphincter,
    mesh: &Mesh,
    parts: &Parts,
    eye: EyeVertices,
) -> Option<Mask> {
    let weights = weights(s, mesh, parts, eye)?;
    Some(Mask {
        muscles: vec![name.to_string()],
        gain: 1.0,
        weights: weights
            .iter()
            .enumerate()
            .filter_map(|(v, w)| {
                let w = (*w)?;
                (w < 1.0 - EPSILON).then_some((v as u32, w as f32))
            })
            .collect(),
    })
}

/// Takes the rings `names` out of the per-vertex masks they share with other muscles (the
/// template's, carried: the side step, weighing skin), then adds their own `masks`. Their
/// own masks (gain, depth, reach) and the still parts' (zeros off the skin) stay. All at
/// once, as a ring and its mirror share their carried mask.
pub(super) fn replace_carried(rig: &mut Rig, parts: &Parts, names: &[String], masks: Vec<Mask>) {
    let skin = |v: u32| parts.of_vertex[v as usize] == Part::Skin;
    for mask in &mut rig.masks {
        let carried = mask.muscles.len() > 1 && mask.weights.iter().any(|&(v, _)| skin(v));
        if carried {
            mask.muscles.retain(|n| !names.contains(n));
        }
    }
    rig.masks.retain(|m| !m.muscles.is_empty());
    rig.masks.extend(masks);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Convergence, Frame};

    /// A flat 41 x 41 sheet, 0.5 apart, with an eye's slit: the triangles between the rows
    /// `y = 0` and `y = 0.5` cut out for `|x| < 6`. The corners `(-6, 0)`, `(6, 0)`; the lid
    /// landmarks `(-2, 0.5)`, `(2, 0.5)` above and `(-2, 0)`, `(2, 0)` below.
    fn slit() -> (Mesh, EyeVertices) {
        let n = 41u32;
        let at = |x: f32, y: f32| ((y + 10.0) * 2.0) as u32 * n + ((x + 10.0) * 2.0) as u32;
        let mut positions = Vec::new();
        for j in 0..n {
            for i in 0..n {
                positions.push(Vec3::new(
                    -10.0 + 0.5 * i as f32,
                    -10.0 + 0.5 * j as f32,
                    0.0,
                ));
            }
        }
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let (x, y) = (-10.0 + 0.5 * i as f32, -10.0 + 0.5 * j as f32);
                if y == 0.0 && x > -6.0 && x < 6.0 - 0.25 {
                    continue;
                }
                let v = j * n + i;
                triangles.push([v, v + 1, v + n]);
                triangles.push([v + 1, v + n + 1, v + n]);
            }
        }
        let eye = EyeVertices {
            corners: [at(-6.0, 0.0), at(6.0, 0.0)],
            upper: [at(-2.0, 0.5), at(2.0, 0.5)],
            lower: [at(-2.0, 0.0), at(2.0, 0.0)],
        };
        (Mesh::new(positions, triangles).unwrap(), eye)
    }

    fn ring() -> Sphincter {
        Sphincter {
            centre: Vec3::new(0.0, 0.25, 0.0),
            semi_major: 9.5,
            semi_minor: 9.5,
            convergence: Convergence::MajorAxis,
            bulge: 0.0,
            frame: Frame {
                x: Vec3::X,
                y: Vec3::Y,
            },
        }
    }

    /// The lower lid takes the whole weight, the upper lid and the corners none, and across
    /// the skin round the corners the weight changes by no more than its bound (`3 / g` for
    /// the side, `1.5 / (0.3 w)` for the corners' fade per unit), where a step (the carried
    /// mask's) changes by 2 per unit between rows 0.5 apart.
    #[test]
    fn the_weight_is_whole_on_the_lower_lid_and_continuous_round_the_corners() {
        let (mesh, eye) = slit();
        let parts = Parts {
            of_vertex: vec![Part::Skin; mesh.vertex_count()],
            choices: Vec::new(),
        };
        let w = weights(&ring(), &mesh, &parts, eye).unwrap();
        let at = |v: u32| w[v as usize].unwrap();
        for v in eye.lower {
            assert!((at(v) - 1.0).abs() < 1e-9, "lower lid {}", at(v));
        }
        for v in eye.upper.into_iter().chain(eye.corners) {
            assert!(at(v) < 1e-9, "upper lid or corner {}", at(v));
        }
        // the lids' landmarks are 9 apart round a corner; the eye is 12 wide
        let bound = 3.0 / 9.0 + 1.5 / (CORNER_FADE * 12.0);
        for [a, b] in mesh.edges() {
            let (Some(x), Some(y)) = (w[a as usize], w[b as usize]) else {
                continue;
            };
            let length = f64::from(mesh.positions[a as usize].distance(mesh.positions[b as usize]));
            assert!(
                (x - y).abs() <= bound * length + 1e-9,
                "{x} at {a}, {y} at {b}, {length} apart"
            );
        }
    }

    /// The carried masks the ring shares (a side step weighing skin) are left for it, its own
    /// masks and the still parts' zeros stay, and its new mask is added.
    #[test]
    fn only_the_shared_carried_mask_is_replaced() {
        let parts = Parts {
            of_vertex: vec![Part::Skin, Part::Still],
            choices: Vec::new(),
        };
        let mask = |muscles: &[&str], weights: Vec<(u32, f32)>| Mask {
            muscles: muscles.iter().map(|m| m.to_string()).collect(),
            gain: 1.0,
            weights,
        };
        let mut rig = Rig {
            masks: vec![
                mask(&["L", "R"], vec![(0, 0.0)]),
                mask(&["L", "R", "X"], vec![(1, 0.0)]),
                mask(&["L"], vec![(0, 0.5)]),
            ],
            version: crate::model::RIG_VERSION,
            mesh: "mesh.obj".into(),
            landmarks: None,
            combine: Default::default(),
            muscles: Vec::new(),
            jaw: None,
        };
        let names = ["L".to_string(), "R".to_string()];
        replace_carried(
            &mut rig,
            &parts,
            &names,
            vec![mask(&["L"], vec![(0, 0.25)])],
        );
        let named: Vec<Vec<String>> = rig.masks.iter().map(|m| m.muscles.clone()).collect();
        assert_eq!(named, [vec!["L", "R", "X"], vec!["L"], vec!["L"]]);
        assert_eq!(rig.masks[2].weights, [(0, 0.25)]);
    }
}
