//! The jaw: a weighted rotation of the lower face about a pivot (MODEL-NOTES section 5).

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The jaw of a rig.
///
/// Activation `K` (0.0 to 4.0) turns the jaw by `K * degrees_per_unit` degrees about the x
/// axis through `pivot`; positive angles open the mouth (the chin moves down and back). Each
/// vertex's weight blends between its rotated and unrotated position, so the lip corners
/// (weight 0) never tear.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Jaw {
    /// The point the jaw turns about (near the temporomandibular joint).
    pub pivot: Vec3,
    /// Degrees of rotation per unit of jaw activation (the paper: 1).
    pub degrees_per_unit: f32,
    /// `(vertex, weight)` pairs, weight in 0.0 to 1.0, sorted by vertex; vertices not listed
    /// do not move with the jaw.
    pub weights: Vec<(u32, f32)>,
}
