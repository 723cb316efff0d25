//! Per-vertex weights eased where a fitted mesh's weights change faster between neighbours
//! than the template's do: the jaw's round the mouth corners, the lip muscles' masks over
//! the whole face.
//!
//! Weights are carried from the template by nearest point, so a mesh finer than the template
//! sees each template vertex's weight over a patch and a step where the nearest vertex
//! changes; and where the mesh's lips join sooner than the template's (MakeHuman's meet in
//! front of the corner landmarks), a vertex of one lip lies nearest the template's other lip.
//! Two vertices a millimetre apart then took weights of template vertices several
//! millimetres apart, or of the two lips: MakeHuman's corners took jaw weights 0.19 and 0.46
//! across a 0.6 mm edge (7x at AU26), and the levator labii's mask 1.0 and 0.44 across a
//! 1.2 mm edge just inside each corner (3.5x at AU10). Wherever an edge changes faster than
//! the template lets it change, the weights become a ramp of the template's steepest slope
//! ([`ease`]), as far round as the step asks. The template fitted to itself has no steeper
//! edge and keeps its weights; an open slit has no edges across it, so the lips stay apart.

use glam::Vec3;

use super::lipsides::LipSides;
use super::parts::{Part, Parts};
use super::Template;
use crate::model::{Field, Mask, Mesh, Muscle};

/// How far round each mouth corner the jaw's weights are eased, in outer mouth widths: as far
/// as the template's own corners ease the mandible's weights in (`face::jaw_skin`, 30 mm of
/// a 52 mm mouth). The ease keeps what lies beyond as it is, so its border is a step where
/// the eased weights and the carried ones differ; at a quarter of the mouth's width that
/// border crossed the lips beside the corners, and MediaPipe's face cut in sixteen stretched
/// an edge there 3.31x at AU27 (its weights 0.13 against 0.01 across 1.4 mm).
const CORNER_REACH: f32 = 0.6;
/// A mask whose change strains the template's skin less than this anywhere (its change
/// per unit length times its muscles' pull, a fraction of the edge's length) changes only
/// where its muscles do not pull: the template says nothing of how fast it may change under
/// their pull, and it is left as carried (the mentalis's: 0.0006 on the built-in face).
const MIN_STRAIN: f64 = 0.01;
/// The slope of the ramps [`ease`] makes, as a share of the limit. The template's steepest
/// slope is reached at one of its edges; a ramp holds its slope over its whole length, and
/// at the full limit the fitted MediaPipe face's levator labii stretched its lips 2.59x at
/// 2.0 (the curved ramps of a relaxation toward the neighbours' mean stayed under 2.5x).
/// Measured, not derived: at 0.7 every fitted head's `grimace check` is as it was.
const RAMP_SHARE: f64 = 0.7;

/// How steep a weight may change along an edge: its change times the edge's `strength` (the
/// largest of its ends'), per unit length.
fn slope(w: [f32; 2], strength: [f64; 2], len: f64) -> f64 {
    f64::from(w[0] - w[1]).abs() * strength[0].max(strength[1]) / len
}

/// The steepest change of `weights` along the edges of `mesh` that `counts` (given both
/// ends) keeps, per unit length, each change weighted by the edge's `strength`.
pub(super) fn steepest(
    mesh: &Mesh,
    weights: &[f32],
    strength: &dyn Fn(usize) -> f64,
    counts: &dyn Fn(usize, usize) -> bool,
) -> f64 {
    mesh.edges()
        .into_iter()
        .map(|[a, b]| (a as usize, b as usize))
        .filter(|&(a, b)| counts(a, b))
        .filter_map(|(a, b)| {
            let len = f64::from(mesh.positions[a].distance(mesh.positions[b]));
            (len > 0.0).then(|| slope([weights[a], weights[b]], [strength(a), strength(b)], len))
        })
        .fold(0.0, f64::max)
}

