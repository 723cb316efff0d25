//! Where each skin vertex of a fitted mesh comes from on the template, which the carried
//! masks, the depth and side masks and the rings' reach all read.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::lipsides::LipSides;
use super::nearest::{weighted, Nearest};
use super::parts::{Part, Parts};
use super::regions::{Opening, Side};
use super::warp::Warp;
use super::Template;
use crate::landmarks::FaceFrame;
use crate::model::Mesh;

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
    /// Per mesh vertex with a source, the template vertices its carried weights are blended
    /// from and their shares ([`Nearest::blend_shares`]; on a lip, none of the template's
    /// other lip): the nearest alone gave a mesh finer than the template steps of weight
    /// between neighbouring vertices, and a smile crumpled the skin round the mouth.
    pub(super) around: Vec<Vec<(u32, f64)>>,
    /// Per mesh vertex in the mouth's zone whose nearest source is on the template's other
    /// lip, its source on its own lip ([`LipSource`]); empty when either face's lips were
    /// not found.
    pub(super) on_lips: Vec<Option<LipSource>>,
    /// Per mesh vertex by the face's midline, how much of its carried weights it reads at
    /// its sources' mirror images ([`Midline`]); empty when not found.
    pub(super) midline: Vec<Option<Mirrored>>,
    /// Per template vertex, the template skin vertex nearest its mirror image across the
    /// template's midline; empty when [`Sources::with_midline`] was not run.
    pub(super) mirror_of: Vec<u32>,
}

/// Skin this close to the face's midline (as fractions of the landmarks' spread) may read its
/// carried weights from both sides of the template, fading to its own source alone by the
/// second distance.
const MIDLINE_BAND: (f64, f64) = (0.02, 0.05);

/// How a mesh vertex by the midline reads a template weight. Its nearest template vertex
/// lies on one side or the other, whichever happens to be nearer: a vertex exactly on a
/// symmetric mesh's midline took a one-sided muscle's carried mask from one side of the
/// template, its mirror muscle's from the same side, so the rig was not symmetric (the
/// levator labii's mask gave 0.83 against 0.17 across the midline of fitted MakeHuman,
/// stretching an edge 3.4 times at AU10). Such a vertex blends its source's weight with the
/// weight at the source's mirror image on the template, by how much nearer the midline it
/// lies than its source: half and half on the midline, its own source alone where it lies
/// as far out as its source (a fit to the template itself blends nothing).
#[derive(Debug, Clone, Copy)]
pub(super) struct Mirrored {
    /// The share read from the mirror images (0 to 1).
    pub(super) share: f64,
}

impl Mirrored {
    /// A template weight read at a vertex: `read` of its sources (`false`) blended with
    /// `read` of their mirror images (`true`).
    pub(super) fn blend(this: Option<&Mirrored>, read: impl Fn(bool) -> f64) -> f64 {
        match this {
            Some(m) if m.share > 0.0 => (1.0 - m.share) * read(false) + m.share * read(true),
            _ => read(false),
        }
    }
}

/// Where a mesh vertex by the mouth comes from on its own lip of the template. The nearest
/// template vertex of all may lie on the other lip: a closed mouth's upper lip curls down
/// inside it (MakeHuman's base mesh), and the last millimetres of its lining lie nearer the
/// template's lower lip; a lip mask carried from there stepped from full pull to none
/// across the one edge between two rows of the same lip (the levator labii's, 6.6 times
/// its rest length at AU10). Such a vertex reads its carried weights on its own lip.
#[derive(Debug, Clone)]
pub(super) struct LipSource {
    /// The template vertices of the vertex's own lip its weights are read from, and their
    /// shares ([`Nearest::blend_shares`]: the nearest one alone stepped between the rows of
    /// a mesh finer than the template).
    pub(super) own: Vec<(u32, f64)>,
    /// The mouth's zone weight at the vertex (0 away from the lips, up to 1 between the
    /// corners): how much the own lip's sources replace the ones around it.
    pub(super) zone: f64,
}

