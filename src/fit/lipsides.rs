//! Which lip each skin vertex belongs to, found by walking the mesh from the lip landmarks
//! rather than by height.
//!
//! A mouth's lips are not split by a plane: a full upper lip curls down below the line
//! halfway between the inner lip landmarks (MakeHuman's base mesh), and a lower lip may rise
//! above it. What holds is connectivity: the upper lip and everything reached from it
//! without crossing the slit stays with the skull, the lower lip and what hangs from it
//! follows the jaw. Each skin vertex is given to the lip whose landmarks are nearer along the
//! mesh's edges (the upper lip's 49-53 and 61-63, the lower lip's 55-59 and 65-67; the
//! corners belong to both and seed neither). Across an open or cut slit the only ways from
//! one lip to the other run round the corners or deep through a mouth bag, so the boundary
//! between the two lies on the slit between the corners, along the middle of a band of skin
//! that still joins the lips (a mouth fitted with `--keep-lips`), and runs out from the
//! corners into the cheeks, where the mouth's side weights fade out anyway
//! ([`Opening::side_weight`] is 0 at and beyond the corners).

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashSet};

use glam::Vec3;

use super::parts::{Part, Parts};
use super::regions::{Opening, Side};
use super::Template;
use crate::landmarks::{nearest_vertex, COUNT};
use crate::model::mesh::Distance;
use crate::model::Mesh;

/// The upper lip's landmarks that seed the walk: the outer upper lip between the corners and
/// the upper inner lip.
const UPPER_SEEDS: [usize; 8] = [49, 50, 51, 52, 53, 61, 62, 63];
/// The lower lip's: the outer lower lip between the corners and the lower inner lip.
const LOWER_SEEDS: [usize; 8] = [55, 56, 57, 58, 59, 65, 66, 67];

/// The lip each skin vertex of a mesh belongs to.
#[derive(Debug, Clone, PartialEq)]
pub struct LipSides {
    /// Per vertex: the lip it is reached from first; `None` for parts that are not skin and
    /// skin reached from neither lip.
    of_vertex: Vec<Option<Side>>,
    /// Each mouth corner as the segment from its inner corner (60, 64: where the slit ends)
    /// to its outer one (48, 54).
    corners: [[Vec3; 2]; 2],
    /// The outer mouth width (48 to 54).
    width: f32,
}

impl LipSides {
    /// The lips of `mesh` from its 68 landmark vertices; `None` when the landmarks do not fit
    /// the mesh or a lip has no skin vertex of its own.
    pub fn find(mesh: &Mesh, landmarks: &[u32], parts: &Parts) -> Option<LipSides> {
        LipSides::of_skin(mesh, landmarks, |v| {
            parts.of_vertex.get(v as usize) == Some(&Part::Skin)
        })
    }

    /// The lips of a template, whose skin is every vertex its rig's still mask does not hold
    /// and whose landmarks are points (each taken at its nearest vertex). The template's
    /// sides are found the same way as the mesh's, so a fit to the template itself splits
    /// nothing differently.
    pub fn of_template(template: Template<'_>) -> Option<LipSides> {
        let still: HashSet<u32> = template
            .rig
            .masks
            .iter()
            .filter(|m| super::parts::is_still(template.rig, m))
            .flat_map(|m| m.weights.iter().map(|&(v, _)| v))
            .collect();
        let landmarks: Vec<u32> = template
            .landmarks
            .iter()
            .map(|&p| nearest_vertex(&template.mesh.positions, p))
            .collect();
        LipSides::of_skin(template.mesh, &landmarks, |v| !still.contains(&v))
    }

    fn of_skin(mesh: &Mesh, landmarks: &[u32], skin: impl Fn(u32) -> bool) -> Option<LipSides> {
        let n = mesh.vertex_count();
        if landmarks.len() != COUNT || landmarks.iter().any(|&v| v as usize >= n) {
            return None;
        }
        let seeds = |ids: &[usize]| -> Vec<u32> {
            ids.iter()
                .map(|&i| landmarks[i])
                .filter(|&v| skin(v))
                .collect()
        };
        let (upper, lower) = (seeds(&UPPER_SEEDS), seeds(&LOWER_SEEDS));
        // a vertex both lips share (a closed mouth's one row) seeds neither
        let upper: Vec<u32> = upper
            .iter()
            .copied()
            .filter(|v| !lower.contains(v))
            .collect();
        let lower: Vec<u32> = lower
            .iter()
            .copied()
            .filter(|v| !upper.contains(v))
            .collect();
        if upper.is_empty() || lower.is_empty() {
            return None;
        }
        let mut neighbours: Vec<Vec<(u32, f32)>> = vec![Vec::new(); n];
        for [a, b] in mesh.edges() {
            if skin(a) && skin(b) {
                let d = mesh.positions[a as usize].distance(mesh.positions[b as usize]);
                neighbours[a as usize].push((b, d));
                neighbours[b as usize].push((a, d));
            }
        }
        let at = |i: usize| mesh.positions[landmarks[i] as usize];
        Some(LipSides {
            of_vertex: nearer_seed(&neighbours, &upper, &lower),
            corners: [[at(60), at(48)], [at(64), at(54)]],
            width: at(48).distance(at(54)),
        })
    }

