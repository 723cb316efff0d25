//! The deformation: a sparse blend of muscle fields, then the jaw.
//!
//! [`BoundRig::bind`] places a rig on a mesh once: it checks every parameter, computes each
//! muscle's [`Field`] from the rest positions and lays the fields out per vertex (a CSR table:
//! for each influenced vertex, its `(muscle, displacement)` entries). [`BoundRig::deform`] is
//! then a pure function of the activations: rest positions plus the activation-weighted
//! displacements (summed or averaged), then the weighted jaw rotation. Its cost is the number
//! of influenced `(vertex, muscle)` pairs plus one copy of the rest positions; it allocates
//! nothing once the output buffer has the mesh's size.

use std::cell::RefCell;
use std::sync::Arc;

use glam::Vec3;
use rayon::prelude::*;
use thiserror::Error;

use super::activations::{ActivationError, Activations, MUSCLE_RANGE};
use super::field::{validate_muscle, Field, InvalidParameter};
use super::mesh::{Mesh, MeshError};
use super::muscle::MuscleKind;
use super::rig::{Combine, Rig};

mod cache;
mod checks;
mod guard;
mod sample;
mod skin;
mod slide;
mod spread;
mod stretch;
mod whole;

pub use cache::{CacheParts, BIND_CODE, CACHE_PATCH_FLOATS};
use checks::{bind_jaw, check_budget, check_reach, mask_scales};
use guard::Guard;
pub use sample::{SampledPose, Sampler};
use skin::Adjacency;
pub use skin::SkinRules;
use slide::Patch;
use spread::Surface;

/// Meshes with at least this many vertices are deformed in parallel chunks.
pub const PARALLEL_MIN_VERTICES: usize = 32_768;
/// Vertices per parallel chunk.
const PARALLEL_CHUNK: usize = 16_384;

/// Largest coordinate magnitude a bound rig may reach at full activation. Far beyond any
/// face, and far enough from `f32::MAX` that sums and the jaw rotation stay finite.
pub const MAX_REACH: f64 = 1e30;

/// Why a rig cannot be placed on a mesh.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BindError {
    /// The mesh itself is unusable.
    #[error("the mesh is unusable: {0}")]
    Mesh(#[from] MeshError),
    /// A muscle parameter is out of its range or not finite.
    #[error("muscle `{muscle}`: {parameter} {message}")]
    InvalidParameter {
        /// The muscle's name.
        muscle: String,
        /// The parameter's name as written in rig files.
        parameter: &'static str,
        /// What is wrong with it.
        message: String,
    },
    /// Two muscles share a name.
    #[error("two muscles are named `{0}`; muscle names must be unique")]
    DuplicateMuscle(String),
    /// A muscle names a mirror partner the rig does not have.
    #[error("muscle `{muscle}` names `{mirror}` as its mirror, but the rig has no such muscle")]
    MissingMirror {
        /// The muscle naming the partner.
        muscle: String,
        /// The missing partner's name.
        mirror: String,
    },
    /// A jaw parameter is not finite (or the pivot lies beyond any usable coordinate).
    #[error("jaw: {parameter} {value} is not a usable finite value")]
    JawParameter {
        /// `pivot` or `degrees_per_unit`.
        parameter: &'static str,
        /// The value as written.
        value: String,
    },
    /// A jaw weight lies outside 0.0-1.0 or is not finite.
    #[error("jaw: vertex {vertex} has weight {weight}, outside 0.0 to 1.0")]
    JawWeight {
        /// The vertex.
        vertex: u32,
        /// The weight given.
        weight: f32,
    },
    /// A jaw weight names a vertex the mesh does not have.
    #[error("jaw: vertex {vertex} does not exist; the mesh has {count} vertices")]
    JawVertex {
        /// The vertex.
        vertex: u32,
        /// Number of vertices in the mesh.
        count: usize,
    },
    /// A jaw vertex is listed twice.
    #[error("jaw: vertex {0} is listed twice")]
    JawDuplicateVertex(u32),
    /// A mask is malformed: an unknown muscle, a vertex out of range or repeated, a weight
    /// outside 0.0-1.0.
    #[error("mask {mask}: {message}")]
    Mask {
        /// The mask's position in the rig's list (0-based).
        mask: usize,
        /// What is wrong.
        message: String,
    },
    /// The rig and mesh together have more `(vertex, muscle)` pairs than can be indexed.
    #[error("the muscles influence more than {} (vertex, muscle) pairs", u32::MAX)]
    TooManyPairs,
    /// The fields would take more memory than grimace allows ([`MAX_INFLUENCES`]).
    #[error(
        "the muscles move more than {} (vertex, muscle) pairs of this {vertices}-vertex mesh \
         (passed at muscle `{muscle}`), about 1.2 GB bound; use fewer or smaller muscles, or a \
         smaller mesh",
        MAX_INFLUENCES
    )]
    TooManyInfluences {
        /// The muscle at which the count passed the limit.
        muscle: String,
        /// The mesh's vertex count.
        vertices: usize,
    },
    /// The skin rules are out of range.
    #[error("{0}")]
    Skin(String),
    /// A muscle would move vertices to astronomically large coordinates.
    #[error("muscle `{muscle}` moves vertex {vertex} beyond any usable coordinate")]
    OutOfReach {
        /// The muscle's name.
        muscle: String,
        /// The vertex.
        vertex: u32,
    },
}

