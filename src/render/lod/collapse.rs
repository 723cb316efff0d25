//! Edge collapse: the simplification that makes a level of detail.
//!
//! Each step moves one vertex onto a neighbour along a short edge (a half-edge collapse),
//! so every vertex left is a vertex of the input at its own rest position. A collapse is
//! made only when it keeps the surface a clean surface and keeps what the renderer draws:
//!
//! * the edge is at most the level's length, and so is every edge the collapse makes;
//!   or, where the surface is flat, at most [`FLAT_STRETCH`] times it: a collapse may make
//!   longer edges when the vertex it removes (and every vertex merged into it before) lies
//!   within [`FLAT_TOLERANCE`] of the level's length of the surface left and lies on no
//!   border or crease, so a flat or gently curved region (a cheek, a subdivided facet) gets
//!   fewer, larger triangles while the picture moves by a fraction of a dot;
//! * the two vertices have the same signature (named groups, part label): part boundaries
//!   and the mouth's and eyes' parts stay where they were;
//! * a border vertex moves only along a border edge onto a border vertex, and a crease
//!   vertex only along a crease or border edge onto a crease or border vertex: mouth slit,
//!   eye openings, rim and the creases the renderer draws stay chains of edges;
//! * the link condition holds (the two vertices share exactly the neighbours of the
//!   triangles on their edge), so no edge gets a third triangle and no hole opens;
//! * no triangle turns over or degenerates, so no silhouette appears across the face.

use glam::Vec3;

/// Passes over the edges, shortest first; later passes find collapses that earlier ones
/// made possible.
const PASSES: usize = 2;

/// How much longer than the level's length an edge may grow where the surface is flat.
pub(super) const FLAT_STRETCH: f32 = 3.0;

/// How far, as a fraction of the level's length, the vertices a long collapse removes may
/// lie from the surface left (at the level's length of four dots, a fifth of a dot).
const FLAT_TOLERANCE: f32 = 0.05;

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
    crease: Vec<bool>,
    /// Per vertex: how far the vertices merged into it so far may lie from the surface
    /// (a bound, summed along each chain of collapses).
    error: Vec<f32>,
    /// The cosine of the crease angle.
    cos_crease: f32,
    /// Scratch lists reused by every collapse (nothing is allocated per edge).
    scratch: Scratch,
}

/// The lengths one level's collapses keep to (squared lengths, and a distance).
#[derive(Debug, Clone, Copy)]
struct Limit {
    /// The longest edge a collapse may make anywhere.
    short: f32,
    /// The longest edge a collapse may make where the surface stays within `tolerance`.
    flat: f32,
    tolerance: f32,
}

/// The lists one collapse looks at: the triangles around its two vertices, those on its
/// edge, and the two vertices' rings.
#[derive(Default)]
struct Scratch {
    tv: Vec<u32>,
    tu: Vec<u32>,
    shared: Vec<u32>,
    ring_v: Vec<u32>,
    ring_u: Vec<u32>,
}

