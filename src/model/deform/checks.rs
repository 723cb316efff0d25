//! The checks of a rig at bind time that are not about one muscle's parameters: unique
//! names and mirror partners, the influence budget, the masks and the reach at full
//! activation.

use std::collections::BTreeSet;

use glam::Vec3;

use super::{BindError, BoundJaw, MAX_INFLUENCES, MAX_REACH};
use crate::model::activations::MUSCLE_RANGE;
use crate::model::field::Field;
use crate::model::Rig;

/// Refuses a rig whose fields would pass [`MAX_INFLUENCES`], before any is kept. Only rigs
/// that could pass it (muscles times vertices above the limit) pay for the counting pass.
pub(super) fn check_budget(rig: &Rig, rest: &[Vec3]) -> Result<(), BindError> {
    if rig.muscles.len().saturating_mul(rest.len()) <= MAX_INFLUENCES {
        return Ok(());
    }
    let mut total = 0usize;
    for muscle in &rig.muscles {
        total += Field::count(&muscle.kind, rest);
        if total > MAX_INFLUENCES {
            return Err(BindError::TooManyInfluences {
                muscle: muscle.name.clone(),
                vertices: rest.len(),
            });
        }
    }
    Ok(())
}

/// Per muscle, the product of the weights of the masks naming it (one per vertex), or
/// `None` for a muscle no mask names.
pub(super) fn mask_scales(rig: &Rig, count: usize) -> Result<Vec<Option<Vec<f32>>>, BindError> {
    let mut scales: Vec<Option<Vec<f32>>> = vec![None; rig.muscles.len()];
    for (index, mask) in rig.masks.iter().enumerate() {
        let bad = |message: String| BindError::Mask {
            mask: index,
            message,
        };
        let mut previous: Option<u32> = None;
        for &(vertex, weight) in &mask.weights {
            if vertex as usize >= count {
                return Err(bad(format!(
                    "vertex {vertex} does not exist; the mesh has {count} vertices"
                )));
            }
            if previous.is_some_and(|p| p >= vertex) {
                return Err(bad(format!(
                    "vertices must be sorted with no repeats; {vertex} comes after {}",
                    previous.unwrap_or(0)
                )));
            }
            previous = Some(vertex);
            if !(weight.is_finite() && (0.0..=1.0).contains(&weight)) {
                return Err(bad(format!(
                    "vertex {vertex} has weight {weight}, outside 0.0 to 1.0"
                )));
            }
        }
        if !(mask.gain.is_finite() && mask.gain > 0.0 && mask.gain <= 1e6) {
            return Err(bad(format!(
                "gain {} must be a finite number above 0 and at most 1e6",
                mask.gain
            )));
        }
        for name in &mask.muscles {
            let muscle = rig
                .muscle_index(name)
                .ok_or_else(|| bad(format!("names `{name}`, which is not a muscle of the rig")))?;
            let scale = scales[muscle].get_or_insert_with(|| vec![1.0; count]);
            if mask.gain != 1.0 {
                scale.iter_mut().for_each(|s| *s *= mask.gain);
            }
            for &(vertex, weight) in &mask.weights {
                scale[vertex as usize] *= weight;
            }
        }
    }
    Ok(scales)
}

/// Refuses rigs whose full activation would leave the range where `f32` sums stay finite.
pub(super) fn check_reach(rig: &Rig, rest: &[Vec3], fields: &[Field]) -> Result<(), BindError> {
    let max = *MUSCLE_RANGE.end() as f64;
    let mut reach: Vec<f64> = rest.iter().map(|p| p.as_dvec3().length()).collect();
    for (muscle, field) in rig.muscles.iter().zip(fields) {
        for (&v, d) in field.vertices.iter().zip(&field.displacements) {
            let r = &mut reach[v as usize];
            *r += max * d.as_dvec3().length();
            if !r.is_finite() || *r > MAX_REACH {
                return Err(BindError::OutOfReach {
                    muscle: muscle.name.clone(),
                    vertex: v,
                });
            }
        }
    }
    Ok(())
}

/// Unique muscle names, and every mirror partner present.
pub(super) fn validate_names(rig: &Rig) -> Result<(), BindError> {
    let mut seen = BTreeSet::new();
    for m in &rig.muscles {
        if !seen.insert(m.name.as_str()) {
            return Err(BindError::DuplicateMuscle(m.name.clone()));
        }
    }
    for m in &rig.muscles {
        if let Some(mirror) = &m.mirror {
            if !seen.contains(mirror.as_str()) {
                return Err(BindError::MissingMirror {
                    muscle: m.name.clone(),
                    mirror: mirror.clone(),
                });
            }
        }
    }
    Ok(())
}

/// Checks the jaw and keeps its vertices of non-zero weight, sorted.
pub(super) fn bind_jaw(rig: &Rig, count: usize) -> Result<Option<BoundJaw>, BindError> {
    let Some(jaw) = &rig.jaw else {
        return Ok(None);
    };
    if !(jaw.pivot.is_finite() && jaw.pivot.as_dvec3().length() <= MAX_REACH) {
        return Err(BindError::JawParameter {
            parameter: "pivot",
            value: jaw.pivot.to_string(),
        });
    }
    if !jaw.degrees_per_unit.is_finite() {
        return Err(BindError::JawParameter {
            parameter: "degrees_per_unit",
            value: jaw.degrees_per_unit.to_string(),
        });
    }
    let axis = jaw.axis.normalize_or_zero();
    if axis == Vec3::ZERO {
        return Err(BindError::JawParameter {
            parameter: "axis",
            value: jaw.axis.to_string(),
        });
    }
    let slide_per_unit = jaw.slide * jaw.degrees_per_unit;
    if !(slide_per_unit.is_finite() && slide_per_unit.as_dvec3().length() <= MAX_REACH) {
        return Err(BindError::JawParameter {
            parameter: "slide",
            value: jaw.slide.to_string(),
        });
    }
    let mut weights = jaw.weights.clone();
    weights.sort_by_key(|&(v, _)| v);
    for pair in weights.windows(2) {
        if pair[0].0 == pair[1].0 {
            return Err(BindError::JawDuplicateVertex(pair[0].0));
        }
    }
    for &(vertex, weight) in &weights {
        if vertex as usize >= count {
            return Err(BindError::JawVertex { vertex, count });
        }
        if !(0.0..=1.0).contains(&weight) {
            return Err(BindError::JawWeight { vertex, weight });
        }
    }
    weights.retain(|&(_, w)| w > 0.0);
    Ok(Some(BoundJaw {
        pivot: jaw.pivot,
        axis,
        radians_per_unit: (jaw.degrees_per_unit as f64).to_radians(),
        slide_per_unit,
        vertices: weights.iter().map(|&(v, _)| v).collect(),
        weights: weights.iter().map(|&(_, w)| w).collect(),
        rows: Vec::new(),
    }))
}