impl From<InvalidParameter> for BindError {
    fn from(e: InvalidParameter) -> Self {
        BindError::InvalidParameter {
            muscle: e.muscle,
            parameter: e.parameter,
            message: e.message,
        }
    }
}

/// One `(muscle, displacement)` entry of a vertex's CSR row: 16 bytes, read in one stream.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry {
    displacement: Vec3,
    muscle: u32,
}

/// The jaw prepared for evaluation.
#[derive(Debug, Clone, PartialEq)]
struct BoundJaw {
    pivot: Vec3,
    /// Unit axis of the turn; exactly `Vec3::X` for the usual jaw.
    axis: Vec3,
    radians_per_unit: f64,
    /// Translation per unit of activation (the slide per degree times the degrees per unit).
    slide_per_unit: Vec3,
    /// Jaw vertices with a non-zero weight, sorted.
    vertices: Vec<u32>,
    weights: Vec<f32>,
    /// The CSR row of each jaw vertex, [`NO_ROW`] when no muscle moves it.
    rows: Vec<u32>,
}

/// Marks a vertex that no muscle moves (it has no CSR row).
const NO_ROW: u32 = u32::MAX;

/// The jaw motion of one deformation: `cos` and `sin` of the jaw angle, and the slide.
#[derive(Debug, Clone, Copy)]
struct JawTurn {
    pivot: Vec3,
    cos: f32,
    sin: f32,
    /// The rotation matrix when the axis is not the x axis.
    general: Option<glam::Mat3>,
    /// The translation after the turn; `None` for the paper's pure rotation, which keeps
    /// its arithmetic bit for bit.
    shift: Option<Vec3>,
}

impl JawTurn {
    /// Eqs. 16-19: rotate `p` about the x axis through the pivot, slide it, then blend by
    /// `weight`. A jaw with another axis turns about it instead.
    #[inline]
    fn apply(&self, p: Vec3, weight: f32) -> Vec3 {
        if self.general.is_some() || self.shift.is_some() {
            return self.apply_general(p, weight);
        }
        let y = p.y - self.pivot.y;
        let z = p.z - self.pivot.z;
        let ry = self.pivot.y + (self.cos * y - self.sin * z);
        let rz = self.pivot.z + (self.sin * y + self.cos * z);
        let keep = 1.0 - weight;
        Vec3::new(p.x, ry * weight + p.y * keep, rz * weight + p.z * keep)
    }

    /// A turn about any axis and the slide after it, blended by `weight`.
    fn apply_general(&self, p: Vec3, weight: f32) -> Vec3 {
        let d = p - self.pivot;
        let turned = match &self.general {
            Some(rotation) => *rotation * d,
            None => Vec3::new(
                d.x,
                self.cos * d.y - self.sin * d.z,
                self.sin * d.y + self.cos * d.z,
            ),
        };
        let moved = self.pivot + turned + self.shift.unwrap_or(Vec3::ZERO);
        moved * weight + p * (1.0 - weight)
    }
}

