//! Deforming only some vertices: the level of detail a big mesh is drawn with.
//!
//! The editor draws a simplified copy of a big mesh whose vertices are vertices of the full
//! mesh (`render::Lod`); [`BoundRig::deform_at`] gives exactly what [`BoundRig::deform`]
//! gives at those vertices, at the cost of those vertices (and, under the skin's area bound,
//! of the few neighbours their scale reads), not of the whole mesh; and
//! [`BoundRig::update_sampled`] keeps such a list in step with a change of one muscle at
//! the cost of the listed vertices that muscle reaches.

use glam::Vec3;
use rayon::prelude::*;

use super::{BoundRig, JawTurn, NO_ROW, PARALLEL_CHUNK};
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
    /// Per muscle, then the jaw: the places in `needed` whose position before the area
    /// bound it moves (their CSR rows hold its entry, or they have a jaw weight).
    moves: Vec<Vec<u32>>,
    /// Per muscle, then the jaw: the listed vertices whose position it may change (moved
    /// by it, or guarded with a checked triangle that it moves).
    changes: Vec<Vec<u32>>,
}

/// A sampled deformation kept between changes ([`BoundRig::deform_sampled_pose`]), so that
/// a change of one muscle recomputes only the listed vertices it reaches
/// ([`BoundRig::update_sampled`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SampledPose {
    /// Per needed vertex of the sampler: its position before the area bound.
    before: Vec<Vec3>,
    /// Per listed vertex: its deformed position.
    positions: Vec<Vec3>,
}

impl SampledPose {
    /// The listed vertices' deformed positions, in the sampler's order (empty before the
    /// first deformation).
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }
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
        // a split vertex's copy takes its lead's position
        let leads: Vec<u32> = vertices.iter().map(|&v| self.lead(v)).collect();
        let vertices = &leads[..];
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
        let mut sampler = Sampler {
            needed,
            rows,
            jaw,
            at,
            tri_start,
            tris,
            moves: Vec::new(),
            changes: Vec::new(),
        };
        sampler.moves = self.sampled_moves(&sampler);
        sampler.changes = sampler
            .moves
            .par_iter()
            .map(|moved| sampler.reached(moved))
            .collect();
        Ok(sampler)
    }

    /// Per muscle, then the jaw: the places in `sampler.needed` it moves.
    fn sampled_moves(&self, sampler: &Sampler) -> Vec<Vec<u32>> {
        let mut moves = vec![Vec::new(); self.fields.len() + 1];
        for (i, &row) in sampler.rows.iter().enumerate() {
            if row == NO_ROW {
                continue;
            }
            let span =
                self.row_start[row as usize] as usize..self.row_start[row as usize + 1] as usize;
            for e in &self.entries[span] {
                if let Some(list) = moves.get_mut(e.muscle as usize) {
                    list.push(i as u32);
                }
            }
        }
        if let Some(jaw) = moves.last_mut() {
            jaw.extend((0..sampler.jaw.len() as u32).filter(|&i| sampler.jaw[i as usize] > 0.0));
        }
        for list in &mut moves {
            list.dedup();
        }
        moves
    }

    /// [`BoundRig::deform_at`] of the vertices `sampler` lists (made by this rig as bound
    /// now): their positions, bit for bit those of a whole deformation, into `out`.
    pub fn deform_sampled(
        &self,
        act: &Activations,
        sampler: &Sampler,
        out: &mut Vec<Vec3>,
    ) -> Result<(), ActivationError> {
        let mut pose = SampledPose {
            before: Vec::new(),
            positions: std::mem::take(out),
        };
        let done = self.deform_sampled_pose(act, sampler, &mut pose);
        *out = pose.positions;
        done
    }

    /// [`BoundRig::deform_sampled`] into `pose`, kept for [`BoundRig::update_sampled`].
    pub fn deform_sampled_pose(
        &self,
        act: &Activations,
        sampler: &Sampler,
        pose: &mut SampledPose,
    ) -> Result<(), ActivationError> {
        act.validate(&self.rig)?;
        let average = self.rig.combine == Combine::Average;
        let turn = self.jaw.as_ref().and(self.jaw_turn(act.jaw));
        let muscles = &act.muscles[..];
        let before_one = |i: usize| {
            let v = sampler.needed[i] as usize;
            self.moved(v, sampler.rows[i], sampler.jaw[i], muscles, average, None)
        };
        let SampledPose { before, positions } = pose;
        before.clear();
        before.resize(sampler.needed.len(), Vec3::ZERO);
        chunked(before, |start, chunk| {
            for (k, p) in chunk.iter_mut().enumerate() {
                *p = before_one(start + k);
            }
        });
        positions.clear();
        positions.resize(sampler.len(), Vec3::ZERO);
        let after_one = |k: usize| self.bounded(sampler, before, k, turn);
        chunked(positions, |start, chunk| {
            for (k, p) in chunk.iter_mut().enumerate() {
                *p = after_one(start + k);
            }
        });
        Ok(())
    }

    /// Brings `pose` to `act` after the muscles `changed` (indices; the muscle count stands
    /// for the jaw) changed, recomputing only the vertices they reach.
    ///
    /// `pose` must hold [`BoundRig::deform_sampled_pose`] of `sampler` by activations that
    /// differ from `act` in those muscles only; afterwards it holds that of `act`, bit for
    /// bit. A pose of another size is deformed whole.
    pub fn update_sampled(
        &self,
        act: &Activations,
        changed: &[usize],
        sampler: &Sampler,
        pose: &mut SampledPose,
    ) -> Result<(), ActivationError> {
        act.validate(&self.rig)?;
        let fits =
            pose.before.len() == sampler.needed.len() && pose.positions.len() == sampler.len();
        if !fits || changed.iter().any(|&k| k >= sampler.moves.len()) {
            return self.deform_sampled_pose(act, sampler, pose);
        }
        let average = self.rig.combine == Combine::Average;
        let turn = self.jaw.as_ref().and(self.jaw_turn(act.jaw));
        let muscles = &act.muscles[..];
        // Every moved position first: a bound vertex reads its neighbours' positions.
        for &k in changed {
            for &i in &sampler.moves[k] {
                let i = i as usize;
                let v = sampler.needed[i] as usize;
                pose.before[i] =
                    self.moved(v, sampler.rows[i], sampler.jaw[i], muscles, average, None);
            }
        }
        for &k in changed {
            for &l in &sampler.changes[k] {
                pose.positions[l as usize] = self.bounded(sampler, &pose.before, l as usize, turn);
            }
        }
        Ok(())
    }

    /// Listed vertex `k` after the area bound, from the positions `before` it (muscles and
    /// slide), then turned by the jaw.
    #[inline]
    fn bounded(&self, sampler: &Sampler, before: &[Vec3], k: usize, turn: Option<JawTurn>) -> Vec3 {
        let i = sampler.at[k] as usize;
        let v = sampler.needed[i] as usize;
        let p = before[i];
        let tris = &sampler.tris[sampler.tri_start[k] as usize..sampler.tri_start[k + 1] as usize];
        if tris.is_empty() {
            return Self::turned(p, sampler.jaw[i], turn);
        }
        let moved = |j: u32| before[j as usize] - self.rest[sampler.needed[j as usize] as usize];
        let mut sum = 0.0f32;
        for &(t, [a, b, c]) in tris {
            let p0 = moved(a);
            let d1 = moved(b) - p0;
            let d2 = moved(c) - p0;
            sum += self.guard.triangle_scale(t as usize, d1, d2);
        }
        Self::turned(
            self.scaled(v, p, sum / tris.len() as f32),
            sampler.jaw[i],
            turn,
        )
    }
}

