//! The jaw: a weighted rotation of the lower face about a pivot (MODEL-NOTES section 5), with
//! an optional forward slide in proportion to the angle (the condyle's glide).

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The jaw of a rig.
///
/// Activation `K` (0.0 to 4.0) turns the jaw by `theta = K * degrees_per_unit` degrees about
/// `axis` (the x axis unless given) through `pivot`, then moves it by `theta * slide` (the
/// temporomandibular joint's glide: the condyle slides forward and down the articular
/// eminence as the mouth opens); positive angles open the mouth. Each vertex's weight blends
/// between its moved and unmoved position, so the lip corners (weight 0) never tear.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Jaw {
    /// The point the jaw turns about (near the temporomandibular joint).
    pub pivot: Vec3,
    /// Degrees of rotation per unit of jaw activation (the paper: 1).
    pub degrees_per_unit: f32,
    /// `(vertex, weight)` pairs, weight in 0.0 to 1.0, sorted by vertex; vertices not listed
    /// do not move with the jaw.
    pub weights: Vec<(u32, f32)>,
    /// The axis the jaw turns about (through `pivot`; right-hand rule, so positive angles
    /// open the mouth when it points along the face's x axis). The x axis unless a fitted
    /// mesh lies another way round.
    #[serde(default = "x_axis", skip_serializing_if = "is_x_axis")]
    pub axis: Vec3,
    /// Translation per degree of turn (mesh units, mesh axes): the condyle's slide forward
    /// and down as the jaw opens. Zero (the paper's pure rotation) unless given, so rig
    /// files written before it load unchanged.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub slide: Vec3,
}

fn is_zero(v: &Vec3) -> bool {
    *v == Vec3::ZERO
}

/// The jaw's axis in rigs that do not give one.
pub fn x_axis() -> Vec3 {
    Vec3::X
}

/// [`x_axis`] as an array, for file readers.
pub fn x_axis_p3() -> [f32; 3] {
    [1.0, 0.0, 0.0]
}

fn is_x_axis(axis: &Vec3) -> bool {
    *axis == Vec3::X
}
