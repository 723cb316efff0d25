//! Activations: the numbers the user edits, one per muscle plus the jaw.

use std::ops::RangeInclusive;

use thiserror::Error;

use super::rig::Rig;

/// The allowed range of a muscle activation.
pub const MUSCLE_RANGE: RangeInclusive<f32> = 0.0..=2.0;
/// The allowed range of the jaw activation.
pub const JAW_RANGE: RangeInclusive<f32> = 0.0..=4.0;

/// An activation that cannot be applied.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ActivationError {
    /// A muscle activation is NaN or infinite.
    #[error("activation of `{muscle}` is not a finite number ({value})")]
    NotFinite {
        /// The muscle's name (`jaw` for the jaw).
        muscle: String,
        /// The value given.
        value: f32,
    },
    /// A muscle activation lies outside 0.0-2.0 (or the jaw outside 0.0-4.0).
    #[error("activation of `{muscle}` is {value}, outside the allowed range {min} to {max}")]
    OutOfRange {
        /// The muscle's name (`jaw` for the jaw).
        muscle: String,
        /// The value given.
        value: f32,
        /// Lowest allowed value.
        min: f32,
        /// Highest allowed value.
        max: f32,
    },
    /// The activations do not match the rig's muscles.
    #[error("{given} muscle activations given, but the rig has {expected} muscles")]
    WrongCount {
        /// Number of activations given.
        given: usize,
        /// Number of muscles in the rig.
        expected: usize,
    },
    /// A muscle name the rig does not have.
    #[error("the rig has no muscle named `{0}`")]
    UnknownMuscle(String),
    /// A muscle number the rig does not have.
    #[error("the rig has no muscle number {index}; it has {count} muscles")]
    NoSuchMuscle {
        /// The muscle number asked for (0-based).
        index: usize,
        /// Number of muscles in the rig.
        count: usize,
    },
    /// A mesh or position buffer whose size does not match the bound mesh.
    #[error("{given} vertices given, but the rig is bound to a mesh of {expected} vertices")]
    VertexCount {
        /// Number of vertices given.
        given: usize,
        /// Number of vertices of the bound mesh.
        expected: usize,
    },
}

/// One activation per muscle of a rig (in the rig's order) plus the jaw.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Activations {
    /// Muscle activations, indexed like [`Rig::muscles`].
    pub muscles: Vec<f32>,
    /// Jaw activation.
    pub jaw: f32,
}

impl Activations {
    /// All muscles and the jaw at rest.
    pub fn zero(rig: &Rig) -> Activations {
        Activations {
            muscles: vec![0.0; rig.muscles.len()],
            jaw: 0.0,
        }
    }

    /// Checks count, finiteness and ranges against the rig.
    pub fn validate(&self, rig: &Rig) -> Result<(), ActivationError> {
        if self.muscles.len() != rig.muscles.len() {
            return Err(ActivationError::WrongCount {
                given: self.muscles.len(),
                expected: rig.muscles.len(),
            });
        }
        for (value, muscle) in self.muscles.iter().zip(&rig.muscles) {
            check(&muscle.name, *value, &MUSCLE_RANGE)?;
        }
        check("jaw", self.jaw, &JAW_RANGE)
    }

    /// True when every muscle and the jaw are at zero.
    pub fn is_rest(&self) -> bool {
        self.jaw == 0.0 && self.muscles.iter().all(|&a| a == 0.0)
    }
}

/// Checks one value against a range, naming the muscle in the error.
pub fn check(muscle: &str, value: f32, range: &RangeInclusive<f32>) -> Result<(), ActivationError> {
    if !value.is_finite() {
        return Err(ActivationError::NotFinite {
            muscle: muscle.to_string(),
            value,
        });
    }
    if !range.contains(&value) {
        return Err(ActivationError::OutOfRange {
            muscle: muscle.to_string(),
            value,
            min: *range.start(),
            max: *range.end(),
        });
    }
    Ok(())
}
