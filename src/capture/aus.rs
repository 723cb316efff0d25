//! AU intensities from solved activations: the non-negative combination of the AU table's
//! entries whose landmark motion is closest to the motion the solved activations make
//! (bounded least squares, [`crate::fit::lsq`]), each weight 0-1 written on OpenFace's 0-5
//! scale.
//!
//! The comparison is made on what the activations do to the landmarks, not on the
//! activations themselves: a lip-corner pull the solve found with the zygomatic minor and the
//! risorius is still the table's AU12 (the zygomatic major) if it moves the landmarks alike.
//!
//! Lips Part (AU25) is the exception: FACS scores it by the lips' separation, with or
//! without the jaw, so it is read there ([`LIPS_PART`]) on its entry's own opening. In the
//! joint fit the jaw's drop, which AU25, AU26 and AU27 all carry, decided it. The
//! separation is read on both contours of the lips, the inner and the outer: the rig's
//! inner-lip landmarks part less than a real mouth's in a smile (its lips do not thin and
//! part as they stretch), while the outer contour's motion is reproduced in full
//! (docs/capture.md, "AU25 diagnosed").

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
    /// AU25's column and its entry's opening of the lips ([`LIPS_PART`]).
    lips_part: Option<(usize, Vec<DVec3>)>,
}

/// The FACS number of Lips Part.
pub const LIPS_PART_AU: u8 = 25;

/// The lips' facing pairs (upper, lower) of the 68 landmarks, the inner contour's three
/// and the outer contour's three: their separation is what FACS calls the lips' part,
/// whether the jaw drops with it or not. FACS looks at the inner contour; the outer one is
/// where a rig reproduces the lips' motion most fully (its inner-lip points lag their lip
/// when the mouth stretches), so both are read.
pub const LIPS_PART: [(usize, usize); 6] =
    [(61, 67), (62, 66), (63, 65), (50, 58), (51, 57), (52, 56)];

/// How far each pair of [`LIPS_PART`] separates under a landmark motion.
fn lip_separation(motion: &[DVec3]) -> Vec<DVec3> {
    LIPS_PART
        .iter()
        .map(|&(upper, lower)| motion[lower] - motion[upper])
        .collect()
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
        let lips_part = kept
            .iter()
            .position(|&n| n == LIPS_PART_AU)
            .map(|k| (k, lip_separation(&entries[k])))
            .filter(|(_, gap)| gap.iter().map(|d| d.length_squared()).sum::<f64>() > 0.0);
        // Lips Part is read on its own; in the joint fit its column is empty (held at 0), so
        // the jaw's drop goes to the AUs that are the jaw's (AU26, AU27).
        let joint = |i: usize| lips_part.as_ref().is_none_or(|(k, _)| *k != i);
        let k = entries.len();
        let mut gram = vec![0.0; k * k];
        for i in (0..k).filter(|&i| joint(i)) {
            for j in (0..k).filter(|&j| joint(j)) {
                gram[i * k + j] = weighted_dot(&weights, &entries[i], &entries[j]);
            }
        }
        AuProjection {
            numbers: kept,
            entries,
            weights,
            gram,
            lips_part,
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
            .enumerate()
            .map(|(i, e)| {
                let joint = self.gram[i * self.entries.len() + i] > 0.0;
                if joint {
                    weighted_dot(&self.weights, e, motion)
                } else {
                    0.0
                }
            })
            .collect();
        let k = c.len();
        let mut weights = box_least_squares(&self.gram, &c, &vec![0.0; k], &vec![1.0; k]);
        // Lips Part is the lips' separation: read there, on the entry's own opening,
        // not from the jaw's drop the table's entries share with AU26 and AU27.
        if let Some((k, entry)) = &self.lips_part {
            let seen = lip_separation(motion);
            let dot =
                |a: &[DVec3], b: &[DVec3]| a.iter().zip(b).map(|(a, b)| a.dot(*b)).sum::<f64>();
            weights[*k] = (dot(&seen, entry) / dot(entry, entry)).clamp(0.0, 1.0);
        }
        weights
            .into_iter()
            .map(|w| w * f64::from(OPENFACE_MAX_INTENSITY))
            .collect()
    }
}