    /// The outer mouth width (landmarks 48 to 54).
    pub fn width(&self) -> f32 {
        self.width
    }

    /// The distance from `p` to the nearer mouth corner (the segment from the inner corner
    /// to the outer).
    pub fn corner_distance(&self, p: Vec3) -> f32 {
        self.corners
            .iter()
            .map(|&[a, b]| {
                let d = b - a;
                let t = if d.length_squared() > 0.0 {
                    ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                p.distance(a + d * t)
            })
            .fold(f32::INFINITY, f32::min)
    }

    /// The lip vertex `v` belongs to, if any.
    pub fn side(&self, v: usize) -> Option<Side> {
        self.of_vertex.get(v).copied().flatten()
    }

    /// How much vertex `v` at `p` belongs to `side` of the mouth `opening`: the opening's
    /// zone weight (up to 1 between the corners, 0 at and beyond them and far from the line)
    /// given wholly to the lip the vertex is reached from, whichever side of the line it
    /// lies; by height ([`Opening::side_weight`]) where no lip reaches it.
    pub fn side_weight(&self, opening: &Opening, v: usize, p: Vec3, side: Side) -> f64 {
        match self.side(v) {
            None => opening.side_weight(p, side),
            Some(own) if own == side => {
                opening.side_weight(p, Side::Upper) + opening.side_weight(p, Side::Lower)
            }
            Some(_) => 0.0,
        }
    }
}

/// The weight of vertex `v` at `p` on `side` of `opening`: by its lip ([`LipSides`]) for the
/// mouth when the lips were found, by height otherwise (and for the eyes).
pub fn side_weight(
    lips: Option<&LipSides>,
    opening: &Opening,
    v: usize,
    p: Vec3,
    side: Side,
) -> f64 {
    match lips {
        Some(lips) if opening.name == "mouth" => lips.side_weight(opening, v, p, side),
        _ => opening.side_weight(p, side),
    }
}

/// Dijkstra's walk from both seed sets at once: each vertex takes the side whose seeds are
/// nearer along the edges (ties to the upper lip, which stays still).
fn nearer_seed(neighbours: &[Vec<(u32, f32)>], upper: &[u32], lower: &[u32]) -> Vec<Option<Side>> {
    let mut best: Vec<Option<(f32, Side)>> = vec![None; neighbours.len()];
    let mut queue = BinaryHeap::new();
    for (seeds, side, rank) in [(upper, Side::Upper, 0u8), (lower, Side::Lower, 1u8)] {
        for &v in seeds {
            if best[v as usize].is_none() {
                best[v as usize] = Some((0.0, side));
                queue.push(Reverse((Distance(0.0), rank, v)));
            }
        }
    }
    while let Some(Reverse((Distance(d), rank, v))) = queue.pop() {
        // the queue holds the f32 sums exactly, widened
        let d = d as f32;
        let side = if rank == 0 { Side::Upper } else { Side::Lower };
        if best[v as usize].is_some_and(|(b, s)| b < d || (b == d && s != side)) {
            continue;
        }
        for &(w, len) in &neighbours[v as usize] {
            let next = d + len;
            if best[w as usize].is_none_or(|(b, _)| next < b) {
                best[w as usize] = Some((next, side));
                queue.push(Reverse((Distance(f64::from(next)), rank, w)));
            }
        }
    }
    best.into_iter().map(|b| b.map(|(_, s)| s)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path 0-1-2-3-4 seeded at both ends: each vertex goes to the nearer end.
    #[test]
    fn nearer_seed_splits_a_path_at_its_middle() {
        let lengths = [1.0, 1.0, 3.0, 1.0];
        let mut neighbours = vec![Vec::new(); 5];
        for (i, &l) in lengths.iter().enumerate() {
            neighbours[i].push((i as u32 + 1, l));
            neighbours[i + 1].push((i as u32, l));
        }
        let sides = nearer_seed(&neighbours, &[0], &[4]);
        assert_eq!(
            sides,
            vec![
                Some(Side::Upper),
                Some(Side::Upper),
                Some(Side::Upper),
                Some(Side::Lower),
                Some(Side::Lower)
            ]
        );
    }
}
