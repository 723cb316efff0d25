//! The whole mesh's deformation, reading only what the activations move.
//!
//! An expression activates a few of a rig's muscles (six action units drive about a third
//! of the default rig's), and the rest add exact zeros. So [`BoundRig::deform`] goes muscle
//! by muscle over the *active* muscles' fields only, adding each displacement into its
//! vertex's sum, in the order the per-vertex rows hold them (so each sum is the one
//! [`BoundRig::row_position`] adds up, bit for bit: a skipped term is a product with zero,
//! and adding one to a sum that starts at +0 never changes it); each vertex's sum is then
//! finished (the slide, the average) by the one per-row arithmetic the partial updates
//! use. The mesh is cut into vertex ranges done in parallel on big meshes, the jaw is
//! turned in the same pass, and the area bound's two steps (every checked triangle's scale,
//! then every guarded vertex's) run in parallel ranges too.

use glam::Vec3;
use rayon::prelude::*;

use super::{BoundRig, JawTurn, PARALLEL_MIN_VERTICES};
use crate::model::muscle::MuscleKind;

/// Checked triangles per parallel task of the area bound.
const TRIANGLE_CHUNK: usize = 8_192;

/// Vertices per parallel task of the whole deformation: the work gathers where the active
/// muscles are (the mouth, the brows), so ranges this small (13 on a 108k head) keep both
/// cores busy to the end.
const VERTEX_CHUNK: usize = 8_192;

/// One range's running sums: per row, the sliding muscles' sum (or the only sum when
/// nothing slides), the sphincters' sum, and the count of active muscles.
#[derive(Default)]
struct Sums {
    first: Vec<Vec3>,
    second: Vec<Vec3>,
    active: Vec<u32>,
}

thread_local! {
    /// Per thread: the sums of the range it works on, kept so a deformation allocates
    /// nothing once they are sized.
    static SUMS: std::cell::RefCell<Sums> = std::cell::RefCell::default();
    /// Per thread: which items of the range it works on an active muscle (or the jaw) may
    /// have moved under the area bound.
    static MARKS: std::cell::RefCell<Vec<bool>> = std::cell::RefCell::default();
    /// The muscles (then the jaw, numbered after them) active in this deformation.
    static ACTIVE: std::cell::RefCell<Vec<usize>> = std::cell::RefCell::default();
}

impl BoundRig {
    /// Every vertex of the mesh deformed by `muscles` (validated activations) and the jaw
    /// turn, before the area bound, into `out` (the mesh's size).
    pub(super) fn deform_whole(&self, muscles: &[f32], turn: Option<JawTurn>, out: &mut [Vec3]) {
        let chunk = (out.len() >= PARALLEL_MIN_VERTICES).then_some(VERTEX_CHUNK);
        self.deform_ranges(muscles, turn, out, chunk);
    }

    /// [`BoundRig::deform_whole`] in parallel ranges of `chunk` vertices (one range when
    /// `None`): every range gives the same bits.
    fn deform_ranges(
        &self,
        muscles: &[f32],
        turn: Option<JawTurn>,
        out: &mut [Vec3],
        chunk: Option<usize>,
    ) {
        in_ranges(out, chunk, |start, range| {
            SUMS.with_borrow_mut(|sums| self.fill_sparse(start, range, muscles, sums));
            self.turn_range(start, range, turn);
        });
    }