/// A rig placed on a mesh, with every muscle's field precomputed.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundRig {
    rig: Rig,
    rest: Vec<Vec3>,
    fields: Vec<Field>,
    /// CSR rows: the influenced vertices, sorted.
    row_vertex: Vec<u32>,
    /// CSR row starts into the entry arrays (`row_vertex.len() + 1` items).
    row_start: Vec<u32>,
    /// The CSR entries, rows one after another, each row in muscle order.
    entries: Vec<Entry>,
    /// Per muscle: the CSR rows of the vertices in its field.
    muscle_rows: Vec<Vec<u32>>,
    /// Per CSR row: the jaw weight of its vertex (0 when not a jaw vertex).
    row_jaw_weight: Vec<f32>,
    jaw: Option<BoundJaw>,
    /// The rules that keep the skin on the face.
    skin: SkinRules,
    /// Per CSR row: the rest surface around its vertex (empty when nothing slides).
    patches: Vec<Patch>,
    /// Per CSR row: where its sphincter entries start (empty when nothing slides).
    row_split: Vec<u32>,
    /// The triangles checked against the area bound.
    guard: Guard,
    /// Per vertex: its CSR row or [`NO_ROW`] (empty without a guard).
    vertex_row: Vec<u32>,
    /// Per vertex: its jaw weight (empty without a guard).
    vertex_jaw: Vec<f32>,
    /// The mesh, kept when the skin rules are on so a rebind can fit them again (shared
    /// with the caller's after [`BoundRig::share_mesh`]).
    skin_mesh: Option<Arc<Mesh>>,
    /// The rest surface's operators, kept when the fields are spread (a rebind spreads the
    /// changed fields again).
    surface: Option<Arc<Surface>>,
    /// The spread length the fields were spread by (0 when they are not).
    spread_length: f64,
    /// Copies of split vertices, in no triangle, each moved with its lead ([`Mesh::followers`]).
    followers: Vec<[u32; 2]>,
}

thread_local! {
    /// Per thread: positions before the area bound (partial updates) and the scales of the
    /// guarded vertices, kept so that a deformation allocates nothing once they are sized.
    static SCRATCH: RefCell<(Vec<Vec3>, Vec<f32>)> = const { RefCell::new((Vec::new(), Vec::new())) };
}

impl BoundRig {
    /// Checks the rig against the mesh and precomputes every muscle's field: the paper's
    /// deformation, linear in the activations ([`SkinRules::PAPER`]).
    pub fn bind(rig: &Rig, mesh: &Mesh) -> Result<BoundRig, BindError> {
        BoundRig::bind_with(rig, mesh, SkinRules::PAPER)
    }

    /// [`BoundRig::bind`] with skin rules that keep displaced skin on the face
    /// ([`SkinRules::DEFAULT`]: what the editor, `grimace play` and `grimace render` use).
    pub fn bind_with(rig: &Rig, mesh: &Mesh, skin: SkinRules) -> Result<BoundRig, BindError> {
        skin.check().map_err(BindError::Skin)?;
        mesh.validate()?;
        checks::validate_names(rig)?;
        for muscle in &rig.muscles {
            validate_muscle(muscle)?;
        }
        let rest = mesh.positions.clone();
        check_budget(rig, &rest)?;
        // the mesh's edges, found once for both of the stretch limit's caps
        let adjacency = (skin.stretch > 0.0).then(|| Adjacency::of(mesh));
        let mut jaw = bind_jaw(rig, rest.len())?;
        if let (Some(jaw), Some(adjacency)) = (&mut jaw, &adjacency) {
            stretch::limit_jaw(jaw, &rest, adjacency, skin.stretch);
        }
        let scales = mask_scales(rig, rest.len())?;
        // each muscle's field reads the rest mesh only: one muscle per task, in rig order
        let fields: Vec<Field> = rig
            .muscles
            .par_iter()
            .zip(&scales)
            .map(|(m, scale)| {
                let field = Field::of(&m.kind, &rest);
                match scale {
                    Some(scale) => field.scaled(scale),
                    None => field,
                }
            })
            .collect();
        let surface = (skin.spread > 0.0).then(|| Arc::new(Surface::of(mesh)));
        let fields = match &surface {
            Some(surface) => {
                let length = spread::spread_length(rig, skin.spread);
                spread::spread_all(surface, rig, fields, &scales, length)
            }
            None => fields,
        };
        let fields = match (stretch::Limit::of(skin.stretch), &adjacency) {
            (Some(limit), Some(adjacency)) => {
                let all: Vec<usize> = (0..fields.len()).collect();
                stretch::limit_all(rig, &fields, &all, &rest, adjacency, limit)
            }
            _ => fields,
        };
        check_reach(rig, &rest, &fields)?;
        let mut bound = BoundRig::unbuilt(rig, rest, fields, jaw, skin, surface);
        bound.build_rows()?;
        bound.build_skin(mesh);
        bound.followers = mesh.followers();
        Ok(bound)
    }

