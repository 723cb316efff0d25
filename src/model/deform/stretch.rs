//! The stretch limit: how fast a linear or sheet muscle's pull may change along the skin.
//!
//! A Waters muscle's pull is largest inside its zone and is cut to nothing by a quarter
//! cosine at the falloff's end, so it changes fastest right where it stops: about 1.6 units
//! of travel per unit of skin for the orbital orbicularis at 2.0. A mesh with edges of a
//! few millimetres resolves that slope and the edges there stretch 2.7 times their length;
//! a coarse mesh hides it. Skin does not stretch so: it stiffens sharply beyond a moderate
//! strain and drags its neighbours along (the strain limiting of cloth models, Provot 1995).
//!
//! At bind time each field's size is capped by the largest function of the vertices that
//! grows along each edge by no more than keeps the edge within the limit at the largest
//! activation (given the angle between the motion and the edge, [`Limit::slope`]), is 0 on
//! the vertices the muscle does not move, and stays below the field's own size (a lower
//! Lipschitz envelope, found by Dijkstra's algorithm along the edges). Each displacement
//! keeps its direction and is shortened to that size where it is larger. The muscle's
//! largest travel is kept where its zone is wide enough to reach it. A mirror pair is also
//! capped by its sum ([`limit_all`]), and the jaw's weights the same way ([`limit_jaw`]). The
//! result is again a field, so a frame stays a linear blend; the limit costs nothing per
//! frame.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::skin::Adjacency;
use super::BoundJaw;
use crate::model::activations::{JAW_RANGE, MUSCLE_RANGE};
use crate::model::field::Field;
use crate::model::muscle::MuscleKind;
use crate::model::Rig;

/// The stretch limit at a muscle's largest activation.
#[derive(Debug, Clone, Copy)]
pub(super) struct Limit {
    /// Largest stretch of an edge (its length over its rest length).
    stretch: f64,
    /// The largest activation (2.0).
    activation: f64,
}

impl Limit {
    /// The limit for [`super::SkinRules::stretch`]: none when it is 0.
    pub(super) fn of(stretch: f32) -> Option<Limit> {
        (stretch > 0.0).then(|| Limit {
            stretch: f64::from(stretch),
            activation: f64::from(*MUSCLE_RANGE.end()),
        })
    }

    /// How much larger a vertex's size (travel at activation 1) may be than its
    /// neighbour's, per unit of the edge between them, when it moves at `cos` to the edge
    /// (the cosine of its direction with the edge from the neighbour to it). With both
    /// moving alike in direction, at the largest activation `a` the edge's length over its
    /// rest length is `|e + a x|`, `e` the edge's unit vector and `x` the difference per unit
    /// length: at most `stretch` when `a x <= -cos + sqrt(cos^2 + stretch^2 - 1)`;
    /// `stretch - 1` moving straight away from the neighbour, `sqrt(stretch^2 - 1)` across
    /// the edge, `stretch + 1` straight toward it. Skin pushed together is left to the area
    /// bound: bounding it here too (the edge kept to half its length) turned triangles over
    /// at the smile's corners on MediaPipe's face cut in sixteen.
    fn slope(&self, cos: f64) -> f64 {
        let s = self.stretch;
        (-cos + (cos * cos + s * s - 1.0).sqrt()) / self.activation
    }
}

/// The jaw's limit over the muscles': at the muscles' 2.0 the built-in face's mouth corners
/// sank less than a third of the lower lip's drop at AU26 (7.6 of 22.9 mm; the oval opening
/// that keeps AU26 from reading as a smile), at 2.25 they sink as before.
const JAW_OVER_MUSCLES: f32 = 1.125;

