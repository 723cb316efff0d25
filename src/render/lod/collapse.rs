//! Edge collapse: the simplification that makes a level of detail.
//!
//! Each step moves one vertex onto a neighbour along a short edge (a half-edge collapse),
//! so every vertex left is a vertex of the input at its own rest position. A collapse is
//! made only when it keeps the surface a clean surface and keeps what the renderer draws:
//!
//! * the edge is at most the level's length, and so is every edge the collapse makes;
//! * the two vertices have the same signature (named groups, part label): part boundaries
//!   and the mouth's and eyes' parts stay where they were;
//! * a border vertex moves only along a border edge onto a border vertex: mouth slit, eye
//!   openings and rim stay chains of border edges;
//! * the link condition holds (the two vertices share exactly the neighbours of the
//!   triangles on their edge), so no edge gets a third triangle and no hole opens;
//! * no triangle turns over or degenerates, so no silhouette appears across the face.

use glam::Vec3;

/// Passes over the edges, shortest first; later passes find collapses that earlier ones
/// made possible.
const PASSES: usize = 4;

/// The mesh being simplified.
pub(super) struct Collapser<'a> {
    positions: &'a [Vec3],
    signature: &'a [u64],
    triangles: Vec<[u32; 3]>,
    alive: Vec<bool>,
    /// Per vertex: its live triangles (dead ones are dropped when next read).
    around: Vec<Vec<u32>>,
    /// Per vertex: still in the mesh.
    kept: Vec<bool>,
    border: Vec<bool>,
}