    /// The muscles in the order a row's entries hold them, with whether each adds to a
    /// row's second sum: with the slide, the sliding muscles first and the sphincters after
    /// (as `build_rows` lays them out), else all in rig order into one sum.
    fn entry_order(&self) -> impl Iterator<Item = (usize, bool)> + '_ {
        let slides = self.skin.slide > 0.0;
        let late =
            move |m: usize| slides && matches!(self.rig.muscles[m].kind, MuscleKind::Sphincter(_));
        // A row without a patch (no slide) adds everything into one sum.
        let split = !self.patches.is_empty();
        [false, true].into_iter().flat_map(move |pass| {
            (0..self.fields.len())
                .filter(move |&m| late(m) == pass)
                .map(move |m| (m, split && pass))
        })
    }

    /// The vertices `start..start + out.len()` moved by the active muscles (no jaw, no
    /// area bound): rest positions copied where no muscle reaches, each row's sum from its
    /// active muscles' displacements, finished by [`BoundRig::finish_row`].
    fn fill_sparse(&self, start: usize, out: &mut [Vec3], muscles: &[f32], sums: &mut Sums) {
        let end = start + out.len();
        out.copy_from_slice(&self.rest[start..end]);
        let first = self.row_vertex.partition_point(|&v| (v as usize) < start);
        let last = self.row_vertex.partition_point(|&v| (v as usize) < end);
        let rows = last - first;
        let average = self.rig.combine == crate::model::rig::Combine::Average;
        for list in [&mut sums.first, &mut sums.second] {
            list.clear();
            list.resize(rows, Vec3::ZERO);
        }
        sums.active.clear();
        sums.active.resize(rows, 0);
        for (m, second) in self.entry_order() {
            let a = muscles[m];
            if a == 0.0 {
                continue;
            }
            let (list, field) = (&self.muscle_rows[m], &self.fields[m]);
            let from = list.partition_point(|&r| (r as usize) < first);
            let to = list.partition_point(|&r| (r as usize) < last);
            let target = if second {
                &mut sums.second
            } else {
                &mut sums.first
            };
            for (&row, &d) in list[from..to].iter().zip(&field.displacements[from..to]) {
                let r = row as usize - first;
                target[r] += d * a;
                sums.active[r] += 1;
            }
        }
        for (r, &v) in self.row_vertex[first..last].iter().enumerate() {
            let (row, v) = (first + r, v as usize);
            let (a, b, n) = (sums.first[r], sums.second[r], sums.active[r]);
            if n == 0 {
                // Nothing active moves it: a zero sum keeps the rest position (copied).
                continue;
            }
            out[v - start] = if average {
                self.finish_row::<true>(row, v, a, b, n)
            } else {
                self.finish_row::<false>(row, v, a, b, n)
            };
        }
    }

    /// Turns the jaw's vertices among `start..start + out.len()` by `turn`.
    fn turn_range(&self, start: usize, out: &mut [Vec3], turn: Option<JawTurn>) {
        let (Some(jaw), Some(turn)) = (&self.jaw, turn) else {
            return;
        };
        let end = start + out.len();
        let from = jaw.vertices.partition_point(|&v| (v as usize) < start);
        let to = jaw.vertices.partition_point(|&v| (v as usize) < end);
        for (&v, &w) in jaw.vertices[from..to].iter().zip(&jaw.weights[from..to]) {
            let p = &mut out[v as usize - start];
            *p = turn.apply(*p, w);
        }
    }

    /// Turns every jaw vertex of `out` by `turn` (after the area bound).
    pub(super) fn turn_whole(&self, turn: Option<JawTurn>, out: &mut [Vec3]) {
        let chunk = (out.len() >= PARALLEL_MIN_VERTICES).then_some(VERTEX_CHUNK);
        in_ranges(out, chunk, |start, range| {
            self.turn_range(start, range, turn)
        });
    }

    /// The area bound over a whole deformation: every checked triangle's scale from the
    /// positions before the bound (`out`: the muscles and the slide, not the jaw), then each
    /// guarded vertex's displacement scaled by the mean of its triangles' (what
    /// `Guard::triangle_scales` and `Guard::vertex_scale` give), in parallel ranges on big
    /// meshes.
    ///
    /// Only the triangles an active muscle may have moved are computed (`Guard::rescale`,
    /// what a partial update recomputes): every other one has its vertices at rest, bit for
    /// bit, and so the scale 1 exactly.
    pub(super) fn bound_areas(&self, muscles: &[f32], out: &mut [Vec3]) {
        let big = out.len() >= PARALLEL_MIN_VERTICES;
        let chunks = big.then_some((TRIANGLE_CHUNK, VERTEX_CHUNK));
        let jaw = self.fields.len();
        ACTIVE.with_borrow_mut(|active| {
            active.clear();
            // the jaw turns after the bound: its triangles keep their scale for it
            active.extend((0..self.guard.rescale.len()).filter(|&k| k != jaw && muscles[k] != 0.0));
            self.bound_ranges(out, active, chunks);
        });
    }

    /// [`BoundRig::bound_areas`] in parallel ranges of `(triangles, vertices)` (one range
    /// each when `None`), computing the scales of the triangles the `active` muscles (and
    /// jaw) rescale and settling the guarded vertices they settle: every range gives the
    /// same bits. Each range marks its own items from the sorted lists, so nothing runs
    /// on one thread over the whole mesh.
    fn bound_ranges(&self, out: &mut [Vec3], active: &[usize], chunks: Option<(usize, usize)>) {
        super::SCRATCH.with_borrow_mut(|(_, scales)| {
            // Sized once; each range sets its own scales (1 where nothing moved).
            scales.resize(self.guard.triangles.len(), 1.0);
            let at: &[Vec3] = out;
            in_ranges(scales, chunks.map(|c| c.0), |start, range| {
                range.fill(1.0);
                MARKS.with_borrow_mut(|marks| {
                    let lists = active.iter().map(|&k| &self.guard.rescale[k][..]);
                    mark_range(marks, start, range.len(), lists, |t| t as usize - start);
                    for (k, s) in range.iter_mut().enumerate() {
                        if marks[k] {
                            *s = self.triangle_scale_at(start + k, at);
                        }
                    }
                });
            });
            let scales: &[f32] = scales;
            in_ranges(out, chunks.map(|c| c.1), |start, range| {
                let vertices = &self.guard.vertices;
                let end = start + range.len();
                let from = vertices.partition_point(|&v| (v as usize) < start);
                let to = vertices.partition_point(|&v| (v as usize) < end);
                MARKS.with_borrow_mut(|marks| {
                    // The settle lists hold mesh vertices, sorted: those in this range are
                    // the guarded vertices `from..to`.
                    let lists = active.iter().map(|&k| &self.guard.settle[k][..]);
                    let guarded = |v: u32| self.guard.index_of(v as usize) as usize - from;
                    mark_range(marks, start, range.len(), lists, guarded);
                    for (g, &v) in vertices[from..to].iter().enumerate() {
                        // The others' triangles all have the scale 1: so has their mean.
                        if !marks[g] {
                            continue;
                        }
                        let v = v as usize;
                        let scale = self.guard.vertex_scale(from + g, scales);
                        range[v - start] = self.scaled(v, range[v - start], scale);
                    }
                });
            });
        });
    }

    /// Checked triangle `t`'s scale for the positions `at` before the bound (the per
    /// triangle arithmetic of `Guard::triangle_scales`).
    #[inline]
    fn triangle_scale_at(&self, t: usize, at: &[Vec3]) -> f32 {
        let [i0, i1, i2] = self.guard.triangles[t].map(|i| i as usize);
        let p0 = at[i0] - self.rest[i0];
        let d1 = at[i1] - self.rest[i1] - p0;
        let d2 = at[i2] - self.rest[i2] - p0;
        self.guard.triangle_scale(t, d1, d2)
    }
}

