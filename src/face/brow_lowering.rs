//! The brow lowerer's body (AU4): the upper fibres of the orbicularis oculi's orbital part as
//! a sheet pair, `Orbicularis_Oculi_Superior`, that brings the whole eyebrow down, head,
//! middle and tail, over an upper lid that stays.
//!
//! FACS describes AU4 as lowering the eyebrows and pushing the eye cover fold down. The
//! corrugator and the depressor supercilii draw the brow's head down and in; the brow's body
//! and tail come down with the orbital fibres above the orbit's rim, and a face tracker reads
//! a brow lowered only when the whole brow comes down (about 8 mm on the built-in face,
//! `docs/gallery.md`, "What the tracker keys on"). The lid margin is held by the levator and
//! the tarsus, so the lowering fades out there: the skin between the brow's lower edge and
//! the upper lid margin (the eye cover fold) takes the compression.
//!
//! The sheet's own profile (a sine rising from its fixed line) is steepest at the fixed line,
//! which dragged the upper lid down with the brow when the fixed line ran along the lid. So
//! the sheet is long, from below the eyes to above the brow with all four corners at one
//! depth (its pull in the face's plane, nearly even over the brow), and a mask gives the
//! lowering its shape: nothing at or below the upper lid margin, rising evenly to the full
//! pull at the eyebrow's lower edge (an even ramp compresses the fold least), full over the
//! brow, fading out beyond the brow's tail and, like the medial frontalis, across the
//! midline (each side gives the glabella half).

use glam::Vec3;

use super::anthropometry::{units, y_units, MM_PER_UNIT, Y_ORIGIN_MM};
use super::brow::{hair_band, HAIR_HEAD_X, HAIR_TAIL_X, MIDLINE_FADE_MM};
use super::{round3, rounded, surface};
use crate::model::{Mask, Mesh, Sheet};

/// The muscle pair's base name.
pub(super) const NAME: &str = "Orbicularis_Oculi_Superior";

/// The sheet's fixed line, below the eyes (height above the nasion, mm): far enough that the
/// pull over the lids and the brow is nearly even (the mask shapes it).
const ATTACHMENT_Y: f64 = -45.0;
/// The insertion line, along the top of the eyebrows (mm above the nasion).
const INSERTION_Y: f64 = 17.0;
/// Above the insertion line the pull fades out over the forehead's lower part (mm).
const FOREHEAD_FADE_MM: f64 = 20.0;
/// The ends of the sheet's lines (mm from the midline), over the brow's span: within the box
/// of the rig's other anchors, on which the skin spread measures its length
/// (`docs/model.md`), so adding the sheet changes no other muscle's spread field.
const LINES_X: (f64, f64) = (6.0, 54.0);
/// The sheet's width (mm), centred on its lines: from 25 mm across the midline (the mask
/// halves it there) to beyond the temple, so its own side taper falls outside the brow.
const WIDTH_MM: f64 = 110.0;
/// Where the sheet's depth is taken (mm): the skin over the brow's middle, 3 mm under it.
pub(super) const DEPTH_AT: (f64, f64, f64) = (30.0, 11.0, 3.0);
/// Beyond the brow's tail the lowering fades out over this distance (mm), into the temple.
const TAIL_FADE_MM: f64 = 15.0;

/// The left sheet, its four corners at depth `z` (mesh units: the skin under [`DEPTH_AT`],
/// that far under it): attachment and insertion lines across the face at one depth, so the
/// pull lies in the face's plane (`face::rigs` places it and mirrors it).
pub(super) fn sheet(z: f32) -> Sheet {
    let at = |x: f64, y: f64| rounded(Vec3::new(units(x) as f32, y_units(y) as f32, z));
    let axis = units(INSERTION_Y - ATTACHMENT_Y) as f32;
    Sheet {
        attachment: [at(LINES_X.0, ATTACHMENT_Y), at(LINES_X.1, ATTACHMENT_Y)],
        insertion: [at(LINES_X.0, INSERTION_Y), at(LINES_X.1, INSERTION_Y)],
        length: round3(axis + units(FOREHEAD_FADE_MM) as f32),
        width: round3(units(WIDTH_MM) as f32),
    }
}

/// The upper lid margin's height (mm above the nasion) across the eye, from the left eye's
/// margin vertices and corners: piecewise linear in x (mm), held at the corners' heights
/// beyond them.
struct LidLine(Vec<(f64, f64)>);