impl LipSource {
    /// A template weight (per template vertex) read at this vertex: `around`, the value
    /// blended from the sources around it, blended by the zone toward its own lip's.
    pub(super) fn blend(&self, around: f64, weight: impl Fn(u32) -> f64) -> f64 {
        (1.0 - self.zone) * around + self.zone * weighted(&self.own, weight)
    }
}

impl Sources {
    /// A template value (per template vertex) read at mesh vertex `v`, which has a source:
    /// blended from the template vertices [`Sources::around`] it, and toward its own lip's
    /// where it has a [`LipSource`]. The nearest source alone steps between
    /// neighbouring vertices of a mesh finer than the template.
    pub(super) fn read(&self, v: usize, at: impl Fn(u32) -> f64) -> f64 {
        let around = weighted(&self.around[v], &at);
        match self.on_lips.get(v).and_then(Option::as_ref) {
            Some(lip) => lip.blend(around, at),
            None => around,
        }
    }

    pub(super) fn find(template: Template<'_>, warp: &Warp, mesh: &Mesh, parts: &Parts) -> Sources {
        let ids = template_skin(template);
        let points = ids
            .iter()
            .map(|&v| warp.apply_f32(template.mesh.positions[v as usize]))
            .collect();
        let index = Nearest::new(points, ids);
        let (near, far) = (MASK_FADE.0 * warp.spread, MASK_FADE.1 * warp.spread);
        // one nearest search per vertex, independent: on the rayon pool, in vertex order
        let of_vertex: Vec<Option<(u32, f64)>> = mesh
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
        let around = mesh
            .positions
            .par_iter()
            .zip(&of_vertex)
            .map(|(p, source)| match source {
                Some(_) => index.blend_shares(*p),
                None => Vec::new(),
            })
            .collect();
        Sources {
            of_vertex,
            around,
            on_lips: Vec::new(),
            midline: Vec::new(),
            mirror_of: Vec::new(),
        }
    }

    /// Finds the mesh vertices by the face's midline that read their carried weights from
    /// both sides of the template ([`Mirrored`]), given the faces' frames and landmarks
    /// (template first, then the mesh).
    pub(super) fn with_midline(
        mut self,
        template: Template<'_>,
        warp: &Warp,
        mesh: &Mesh,
        frames: [&FaceFrame; 2],
        landmarks: [&[Vec3]; 2],
    ) -> Sources {
        let ids = template_skin(template);
        let at = |v: u32| template.mesh.positions[v as usize];
        let index = Nearest::new(ids.iter().map(|&v| at(v)).collect(), ids.clone());
        let from = midline(frames[0], landmarks[0]);
        let lateral = frames[0].lateral.as_vec3();
        self.mirror_of = (0..template.mesh.vertex_count() as u32)
            .into_par_iter()
            .map(|v| {
                let image = at(v) - 2.0 * from(at(v)) as f32 * lateral;
                index.nearest(image).map_or(v, |(id, _)| id)
            })
            .collect();
        let to = midline(frames[1], landmarks[1]);
        let (near, far) = (MIDLINE_BAND.0 * warp.spread, MIDLINE_BAND.1 * warp.spread);
        self.midline = mesh
            .positions
            .iter()
            .enumerate()
            .map(|(v, p)| {
                let (id, _) = self.of_vertex[v]?;
                let (here, there) = (to(*p), to(warp.apply_f32(at(id))));
                let window = 1.0 - super::regions::smoothstep(near, far, here.abs());
                // where the vertex lies as far out as its source, on its side, it reads
                // the source alone; on the midline half and half; beyond it, the image
                let ratio = if there.abs() > 1e-9 * warp.spread {
                    here / there
                } else {
                    1.0
                };
                let share = window * (0.5 * (1.0 - ratio)).clamp(0.0, 1.0);
                (share > 0.0).then_some(Mirrored { share })
            })
            .collect();
        self
    }

