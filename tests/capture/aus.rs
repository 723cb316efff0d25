//! AU intensities derived from solved landmark motion (`capture --aus`): each AU read where
//! FACS scores it.

use glam::{DVec3, Vec3};
use grimace::capture::{AuProjection, LandmarkModel};
use grimace::model::Activations;

/// The built-in face, its landmark model and the built-in table's projection.
fn projection() -> (grimace::model::BoundRig, LandmarkModel) {
    let face = crate::synthetic::face();
    let model = LandmarkModel::new(&face.bound, &face.vertices);
    (face.bound, model)
}

/// The AU intensity (0-5) `number` for the landmark motion of `muscles` and `jaw`.
fn au_of(number: u8, muscles: &[(&str, f32)], jaw: f32) -> f64 {
    let (bound, model) = projection();
    let table = grimace::io::builtin::default_table();
    let projection = AuProjection::new(&table, &bound, &model);
    let rig = bound.rig();
    let mut act = Activations::zero(rig);
    for (name, value) in muscles {
        act.muscles[rig.muscle_index(name).unwrap()] = *value;
    }
    act.jaw = jaw;
    let mut scratch: Vec<Vec3> = Vec::new();
    let motion: Vec<DVec3> = model.displacement(&bound, &act, &mut scratch);
    let k = projection
        .numbers()
        .iter()
        .position(|&n| n == number)
        .unwrap();
    projection.intensities(&motion)[k]
}

#[test]
fn lips_parted_by_the_lower_lip_alone_read_as_lips_part() {
    // The lower lip's depressors part the lips with the jaw at rest: FACS scores AU25 (with
    // AU16). The joint fit gave it all to AU16, whose entry is these muscles alone.
    let depressors = [
        ("L_Depressor_Labii_Inferioris", 0.8),
        ("R_Depressor_Labii_Inferioris", 0.8),
    ];
    let parted = au_of(25, &depressors, 0.0);
    assert!(
        parted > 1.0,
        "AU25 {parted:.2} for lips parted without the jaw"
    );
    assert_eq!(au_of(25, &[], 0.0), 0.0, "rest reads no AU25");
}

#[test]
fn lips_part_follows_the_inner_lips_not_the_jaw() {
    // The same jaw drop, once with the lips left to part and once held together by the lip
    // sphincter: the lips' part is less when they are held.
    let open = au_of(25, &[], 0.5);
    let held = au_of(
        25,
        &[
            ("Orbicularis_Oris", 2.0),
            ("Orbicularis_Oris_Marginal", 2.0),
        ],
        0.5,
    );
    assert!(open > 0.5, "AU25 {open:.2} for a jaw drop with lips parted");
    assert!(
        held < open - 0.2,
        "lips held: AU25 {held:.2}, parted: {open:.2}"
    );
}

#[test]
fn the_jaw_reads_as_jaw_drop_whatever_the_lower_lip_does() {
    // The table's own AU25 (lower-lip depressors and a little jaw): its jaw is still a jaw
    // drop. The joint fit matched the whole entry to AU25 and left AU26 at 0.
    let depressors = [
        ("L_Depressor_Labii_Inferioris", 0.6),
        ("R_Depressor_Labii_Inferioris", 0.6),
    ];
    let alone = au_of(26, &[], 0.8);
    let with_lips = au_of(26, &depressors, 0.8);
    assert!(alone > 1.0, "AU26 {alone:.2} for a jaw drop");
    assert!(
        with_lips > 0.7 * alone,
        "AU26 {with_lips:.2} with the lower lip down, {alone:.2} without"
    );
}

#[test]
fn lips_part_is_read_on_both_contours_of_the_lips() {
    // A rig's inner-lip points can lag their lip (on a real recording the default rig's
    // smile parts the inner lips less than the subject's, docs/capture.md): the table's AU25
    // with its inner-lip points held where they rest still reads as lips part, from the
    // outer contour, and the whole entry reads in full.
    let (bound, model) = projection();
    let table = grimace::io::builtin::default_table();
    let projection = AuProjection::new(&table, &bound, &model);
    let act = table
        .entry_activations(&grimace::facs::AuKey::new(25), bound.rig())
        .unwrap();
    let mut scratch: Vec<Vec3> = Vec::new();
    let full: Vec<DVec3> = model.displacement(&bound, &act, &mut scratch);
    let mut outer_only = full.clone();
    outer_only[60..68].fill(DVec3::ZERO);
    let k = projection.numbers().iter().position(|&n| n == 25).unwrap();
    let whole = projection.intensities(&full)[k];
    let outer = projection.intensities(&outer_only)[k];
    assert!(
        (whole - 5.0).abs() < 1e-6,
        "the entry itself reads {whole:.2}"
    );
    assert!(
        outer > 1.5 && outer < whole,
        "inner lips held: AU25 {outer:.2} of {whole:.2}"
    );
}