/// Lowers the jaw's weights so that its turn at the largest activation (4.0) stretches no
/// edge beyond `stretch` (the muscles' limit) times [`JAW_OVER_MUSCLES`] its rest length
/// where neighbours move alike in direction: the jaw's displacement of a vertex is its
/// weight times the full turn's (`JawTurn::apply` blends linearly), so the weights times the
/// turn are capped as a muscle's field is. The jaw keeps every vertex (a weight may fall to
/// 0), so a rebind keeps its rows.
pub(super) fn limit_jaw(jaw: &mut BoundJaw, rest: &[Vec3], adjacency: &Adjacency, stretch: f32) {
    let Some(turn) = jaw.turn(*JAW_RANGE.end()) else {
        return;
    };
    if stretch <= 0.0 {
        return;
    }
    let limit = Limit {
        stretch: f64::from(stretch * JAW_OVER_MUSCLES),
        activation: 1.0,
    };
    let field = Field {
        vertices: jaw.vertices.clone(),
        displacements: jaw
            .vertices
            .iter()
            .zip(&jaw.weights)
            .map(|(&v, &w)| turn.apply(rest[v as usize], w) - rest[v as usize])
            .collect(),
    };
    let scale = scales(&[&field], adjacency, rest, limit);
    for (w, (_, c)) in jaw.weights.iter_mut().zip(&scale) {
        if *c < 1.0 {
            *w = (f64::from(*w) * c) as f32;
        }
    }
}

/// A vertex waiting in Dijkstra's queue, smallest size first.
#[derive(PartialEq)]
struct Waiting(f64, u32);

impl Eq for Waiting {}

