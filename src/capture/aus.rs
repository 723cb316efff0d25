//! AU intensities from solved activations: the non-negative combination of the AU table's
//! entries whose landmark motion is closest to the motion the solved activations make
//! (bounded least squares, [`crate::fit::lsq`]), each weight 0-1 written on OpenFace's 0-5
//! scale.
//!
//! The comparison is made on what the activations do to the landmarks, not on the
//! activations themselves: a lip-corner pull the solve found with the zygomatic minor and the
//! risorius is still the table's AU12 (the zygomatic major) if it moves the landmarks alike.

use glam::{DVec3, Vec3};

use super::pose::landmark_weight;
use super::rig_model::LandmarkModel;
use super::solver::weighted_dot;
use crate::facs::{AuKey, AuTable};
use crate::fit::lsq::box_least_squares;
use crate::io::openface::OPENFACE_MAX_INTENSITY;
use crate::model::BoundRig;

/// The AU entries of a table on a rig, as landmark motion, ready to project onto.
#[derive(Debug, Clone)]
pub struct AuProjection {
    numbers: Vec<u8>,
    /// One landmark motion per AU, at full intensity.
    entries: Vec<Vec<DVec3>>,
    weights: Vec<DVec3>,
    gram: Vec<f64>,
}

impl AuProjection {
    /// The projection onto every AU the table gives both sides of (bilateral entries, or
    /// both unilateral ones) that moves a landmark, in AU order.
    pub fn new(table: &AuTable, bound: &BoundRig, model: &LandmarkModel) -> AuProjection {
        let mut numbers: Vec<u8> = table.aus.keys().map(|k| k.number).collect();
        numbers.dedup();
        let weights: Vec<DVec3> = (0..model.rest().len()).map(landmark_weight).collect();
        let mut kept = Vec::new();
        let mut entries = Vec::new();
        let mut scratch: Vec<Vec3> = Vec::new();
        for number in numbers {
            let Ok(act) = table.entry_activations(&AuKey::new(number), bound.rig()) else {
                continue;
            };
            let motion = model.displacement(bound, &act, &mut scratch);
            if weighted_dot(&weights, &motion, &motion) > 0.0 {
                kept.push(number);
                entries.push(motion);
            }
        }
        let k = entries.len();
        let mut gram = vec![0.0; k * k];
        for i in 0..k {
            for j in 0..k {
                gram[i * k + j] = weighted_dot(&weights, &entries[i], &entries[j]);
            }
        }
        AuProjection {
            numbers: kept,
            entries,
            weights,
            gram,
        }
    }

    /// The AU numbers, in column order.
    pub fn numbers(&self) -> &[u8] {
        &self.numbers
    }

    /// The column names in OpenFace's style (`AU01_r`).
    pub fn names(&self) -> Vec<String> {
        self.numbers.iter().map(|n| format!("AU{n:02}_r")).collect()
    }

    /// The intensities (0-5) of each AU for the landmark motion `motion` of solved
    /// activations ([`super::Captured::motion`]).
    pub fn intensities(&self, motion: &[DVec3]) -> Vec<f64> {
        let c: Vec<f64> = self
            .entries
            .iter()
            .map(|e| weighted_dot(&self.weights, e, motion))
            .collect();
        let k = c.len();
        let weights = box_least_squares(&self.gram, &c, &vec![0.0; k], &vec![1.0; k]);
        weights
            .into_iter()
            .map(|w| w * f64::from(OPENFACE_MAX_INTENSITY))
            .collect()
    }
}
