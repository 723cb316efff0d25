//! Topology checks for a triangle mesh: edge use, winding consistency, boundary loops.
//!
//! Used to recover the default face's slits from a mesh read back from a file, and by the
//! tests that keep the generated face clean.

use std::collections::BTreeMap;

use crate::model::Mesh;

/// For each undirected edge `[low, high]`, how many triangles use it in each direction:
/// `(low -> high, high -> low)`.
pub fn edge_uses(mesh: &Mesh) -> BTreeMap<[u32; 2], (u32, u32)> {
    let mut uses: BTreeMap<[u32; 2], (u32, u32)> = BTreeMap::new();
    for t in &mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let entry = uses.entry([a.min(b), a.max(b)]).or_default();
            if a < b {
                entry.0 += 1;
            } else {
                entry.1 += 1;
            }
        }
    }
    uses
}

/// The boundary edges (used by exactly one triangle), directed as that triangle uses them.
pub fn boundary_edges(mesh: &Mesh) -> Vec<(u32, u32)> {
    edge_uses(mesh)
        .into_iter()
        .filter_map(|([a, b], (ab, ba))| match (ab, ba) {
            (1, 0) => Some((a, b)),
            (0, 1) => Some((b, a)),
            _ => None,
        })
        .collect()
}

/// The boundary loops, each a cycle of vertices in the direction the triangles run round
/// it. Assumes every boundary vertex has exactly one outgoing boundary edge (a manifold
/// boundary); a vertex with more ends its walk early rather than looping forever.
pub fn boundary_loops(mesh: &Mesh) -> Vec<Vec<u32>> {
    let next: BTreeMap<u32, u32> = boundary_edges(mesh).into_iter().collect();
    let mut seen = std::collections::BTreeSet::new();
    let mut loops = Vec::new();
    for &start in next.keys() {
        if seen.contains(&start) {
            continue;
        }
        let mut cycle = Vec::new();
        let mut v = start;
        while seen.insert(v) {
            cycle.push(v);
            match next.get(&v) {
                Some(&w) => v = w,
                None => break,
            }
        }
        loops.push(cycle);
    }
    loops
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn square() -> Mesh {
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        Mesh::new(p, vec![[0, 1, 2], [0, 2, 3]]).expect("valid square")
    }

    #[test]
    fn a_square_has_one_boundary_loop_of_four() {
        let loops = boundary_loops(&square());
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].len(), 4);
    }

    #[test]
    fn the_shared_diagonal_is_used_once_each_way() {
        let uses = edge_uses(&square());
        assert_eq!(uses[&[0, 2]], (1, 1));
        assert_eq!(uses[&[0, 1]], (1, 0));
    }
}
