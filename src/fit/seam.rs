//! The mesh around an opening (the mouth, an eye) and the guided chains of edges along it:
//! the lip cut ([`super::lipcut`]) and the eye cut ([`super::eyecut`]) both find their lines
//! here, as the shortest chain of mesh edges through a contour's landmarks, each step weighed
//! up by its distance from the landmarks' polyline so the chain follows the contour.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap, HashSet};

use glam::Vec3;

use crate::model::mesh::Distance;
use crate::model::Mesh;

/// The distance from `p` to a polyline.
pub(super) fn distance_to_polyline(p: Vec3, line: &[Vec3]) -> f32 {
    nearest_segment(p, line).0
}

/// The distance from `p` to a polyline and the unit direction of its nearest segment (zero
/// for a line of no segment or a segment of no length).
pub(super) fn nearest_segment(p: Vec3, line: &[Vec3]) -> (f32, Vec3) {
    line.windows(2)
        .map(|s| {
            let d = s[1] - s[0];
            let t = if d.length_squared() > 0.0 {
                ((p - s[0]).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (p.distance(s[0] + d * t), d.normalize_or_zero())
        })
        .fold((f32::INFINITY, Vec3::ZERO), |best, s| {
            if s.0 < best.0 {
                s
            } else {
                best
            }
        })
}

/// The skin between an opening's two lines: the union of what `grow` grows from each of
/// `seeds` (the triangles just inside the upper line, [`Graph::below`]) where it succeeds,
/// sorted; `None` when it succeeds from none. Seeds are grown one at a time because on an
/// uneven surface a line's edge can tilt enough that its lower-looking triangle lies on the
/// upper lip or lid itself: grown together with the right seeds, that one spread the skin
/// over the face and a covered eye or joined lips were taken for an opening (`docs/fitting.md`,
/// "Uneven lips"). Every right seed grows the same skin on a smooth opening; where the lines
/// touch between the corners, the pieces on either side are each grown from their own seeds.
pub(super) fn grown_from_each(
    seeds: &[usize],
    mut grow: impl FnMut(usize) -> Option<Vec<usize>>,
) -> Option<Vec<usize>> {
    let mut skin: Vec<usize> = vec![];
    for &seed in seeds {
        if skin.binary_search(&seed).is_ok() {
            continue;
        }
        if let Some(piece) = grow(seed) {
            skin.extend(piece);
            skin.sort_unstable();
            skin.dedup();
        }
    }
    (!skin.is_empty()).then_some(skin)
}

/// The mesh around an opening (the mouth, an eye): neighbours and the triangles on each edge
/// and vertex, of the triangles with a corner near it.
pub(super) struct Graph {
    pub(super) near: Vec<bool>,
    pub(super) neighbours: HashMap<u32, Vec<u32>>,
    /// The triangles on each edge (its ends in [`key`] order).
    edge_triangles: HashMap<[u32; 2], Vec<usize>>,
    pub(super) vertex_triangles: HashMap<u32, Vec<usize>>,
}

/// An edge's key: its ends, the smaller first.
pub(super) fn key(a: u32, b: u32) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

impl Graph {
    /// The triangles on `edge` (a [`key`]), none for an edge outside the graph.
    pub(super) fn across(&self, edge: &[u32; 2]) -> &[usize] {
        self.edge_triangles.get(edge).map_or(&[][..], Vec::as_slice)
    }

    /// The triangles just below `line` (a lip line, a lid margin): on each of its edges with
    /// two triangles (less the edges in `skip`), the one whose third corner is lower by
    /// `lowness`, where it is lower by more than `decisive` times the edge's length.
    pub(super) fn below(
        &self,
        mesh: &Mesh,
        (line, skip): (&[u32], &HashSet<[u32; 2]>),
        lowness: impl Fn(Vec3) -> f32,
        decisive: f32,
    ) -> Vec<usize> {
        let mut below = vec![];
        for pair in line.windows(2) {
            let edge = key(pair[0], pair[1]);
            if skip.contains(&edge) {
                continue;
            }
            let tris = self.across(&edge);
            if let [t0, t1] = tris[..] {
                let third = |t: usize| {
                    let v = mesh.triangles[t]
                        .iter()
                        .find(|&&v| v != pair[0] && v != pair[1])
                        .copied()
                        .unwrap_or(pair[0]);
                    lowness(mesh.positions[v as usize])
                };
                let (s0, s1) = (third(t0), third(t1));
                let length =
                    mesh.positions[pair[0] as usize].distance(mesh.positions[pair[1] as usize]);
                if (s0 - s1).abs() > decisive * length {
                    below.push(if s0 > s1 { t0 } else { t1 });
                }
            }
        }
        below
    }

    /// The mesh within `reach` of `centre`.
    pub(super) fn new(mesh: &Mesh, centre: Vec3, reach: f32) -> Graph {
        let near: Vec<bool> = mesh
            .positions
            .iter()
            .map(|p| p.distance(centre) <= reach)
            .collect();
        let mut graph = Graph {
            near,
            neighbours: HashMap::new(),
            edge_triangles: HashMap::new(),
            vertex_triangles: HashMap::new(),
        };
        for (t, tri) in mesh.triangles.iter().enumerate() {
            if !tri.iter().any(|&v| graph.near[v as usize]) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                graph.edge_triangles.entry(key(a, b)).or_default().push(t);
                graph.vertex_triangles.entry(a).or_default().push(t);
                for (x, y) in [(a, b), (b, a)] {
                    let list = graph.neighbours.entry(x).or_default();
                    if !list.contains(&y) {
                        list.push(y);
                    }
                }
            }
        }
        graph
    }

    /// The chain of edges through the landmarks `ids` (corner to corner), guided by their
    /// polyline (a step `sigma` off it costs twice its length), through none of `avoid` but
    /// its own landmarks; `None` when a landmark cannot be reached or the chain crosses
    /// itself.
    pub(super) fn line(
        &self,
        mesh: &Mesh,
        sigma: f32,
        landmarks: &[u32],
        (ids, guide): (&[usize], &[Vec3]),
        avoid: &HashSet<u32>,
    ) -> Option<Vec<u32>> {
        let mut line = vec![landmarks[ids[0]]];
        for &i in &ids[1..] {
            let from = *line.last()?;
            let to = landmarks[i];
            if from != to {
                let step = self.guided_path(mesh, sigma, (from, to), guide, avoid)?;
                line.extend_from_slice(&step[1..]);
            }
        }
        let unique: HashSet<u32> = line.iter().copied().collect();
        (unique.len() == line.len() && line.len() >= 3).then_some(line)
    }

    /// The upper and lower chains of an opening (`contours`: each one's landmarks and
    /// guide, corner to corner) kept apart: on an uneven mesh the shortest chain along one
    /// lip may step onto a vertex of the other at a corner, and the two chains then share an
    /// edge there (MediaPipe's face moved 0.3 mm: the upper chain took a lower lip vertex
    /// beside the corner, the band between the chains leaked through the shared edge into
    /// the lower lip, and the joined lips were not cut). A vertex on both chains but not a
    /// landmark of both goes to the side `lowness` puts it on (above the opening where
    /// negative), and the other chain is found again without it. Chains that are one row
    /// (the same vertices) are kept as they are.
    pub(super) fn two_lines(
        &self,
        mesh: &Mesh,
        sigma: f32,
        landmarks: &[u32],
        contours: [(&[usize], &[Vec3]); 2],
        lowness: impl Fn(Vec3) -> f32,
    ) -> Option<(Vec<u32>, Vec<u32>)> {
        let none = HashSet::new();
        let upper = self.line(mesh, sigma, landmarks, contours[0], &none)?;
        let lower = self.line(mesh, sigma, landmarks, contours[1], &none)?;
        if upper == lower {
            return Some((upper, lower));
        }
        let own = |ids: &[usize]| -> HashSet<u32> { ids.iter().map(|&i| landmarks[i]).collect() };
        let (own_upper, own_lower) = (own(contours[0].0), own(contours[1].0));
        let on_lower: HashSet<u32> = lower.iter().copied().collect();
        let shared: Vec<u32> = upper
            .iter()
            .copied()
            .filter(|v| on_lower.contains(v))
            .filter(|v| !(own_upper.contains(v) && own_lower.contains(v)))
            .collect();
        if shared.is_empty() {
            return Some((upper, lower));
        }
        let (lower_side, upper_side): (HashSet<u32>, HashSet<u32>) = shared
            .iter()
            .partition(|&&v| lowness(mesh.positions[v as usize]) > 0.0);
        let upper = if lower_side.is_empty() {
            upper
        } else {
            self.line(mesh, sigma, landmarks, contours[0], &lower_side)?
        };
        let lower = if upper_side.is_empty() {
            lower
        } else {
            self.line(mesh, sigma, landmarks, contours[1], &upper_side)?
        };
        Some((upper, lower))
    }

    /// Dijkstra's shortest path from `from` to `to` near the opening, each edge costing its
    /// length times `1 + (d / sigma)^2`, `d` its middle's distance from `guide`, through
    /// none of `avoid` but `to`.
    fn guided_path(
        &self,
        mesh: &Mesh,
        sigma: f32,
        (from, to): (u32, u32),
        guide: &[Vec3],
        avoid: &HashSet<u32>,
    ) -> Option<Vec<u32>> {
        let mut best: HashMap<u32, (f64, u32)> = HashMap::from([(from, (0.0, from))]);
        let mut queue = BinaryHeap::from([(Reverse(Distance(0.0)), from)]);
        while let Some((Reverse(Distance(cost)), v)) = queue.pop() {
            if v == to {
                break;
            }
            if best.get(&v).is_some_and(|&(c, _)| c < cost) {
                continue;
            }
            for &w in self.neighbours.get(&v).map_or(&[][..], Vec::as_slice) {
                if !self.near[w as usize] || (w != to && avoid.contains(&w)) {
                    continue;
                }
                let (a, b) = (mesh.positions[v as usize], mesh.positions[w as usize]);
                let d = distance_to_polyline(0.5 * (a + b), guide) / sigma;
                let next = cost + f64::from(a.distance(b) * (1.0 + d * d));
                if best.get(&w).is_none_or(|&(c, _)| next < c) {
                    best.insert(w, (next, v));
                    queue.push((Reverse(Distance(next)), w));
                }
            }
        }
        let mut path = vec![to];
        let mut v = to;
        while v != from {
            v = best.get(&v)?.1;
            path.push(v);
        }
        path.reverse();
        Some(path)
    }
}