impl<'a> Collapser<'a> {
    /// Prepares `triangles` over `positions` (with each vertex's signature and whether it
    /// lies on a border).
    pub(super) fn new(
        positions: &'a [Vec3],
        triangles: &[[u32; 3]],
        signature: &'a [u64],
        (border, crease): (Vec<bool>, Vec<bool>),
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
            crease,
            error: vec![0.0; positions.len()],
            cos_crease: super::CREASE_DEGREES.to_radians().cos(),
            scratch: Scratch::default(),
        }
    }

    /// Collapses edges up to `length` long while the rules allow.
    pub(super) fn run(&mut self, length: f32) {
        let limit = Limit {
            short: length * length,
            flat: (FLAT_STRETCH * length).powi(2),
            tolerance: FLAT_TOLERANCE * length,
        };
        for _ in 0..PASSES {
            let edges = self.short_edges(limit.flat);
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

    /// Drops dead triangles from `v`'s list.
    fn prune(&mut self, v: u32) {
        let alive = &self.alive;
        self.around[v as usize].retain(|&t| alive[t as usize]);
    }

    /// Moves `v` onto `u` when the rules allow; true when done.
    fn try_collapse(&mut self, v: u32, u: u32, limit: Limit) -> bool {
        let (vi, ui) = (v as usize, u as usize);
        if self.signature[vi] != self.signature[ui] || (self.border[vi] && !self.border[ui]) {
            return false;
        }
        if self.crease[vi] && !(self.crease[ui] || self.border[ui]) {
            return false;
        }
        self.prune(v);
        self.prune(u);
        let mut sc = std::mem::take(&mut self.scratch);
        let error = self.allowed(v, u, limit, &mut sc);
        if let Some(error) = error {
            self.apply(v, u, &sc);
            self.error[u as usize] = self.error[u as usize].max(error);
        }
        self.scratch = sc;
        error.is_some()
    }

    /// Whether moving `v` onto `u` keeps every rule (the lists in `sc` are filled here):
    /// if so, the bound on how far the vertices merged into `v`, `v` included, lie from
    /// the surface after it.
    fn allowed(&self, v: u32, u: u32, limit: Limit, sc: &mut Scratch) -> Option<f32> {
        let tris = &self.triangles;
        sc.tv.clear();
        sc.tv.extend_from_slice(&self.around[v as usize]);
        sc.tu.clear();
        sc.tu.extend_from_slice(&self.around[u as usize]);
        sc.shared.clear();
        sc.shared.extend(
            sc.tv
                .iter()
                .copied()
                .filter(|t| tris[*t as usize].contains(&u)),
        );
        // one triangle on a border edge, two inside; a border vertex slides only along its
        // border
        let want = if self.border[v as usize] { 1 } else { 2 };
        if sc.shared.is_empty() || sc.shared.len() > 2 || (want == 1 && sc.shared.len() != 1) {
            return None;
        }
        if self.crease[v as usize] && sc.shared.len() == 2 && !self.is_crease(sc) {
            return None;
        }
        let (pu, pv) = (self.positions[u as usize], self.positions[v as usize]);
        let (mut long, mut off) = (false, 0.0f32);
        for &t in &sc.tv {
            if sc.shared.contains(&t) {
                continue;
            }
            let tri = tris[t as usize];
            let old = tri.map(|i| self.positions[i as usize]);
            let new = tri.map(|i| {
                if i == v {
                    pu
                } else {
                    self.positions[i as usize]
                }
            });
            let reach = new
                .iter()
                .map(|p| p.distance_squared(pu))
                .fold(0.0, f32::max);
            if reach > limit.flat {
                return None;
            }
            long |= reach > limit.short;
            let n0 = (old[1] - old[0]).cross(old[2] - old[0]);
            let n1 = (new[1] - new[0]).cross(new[2] - new[0]);
            // not turned over, and not thinned to a sliver
            if n1.dot(n0) <= 0.1 * n0.length() * n1.length() || n1.length_squared() == 0.0 {
                return None;
            }
            off = off.max((pv - pu).dot(n1).abs() / n1.length());
        }
        let error = self.error[v as usize] + off;
        // The distance above is across the surface only: a border or crease vertex moved
        // along its line could straighten it (a lip's edge), so a border vertex makes a long
        // collapse only where its border runs straight on, and a crease vertex never.
        if long
            && (error.is_nan()
                || error > limit.tolerance
                || self.crease[v as usize]
                || !self.border_straight(v, u, limit, sc))
        {
            return None;
        }
        // last, as the dearest check
        self.link_holds(v, u, sc).then_some(error)
    }

    /// Whether border vertex `v` lies within the tolerance of the line from `u` to its
    /// other border neighbour (the vertex across the one other border edge of `v`'s
    /// triangles, `sc.tv`); true for a vertex on no border. Uses `sc.ring_v` as scratch.
    fn border_straight(&self, v: u32, u: u32, limit: Limit, sc: &mut Scratch) -> bool {
        if !self.border[v as usize] {
            return true;
        }
        let ring = &mut sc.ring_v;
        ring.clear();
        for &t in &sc.tv {
            ring.extend(self.triangles[t as usize].into_iter().filter(|&w| w != v));
        }
        ring.sort_unstable();
        // A neighbour across a border edge is in one triangle of the fan, the others in two.
        let once = |k: usize| {
            (k == 0 || ring[k - 1] != ring[k]) && (k + 1 == ring.len() || ring[k + 1] != ring[k])
        };
        let mut other = (0..ring.len()).filter(|&k| once(k) && ring[k] != u);
        let (Some(k), None) = (other.next(), other.next()) else {
            return false;
        };
        let (pv, pu, pw) = [v, u, ring[k]].map(|i| self.positions[i as usize]).into();
        let along = pw - pu;
        let off = (pv - pu).cross(along).length() / along.length();
        off <= limit.tolerance
    }

    /// Whether the edge of the two triangles in `sc.shared` is a crease.
    fn is_crease(&self, sc: &Scratch) -> bool {
        let normal = |t: u32| {
            let [a, b, c] = self.triangles[t as usize].map(|v| self.positions[v as usize]);
            (b - a).cross(c - a).normalize_or_zero()
        };
        normal(sc.shared[0]).dot(normal(sc.shared[1])) < self.cos_crease
    }

    /// Moves `v` onto `u`: the triangles on their edge go, `v`'s others now use `u`.
    fn apply(&mut self, v: u32, u: u32, sc: &Scratch) {
        for &t in &sc.shared {
            self.alive[t as usize] = false;
        }
        for &t in &sc.tv {
            if !self.alive[t as usize] {
                continue;
            }
            for i in self.triangles[t as usize].iter_mut() {
                if *i == v {
                    *i = u;
                }
            }
            self.around[u as usize].push(t);
        }
        self.around[v as usize].clear();
        self.kept[v as usize] = false;
    }

    /// The link condition: the vertices next to both `v` and `u` are exactly the third
    /// vertices of the triangles on their edge.
    fn link_holds(&self, v: u32, u: u32, sc: &mut Scratch) -> bool {
        let tris = &self.triangles;
        let ring = |list: &[u32], me: u32, out: &mut Vec<u32>| {
            out.clear();
            out.extend(
                list.iter()
                    .flat_map(|&t| tris[t as usize])
                    .filter(|&w| w != me),
            );
            out.sort_unstable();
            out.dedup();
        };
        ring(&sc.tv, v, &mut sc.ring_v);
        ring(&sc.tu, u, &mut sc.ring_u);
        let common = sc
            .ring_v
            .iter()
            .filter(|w| **w != u && sc.ring_u.binary_search(w).is_ok())
            .count();
        // the third vertices of the edge's triangles: one or two, all different
        let mut opposite = [u32::MAX; 2];
        for (k, &t) in sc.shared.iter().enumerate() {
            opposite[k] = tris[t as usize]
                .into_iter()
                .find(|&w| w != v && w != u)
                .unwrap_or(u32::MAX);
        }
        let distinct = if sc.shared.len() == 2 && opposite[0] != opposite[1] {
            2
        } else {
            1
        };
        common == distinct
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
