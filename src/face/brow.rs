//! The medial frontalis of the default rig: the frontalis sheet's medial fibres as a muscle of
//! their own, for AU1 (the inner brow raiser).
//!
//! The sheet reaches across the midline and a mask gives it its medial share: full over the
//! head of the brow, fading smoothly out toward the brow's tail and, across the midline, into
//! the other side's sheet (each side gives the midline half, so both sides together lift the
//! glabella as much as the heads of the brows). A sheet's own side taper is short (a quarter
//! of its half-width), and at the 11 mm an inner brow rises the skin sheared across so short a
//! taper turns triangles over; the mask spreads the change over the brow's middle.

use super::anthropometry::units;
use super::{round3, surface};
use crate::model::{Mask, Mesh};

/// From the midline, where the medial share starts to fade (mm): the head of the brow and the
/// skin above it get the full pull.
pub(super) const MEDIAL_FULL_MM: f64 = 14.0;
/// From the midline, where the medial share has faded out (mm): short of the brow's tail,
/// which AU1 leaves (AU2 raises it).
pub(super) const MEDIAL_END_MM: f64 = 42.0;
/// Half the width of the fade across the midline (mm).
const MIDLINE_FADE_MM: f64 = 6.0;

/// The medial share of the pull at `x` (mm from the midline, the muscle's own side positive).
fn medial_share(x: f64) -> f64 {
    let across = surface::smoothstep(-MIDLINE_FADE_MM, MIDLINE_FADE_MM, x);
    across * (1.0 - surface::smoothstep(MEDIAL_FULL_MM, MEDIAL_END_MM, x))
}

/// The mask giving muscle `name` (on the side whose x has sign `own_side`) its medial share,
/// listing the skin at or above `lowest_y` (mesh units) where the share is under 1.
pub(super) fn medial_mask(mesh: &Mesh, name: &str, own_side: f32, lowest_y: f32) -> Mask {
    let weights = mesh
        .positions
        .iter()
        .enumerate()
        .filter(|(_, p)| p.y >= lowest_y)
        .filter_map(|(i, p)| {
            let x_mm = f64::from(p.x * own_side) / units(1.0);
            let w = round3(medial_share(x_mm) as f32);
            (w < 1.0).then_some((i as u32, w))
        })
        .collect();
    Mask {
        muscles: vec![name.to_string()],
        gain: 1.0,
        weights,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_medial_share_is_full_at_the_head_of_the_brow_and_halves_at_the_midline() {
        assert!((medial_share(0.0) - 0.5).abs() < 1e-9);
        assert!((medial_share(MEDIAL_FULL_MM) - 1.0).abs() < 1e-9);
        assert_eq!(medial_share(MEDIAL_END_MM), 0.0);
        assert_eq!(medial_share(-MIDLINE_FADE_MM), 0.0);
        // the two sides' shares add to one across the midline
        for x in [-4.0, -1.0, 0.0, 2.5, 5.0] {
            assert!((medial_share(x) + medial_share(-x) - 1.0).abs() < 1e-9);
        }
    }
}