impl<'a> Collapser<'a> {
    /// Prepares `triangles` over `positions` (with each vertex's signature and whether it
    /// lies on a border).
    pub(super) fn new(
        positions: &'a [Vec3],
        triangles: &[[u32; 3]],
        signature: &'a [u64],
        border: Vec<bool>,
    ) -> Collapser<'a> {
        let mut around = vec![Vec::new(); positions.len()];
        let mut tris = Vec::with_capacity(triangles.len());
        for t in triangles {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                continue;
            }
            for &v in t {
                around[v as usize].push(tris.len() as u32);
            }
            tris.push(*t);
        }
        Collapser {
            positions,
            signature,
            alive: vec![true; tris.len()],
            triangles: tris,
            around,
            kept: vec![true; positions.len()],
            border,
        }
    }

    /// Collapses edges up to `length` long while the rules allow.
    pub(super) fn run(&mut self, length: f32) {
        let limit = length * length;
        for _ in 0..PASSES {
            let edges = self.short_edges(limit);
            let mut done = 0usize;
            for (a, b) in edges {
                if !(self.kept[a as usize] && self.kept[b as usize]) {
                    continue;
                }
                if self.try_collapse(b, a, limit) || self.try_collapse(a, b, limit) {
                    done += 1;
                }
            }
            if done * 100 < self.triangles.len() {
                break;
            }
        }
    }

    /// The live edges no longer than `limit` (squared), shortest first.
    fn short_edges(&self, limit: f32) -> Vec<(u32, u32)> {
        let mut edges: Vec<(f32, u32, u32)> = Vec::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            if !self.alive[t] {
                continue;
            }
            for (a, b) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
                // each interior edge is seen twice; keep the copy with a < b (borders once
                // either way)
                if a > b && !self.border[a as usize] {
                    continue;
                }
                let d = self.positions[a as usize].distance_squared(self.positions[b as usize]);
                if d <= limit {
                    edges.push((d, a.min(b), a.max(b)));
                }
            }
        }
        edges.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        edges.dedup_by(|x, y| (x.1, x.2) == (y.1, y.2));
        edges.into_iter().map(|(_, a, b)| (a, b)).collect()
    }

    /// The live triangles around `v` (dropping dead ones from its list).
    fn live(&mut self, v: u32) -> Vec<u32> {
        let alive = &self.alive;
        let list = &mut self.around[v as usize];
        list.retain(|&t| alive[t as usize]);
        list.clone()
    }

    /// Moves `v` onto `u` when the rules allow; true when done.
    fn try_collapse(&mut self, v: u32, u: u32, limit: f32) -> bool {
        let (vi, ui) = (v as usize, u as usize);
        if self.signature[vi] != self.signature[ui] {
            return false;
        }
        if self.border[vi] && !self.border[ui] {
            return false;
        }
        let tv = self.live(v);
        let tu = self.live(u);
        let shared: Vec<u32> = tv
            .iter()
            .copied()
            .filter(|t| self.triangles[*t as usize].contains(&u))
            .collect();
        if shared.is_empty() || shared.len() > 2 {
            return false;
        }
        // a border vertex slides only along its border
        if self.border[vi] && shared.len() != 1 {
            return false;
        }
        if !self.link_holds(v, u, &tv, &tu, &shared) {
            return false;
        }
        let pu = self.positions[ui];
        for &t in &tv {
            if shared.contains(&t) {
                continue;
            }
            let tri = self.triangles[t as usize];
            let old = tri.map(|i| self.positions[i as usize]);
            let new = tri.map(|i| {
                if i == v {
                    pu
                } else {
                    self.positions[i as usize]
                }
            });
            if new.iter().any(|p| p.distance_squared(pu) > limit) {
                return false;
            }
            let n0 = (old[1] - old[0]).cross(old[2] - old[0]);
            let n1 = (new[1] - new[0]).cross(new[2] - new[0]);
            // not turned over, and not thinned to a sliver
            if n1.dot(n0) <= 0.1 * n0.length() * n1.length() || n1.length_squared() == 0.0 {
                return false;
            }
        }
        for &t in &shared {
            self.alive[t as usize] = false;
        }
        for &t in &tv {
            if !self.alive[t as usize] {
                continue;
            }
            for i in self.triangles[t as usize].iter_mut() {
                if *i == v {
                    *i = u;
                }
            }
            self.around[ui].push(t);
        }
        self.around[vi].clear();
        self.kept[vi] = false;
        true
    }

    /// The link condition: the vertices next to both `v` and `u` are exactly the third
    /// vertices of the triangles on their edge.
    fn link_holds(&self, v: u32, u: u32, tv: &[u32], tu: &[u32], shared: &[u32]) -> bool {
        let ring = |tris: &[u32], me: u32| -> Vec<u32> {
            let mut r: Vec<u32> = tris
                .iter()
                .flat_map(|&t| self.triangles[t as usize])
                .filter(|&w| w != me)
                .collect();
            r.sort_unstable();
            r.dedup();
            r
        };
        let (rv, ru) = (ring(tv, v), ring(tu, u));
        let common = rv.iter().filter(|w| ru.binary_search(w).is_ok()).count();
        let mut opposite: Vec<u32> = shared
            .iter()
            .flat_map(|&t| self.triangles[t as usize])
            .filter(|&w| w != v && w != u)
            .collect();
        opposite.sort_unstable();
        opposite.dedup();
        common == opposite.len()
    }

    /// The simplified mesh: per vertex left its input vertex, per input vertex its new
    /// number (`u32::MAX` when gone), and the live triangles in the new numbers.
    pub(super) fn finish(self) -> (Vec<u32>, Vec<u32>, Vec<[u32; 3]>) {
        let mut used = vec![false; self.positions.len()];
        for (t, _) in self.triangles.iter().zip(&self.alive).filter(|(_, &a)| a) {
            for &v in t {
                used[v as usize] = true;
            }
        }
        let mut number = vec![u32::MAX; self.positions.len()];
        let mut kept = Vec::new();
        for (v, &k) in used.iter().enumerate() {
            if k {
                number[v] = kept.len() as u32;
                kept.push(v as u32);
            }
        }
        let triangles = self
            .triangles
            .iter()
            .zip(&self.alive)
            .filter(|(_, &a)| a)
            .map(|(t, _)| t.map(|v| number[v as usize]))
            .collect();
        (kept, number, triangles)
    }
}