/// How far from each mouth corner the jaw's ease crosses from one lip to the other, in
/// outer mouth widths: where the lips are joined (a mesh fitted without its lips cut) the
/// lips part between the corners, and easing across the joined lips there gave the upper
/// lip the jaw (MediaPipe's face: its inner upper lip moved with the chin at AU26).
const JOINED_REACH: f32 = 0.25;

/// Whether vertex `p` lies within [`JOINED_REACH`] of a mouth corner of `lips`, where the
/// jaw's ease may cross from one lip to the other.
pub(super) fn by_corner(lips: &LipSides, p: Vec3) -> bool {
    lips.corner_distance(p) <= JOINED_REACH * lips.width()
}

/// Whether vertex `p` lies within [`CORNER_REACH`] of a mouth corner of `lips`.
pub(super) fn near_corner(lips: &LipSides, p: Vec3) -> bool {
    lips.corner_distance(p) <= CORNER_REACH * lips.width()
}

/// Where [`ease`] works: the vertices `within` it (by place), and the edges `apart` (given
/// both ends) across which the weights may jump.
pub(super) type Region<'a> = (&'a dyn Fn(Vec3) -> bool, &'a dyn Fn(usize, usize) -> bool);

/// The whole skin, with no edge the weights may jump across.
pub(super) const EVERYWHERE: Region<'static> = (&|_| true, &|_, _| false);

/// Eases `w` on the skin of `mesh` `within` a region (along its edges but those `apart`
/// says the weights may jump across) where an edge there is steeper than
/// `limit` (per mesh unit, each change weighted by `strength` as in [`steepest`]): each
/// vertex takes the mean of the largest weights under `w` and the least above it that
/// change no faster than [`RAMP_SHARE`] of it (the slope-limited lower and upper envelopes,
/// `model::envelope`), so a step becomes a ramp centred on it (of half that slope: each
/// envelope takes the whole step on its side). Weights no steeper than the limit anywhere
/// are kept exactly. Found nearest first along the edges, it reaches as far as
/// the step asks whatever the mesh's resolution: relaxing toward the mean of the neighbours,
/// round after round, spread a step over a fixed number of edges, and a mesh four times
/// finer than MediaPipe's (0.85 mm edges) kept the levator labii's mask stepping 0.4 to 0.8
/// over 2 mm after 400 rounds (11 triangles turned over at 2.0).
pub(super) fn ease(
    mesh: &Mesh,
    parts: &Parts,
    w: &mut [f32],
    (within, apart): Region<'_>,
    (limit, strength): (f64, &dyn Fn(usize) -> f64),
) {
    let skin = |v: usize| parts.of_vertex[v] == Part::Skin;
    let near: Vec<bool> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(v, p)| skin(v) && within(*p))
        .collect();
    // each skin edge by the region, as the length the weight may change over along it: its
    // length over the larger pull at its ends (an edge nothing pulls constrains nothing)
    let mut neighbours: Vec<Vec<(usize, f64)>> = vec![Vec::new(); mesh.vertex_count()];
    for [a, b] in mesh.edges() {
        let (a, b) = (a as usize, b as usize);
        if !(near[a] || near[b]) || !skin(a) || !skin(b) || apart(a, b) {
            continue;
        }
        let len = f64::from(mesh.positions[a].distance(mesh.positions[b]));
        let pull = strength(a).max(strength(b));
        if len > 0.0 && pull > 0.0 {
            neighbours[a].push((b, len / pull));
            neighbours[b].push((a, len / pull));
        }
    }
    // weights no steeper than the limit anywhere are kept (the template fitted to itself)
    let steep = (0..w.len()).any(|a| {
        neighbours[a]
            .iter()
            .any(|&(b, length)| f64::from(w[a] - w[b]).abs() > limit * (1.0 + 1e-3) * length)
    });
    if !steep {
        return;
    }
    let linked: Vec<usize> = (0..w.len())
        .filter(|&v| !neighbours[v].is_empty())
        .collect();
    let rise = |value: f64, length: f64| value + limit * RAMP_SHARE * length;
    let mut lower: Vec<f64> = w.iter().map(|&x| f64::from(x)).collect();
    let mut upper: Vec<f64> = w.iter().map(|&x| -f64::from(x)).collect();
    let around = |v: usize| neighbours[v].iter().copied();
    crate::model::envelope::lower_envelope(&mut lower, linked.iter().copied(), around, rise);
    crate::model::envelope::lower_envelope(&mut upper, linked.iter().copied(), around, rise);
    for &v in linked.iter().filter(|&&v| near[v]) {
        let eased = 0.5 * (lower[v] - upper[v]);
        if eased != f64::from(w[v]) {
            w[v] = eased as f32;
        }
    }
}