    /// A bound rig of these fields with its rows and skin rules not built yet (both binds,
    /// the fresh one and the cached one, start from it).
    fn unbuilt(
        rig: &Rig,
        rest: Vec<Vec3>,
        fields: Vec<Field>,
        jaw: Option<BoundJaw>,
        skin: SkinRules,
        surface: Option<Arc<Surface>>,
    ) -> BoundRig {
        BoundRig {
            rig: rig.clone(),
            rest,
            fields,
            row_vertex: Vec::new(),
            row_start: Vec::new(),
            entries: Vec::new(),
            muscle_rows: Vec::new(),
            row_jaw_weight: Vec::new(),
            jaw,
            skin,
            patches: Vec::new(),
            row_split: Vec::new(),
            guard: Guard::default(),
            vertex_row: Vec::new(),
            vertex_jaw: Vec::new(),
            skin_mesh: None,
            surface,
            spread_length: spread::spread_length(rig, skin.spread),
            followers: Vec::new(),
        }
    }

    /// Fits the rest surface around every moved vertex and finds the triangles to check.
    fn build_skin(&mut self, mesh: &Mesh) {
        self.patches.clear();
        if !self.skin.is_paper() && self.skin.slide > 0.0 {
            let (lo, hi) = mesh.bounds();
            let radius = (hi - lo).length() * self.skin.patch;
            // the patches' surface goes by the face's size, not by the mesh's resolution
            let face = spread::spread_length(&self.rig, 1.0);
            let area = if face > 0.0 {
                slide::PATCH_AREA * face * face
            } else {
                f64::INFINITY
            };
            let adjacency = Adjacency::of(mesh);
            let normals = skin::outward_normals(mesh);
            self.patches =
                slide::fit_patches(mesh, &adjacency, &normals, &self.row_vertex, (radius, area));
        }
        self.build_guard(mesh);
    }

    /// Finds the triangles the area bound checks (the part of the skin rules a bind cache
    /// does not keep: it is quick to find again).
    fn build_guard(&mut self, mesh: &Mesh) {
        self.guard = Guard::default();
        self.vertex_row.clear();
        self.vertex_jaw.clear();
        if self.skin.is_paper() {
            return;
        }
        if self.skin_mesh.is_none() {
            self.skin_mesh = Some(Arc::new(mesh.clone()));
        }
        let n = self.rest.len();
        if self.skin.min_area <= 0.0 {
            return;
        }
        // how far each vertex can move at any activation in range
        let max = *MUSCLE_RANGE.end();
        let mut reach = vec![0.0f32; n];
        for field in &self.fields {
            for (&v, d) in field.vertices.iter().zip(&field.displacements) {
                reach[v as usize] += max * d.length();
            }
        }
        // the slide adds at most twice the displacement's length times its fraction
        reach
            .iter_mut()
            .for_each(|r| *r *= 1.0 + 2.0 * self.skin.slide);
        // the jaw turns after the bound (it holds the muscles back, not the jaw), but a turn
        // moves its guarded vertices, so they are settled again when it changes
        let mut moved: Vec<&[u32]> = self.fields.iter().map(|f| &f.vertices[..]).collect();
        moved.push(self.jaw.as_ref().map_or(&[], |j| &j.vertices[..]));
        self.guard = Guard::new(mesh, self.skin.min_area, &reach, &moved);
        if self.guard.is_empty() {
            return;
        }
        self.vertex_row = vec![NO_ROW; n];
        for (row, &v) in self.row_vertex.iter().enumerate() {
            self.vertex_row[v as usize] = row as u32;
        }
        self.vertex_jaw = vec![0.0; n];
        if let Some(jaw) = &self.jaw {
            for (&v, &w) in jaw.vertices.iter().zip(&jaw.weights) {
                self.vertex_jaw[v as usize] = w;
            }
        }
    }