    /// Finds the mouth vertices whose nearest source lies on the template's other lip, and
    /// their source on their own lip ([`LipSource`]), given the mouth and the lips of the
    /// template (first) and of the mesh (second).
    pub(super) fn with_lips(
        mut self,
        template: Template<'_>,
        warp: &Warp,
        mesh: &Mesh,
        mouths: [&Opening; 2],
        lips: [&LipSides; 2],
    ) -> Sources {
        let zone = |mouth: &Opening, p: Vec3| {
            mouth.side_weight(p, Side::Upper) + mouth.side_weight(p, Side::Lower)
        };
        let lip_index = |side: Side| {
            let ids: Vec<u32> = (0..template.mesh.vertex_count() as u32)
                .filter(|&v| {
                    lips[0].side(v as usize) == Some(side)
                        && zone(mouths[0], template.mesh.positions[v as usize]) > 0.0
                })
                .collect();
            let points = ids
                .iter()
                .map(|&v| warp.apply_f32(template.mesh.positions[v as usize]))
                .collect();
            Nearest::new(points, ids)
        };
        let (upper, lower) = (lip_index(Side::Upper), lip_index(Side::Lower));
        self.on_lips = mesh
            .positions
            .par_iter()
            .enumerate()
            .map(|(v, p)| {
                let (id, _) = self.of_vertex[v]?;
                let own = lips[1].side(v)?;
                if lips[0].side(id as usize) == Some(own) {
                    return None;
                }
                let zone = zone(mouths[1], *p).min(1.0);
                let index = if own == Side::Upper { &upper } else { &lower };
                (zone > 0.0).then_some(LipSource {
                    own: Some(index.blend_shares(*p)).filter(|own| !own.is_empty())?,
                    zone,
                })
            })
            .collect();
        // a lip's vertex blends nothing from the template's other lip
        for (v, around) in self.around.iter_mut().enumerate() {
            let Some(own) = lips[1].side(v) else {
                continue;
            };
            let other = |u: u32| lips[0].side(u as usize).is_some_and(|s| s != own);
            if around.iter().any(|&(u, _)| other(u)) {
                around.retain(|&(u, _)| !other(u));
                let total: f64 = around.iter().map(|&(_, w)| w).sum();
                if total > 0.0 {
                    around.iter_mut().for_each(|(_, w)| *w /= total);
                } else if let Some((id, _)) = self.of_vertex[v] {
                    *around = vec![(id, 1.0)];
                }
            }
        }
        self
    }
}

/// The template's skin vertices: all but those its still mask holds.
fn template_skin(template: Template<'_>) -> Vec<u32> {
    let skin = template_skin_flags(template);
    (0..skin.len() as u32)
        .filter(|&v| skin[v as usize])
        .collect()
}

/// Per template vertex, whether it is skin: not held by the template's still mask.
pub(super) fn template_skin_flags(template: Template<'_>) -> Vec<bool> {
    let mut skin = vec![true; template.mesh.vertex_count()];
    for mask in template
        .rig
        .masks
        .iter()
        .filter(|m| super::parts::is_still(template.rig, m))
    {
        for &(v, _) in &mask.weights {
            if let Some(s) = skin.get_mut(v as usize) {
                *s = false;
            }
        }
    }
    skin
}

/// A face's midline plane: through the mean of its 68 landmarks (a symmetric layout), across
/// its lateral axis. Returns the signed distance of a point from it.
fn midline(frame: &FaceFrame, landmarks: &[Vec3]) -> impl Fn(Vec3) -> f64 {
    let n = landmarks.len().max(1) as f64;
    let centre = landmarks.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / n;
    let lateral = frame.lateral;
    move |p: Vec3| (p.as_dvec3() - centre).dot(lateral)
}
