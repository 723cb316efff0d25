//! Topology checks for a triangle mesh: boundary loops (edge use and boundary edges are
//! `Mesh::edge_uses` and `Mesh::boundary_edges`).
//!
//! Used to recover the default face's slits from a mesh read back from a file, and by the
//! tests that keep the generated face clean.

use std::collections::BTreeMap;

use crate::model::Mesh;

/// The boundary loops, each a cycle of vertices in the direction the triangles run round
/// it. Assumes every boundary vertex has exactly one outgoing boundary edge (a manifold
/// boundary); a vertex with more ends its walk early rather than looping forever.
pub fn boundary_loops(mesh: &Mesh) -> Vec<Vec<u32>> {
    let next: BTreeMap<u32, u32> = mesh.boundary_edges().into_iter().collect();
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
        let uses = square().edge_uses();
        assert_eq!(uses[&[0, 2]], (1, 1));
        assert_eq!(uses[&[0, 1]], (1, 0));
    }
}