    /// Fits the skin rules again after the fields or the jaw changed (a rebind).
    fn rebuild_skin(&mut self) {
        if let Some(mesh) = self.skin_mesh.clone() {
            self.build_skin(&mesh);
        }
    }

    /// Keeps `mesh` instead of this rig's own copy of the mesh it was bound to, when they
    /// are the same mesh (else nothing changes): a big mesh is then held once, by the
    /// caller and the bound rig together. Whether it is shared now.
    pub fn share_mesh(&mut self, mesh: &Arc<Mesh>) -> bool {
        match &self.skin_mesh {
            Some(kept) if Arc::ptr_eq(kept, mesh) => true,
            Some(kept) if **kept == **mesh => {
                self.skin_mesh = Some(Arc::clone(mesh));
                true
            }
            _ => false,
        }
    }

    /// The skin rules this rig was bound with.
    pub fn skin(&self) -> SkinRules {
        self.skin
    }

    /// Number of triangles checked against the area bound.
    pub fn guarded_triangles(&self) -> usize {
        self.guard.triangles.len()
    }

    /// Lays the fields out per vertex (CSR), entries of a row in muscle order.
    fn build_rows(&mut self) -> Result<(), BindError> {
        let n = self.rest.len();
        let mut counts = vec![0u32; n];
        for field in &self.fields {
            for &v in &field.vertices {
                counts[v as usize] += 1;
            }
        }
        let mut row_of = vec![NO_ROW; n];
        self.row_start.push(0);
        let mut total = 0u32;
        for (v, &c) in counts.iter().enumerate() {
            if c > 0 {
                row_of[v] = self.row_vertex.len() as u32;
                self.row_vertex.push(v as u32);
                total = total.checked_add(c).ok_or(BindError::TooManyPairs)?;
                self.row_start.push(total);
            }
        }
        let mut fill: Vec<u32> = self.row_start[..self.row_vertex.len()].to_vec();
        self.entries = vec![
            Entry {
                displacement: Vec3::ZERO,
                muscle: 0
            };
            total as usize
        ];
        // With the slide, each row holds the muscles that slide (linear, sheet) before the
        // sphincters (which pull in the face's plane by construction), split at `row_split`.
        let slides = self.skin.slide > 0.0;
        let sphincter =
            |m: usize| slides && matches!(self.rig.muscles[m].kind, MuscleKind::Sphincter(_));
        let mut muscle_rows = vec![Vec::new(); self.fields.len()];
        for late in [false, true] {
            for (m, field) in self.fields.iter().enumerate() {
                if sphincter(m) != late {
                    continue;
                }
                let mut rows = Vec::with_capacity(field.len());
                for (&v, &d) in field.vertices.iter().zip(&field.displacements) {
                    let row = row_of[v as usize];
                    let slot = fill[row as usize] as usize;
                    fill[row as usize] += 1;
                    self.entries[slot] = Entry {
                        displacement: d,
                        muscle: m as u32,
                    };
                    rows.push(row);
                }
                muscle_rows[m] = rows;
            }
            if slides && !late {
                self.row_split = fill.clone();
            }
        }
        self.muscle_rows = muscle_rows;
        self.row_jaw_weight = vec![0.0; self.row_vertex.len()];
        if let Some(jaw) = &mut self.jaw {
            jaw.rows = jaw.vertices.iter().map(|&v| row_of[v as usize]).collect();
            for (&row, &w) in jaw.rows.iter().zip(&jaw.weights) {
                if row != NO_ROW {
                    self.row_jaw_weight[row as usize] = w;
                }
            }
        }
        Ok(())
    }

    /// The rig as bound.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The rest positions of the mesh the rig is bound to.
    pub fn rest(&self) -> &[Vec3] {
        &self.rest
    }

    /// The field of muscle `index` (displacement per unit activation), if it exists.
    pub fn field(&self, index: usize) -> Option<&Field> {
        self.fields.get(index)
    }