impl LidLine {
    fn of(mesh: &Mesh) -> Option<LidLine> {
        let margin = mesh.groups.get("left_upper_lid")?;
        let corner = |name: &str| match mesh.groups.get(name).map(Vec::as_slice) {
            Some([v]) => Some(*v),
            _ => None,
        };
        let corners = [
            corner("left_inner_eye_corner")?,
            corner("left_outer_eye_corner")?,
        ];
        let mut points: Vec<(f64, f64)> = margin
            .iter()
            .chain(&corners)
            .map(|&v| mm(mesh.positions[v as usize]))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points.dedup_by(|a, b| a.0 == b.0);
        Some(LidLine(points))
    }

    fn height(&self, x: f64) -> f64 {
        let (first, last) = (self.0[0], self.0[self.0.len() - 1]);
        if x <= first.0 {
            return first.1;
        }
        if x >= last.0 {
            return last.1;
        }
        let k = self.0.partition_point(|p| p.0 <= x);
        let (a, b) = (self.0[k - 1], self.0[k]);
        a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)
    }
}

/// A position as front-view mm: from the midline, above the nasion.
fn mm(p: Vec3) -> (f64, f64) {
    (
        f64::from(p.x) * MM_PER_UNIT,
        f64::from(p.y) * MM_PER_UNIT + Y_ORIGIN_MM,
    )
}

/// The eyebrow's lower edge (mm above the nasion) over `x` mm from the midline: the drawn
/// brow's band, held at its head's and tail's heights beyond them.
fn brow_lower_edge(x: f64) -> f64 {
    let t = ((x - HAIR_HEAD_X) / (HAIR_TAIL_X - HAIR_HEAD_X)).clamp(0.0, 1.0);
    let (middle, half) = hair_band(t);
    middle - half
}

/// The share of the lowering at `(x, y)` mm (x from the midline, the muscle's side
/// positive): 0 at and below the upper lid margin, rising evenly to 1 at the brow's lower
/// edge, fading out beyond the tail and across the midline.
fn lowering_share(lid: &LidLine, x: f64, y: f64) -> f64 {
    let ax = x.abs();
    let (floor, edge) = (lid.height(ax), brow_lower_edge(ax));
    let rise = ((y - floor) / (edge - floor)).clamp(0.0, 1.0);
    let tail = 1.0 - surface::smoothstep(HAIR_TAIL_X, HAIR_TAIL_X + TAIL_FADE_MM, ax);
    let across = surface::smoothstep(-MIDLINE_FADE_MM, MIDLINE_FADE_MM, x);
    rise * tail * across
}

/// The mask shaping muscle `name` (on the side whose x has sign `own_side`): every vertex
/// within the sheet's reach whose share is under 1. `None` without the left eye's upper lid
/// margin and corners.
pub(super) fn mask(mesh: &Mesh, name: &str, own_side: f32) -> Option<Mask> {
    let lid = LidLine::of(mesh)?;
    let reach = ATTACHMENT_Y..=INSERTION_Y + FOREHEAD_FADE_MM;
    let weights = mesh
        .positions
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let (x, y) = mm(*p);
            if !reach.contains(&y) {
                return None;
            }
            let w = round3(lowering_share(&lid, x * f64::from(own_side), y) as f32);
            (w < 1.0).then_some((i as u32, w))
        })
        .collect();
    Some(Mask {
        muscles: vec![name.to_string()],
        gain: 1.0,
        weights,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lowering_rises_from_the_lid_margin_to_the_brow_and_halves_at_the_midline() {
        let lid = LidLine(vec![(16.0, -9.0), (30.0, -3.5), (45.0, -6.5)]);
        assert_eq!(
            lowering_share(&lid, 30.0, -3.5),
            0.0,
            "the lid margin stays"
        );
        assert_eq!(lowering_share(&lid, 30.0, -8.0), 0.0, "the eye stays");
        let edge = brow_lower_edge(30.0);
        assert_eq!(
            lowering_share(&lid, 30.0, edge + 1.0),
            1.0,
            "the brow comes down"
        );
        let half = lowering_share(&lid, 30.0, 0.5 * (edge - 3.5));
        assert!((half - 0.5).abs() < 1e-9, "an even ramp: {half}");
        assert_eq!(lowering_share(&lid, HAIR_TAIL_X + TAIL_FADE_MM, 12.0), 0.0);
        let mid = lowering_share(&lid, 0.0, 20.0);
        assert!((mid - 0.5).abs() < 1e-9, "{mid}");
        assert_eq!(lowering_share(&lid, -MIDLINE_FADE_MM, 20.0), 0.0);
    }
}
