//! Deforming only some vertices: the level of detail a big mesh is drawn with.
//!
//! The editor draws a simplified copy of a big mesh whose vertices are vertices of the full
//! mesh (`render::Lod`); [`BoundRig::deform_at`] gives exactly what [`BoundRig::deform`]
//! gives at those vertices, at the cost of those vertices (and, under the skin's area bound,
//! of the few neighbours their scale reads), not of the whole mesh.

use glam::Vec3;
use rayon::prelude::*;

use super::{BoundRig, JawTurn, NO_ROW, PARALLEL_CHUNK};
use crate::model::activations::{ActivationError, Activations};
use crate::model::rig::Combine;

/// Lists of at least this many vertices are deformed in parallel chunks.
const PARALLEL_MIN: usize = 8_192;

impl BoundRig {
    /// The positions [`BoundRig::deform`] gives at `vertices`, bit for bit, into `out`
    /// (resized to `vertices.len()`). A vertex number beyond the mesh is an error.
    pub fn deform_at(
        &self,
        act: &Activations,
        vertices: &[u32],
        out: &mut Vec<Vec3>,
    ) -> Result<(), ActivationError> {
        act.validate(&self.rig)?;
        let n = self.rest.len();
        if let Some(&v) = vertices.iter().find(|&&v| v as usize >= n) {
            return Err(ActivationError::VertexCount {
                given: v as usize + 1,
                expected: n,
            });
        }
        out.clear();
        out.resize(vertices.len(), Vec3::ZERO);
        let average = self.rig.combine == Combine::Average;
        let turn = self.jaw.as_ref().and(self.jaw_turn(act.jaw));
        let one = |v: u32| self.sampled(v as usize, &act.muscles, average, turn);
        if vertices.len() >= PARALLEL_MIN {
            out.par_chunks_mut(PARALLEL_CHUNK)
                .zip(vertices.par_chunks(PARALLEL_CHUNK))
                .for_each(|(o, vs)| o.iter_mut().zip(vs).for_each(|(p, &v)| *p = one(v)));
        } else {
            out.iter_mut().zip(vertices).for_each(|(p, &v)| *p = one(v));
        }
        Ok(())
    }

    /// Vertex `v` as a whole deformation leaves it: muscles, jaw, then the area bound.
    fn sampled(&self, v: usize, muscles: &[f32], average: bool, turn: Option<JawTurn>) -> Vec3 {
        let p = self.before_bound(v, muscles, average, turn);
        let g = self.guard.index_of(v);
        if self.guard.is_empty() || g == NO_ROW {
            return p;
        }
        let scale = self.guard.scale_at(g as usize, &self.rest, |w| {
            if w == v {
                p
            } else {
                self.before_bound(w, muscles, average, turn)
            }
        });
        self.scaled(v, p, scale)
    }

    /// Vertex `v` after the muscles and the jaw, before the area bound, found without the
    /// per-vertex tables a guard keeps (the same arithmetic as [`BoundRig::deform`]).
    fn before_bound(
        &self,
        v: usize,
        muscles: &[f32],
        average: bool,
        turn: Option<JawTurn>,
    ) -> Vec3 {
        let mut p = match self.row_vertex.binary_search(&(v as u32)) {
            Err(_) => self.rest[v],
            Ok(row) if average => self.row_position::<true>(row, v, muscles),
            Ok(row) => self.row_position::<false>(row, v, muscles),
        };
        if let (Some(turn), Some(jaw)) = (turn, &self.jaw) {
            if let Ok(i) = jaw.vertices.binary_search(&(v as u32)) {
                p = turn.apply(p, jaw.weights[i]);
            }
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use crate::io::builtin;
    use crate::model::{Activations, Deformation};

    #[test]
    fn deforming_some_vertices_matches_a_whole_deformation_bit_for_bit() {
        let mesh = builtin::default_mesh();
        let rig = builtin::default_rig();
        let table = builtin::default_table();
        let every: Vec<u32> = (0..mesh.positions.len() as u32).collect();
        let some: Vec<u32> = every.iter().copied().filter(|v| v % 7 == 3).collect();
        for deformation in Deformation::ALL {
            let bound = deformation.bind(&rig, &mesh).unwrap();
            let mut states = vec![Activations::zero(&rig)];
            for name in ["happiness", "surprise", "anger"] {
                states.push(table.expression_activations(name, &rig).unwrap());
            }
            let mut open = Activations::zero(&rig);
            open.jaw = 3.0;
            open.muscles.iter_mut().for_each(|a| *a = 1.5);
            states.push(open);
            for act in &states {
                let (mut full, mut part) = (Vec::new(), Vec::new());
                bound.deform(act, &mut full).unwrap();
                for vertices in [&every, &some] {
                    bound.deform_at(act, vertices, &mut part).unwrap();
                    for (p, &v) in part.iter().zip(vertices.iter()) {
                        let q = full[v as usize];
                        assert_eq!(
                            p.to_array().map(f32::to_bits),
                            q.to_array().map(f32::to_bits),
                            "{deformation} vertex {v}"
                        );
                    }
                }
            }
            let n = mesh.positions.len() as u32;
            assert!(bound
                .deform_at(&states[0], &[0, n], &mut Vec::new())
                .is_err());
        }
    }
}
