//! Deforming only some vertices: the level of detail a big mesh is drawn with.
//!
//! The editor draws a simplified copy of a big mesh whose vertices are vertices of the full
//! mesh (`render::Lod`); [`BoundRig::deform_at`] gives exactly what [`BoundRig::deform`]
//! gives at those vertices, at the cost of those vertices (and, under the skin's area bound,
//! of the few neighbours their scale reads), not of the whole mesh.

use glam::Vec3;
use rayon::prelude::*;

use super::{BoundRig, NO_ROW, PARALLEL_CHUNK};
use crate::model::activations::{ActivationError, Activations};
use crate::model::rig::Combine;

/// Lists of at least this many vertices are deformed in parallel chunks.
const PARALLEL_MIN: usize = 8_192;

/// What deforming a fixed list of vertices reads, found once: each vertex's CSR row and jaw
/// weight, and, for the vertices under the skin's area bound, their checked triangles'
/// vertices. Valid for the [`BoundRig`] it was made by until that is bound again.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Sampler {
    /// The vertices whose positions before the area bound are needed, sorted: the list and
    /// the vertices of its guarded vertices' checked triangles.
    needed: Vec<u32>,
    /// Per needed vertex: its CSR row or [`NO_ROW`], and its jaw weight.
    rows: Vec<u32>,
    jaw: Vec<f32>,
    /// Per listed vertex: its place in `needed`.
    at: Vec<u32>,
    /// Per listed vertex, its checked triangles (CSR): the triangle, and its vertices'
    /// places in `needed`.
    tri_start: Vec<u32>,
    tris: Vec<(u32, [u32; 3])>,
}

impl Sampler {
    /// Number of vertices listed.
    pub fn len(&self) -> usize {
        self.at.len()
    }

    /// True when no vertex is listed.
    pub fn is_empty(&self) -> bool {
        self.at.is_empty()
    }

    /// Number of vertices whose positions a deformation computes: the list and the
    /// vertices its guarded vertices' scales read.
    pub fn reads(&self) -> usize {
        self.needed.len()
    }
}

impl BoundRig {
    /// The positions [`BoundRig::deform`] gives at `vertices`, bit for bit, into `out`
    /// (resized to `vertices.len()`). A vertex number beyond the mesh is an error. For a
    /// list deformed again and again, make its [`BoundRig::sampler`] once.
    pub fn deform_at(
        &self,
        act: &Activations,
        vertices: &[u32],
        out: &mut Vec<Vec3>,
    ) -> Result<(), ActivationError> {
        let sampler = self.sampler(vertices)?;
        self.deform_sampled(act, &sampler, out)
    }

    /// Prepares deforming `vertices` only ([`BoundRig::deform_sampled`]).
    pub fn sampler(&self, vertices: &[u32]) -> Result<Sampler, ActivationError> {
        let n = self.rest.len();
        if let Some(&v) = vertices.iter().find(|&&v| v as usize >= n) {
            return Err(ActivationError::VertexCount {
                given: v as usize + 1,
                expected: n,
            });
        }
        let guarded = |v: u32| {
            let g = self.guard.index_of(v as usize);
            (g != NO_ROW).then(|| self.guard.triangles_of(g as usize))
        };
        let mut needed = vertices.to_vec();
        for &v in vertices {
            for &t in guarded(v).unwrap_or(&[]) {
                needed.extend(self.guard.triangles[t as usize]);
            }
        }
        needed.par_sort_unstable();
        needed.dedup();
        let place = |v: u32| needed.binary_search(&v).unwrap_or(0) as u32;
        let rows = needed
            .par_iter()
            .map(|v| {
                self.row_vertex
                    .binary_search(v)
                    .map_or(NO_ROW, |r| r as u32)
            })
            .collect();
        let jaw = needed
            .par_iter()
            .map(|v| match &self.jaw {
                Some(jaw) => jaw
                    .vertices
                    .binary_search(v)
                    .map_or(0.0, |i| jaw.weights[i]),
                None => 0.0,
            })
            .collect();
        let mut tri_start = vec![0u32];
        let mut tris = Vec::new();
        for &v in vertices {
            for &t in guarded(v).unwrap_or(&[]) {
                tris.push((t, self.guard.triangles[t as usize].map(place)));
            }
            tri_start.push(tris.len() as u32);
        }
        let at = vertices.iter().map(|&v| place(v)).collect();
        Ok(Sampler {
            needed,
            rows,
            jaw,
            at,
            tri_start,
            tris,
        })
    }

    /// [`BoundRig::deform_at`] of the vertices `sampler` lists (made by this rig as bound
    /// now): their positions, bit for bit those of a whole deformation, into `out`.
    pub fn deform_sampled(
        &self,
        act: &Activations,
        sampler: &Sampler,
        out: &mut Vec<Vec3>,
    ) -> Result<(), ActivationError> {
        act.validate(&self.rig)?;
        let average = self.rig.combine == Combine::Average;
        let turn = self.jaw.as_ref().and(self.jaw_turn(act.jaw));
        let muscles = &act.muscles[..];
        let before_one = |i: usize| {
            let v = sampler.needed[i] as usize;
            self.moved(v, sampler.rows[i], sampler.jaw[i], muscles, average, turn)
        };
        let mut before = vec![Vec3::ZERO; sampler.needed.len()];
        chunked(&mut before, |start, chunk| {
            for (k, p) in chunk.iter_mut().enumerate() {
                *p = before_one(start + k);
            }
        });
        out.clear();
        out.resize(sampler.len(), Vec3::ZERO);
        let after_one = |k: usize| self.bounded(sampler, &before, k);
        chunked(out, |start, chunk| {
            for (k, p) in chunk.iter_mut().enumerate() {
                *p = after_one(start + k);
            }
        });
        Ok(())
    }

    /// Listed vertex `k` after the area bound, from the positions `before` it.
    #[inline]
    fn bounded(&self, sampler: &Sampler, before: &[Vec3], k: usize) -> Vec3 {
        let i = sampler.at[k] as usize;
        let v = sampler.needed[i] as usize;
        let p = before[i];
        let tris = &sampler.tris[sampler.tri_start[k] as usize..sampler.tri_start[k + 1] as usize];
        if tris.is_empty() {
            return p;
        }
        let moved = |j: u32| before[j as usize] - self.rest[sampler.needed[j as usize] as usize];
        let mut sum = 0.0f32;
        for &(t, [a, b, c]) in tris {
            let p0 = moved(a);
            let d1 = moved(b) - p0;
            let d2 = moved(c) - p0;
            sum += self.guard.triangle_scale(t as usize, d1, d2);
        }
        self.scaled(v, p, sum / tris.len() as f32)
    }
}

/// Runs `f(start, chunk)` over `out` in chunks, in parallel when it is long.
fn chunked(out: &mut [Vec3], f: impl Fn(usize, &mut [Vec3]) + Sync) {
    if out.len() >= PARALLEL_MIN {
        out.par_chunks_mut(PARALLEL_CHUNK)
            .enumerate()
            .for_each(|(i, chunk)| f(i * PARALLEL_CHUNK, chunk));
    } else {
        f(0, out);
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