/// The template and the mesh with its parts and fitted muscles.
pub(super) struct Faces<'a> {
    /// The template.
    pub(super) template: Template<'a>,
    /// The mesh, its parts and its fitted muscles.
    pub(super) mesh: (&'a Mesh, &'a Parts, &'a [Muscle]),
    /// Each fitted muscle's gain where it is not 1 (the template's masks' gains are carried
    /// into it).
    pub(super) gains: &'a [(String, f64)],
}

/// Eases the carried per-vertex masks of the lips' muscles (`carried`, each with the
/// template's mask it was read from: `(template mask, carried mask)`; masks naming any other
/// muscle are left alone). A mask's change matters as far as its muscles pull there, so each
/// edge's change is weighted by the largest pull of the mask's muscles at its ends (the bare
/// field at activation 1, times the muscle's gain), and the limit is the steepest such
/// change along the template's skin edges.
pub(super) fn ease_masks(faces: &Faces<'_>, lip_muscles: &[String], carried: &mut [(&Mask, Mask)]) {
    let template = faces.template;
    let (mesh, parts, muscles) = faces.mesh;
    let skin_template = super::sources::template_skin_flags(template);
    let count = template.mesh.vertex_count();
    for (from, to) in carried
        .iter_mut()
        .filter(|(from, _)| from.muscles.iter().all(|m| lip_muscles.contains(m)))
    {
        let template_pull = pull(
            &template.rig.muscles,
            &from.muscles,
            &template.mesh.positions,
            &|name| {
                template
                    .rig
                    .masks
                    .iter()
                    .filter(|m| m.muscles.iter().any(|n| n == name))
                    .map(|m| f64::from(m.gain))
                    .product()
            },
        );
        let mut dense = vec![1.0f32; count];
        for &(v, w) in &from.weights {
            if let Some(slot) = dense.get_mut(v as usize) {
                *slot = w;
            }
        }
        let at_template = |v: usize| template_pull.get(v).copied().unwrap_or(0.0);
        let skin = |a: usize, b: usize| skin_template[a] && skin_template[b];
        let limit = steepest(template.mesh, &dense, &at_template, &skin);
        if limit < MIN_STRAIN {
            continue;
        }
        let mesh_pull = pull(muscles, &from.muscles, &mesh.positions, &|name| {
            faces
                .gains
                .iter()
                .find(|(n, _)| n == name)
                .map_or(1.0, |&(_, g)| g)
        });
        let mut w = vec![1.0f32; mesh.vertex_count()];
        for &(v, x) in &to.weights {
            w[v as usize] = x;
        }
        let at_mesh = |v: usize| mesh_pull.get(v).copied().unwrap_or(0.0);
        ease(mesh, parts, &mut w, EVERYWHERE, (limit, &at_mesh));
        to.weights = w
            .iter()
            .enumerate()
            .filter(|&(_, &x)| x < 1.0 - 1e-6)
            .map(|(v, &x)| (v as u32, x))
            .collect();
    }
}