/// Runs `f(start, range)` over `out` cut into ranges of `chunk` items on the rayon pool, or
/// over all of it at once when `chunk` is `None`.
fn in_ranges<T: Send>(out: &mut [T], chunk: Option<usize>, f: impl Fn(usize, &mut [T]) + Sync) {
    match chunk {
        Some(chunk) => out
            .par_chunks_mut(chunk.max(1))
            .enumerate()
            .for_each(|(i, range)| f(i * chunk.max(1), range)),
        None => f(0, out),
    }
}

/// Clears `marks` to `len` items and sets, for every sorted list, the slot `slot(item)`
/// of each of its items in `start..start + len` (the lists' items in that range map to
/// slots below `len`).
fn mark_range<'a>(
    marks: &mut Vec<bool>,
    start: usize,
    len: usize,
    lists: impl Iterator<Item = &'a [u32]>,
    slot: impl Fn(u32) -> usize,
) {
    marks.clear();
    marks.resize(len, false);
    let end = start + len;
    for list in lists {
        let from = list.partition_point(|&i| (i as usize) < start);
        let to = list.partition_point(|&i| (i as usize) < end);
        list[from..to].iter().for_each(|&i| marks[slot(i)] = true);
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::io::builtin;
    use crate::model::{Activations, Deformation};

    /// The whole deformation cut into ranges of any size (as the rayon pool runs a big
    /// mesh's) gives the bits of one range, the area bound included, for every model.
    #[test]
    fn ranges_of_any_size_give_the_same_bits() {
        let mesh = builtin::default_mesh();
        let rig = builtin::default_rig();
        let mut act = builtin::default_table()
            .expression_activations("happiness", &rig)
            .unwrap();
        act.jaw = 2.5;
        let bits = |p: &[Vec3]| -> Vec<[u32; 3]> {
            p.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
        };
        for deformation in Deformation::ALL {
            let bound = deformation.bind(&rig, &mesh).unwrap();
            let turn = bound.jaw.as_ref().and(bound.jaw_turn(act.jaw));
            let mut whole = Vec::new();
            bound.deform(&act, &mut whole).unwrap();
            for chunk in [1, 7, 1000] {
                let mut out = vec![Vec3::ZERO; mesh.positions.len()];
                bound.deform_ranges(&act.muscles, turn, &mut out, Some(chunk));
                if !bound.guard.is_empty() {
                    // what every muscle and the jaw may move computed, as if all were active
                    let every: Vec<usize> = (0..bound.guard.rescale.len()).collect();
                    bound.bound_ranges(&mut out, &every, Some((chunk, chunk + 3)));
                }
                assert_eq!(bits(&out), bits(&whole), "{deformation}, ranges of {chunk}");
            }
            // at rest, every vertex is where it was, bit for bit
            let mut rest = Vec::new();
            bound.deform(&Activations::zero(&rig), &mut rest).unwrap();
            assert_eq!(bits(&rest), bits(&mesh.positions), "{deformation} at rest");
        }
    }
}
