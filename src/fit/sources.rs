//! Where each skin vertex of a fitted mesh comes from on the template, which the carried
//! masks, the depth and side masks and the rings' reach all read.

use rayon::prelude::*;

use super::parts::{Part, Parts};
use super::warp::Warp;
use super::Template;
use crate::model::{Mask, Mesh, Rig};

/// Carried per-vertex mask weights fade back to 1 (no mask) between these distances from the
/// nearest carried template vertex, as fractions of the landmarks' spread: a neck or body
/// beyond the template's face keeps the muscles' own fields, as the jaw's weights fade there.
const MASK_FADE: (f64, f64) = (0.08, 0.2);

/// Where each skin vertex of the mesh comes from on the template: the nearest template skin
/// vertex after the warp, and the share of that vertex's mask weights it takes (1 near the
/// template, fading to 0 where no template vertex is near: a neck or body beyond the
/// template's face keeps the muscles' own fields, as the jaw's weights fade there).
pub(super) struct Sources {
    /// Per mesh vertex: `(template vertex, share)`, `None` for parts that are not skin and
    /// skin far from the template.
    pub(super) of_vertex: Vec<Option<(u32, f64)>>,
}

impl Sources {
    pub(super) fn find(template: Template<'_>, warp: &Warp, mesh: &Mesh, parts: &Parts) -> Sources {
        let count = template.mesh.vertex_count();
        let mut skin = vec![true; count];
        for mask in template
            .rig
            .masks
            .iter()
            .filter(|m| is_still(template.rig, m))
        {
            for &(v, _) in &mask.weights {
                if let Some(s) = skin.get_mut(v as usize) {
                    *s = false;
                }
            }
        }
        let ids: Vec<u32> = (0..count as u32).filter(|&v| skin[v as usize]).collect();
        let points = ids
            .iter()
            .map(|&v| warp.apply_f32(template.mesh.positions[v as usize]))
            .collect();
        let index = super::nearest::Nearest::new(points, ids);
        let (near, far) = (MASK_FADE.0 * warp.spread, MASK_FADE.1 * warp.spread);
        // one nearest search per vertex, independent: on the rayon pool, in vertex order
        let of_vertex = mesh
            .positions
            .par_iter()
            .enumerate()
            .map(|(v, p)| {
                if parts.of_vertex[v] != Part::Skin {
                    return None;
                }
                let (id, d) = index.nearest_within(*p, far as f32)?;
                let share = 1.0 - super::regions::smoothstep(near, far, f64::from(d));
                (share > 0.0).then_some((id, share))
            })
            .collect();
        Sources { of_vertex }
    }
}

/// A mask holding a rig's still parts: weight 0 everywhere it lists, for every muscle.
pub(super) fn is_still(rig: &Rig, mask: &Mask) -> bool {
    mask.weights.iter().all(|&(_, w)| w == 0.0)
        && rig
            .muscles
            .iter()
            .all(|muscle| mask.muscles.contains(&muscle.name))
}