/// Per vertex of `positions`, the largest pull of the named `muscles` of `all` at activation 1
/// (the bare field's length times the muscle's `gain`).
pub(super) fn pull(
    all: &[Muscle],
    muscles: &[String],
    positions: &[Vec3],
    gain: &dyn Fn(&str) -> f64,
) -> Vec<f64> {
    let mut out = vec![0.0f64; positions.len()];
    for m in all.iter().filter(|m| muscles.contains(&m.name)) {
        let field = Field::of(&m.kind, positions);
        let g = gain(&m.name).abs();
        for (&v, d) in field.vertices.iter().zip(&field.displacements) {
            let p = f64::from(d.length()) * g;
            if p > out[v as usize] {
                out[v as usize] = p;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat strip one unit long, `n` columns of squares cut in two, two rows high.
    fn strip(n: usize) -> Mesh {
        let h = 1.0 / n as f32;
        let mut positions = Vec::new();
        for i in 0..=n {
            for j in 0..3 {
                positions.push(Vec3::new(i as f32 * h, j as f32 * h, 0.0));
            }
        }
        let at = |i: usize, j: usize| (i * 3 + j) as u32;
        let mut triangles = Vec::new();
        for i in 0..n {
            for j in 0..2 {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        Mesh::new(positions, triangles).unwrap()
    }

    /// `w` eased over the whole of `mesh`, all skin, with slope limit 4 at unit strength.
    fn ease_all_skin(mesh: &Mesh, w: &mut [f32]) {
        let parts = Parts {
            of_vertex: vec![Part::Skin; mesh.vertex_count()],
            choices: Vec::new(),
        };
        ease(mesh, &parts, w, EVERYWHERE, (4.0, &|_| 1.0));
    }

    /// A step from 0 to 1 at the strip's middle, eased ([`ease_all_skin`]).
    fn eased(n: usize) -> (Mesh, Vec<f32>) {
        let mesh = strip(n);
        let mut w: Vec<f32> = mesh
            .positions
            .iter()
            .map(|p| if p.x < 0.5 { 0.0 } else { 1.0 })
            .collect();
        ease_all_skin(&mesh, &mut w);
        (mesh, w)
    }

    /// A step becomes a ramp over the same length of surface whatever the mesh's resolution
    /// (the relaxation it replaced spread a step over a number of edges, and on a fine mesh
    /// ran out of rounds first), no steeper than the ramp's share of the limit, centred on
    /// the step; a mesh already no steeper than the limit is kept as it is.
    #[test]
    fn a_step_becomes_a_ramp_of_one_length_at_any_resolution() {
        let slope = 4.0 * RAMP_SHARE;
        for n in [40, 400, 2000] {
            let (mesh, w) = eased(n);
            let one = |_: usize| 1.0;
            let steepest = steepest(&mesh, &w, &one, &|_, _| true);
            assert!(steepest <= slope * (1.0 + 1e-3) + 1e-4, "{n}: {steepest}");
            // the ramp: where the weight is strictly between 0 and 1; each envelope takes the
            // whole step over 1 / slope on its side, so their mean spans 2 / slope
            let inside: Vec<f32> = mesh
                .positions
                .iter()
                .zip(&w)
                .filter(|(_, &x)| x > 1e-3 && x < 1.0 - 1e-3)
                .map(|(p, _)| p.x)
                .collect();
            let (lo, hi) = inside
                .iter()
                .fold((f32::MAX, f32::MIN), |(a, b), &x| (a.min(x), b.max(x)));
            let length = f64::from(hi - lo);
            let expected = 2.0 / slope;
            assert!(
                (length - expected).abs() <= 2.0 / n as f64 + 0.01,
                "{n} columns: a ramp {length} long, not {expected}"
            );
            assert!((f64::from(lo + hi) * 0.5 - 0.5).abs() <= 1.0 / n as f64);
        }
        // already gentle: kept bit for bit
        let mesh = strip(40);
        let gentle: Vec<f32> = mesh.positions.iter().map(|p| 0.5 * p.x).collect();
        let mut w = gentle.clone();
        ease_all_skin(&mesh, &mut w);
        assert_eq!(w, gentle);
    }
}