impl Sampler {
    /// The listed vertices whose position may change when the needed vertices at the places
    /// `moved` move: those among them, and the guarded ones reading them.
    fn reached(&self, moved: &[u32]) -> Vec<u32> {
        let mut marked = vec![false; self.needed.len()];
        moved.iter().for_each(|&i| marked[i as usize] = true);
        let hit = |i: u32| marked[i as usize];
        (0..self.at.len())
            .filter(|&k| {
                let tris = &self.tris[self.tri_start[k] as usize..self.tri_start[k + 1] as usize];
                hit(self.at[k]) || tris.iter().any(|(_, t)| t.iter().any(|&i| hit(i)))
            })
            .map(|k| k as u32)
            .collect()
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
    use super::SampledPose;
    use crate::io::builtin;
    use crate::model::{Activations, BoundRig, Deformation};

    /// From `act`, each muscle and the jaw changed in turn: the kept pose updated by the
    /// change alone is the whole deformation's at `vertices`, bit for bit.
    fn update_one_muscle_at_a_time(bound: &BoundRig, act: &Activations, vertices: &[u32]) {
        let sampler = bound.sampler(vertices).unwrap();
        let mut pose = SampledPose::default();
        bound.deform_sampled_pose(act, &sampler, &mut pose).unwrap();
        let mut act = act.clone();
        let mut full = Vec::new();
        let jaw = act.muscles.len();
        for k in 0..=jaw {
            if k == jaw {
                act.jaw = 3.0;
            } else {
                act.muscles[k] = 1.0 + 0.5 * act.muscles[k];
            }
            bound
                .update_sampled(&act, &[k], &sampler, &mut pose)
                .unwrap();
            bound.deform(&act, &mut full).unwrap();
            for (p, &v) in pose.positions().iter().zip(vertices) {
                let q = full[v as usize];
                assert_eq!(
                    p.to_array().map(f32::to_bits),
                    q.to_array().map(f32::to_bits),
                    "{:?} vertex {v} after muscle {k}",
                    bound.skin()
                );
            }
        }
    }

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
            update_one_muscle_at_a_time(&bound, &states[1], &some);
            let n = mesh.positions.len() as u32;
            assert!(bound
                .deform_at(&states[0], &[0, n], &mut Vec::new())
                .is_err());
        }
    }
}