    /// Number of muscles.
    pub fn muscle_count(&self) -> usize {
        self.fields.len()
    }

    /// Number of influenced `(vertex, muscle)` pairs: the work of one deformation.
    pub fn pair_count(&self) -> usize {
        self.entries.len()
    }

    /// Deforms the rest mesh by `act` into `out` (resized to the vertex count).
    ///
    /// Each vertex becomes its rest position plus the sum over muscles of activation times
    /// field displacement ([`Combine::Average`] divides that sum by the number of active
    /// muscles that moved the vertex); then the jaw turns its vertices. Allocates nothing
    /// when `out` already has the capacity.
    pub fn deform(&self, act: &Activations, out: &mut Vec<Vec3>) -> Result<(), ActivationError> {
        act.validate(&self.rig)?;
        let n = self.rest.len();
        if out.len() != n {
            out.clear();
            out.resize(n, Vec3::ZERO);
        }
        // Only the active muscles' fields are read; without the area bound the jaw turns in
        // the same pass.
        let turn = self.jaw.as_ref().and(self.jaw_turn(act.jaw));
        if self.guard.is_empty() {
            self.deform_whole(&act.muscles, turn, out);
        } else {
            // the area bound holds the muscles back; the jaw turns what they made
            self.deform_whole(&act.muscles, None, out);
            self.bound_areas(&act.muscles, out);
            self.turn_whole(turn, out);
        }
        self.follow(out);
        Ok(())
    }

    /// Moves each split vertex's copy to where its lead went.
    fn follow(&self, out: &mut [Vec3]) {
        for &[copy, lead] in &self.followers {
            out[copy as usize] = out[lead as usize];
        }
    }

    /// The vertex whose position `v` takes: its lead when `v` is a copy, else itself.
    pub(super) fn lead(&self, v: u32) -> u32 {
        crate::model::mesh::lead_of(&self.followers, v)
    }

    /// The vertex `v` at `p` before the area bound, its displacement scaled by `scale`, no
    /// lower than the guard allows for so long a travel ([`Guard::least_scale`]; `scale` is
    /// below 1 only for guarded vertices); kept bit for bit when the scale is 1.
    #[inline]
    fn scaled(&self, v: usize, p: Vec3, scale: f32) -> Vec3 {
        if scale >= 1.0 {
            p
        } else {
            let rest = self.rest[v];
            let g = self.guard.index_of(v) as usize;
            let scale = scale.max(self.guard.least_scale(g, (p - rest).length()));
            if scale >= 1.0 {
                return p;
            }
            rest + (p - rest) * scale
        }
    }

    /// The position of vertex `v` before the area bound, from rest: the muscles and the
    /// slide (the same arithmetic as [`BoundRig::deform`]; the jaw turns after the bound).
    #[inline]
    fn unbounded(&self, v: usize, muscles: &[f32], average: bool) -> Vec3 {
        let (row, w) = (self.vertex_row[v], self.vertex_jaw[v]);
        self.moved(v, row, w, muscles, average, None)
    }

    /// `p` turned by the jaw at weight `w` (the last step of [`Self::moved`]).
    #[inline]
    fn turned(p: Vec3, w: f32, turn: Option<JawTurn>) -> Vec3 {
        match turn.filter(|_| w > 0.0) {
            Some(turn) => turn.apply(p, w),
            None => p,
        }
    }

    /// Vertex `v` moved from rest by its CSR row `row` (or [`NO_ROW`]) and its jaw weight
    /// `w`: the one per-vertex arithmetic of [`Self::unbounded`] and the sampled deformation.
    #[inline]
    fn moved(
        &self,
        v: usize,
        row: u32,
        w: f32,
        muscles: &[f32],
        average: bool,
        turn: Option<JawTurn>,
    ) -> Vec3 {
        let p = if row == NO_ROW {
            self.rest[v]
        } else if average {
            self.row_position::<true>(row as usize, v, muscles)
        } else {
            self.row_position::<false>(row as usize, v, muscles)
        };
        Self::turned(p, w, turn)
    }

