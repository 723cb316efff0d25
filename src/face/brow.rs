//! The medial frontalis of the default rig: the frontalis sheet's medial fibres as a muscle of
//! their own, for AU1 (the inner brow raiser).
//!
//! The sheet reaches across the midline and a mask gives it its medial share: full over the
//! head of the brow, fading smoothly out toward the brow's tail and, across the midline, into
//! the other side's sheet (each side gives the midline half, so both sides together lift the
//! glabella as much as the heads of the brows). A sheet's own side taper is short (a quarter
//! of its half-width), and at the 11 mm an inner brow rises the skin sheared across so short a
//! taper turns triangles over; the mask spreads the change over the brow's middle.
//!
//! It also lays out the brow hair ([`hair_groups`]): the skin under each eyebrow, drawn in a
//! darker tone, so the brows the muscles move are visible as brows (to a viewer and to a face
//! tracker, which finds no brow on bare skin).

use std::collections::BTreeMap;

use glam::Vec3;

use super::anthropometry::{
    units, BROW_Y, ENDOCANTHION_X, EXOCANTHION_X, MM_PER_UNIT, Y_ORIGIN_MM,
};
use super::{round3, surface};
use crate::model::{Mask, Mesh};

/// From the midline, where the eyebrow's head starts (mm): a little medial to the inner eye
/// corner, over the root of the nose's side.
pub(super) const HAIR_HEAD_X: f64 = ENDOCANTHION_X - 3.0;
/// From the midline, where the eyebrow's tail ends (mm): beyond the outer eye corner, on the
/// line from the ala through the outer canthus.
pub(super) const HAIR_TAIL_X: f64 = EXOCANTHION_X + 7.0;
/// Along the brow (0 head, 1 tail), where its arch peaks: over the lateral limbus.
const HAIR_PEAK_AT: f64 = 0.65;
/// How far the arch's peak rises over the head's middle, and the tail drops below it (mm).
const HAIR_ARCH_MM: f64 = 2.5;
const HAIR_TAIL_DROP_MM: f64 = 1.5;
/// Half the brow's height at its head and at its tail (mm): a full head, a thin tail.
const HAIR_HEAD_HALF_MM: f64 = 4.5;
const HAIR_TAIL_HALF_MM: f64 = 1.5;

/// From the midline, where the medial share starts to fade (mm): the head of the brow and the
/// skin above it get the full pull.
pub(super) const MEDIAL_FULL_MM: f64 = 14.0;
/// From the midline, where the medial share has faded out (mm): short of the brow's tail,
/// which AU1 leaves (AU2 raises it).
pub(super) const MEDIAL_END_MM: f64 = 42.0;
/// Half the width of the fade across the midline (mm).
pub(super) const MIDLINE_FADE_MM: f64 = 6.0;

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

/// The middle of the eyebrow at `t` along it (0 head, 1 tail), as height above the nasion
/// (mm), and half its height there: it rises from the head to the arch's peak, then falls
/// to the tail, and thins toward the tail.
pub(super) fn hair_band(t: f64) -> (f64, f64) {
    use std::f64::consts::FRAC_PI_2;
    let head = BROW_Y;
    let peak = head + HAIR_ARCH_MM;
    let middle = if t <= HAIR_PEAK_AT {
        head + (peak - head) * (FRAC_PI_2 * t / HAIR_PEAK_AT).sin()
    } else {
        let s = (t - HAIR_PEAK_AT) / (1.0 - HAIR_PEAK_AT);
        peak - (HAIR_ARCH_MM + HAIR_TAIL_DROP_MM) * (1.0 - (FRAC_PI_2 * s).cos())
    };
    let half = HAIR_HEAD_HALF_MM + (HAIR_TAIL_HALF_MM - HAIR_HEAD_HALF_MM) * t.powf(1.5);
    (middle, half)
}

/// Whether a skin point at `x_mm` from the midline and `y_mm` above the nasion lies under
/// an eyebrow.
fn under_hair(x_mm: f64, y_mm: f64) -> bool {
    let t = (x_mm.abs() - HAIR_HEAD_X) / (HAIR_TAIL_X - HAIR_HEAD_X);
    if !(0.0..=1.0).contains(&t) {
        return false;
    }
    let (middle, half) = hair_band(t);
    (y_mm - middle).abs() <= half
}

/// `left_brow_hair` and `right_brow_hair`: the skin vertices (of `skin`, in mesh units)
/// under each eyebrow. They are skin like any other, so the brows move with the skin the
/// muscles move; the renderer draws them in a darker tone.
pub(super) fn hair_groups(skin: &[Vec3], groups: &mut BTreeMap<String, Vec<u32>>) {
    for (i, p) in skin.iter().enumerate() {
        let x = f64::from(p.x) * MM_PER_UNIT;
        let y = f64::from(p.y) * MM_PER_UNIT + Y_ORIGIN_MM;
        if under_hair(x, y) {
            let name = if p.x > 0.0 {
                "left_brow_hair"
            } else {
                "right_brow_hair"
            };
            groups.entry(name.into()).or_default().push(i as u32);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_eyebrow_arches_over_the_eye_and_thins_to_its_tail() {
        let (head, head_half) = hair_band(0.0);
        let (peak, _) = hair_band(HAIR_PEAK_AT);
        let (tail, tail_half) = hair_band(1.0);
        assert!(peak > head && head > tail, "{head} {peak} {tail}");
        assert!(tail_half < head_half);
        assert!(under_hair(HAIR_HEAD_X + 1.0, BROW_Y));
        assert!(under_hair(-(HAIR_HEAD_X + 1.0), BROW_Y));
        assert!(!under_hair(0.0, BROW_Y), "no hair over the glabella");
        assert!(!under_hair(ENDOCANTHION_X + 5.0, 0.0), "no hair on the lid");
    }

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
