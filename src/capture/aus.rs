//! AU intensities from solved activations: the non-negative combination of the AU table's
//! bilateral entries closest to the activations (bounded least squares, [`crate::fit::lsq`]),
//! each weight 0-1 written on OpenFace's 0-5 scale.

use crate::facs::{AuKey, AuTable};
use crate::fit::lsq::box_least_squares;
use crate::io::openface::OPENFACE_MAX_INTENSITY;
use crate::model::{Activations, Rig, JAW_RANGE, MUSCLE_RANGE};

/// The AU entries of a table on a rig, ready to project activations onto.
#[derive(Debug, Clone)]
pub struct AuProjection {
    numbers: Vec<u8>,
    /// One row per AU: its activations scaled to each variable's range.
    entries: Vec<Vec<f64>>,
    gram: Vec<f64>,
}

impl AuProjection {
    /// The projection onto every AU the table gives both sides of (bilateral entries, or
    /// both unilateral ones), in AU order.
    pub fn new(table: &AuTable, rig: &Rig) -> AuProjection {
        let mut numbers: Vec<u8> = table.aus.keys().map(|k| k.number).collect();
        numbers.dedup();
        let mut kept = Vec::new();
        let mut entries = Vec::new();
        for number in numbers {
            let Ok(act) = table.entry_activations(&AuKey::new(number), rig) else {
                continue;
            };
            if act.is_rest() {
                continue;
            }
            kept.push(number);
            entries.push(scaled(&act));
        }
        let k = entries.len();
        let mut gram = vec![0.0; k * k];
        for i in 0..k {
            for j in 0..k {
                gram[i * k + j] = dot(&entries[i], &entries[j]);
            }
        }
        AuProjection {
            numbers: kept,
            entries,
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

    /// The intensities (0-5) of each AU for `act`.
    pub fn intensities(&self, act: &Activations) -> Vec<f64> {
        let target = scaled(act);
        let c: Vec<f64> = self.entries.iter().map(|e| dot(e, &target)).collect();
        let k = c.len();
        let weights = box_least_squares(&self.gram, &c, &vec![0.0; k], &vec![1.0; k]);
        weights
            .into_iter()
            .map(|w| w * f64::from(OPENFACE_MAX_INTENSITY))
            .collect()
    }
}

/// Activations as a vector with every variable on its own range's scale (muscles over 2,
/// the jaw over 4), so the jaw's wider range does not outweigh a muscle.
fn scaled(act: &Activations) -> Vec<f64> {
    let muscle = f64::from(*MUSCLE_RANGE.end());
    let jaw = f64::from(*JAW_RANGE.end());
    act.muscles
        .iter()
        .map(|&a| f64::from(a) / muscle)
        .chain(std::iter::once(f64::from(act.jaw) / jaw))
        .collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
