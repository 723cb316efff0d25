//! How far a fitted ring reaches: no further over the face than the template's ring does.
//!
//! A sphincter pulls everything inside its ellipse. Carried to another face, an eye ring is
//! sized between the eye's width and its opening (`transport`), but the face around differs:
//! a head whose eyes open wider than the template's, or whose brows sit lower, has its brow
//! or the side of its nose inside the fitted eye ring where the template's brow and nose lie
//! on or beyond the rim. Each fitted ring therefore gets a mask that caps its ellipse factor
//! (eq. 3's `f`: 1 at the centre, 0 on the rim) at each skin vertex by the template ring's
//! factor at the vertex's place on the template ([`Sources`], refined by the similarity's
//! inverse from the nearest template vertex): the lids it closes keep their full pull, a brow
//! the template's ring does not reach is not moved. Fitting the template to itself caps
//! nothing.

use glam::{DMat3, DVec3, Vec3};

use super::sources::Sources;
use super::warp::Warp;
use super::Template;
use crate::model::{Field, Mask, Mesh, MuscleKind, Rig, Sphincter};

/// Weights this close to 1 are left out of a mask.
const EPSILON: f64 = 1e-6;

/// The ellipse factor of a sphincter at `p`: `1 - |(x / semi_major, y / semi_minor)|` in its
/// frame about its centre; 1 at the centre, 0 on the rim, negative outside.
fn ellipse_factor(s: &Sphincter, p: DVec3) -> f64 {
    let rotation = s.frame.rotation().unwrap_or(DMat3::IDENTITY);
    let local = rotation.transpose() * (p - s.centre.as_dvec3());
    1.0 - (local.x / f64::from(s.semi_major)).hypot(local.y / f64::from(s.semi_minor))
}

/// One mask per fitted sphincter named in `rings` capping its reach by the template ring's
/// (module docs). `rig` holds the fitted muscles in the template rig's order.
pub(super) fn reach_masks(
    rig: &Rig,
    template: Template<'_>,
    mesh: &Mesh,
    sources: &Sources,
    warp: &Warp,
    rings: &[&str],
) -> Vec<Mask> {
    let inverse = warp.similarity.rotation.transpose() / warp.similarity.scale;
    // where a mesh point lies on the template: its source vertex, moved by the offset from
    // that vertex's warped place, taken back through the similarity
    let on_template = |id: u32, p: Vec3| {
        let source = template.mesh.positions[id as usize];
        let offset = (p - warp.apply_f32(source)).as_dvec3();
        source.as_dvec3() + inverse * offset
    };
    let mut masks = Vec::new();
    for (m, t) in rig.muscles.iter().zip(&template.rig.muscles) {
        let (MuscleKind::Sphincter(s), MuscleKind::Sphincter(ts)) = (&m.kind, &t.kind) else {
            continue;
        };
        if !rings.contains(&m.name.as_str()) {
            continue;
        }
        let field = Field::of(&m.kind, &mesh.positions);
        let weights: Vec<(u32, f32)> = field
            .vertices
            .iter()
            .filter_map(|&v| {
                let (id, share) = sources.of_vertex[v as usize]?;
                let p = mesh.positions[v as usize];
                let here = ellipse_factor(s, p.as_dvec3());
                if here <= 0.0 {
                    return None;
                }
                let there = ellipse_factor(ts, on_template(id, p)).max(0.0);
                let cap = (there / here).min(1.0);
                let w = 1.0 - share * (1.0 - cap);
                (w < 1.0 - EPSILON).then_some((v, w as f32))
            })
            .collect();
        if !weights.is_empty() {
            masks.push(Mask {
                muscles: vec![m.name.clone()],
                gain: 1.0,
                weights,
            });
        }
    }
    masks
}