    /// Rewrites the vertices whose area-bound scale may have changed with a change of
    /// muscle `which` (the jaw when it is the muscle count), from rest.
    fn settle(
        &self,
        which: usize,
        muscles: &[f32],
        average: bool,
        turn: Option<JawTurn>,
        out: &mut [Vec3],
    ) {
        SCRATCH.with_borrow_mut(|(before, scales)| {
            if before.len() < self.rest.len() {
                before.resize(self.rest.len(), Vec3::ZERO);
            }
            if scales.len() < self.guard.triangles.len() {
                scales.resize(self.guard.triangles.len(), 1.0);
            }
            for &v in &self.guard.recompute[which] {
                before[v as usize] = self.unbounded(v as usize, muscles, average);
            }
            let rescale = &self.guard.rescale[which];
            self.guard
                .triangle_scales(Some(rescale), &self.rest, before, scales);
            for &v in &self.guard.settle[which] {
                let v = v as usize;
                let g = self.guard.index_of(v) as usize;
                let scale = self.guard.vertex_scale(g, scales);
                out[v] = Self::turned(self.scaled(v, before[v], scale), self.vertex_jaw[v], turn);
            }
        });
    }

    /// Recomputes, from rest, exactly the vertices in the field of `muscle`, jaw included.
    ///
    /// `out` must hold a deformation of this rig by activations that differ from `act` in
    /// this muscle's activation only; afterwards it equals `deform(act)` bit for bit.
    pub fn update_muscle(
        &self,
        act: &Activations,
        muscle: usize,
        out: &mut [Vec3],
    ) -> Result<(), ActivationError> {
        act.validate(&self.rig)?;
        if out.len() != self.rest.len() {
            return Err(ActivationError::VertexCount {
                given: out.len(),
                expected: self.rest.len(),
            });
        }
        let Some(rows) = self.muscle_rows.get(muscle) else {
            return Err(ActivationError::NoSuchMuscle {
                index: muscle,
                count: self.muscle_count(),
            });
        };
        let average = self.rig.combine == Combine::Average;
        let turn = self.jaw.as_ref().and(self.jaw_turn(act.jaw));
        let guarded = !self.guard.is_empty();
        for &row in rows {
            let row = row as usize;
            let v = self.row_vertex[row];
            if guarded && self.guard.index_of(v as usize) != NO_ROW {
                continue;
            }
            let mut p = if average {
                self.row_position::<true>(row, v as usize, &act.muscles)
            } else {
                self.row_position::<false>(row, v as usize, &act.muscles)
            };
            let w = self.row_jaw_weight[row];
            if let Some(turn) = turn.filter(|_| w > 0.0) {
                p = turn.apply(p, w);
            }
            out[v as usize] = p;
        }
        if guarded {
            self.settle(muscle, &act.muscles, average, turn, out);
        }
        self.follow(out);
        Ok(())
    }

    /// Recomputes, from rest, exactly the jaw's vertices (muscles included).
    ///
    /// `out` must hold a deformation of this rig by activations that differ from `act` in
    /// the jaw activation only; afterwards it equals `deform(act)` bit for bit.
    pub fn update_jaw(&self, act: &Activations, out: &mut [Vec3]) -> Result<(), ActivationError> {
        act.validate(&self.rig)?;
        if out.len() != self.rest.len() {
            return Err(ActivationError::VertexCount {
                given: out.len(),
                expected: self.rest.len(),
            });
        }
        let Some(jaw) = &self.jaw else {
            return Ok(());
        };
        let average = self.rig.combine == Combine::Average;
        let turn = self.jaw_turn(act.jaw);
        let guarded = !self.guard.is_empty();
        for ((&v, &w), &row) in jaw.vertices.iter().zip(&jaw.weights).zip(&jaw.rows) {
            let v = v as usize;
            if guarded && self.guard.index_of(v) != NO_ROW {
                continue;
            }
            let mut p = if row == NO_ROW {
                self.rest[v]
            } else if average {
                self.row_position::<true>(row as usize, v, &act.muscles)
            } else {
                self.row_position::<false>(row as usize, v, &act.muscles)
            };
            if let Some(turn) = turn {
                p = turn.apply(p, w);
            }
            out[v] = p;
        }
        if guarded {
            self.settle(self.fields.len(), &act.muscles, average, turn, out);
        }
        self.follow(out);
        Ok(())
    }

