//! The brow lowerer's ramp on a fitted head: no steeper than on the template.
//!
//! The brow lowerer's sheet (`Orbicularis_Oculi_Superior`, AU4, `face::brow_lowering`) brings
//! the brow down over a lid that stays: its mask rises from nothing at the upper lid margin to
//! the full pull at the brow, over at least 0.42 of the eye's width on the template (13 mm of
//! a 30.6 mm eye), and the skin between, the eye cover fold, takes the compression. Carried to
//! a head whose fold is modelled in small, close rows (MakeHuman's base mesh), that rise fell
//! within 2 mm in places: the skin above the fold came down 3-4 mm while the fold's edge came
//! down 1.3 mm, and at AU4 22 triangles turned over there (30 with the sheet alone at 2.0).
//!
//! So on a fitted head the sheet's effective pull (its carried masks times its own field,
//! relative to the field's largest) may rise along the mesh's edges by at most one full pull
//! per [`RAMP`] eye widths: a distance transform from every vertex (the least of each vertex's
//! own pull and a neighbour's plus the edge's length times the slope), and a mask brings the
//! pull down to that where it is steeper. The brow still comes down as far where the fold
//! leaves room; on the template (which the fit does not touch) nothing is steeper.
//!
//! The eyes' corners are held by the canthal tendons: the ramp starts from nothing within
//! [`CANTHUS`] eye widths of each corner landmark as well (MakeHuman's corner landmarks lie on
//! the lids' backs, 7 mm behind the skin in front of the inner corner). There, on MakeHuman,
//! the skin above the corner came down 0.24 mm at anger (4D+5C+7C+23D) as AU7 raised the skin
//! below it 0.6 mm, and two triangles turned over.

use super::parts::{Part, Parts};
use glam::Vec3;

use crate::model::envelope::lower_envelope;
use crate::model::{Field, Mask, Mesh, Rig};

/// The name the brow lowerer's sheets end with.
const LOWERING: &str = "_Orbicularis_Oculi_Superior";
/// The shortest distance (eye widths) over which the lowering may rise from nothing to its
/// full pull: half as long again as the template's own shortest ramp (0.42).
const RAMP: f64 = 0.6;
/// Around each eye corner the lowering starts from nothing within this distance (eye widths).
const CANTHUS: f64 = 0.3;
/// Caps this close to the pull are left out of the mask.
const EPSILON: f64 = 1e-4;

/// The eyes as the ramp sees them: their width and their corners (the landmarks 36, 39, 42
/// and 45).
pub(super) struct Eyes {
    /// The eye's width (the mean of both).
    pub width: f64,
    /// The four eye corners.
    pub corners: [Vec3; 4],
}

/// One mask per brow lowerer sheet of `rig` capping its rise (module docs). `cut` is the
/// weight the eye sockets leave each vertex (1 where nothing is cut).
pub(super) fn ramp_masks(
    rig: &Rig,
    mesh: &Mesh,
    parts: &Parts,
    cut: &[f64],
    eyes: &Eyes,
) -> Vec<Mask> {
    if eyes.width <= 0.0 {
        return Vec::new();
    }
    let neighbours = neighbours(mesh, parts);
    let slope = 1.0 / (RAMP * eyes.width);
    let canthus = (CANTHUS * eyes.width) as f32;
    let held: Vec<bool> = mesh
        .positions
        .iter()
        .map(|p| eyes.corners.iter().any(|c| c.distance(*p) <= canthus))
        .collect();
    rig.muscles
        .iter()
        .filter(|m| m.name.ends_with(LOWERING))
        .filter_map(|m| {
            let pull = pull(rig, &m.name, &Field::of(&m.kind, &mesh.positions), cut);
            let mut capped: Vec<f64> = pull
                .iter()
                .zip(&held)
                .map(|(&p, &h)| if h { 0.0 } else { p })
                .collect();
            let edges = |v: usize| {
                neighbours[v]
                    .iter()
                    .map(|&(u, length)| (u as usize, length))
            };
            let every_vertex = 0..capped.len();
            lower_envelope(&mut capped, every_vertex, edges, |c, l| c + l * slope);
            let weights: Vec<(u32, f32)> = pull
                .iter()
                .zip(&capped)
                .enumerate()
                .filter(|(_, (p, c))| **p > 0.0 && **c < **p - EPSILON)
                .map(|(v, (p, c))| (v as u32, (c / p) as f32))
                .collect();
            (!weights.is_empty()).then(|| Mask {
                muscles: vec![m.name.clone()],
                gain: 1.0,
                weights,
            })
        })
        .collect()
}

/// Each skin vertex's skin neighbours with the edge's length.
fn neighbours(mesh: &Mesh, parts: &Parts) -> Vec<Vec<(u32, f64)>> {
    let mut out = vec![Vec::new(); mesh.vertex_count()];
    let skin = |v: u32| parts.of_vertex.get(v as usize) == Some(&Part::Skin);
    for [a, b] in mesh.edges() {
        if skin(a) && skin(b) {
            let length = f64::from(mesh.positions[a as usize].distance(mesh.positions[b as usize]));
            out[a as usize].push((b, length));
            out[b as usize].push((a, length));
        }
    }
    out
}

/// The muscle's pull at each vertex relative to its field's largest: the field's length
/// times its masks' weights and the sockets' cut.
fn pull(rig: &Rig, name: &str, field: &Field, cut: &[f64]) -> Vec<f64> {
    let mut pull = vec![0.0; cut.len()];
    let largest = field
        .displacements
        .iter()
        .map(|d| f64::from(d.length()))
        .fold(0.0, f64::max);
    if largest <= 0.0 {
        return pull;
    }
    for (&v, d) in field.vertices.iter().zip(&field.displacements) {
        pull[v as usize] = f64::from(d.length()) / largest * cut[v as usize];
    }
    for mask in rig
        .masks
        .iter()
        .filter(|m| m.muscles.iter().any(|n| n == name))
    {
        for &(v, w) in &mask.weights {
            if let Some(p) = pull.get_mut(v as usize) {
                *p *= f64::from(w);
            }
        }
    }
    pull
}
