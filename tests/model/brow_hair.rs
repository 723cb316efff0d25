//! The built-in face's eyebrows: skin groups drawn darker (`*_brow_hair`) that move with the
//! skin the brow muscles move, so a lowered or raised brow is visible as a brow.

use crate::au_shapes::{face, MM};

/// Each brow is a band over its eye, the mirror image of the other, above the lids and off
/// the glabella.
#[test]
fn the_builtin_face_has_a_brow_over_each_eye() {
    let f = face();
    let rest = &f.mesh.positions;
    let left = f.group("left_brow_hair");
    let right = f.group("right_brow_hair");
    assert_eq!(left.len(), right.len(), "the brows mirror each other");
    assert!(left.len() >= 20, "a brow of {} vertices", left.len());
    let lid_top = f
        .group("left_upper_lid")
        .iter()
        .map(|&v| rest[v as usize].y)
        .fold(f32::MIN, f32::max);
    for &v in left {
        let p = rest[v as usize];
        assert!(p.x * MM > 8.0, "brow hair {} mm from the midline", p.x * MM);
        assert!(p.y > lid_top, "brow hair below the top of the upper lid");
    }
}

/// AU4 lowers the brows as a whole and draws their heads toward each other: the hair's
/// medial half comes down at least 3 mm and in at least 2 mm (the head of the brow, which
/// the corrugator and procerus move most); AU1 raises the medial half at least 4 mm.
#[test]
fn the_brows_lower_at_au4_and_their_heads_rise_at_au1() {
    let f = face();
    let rest = &f.mesh.positions;
    let head_x = f
        .group("left_brow_hair")
        .iter()
        .map(|&v| rest[v as usize].x)
        .fold(f32::MAX, f32::min);
    let tail_x = f
        .group("left_brow_hair")
        .iter()
        .map(|&v| rest[v as usize].x)
        .fold(f32::MIN, f32::max);
    let middle = 0.5 * (head_x + tail_x);
    let medial = |pose: &[glam::Vec3]| {
        let members: Vec<usize> = f
            .group("left_brow_hair")
            .iter()
            .map(|&v| v as usize)
            .filter(|&v| rest[v].x < middle)
            .collect();
        let sum: glam::Vec3 = members.iter().map(|&v| pose[v] - rest[v]).sum();
        sum * MM / members.len() as f32
    };
    let au4 = medial(&f.combo("4"));
    let au1 = medial(&f.combo("1"));
    let whole = f.region(&f.combo("4"), "left_brow_hair", None);
    println!("AU4: medial brow {au4} mm, whole brow {whole} mm; AU1: medial brow {au1} mm");
    assert!(au4.y <= -3.0, "AU4 lowers the brow's head {} mm", -au4.y);
    assert!(au4.x <= -2.0, "AU4 draws the brow's head in {} mm", -au4.x);
    assert!(whole.y <= -2.0, "AU4 lowers the brow {} mm", -whole.y);
    assert!(au1.y >= 4.0, "AU1 raises the brow's head {} mm", au1.y);
}

/// AU4 brings the whole brow down over a lid that stays: the hair's lateral half (the brow's
/// body and tail) comes down as well as its medial half, each at least 0.2 of the eye's
/// width across (6.1 mm on the built-in eye, 30.6 mm from corner to corner), and the upper
/// lid margin moves under 0.03 of it (0.9 mm). A face tracker reads a brow lowered only when
/// the whole brow comes down (`docs/gallery.md`); before the orbital fibres' sheet, AU4 moved
/// the medial half 0.107 of the eye's width (3.3 mm) and the lateral half 0.003.
#[test]
fn au4_lowers_the_whole_brow_over_a_lid_that_stays() {
    let f = face();
    let rest = &f.mesh.positions;
    let eye = (rest[f.vertex("left_outer_eye_corner")].x
        - rest[f.vertex("left_inner_eye_corner")].x)
        .abs();
    let hair = f.group("left_brow_hair");
    let xs = hair.iter().map(|&v| rest[v as usize].x);
    let middle = 0.5 * (xs.clone().fold(f32::MAX, f32::min) + xs.fold(f32::MIN, f32::max));
    let p = f.combo("4");
    let down = |lateral: bool| {
        let members: Vec<usize> = hair
            .iter()
            .map(|&v| v as usize)
            .filter(|&v| (rest[v].x > middle) == lateral)
            .collect();
        let sum: f32 = members.iter().map(|&v| rest[v].y - p[v].y).sum();
        sum / members.len() as f32 / eye
    };
    let (medial, lateral) = (down(false), down(true));
    let lid = f
        .group("left_upper_lid")
        .iter()
        .map(|&v| p[v as usize].distance(rest[v as usize]) / eye)
        .fold(0.0f32, f32::max);
    println!(
        "AU4 (eye widths of {:.1} mm): brow down {medial:.3} medial, {lateral:.3} lateral; lid margin {lid:.3}",
        eye * MM
    );
    assert!(
        medial >= 0.2,
        "the brow's head comes down {medial:.3} eye widths"
    );
    assert!(
        lateral >= 0.2,
        "the brow's tail comes down {lateral:.3} eye widths"
    );
    assert!(lid < 0.03, "the upper lid margin moves {lid:.3} eye widths");
}