    /// The post-muscle position of the vertex of CSR row `row` (the one arithmetic shared by
    /// [`BoundRig::deform`] and [`BoundRig::update_muscle`]).
    ///
    /// Every entry is added without a branch (an inactive muscle adds an exact zero);
    /// average mode also counts the active muscles.
    #[inline(always)]
    fn row_position<const AVERAGE: bool>(&self, row: usize, v: usize, muscles: &[f32]) -> Vec3 {
        let (start, end) = (
            self.row_start[row] as usize,
            self.row_start[row + 1] as usize,
        );
        let mut active = 0u32;
        let mut add = |span: std::ops::Range<usize>| {
            let mut sum = Vec3::ZERO;
            for e in &self.entries[span] {
                let a = muscles[e.muscle as usize];
                sum += e.displacement * a;
                if AVERAGE {
                    active += u32::from(a != 0.0);
                }
            }
            sum
        };
        let (first, second) = if self.patches.get(row).is_some() {
            // the sliding muscles' displacement slides, the sphincters' is added after
            let split = self.row_split[row] as usize;
            (add(start..split), add(split..end))
        } else {
            (add(start..end), Vec3::ZERO)
        };
        self.finish_row::<AVERAGE>(row, v, first, second, active)
    }

    /// The position of the vertex `v` of CSR row `row` from its sums of activation-weighted
    /// displacements: `first` (the sliding muscles', or all of them when the row has no
    /// patch) and `second` (the sphincters'), `active` the muscles that moved it. The one
    /// finishing arithmetic of [`BoundRig::row_position`] and the whole deformation.
    #[inline(always)]
    fn finish_row<const AVERAGE: bool>(
        &self,
        row: usize,
        v: usize,
        first: Vec3,
        second: Vec3,
        active: u32,
    ) -> Vec3 {
        let sum = if let Some(patch) = self.patches.get(row) {
            let (mut slides, mut rest) = (first, second);
            if AVERAGE && active > 1 {
                slides /= active as f32;
                rest /= active as f32;
            }
            patch.slide(slides, self.skin.slide) + rest
        } else {
            let mut sum = first;
            if AVERAGE && active > 1 {
                sum /= active as f32;
            }
            sum
        };
        // Where nothing moved a coordinate, keep the rest value bit for bit (adding a zero
        // would turn a rest coordinate of -0.0 into +0.0).
        let rest = self.rest[v];
        Vec3::select(sum.cmpeq(Vec3::ZERO), rest, rest + sum)
    }

    /// The jaw rotation for jaw activation `k`, or `None` when nothing turns.
    fn jaw_turn(&self, k: f32) -> Option<JawTurn> {
        self.jaw.as_ref()?.turn(k)
    }
}

impl BoundJaw {
    /// The jaw's turn at activation `k` (`None` when it does not turn).
    fn turn(&self, k: f32) -> Option<JawTurn> {
        let angle = k as f64 * self.radians_per_unit;
        (angle != 0.0).then(|| JawTurn {
            pivot: self.pivot,
            cos: angle.cos() as f32,
            sin: angle.sin() as f32,
            general: (self.axis != Vec3::X)
                .then(|| glam::Mat3::from_axis_angle(self.axis, angle as f32)),
            shift: (self.slide_per_unit != Vec3::ZERO).then(|| self.slide_per_unit * k),
        })
    }
}

/// Deforms `rest` by the bound rig: the free-function form of [`BoundRig::deform`].
///
/// `rest` must be the mesh the rig was bound to (checked by vertex count); the positions used
/// are the bound rest positions.
pub fn deform(
    rest: &Mesh,
    rig: &BoundRig,
    act: &Activations,
    out: &mut Vec<Vec3>,
) -> Result<(), ActivationError> {
    if rest.positions.len() != rig.rest.len() {
        return Err(ActivationError::VertexCount {
            given: rest.positions.len(),
            expected: rig.rest.len(),
        });
    }
    rig.deform(act, out)
}

/// The most `(vertex, muscle)` pairs a rig may influence: each costs about 36 bytes bound
/// (its field entry, its CSR entry and its row), so the limit is about 1.2 GB.
pub const MAX_INFLUENCES: usize = 1 << 25;

#[cfg(test)]
mod tests;

mod rebind;
