//! The rig seen through the 68 landmarks: how each muscle and the jaw move the rig's
//! landmark vertices, on the deformation the rig is bound with (skin rules included).
//!
//! - A linear muscle's field is linear in its activation; the skin rules after it (the slide
//!   along the rest surface, the area bound) are not quite, so each muscle's column is the
//!   secant of the bound deformation from rest to [`SECANT_ACTIVATION`], the middle of the
//!   activations people use. The solver then refines on the deformation itself.
//! - The jaw turns its vertices: its motion is tabulated over its whole range
//!   ([`JAW_SAMPLES`] poses) and read, with its slope, by linear interpolation.

use glam::{DVec3, Vec3};

use crate::model::{Activations, BoundRig, JAW_RANGE};

/// The activation each muscle's secant column is taken to.
pub const SECANT_ACTIVATION: f32 = 0.5;

/// Poses of the jaw's motion table, over 0 to 4.
pub const JAW_SAMPLES: usize = 17;

/// The rig's landmark vertices and their motion per muscle and along the jaw's range.
#[derive(Debug, Clone)]
pub struct LandmarkModel {
    vertices: Vec<u32>,
    rest: Vec<DVec3>,
    /// Per muscle, the motion of each landmark per unit activation.
    columns: Vec<Vec<DVec3>>,
    /// The landmarks' displacement from rest at each jaw sample (empty without a jaw).
    jaw_table: Vec<Vec<DVec3>>,
}

impl LandmarkModel {
    /// The model of `bound` at the landmark vertices `vertices` (checked by the caller to be
    /// in range).
    pub fn new(bound: &BoundRig, vertices: &[u32]) -> LandmarkModel {
        let rest: Vec<DVec3> = vertices
            .iter()
            .map(|&v| bound.rest()[v as usize].as_dvec3())
            .collect();
        let mut act = Activations::zero(bound.rig());
        let mut out = Vec::new();
        let mut sample = |act: &Activations| -> Vec<DVec3> {
            // In range by construction, so the rig cannot refuse them.
            if bound.deform(act, &mut out).is_err() {
                return vec![DVec3::ZERO; vertices.len()];
            }
            vertices
                .iter()
                .zip(&rest)
                .map(|(&v, r)| out[v as usize].as_dvec3() - *r)
                .collect()
        };
        let mut columns = Vec::with_capacity(bound.muscle_count());
        for m in 0..bound.muscle_count() {
            act.muscles[m] = SECANT_ACTIVATION;
            let moved = sample(&act);
            act.muscles[m] = 0.0;
            let per_unit = 1.0 / f64::from(SECANT_ACTIVATION);
            columns.push(moved.into_iter().map(|d| d * per_unit).collect());
        }
        let jaw_table = if bound.rig().jaw.is_some() {
            (0..JAW_SAMPLES)
                .map(|i| {
                    act.jaw = jaw_at(i);
                    sample(&act)
                })
                .collect()
        } else {
            Vec::new()
        };
        LandmarkModel {
            vertices: vertices.to_vec(),
            rest,
            columns,
            jaw_table,
        }
    }

    /// The landmark vertices.
    pub fn vertices(&self) -> &[u32] {
        &self.vertices
    }

    /// The landmarks at rest.
    pub fn rest(&self) -> &[DVec3] {
        &self.rest
    }

    /// Number of muscles.
    pub fn muscle_count(&self) -> usize {
        self.columns.len()
    }

    /// Whether the rig has a jaw (then it is the last variable).
    pub fn has_jaw(&self) -> bool {
        !self.jaw_table.is_empty()
    }

    /// Number of variables: the muscles, then the jaw when there is one.
    pub fn variable_count(&self) -> usize {
        self.columns.len() + usize::from(self.has_jaw())
    }

    /// Muscle `m`'s motion of each landmark per unit activation.
    pub fn column(&self, m: usize) -> &[DVec3] {
        &self.columns[m]
    }

    /// The jaw's slope at activation `k`: each landmark's motion per unit of jaw, from the
    /// table segment `k` lies in.
    pub fn jaw_slope(&self, k: f64) -> Vec<DVec3> {
        if self.jaw_table.is_empty() {
            return vec![DVec3::ZERO; self.rest.len()];
        }
        let step = f64::from(jaw_at(1));
        let i = ((k / step).floor().max(0.0) as usize).min(JAW_SAMPLES - 2);
        self.jaw_table[i + 1]
            .iter()
            .zip(&self.jaw_table[i])
            .map(|(b, a)| (*b - *a) / step)
            .collect()
    }

    /// The landmarks' displacement from rest under `act`, on the bound deformation itself.
    pub fn displacement(
        &self,
        bound: &BoundRig,
        act: &Activations,
        out: &mut Vec<Vec3>,
    ) -> Vec<DVec3> {
        if act.is_rest() || bound.deform(act, out).is_err() {
            return vec![DVec3::ZERO; self.rest.len()];
        }
        self.vertices
            .iter()
            .zip(&self.rest)
            .map(|(&v, r)| out[v as usize].as_dvec3() - *r)
            .collect()
    }
}

/// The jaw activation of table sample `i`.
fn jaw_at(i: usize) -> f32 {
    *JAW_RANGE.end() * i as f32 / (JAW_SAMPLES - 1) as f32
}