impl PartialOrd for Waiting {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Waiting {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

/// The fields of the muscles `indices` (in that order) with their sizes capped so that each
/// changes by no more than the limit allows along every edge of `mesh`. `own` holds, by
/// muscle, the fields as masked and spread: at least those of `indices` and of their mirror
/// partners. A muscle with a mirror partner is capped at a vertex only as far as both the
/// muscle alone and the pair's sum need there: where the two sides' fields fade into each
/// other at the midline (the levator labii's lip) the sum is smooth and the bilateral AU
/// keeps its pull, and where the two overlap (the mentalis's chin) each alone is within the
/// limit. Each pair's sum is capped once. A sphincter's field is kept as it is: a ring closes
/// the lids and purses the lips across openings, where the skin around has to follow it.
pub(super) fn limit_all(
    rig: &Rig,
    own: &[Field],
    indices: &[usize],
    rest: &[Vec3],
    adjacency: &Adjacency,
    limit: Limit,
) -> Vec<Field> {
    let ring = |i: usize| matches!(rig.muscles[i].kind, MuscleKind::Sphincter(_));
    let partner = |i: usize| {
        rig.mirror_of(i)
            .filter(|&j| j != i && !ring(i) && !ring(j) && rig.mirror_of(j) == Some(i))
    };
    let mut pairs: Vec<[usize; 2]> = indices
        .iter()
        .filter_map(|&i| partner(i).map(|j| [i.min(j), i.max(j)]))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    let both: Vec<Vec<(u32, f64)>> = pairs
        .par_iter()
        .map(|&[a, b]| scales(&[&own[a], &own[b]], adjacency, rest, limit))
        .collect();
    indices
        .par_iter()
        .map(|&i| {
            let field = &own[i];
            if ring(i) || field.is_empty() {
                return field.clone();
            }
            let alone = scales(&[field], adjacency, rest, limit);
            let scale = match partner(i) {
                Some(j) => {
                    let pair = pairs.binary_search(&[i.min(j), i.max(j)]);
                    the_larger(alone, &both[pair.expect("every pair is capped")])
                }
                None => alone,
            };
            scaled(field, &scale)
        })
        .collect()
}

/// Each of `alone`'s scales, or the pair's at the same vertex where it is larger (`both`
/// lists, sorted, every vertex `alone` lists, and others).
fn the_larger(alone: Vec<(u32, f64)>, both: &[(u32, f64)]) -> Vec<(u32, f64)> {
    let mut at = both.iter().peekable();
    alone
        .into_iter()
        .map(|(v, c)| {
            while at.peek().is_some_and(|(u, _)| *u < v) {
                at.next();
            }
            let pair = at.peek().filter(|(u, _)| *u == v).map_or(c, |&&(_, p)| p);
            (v, c.max(pair))
        })
        .collect()
}

/// `field` with each displacement multiplied by its vertex's scale (`scale` lists the
/// field's vertices in order, perhaps among others); displacements scaled to zero are left
/// out.
fn scaled(field: &Field, scale: &[(u32, f64)]) -> Field {
    let mut out = Field::default();
    let mut at = scale.iter().peekable();
    for (&v, &d) in field.vertices.iter().zip(&field.displacements) {
        while at.peek().is_some_and(|(u, _)| *u < v) {
            at.next();
        }
        let c = at.peek().map_or(1.0, |&&(_, c)| c);
        let d = if c < 1.0 {
            (d.as_dvec3() * c).as_vec3()
        } else {
            d
        };
        if d != Vec3::ZERO {
            out.vertices.push(v);
            out.displacements.push(d);
        }
    }
    out
}

/// The factor (at most 1) by which the sum of `group`'s fields is cut at each of their
/// vertices (sorted) to keep within the limit.
fn scales(group: &[&Field], adjacency: &Adjacency, rest: &[Vec3], limit: Limit) -> Vec<(u32, f64)> {
    // the group's vertices (sorted, each once) and its summed displacement
    let mut vertices: Vec<u32> = group
        .iter()
        .flat_map(|f| f.vertices.iter().copied())
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    let mut local = vec![OUTSIDE; rest.len()];
    for (i, &v) in vertices.iter().enumerate() {
        local[v as usize] = i as u32;
    }
    let mut sum = vec![DVec3::ZERO; vertices.len()];
    for f in group {
        for (&v, d) in f.vertices.iter().zip(&f.displacements) {
            sum[local[v as usize] as usize] += d.as_dvec3();
        }
    }
    let own: Vec<f64> = sum.iter().map(|d| d.length()).collect();
    let direction: Vec<DVec3> = sum.iter().map(|d| d.normalize_or_zero()).collect();
    let size = envelope(
        &vertices,
        &local,
        &direction,
        own.clone(),
        adjacency,
        rest,
        limit,
    );
    vertices
        .iter()
        .zip(size.iter().zip(&own))
        .map(|(&v, (&s, &o))| (v, if s < o { s / o } else { 1.0 }))
        .collect()
}

/// `field` capped alone (the unit tests' shorthand for [`scales`] and [`scaled`]).
#[cfg(test)]
fn capped(
    field: &Field,
    group: &[&Field],
    adjacency: &Adjacency,
    rest: &[Vec3],
    limit: Limit,
) -> Field {
    scaled(field, &scales(group, adjacency, rest, limit))
}

/// Marks a vertex outside the fields being capped.
const OUTSIDE: u32 = u32::MAX;

/// The largest sizes of `vertices` (numbered in `local`, moving along `direction`) that are
/// at most `own`, are 0 on every other vertex, and grow from each neighbour by at most the
/// limit's slope along the edge: Dijkstra's algorithm along the edges, each still neighbour
/// a source of size 0.
fn envelope(
    vertices: &[u32],
    local: &[u32],
    direction: &[DVec3],
    mut size: Vec<f64>,
    adjacency: &Adjacency,
    rest: &[Vec3],
    limit: Limit,
) -> Vec<f64> {
    // how much more than vertex `from` vertex `to` (local `i`) may move
    let rise = |from: u32, to: u32, i: usize| {
        let edge = rest[to as usize].as_dvec3() - rest[from as usize].as_dvec3();
        let length = edge.length();
        if length == 0.0 {
            return 0.0;
        }
        limit.slope(direction[i].dot(edge) / length) * length
    };
    for (i, &v) in vertices.iter().enumerate() {
        for &n in adjacency.of_vertex(v as usize) {
            if local[n as usize] == OUTSIDE {
                size[i] = size[i].min(rise(n, v, i));
            }
        }
    }
    let mut queue: BinaryHeap<Waiting> = size
        .iter()
        .enumerate()
        .map(|(i, &s)| Waiting(s, i as u32))
        .collect();
    let mut done = vec![false; size.len()];
    while let Some(Waiting(s, i)) = queue.pop() {
        if done[i as usize] || s > size[i as usize] {
            continue;
        }
        done[i as usize] = true;
        let v = vertices[i as usize];
        for &n in adjacency.of_vertex(v as usize) {
            let j = local[n as usize];
            if j == OUTSIDE || done[j as usize] {
                continue;
            }
            let through = s + rise(v, n, j as usize);
            if through < size[j as usize] {
                size[j as usize] = through;
                queue.push(Waiting(through, j));
            }
        }
    }
    size
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::mesh::Mesh;

    /// Twice the rest length at 2.0: half a unit of travel per unit of length straight
    /// along an edge.
    const LIMIT: Limit = Limit {
        stretch: 2.0,
        activation: 2.0,
    };

    /// A strip of unit squares along x, two triangles each: vertices `2i` at `(i, 0)` and
    /// `2i + 1` at `(i, 1)`.
    fn strip(squares: u32) -> Mesh {
        let positions = (0..=squares)
            .flat_map(|i| [Vec3::new(i as f32, 0.0, 0.0), Vec3::new(i as f32, 1.0, 0.0)])
            .collect();
        let triangles = (0..squares)
            .flat_map(|i| {
                let [a, b, c, d] = [2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3];
                [[a, c, b], [b, c, d]]
            })
            .collect();
        Mesh::new(positions, triangles).expect("a valid strip")
    }

    /// The field moving every vertex with `x >= from` by `d`.
    fn step(mesh: &Mesh, from: f32, d: Vec3) -> Field {
        let vertices: Vec<u32> = (0..mesh.positions.len() as u32)
            .filter(|&v| mesh.positions[v as usize].x >= from)
            .collect();
        let displacements = vec![d; vertices.len()];
        Field {
            vertices,
            displacements,
        }
    }

    /// `field` capped alone on `mesh`.
    fn alone(field: &Field, mesh: &Mesh) -> Field {
        capped(
            field,
            &[field],
            &Adjacency::of(mesh),
            &mesh.positions,
            LIMIT,
        )
    }

    #[test]
    fn a_step_becomes_a_ramp_of_the_slope_from_the_still_skin() {
        let mesh = strip(10);
        // moving along the strip, away from the still skin
        let field = step(&mesh, 5.0, Vec3::new(3.0, 0.0, 0.0));
        let limited = alone(&field, &mesh);
        assert_eq!(limited.vertices, field.vertices);
        for (&v, d) in limited.vertices.iter().zip(&limited.displacements) {
            let x = mesh.positions[v as usize].x;
            // one unit from the still column at x = 4, then half a unit per unit
            let size = (0.5 * (x - 4.0)).min(3.0);
            assert!((d.x - size).abs() < 1e-6, "x {x}: {d}");
            assert_eq!((d.y, d.z), (0.0, 0.0), "the direction is kept");
        }
    }

    #[test]
    fn a_field_within_the_slope_is_kept_bit_for_bit() {
        let mesh = strip(10);
        let gentle = Field {
            vertices: (0..mesh.positions.len() as u32).collect(),
            displacements: mesh
                .positions
                .iter()
                .map(|p| Vec3::new(0.1 * (p.x + 1.0), 0.0, 0.0))
                .collect(),
        };
        assert_eq!(alone(&gentle, &mesh), gentle);
    }

    #[test]
    fn a_vertex_moves_no_more_than_the_slope_allows_from_the_still_skin() {
        // a spike: one vertex moves far, its neighbours not at all
        let mesh = strip(4);
        let field = Field {
            vertices: vec![4],
            displacements: vec![Vec3::new(5.0, 0.0, 0.0)],
        };
        let limited = alone(&field, &mesh);
        // its still neighbour one unit behind it along its motion bounds it most
        assert_eq!(limited.vertices, vec![4]);
        assert!((limited.displacements[0].x - 0.5).abs() < 1e-6);
    }

    #[test]
    fn halves_that_fade_into_each_other_are_capped_by_their_sum() {
        // the left half fades out over x 4..6 as the right fades in: their sum is even
        let mesh = strip(10);
        let weight = |x: f32| ((6.0 - x) / 2.0).clamp(0.0, 1.0);
        let half = |w: &dyn Fn(f32) -> f32| {
            let mut f = Field::default();
            for (v, p) in mesh.positions.iter().enumerate() {
                if w(p.x) > 0.0 {
                    f.vertices.push(v as u32);
                    f.displacements.push(Vec3::Z * 4.0 * w(p.x));
                }
            }
            f
        };
        let (left, right) = (half(&weight), half(&|x| 1.0 - weight(x)));
        let adjacency = Adjacency::of(&mesh);
        let pair = [&left, &right];
        assert_eq!(
            capped(&left, &pair, &adjacency, &mesh.positions, LIMIT),
            left
        );
        assert_eq!(
            capped(&right, &pair, &adjacency, &mesh.positions, LIMIT),
            right
        );
        // alone, each half's fade (2 units of travel per unit, across the edges) is steeper
        // than the limit allows there (sqrt(3) / 2) and is capped
        assert_ne!(
            capped(&left, &[&left], &adjacency, &mesh.positions, LIMIT),
            left
        );
    }
}
