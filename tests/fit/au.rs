//! Fitting AU entries to target shapes: activations the rig itself made come back, shapes no
//! muscle can make are reported as poorly explained, and the command writes tables.

use glam::Vec3;
use grimace::fit::fit_au;
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig, Deformation};

fn bound() -> BoundRig {
    BoundRig::bind(&builtin::default_rig(), &builtin::default_mesh()).unwrap()
}

fn bound_as(model: Deformation) -> BoundRig {
    model
        .bind(&builtin::default_rig(), &builtin::default_mesh())
        .unwrap()
}

fn shape(bound: &BoundRig, act: &Activations) -> Vec<Vec3> {
    let mut out = Vec::new();
    bound.deform(act, &mut out).unwrap();
    out
}

/// Every AU of the built-in table, made by the rig bound with `model`, fitted back: the
/// activations and the positions they give are recovered.
fn table_comes_back(model: Deformation, explained: f64) {
    let bound = bound_as(model);
    let rig = bound.rig().clone();
    let table = builtin::default_table();
    let (mut worst, mut worst_position) = (0.0f32, 0.0f32);
    for key in table.aus.keys() {
        let want = table.entry_activations(key, &rig).unwrap();
        let target = shape(&bound, &want);
        let fit = fit_au(&bound, &target).unwrap();
        let got = &fit.activations;
        let error = got
            .muscles
            .iter()
            .zip(&want.muscles)
            .map(|(a, b)| (a - b).abs())
            .fold((got.jaw - want.jaw).abs(), f32::max);
        let position = shape(&bound, got)
            .iter()
            .zip(&target)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0f32, f32::max);
        worst = worst.max(error);
        worst_position = worst_position.max(position);
        assert!(error < 1e-3, "{model} AU {key}: {got:?} vs {want:?}");
        assert!(position < 1e-3, "{model} AU {key}: a vertex {position} off");
        assert!(fit.explained > explained, "AU {key}: {}", fit.explained);
    }
    println!(
        "{model}: largest activation error over the table {worst:e}, position error {worst_position:e}"
    );
}

#[test]
fn activations_the_rig_made_come_back() {
    table_comes_back(Deformation::Paper, 0.999_999);
}

#[test]
fn activations_the_skin_deformation_made_come_back() {
    table_comes_back(Deformation::Skin, 0.999_99);
}

#[test]
fn mixed_activations_with_the_jaw_come_back() {
    let bound = bound();
    let rig = bound.rig().clone();
    let mut want = Activations::zero(&rig);
    for (name, value) in [
        ("L_Zygomatic_Major", 1.3),
        ("R_Frontalis_Inner", 0.7),
        ("Orbicularis_Oris", 0.4),
        ("L_Levator_Palpebrae", 2.0),
    ] {
        want.muscles[rig.muscle_index(name).unwrap()] = value;
    }
    want.jaw = 2.6;
    let fit = fit_au(&bound, &shape(&bound, &want)).unwrap();
    for (i, (a, b)) in fit
        .activations
        .muscles
        .iter()
        .zip(&want.muscles)
        .enumerate()
    {
        assert!((a - b).abs() < 1e-3, "{}: {a} vs {b}", rig.muscles[i].name);
    }
    assert!(
        (fit.activations.jaw - want.jaw).abs() < 1e-3,
        "jaw {}",
        fit.activations.jaw
    );
}

#[test]
fn a_shape_no_muscle_makes_is_poorly_explained() {
    let bound = bound();
    let rest = bound.rest().to_vec();
    // The whole head shifted sideways and squashed: no muscle moves the back of the head.
    let target: Vec<Vec3> = rest
        .iter()
        .map(|p| *p + Vec3::new(0.3 + 0.1 * p.y, 0.0, -0.05 * p.x))
        .collect();
    let fit = fit_au(&bound, &target).unwrap();
    assert!(fit.explained < 0.2, "explained {}", fit.explained);
    assert!(fit.explained >= 0.0);
}

#[test]
fn a_target_with_another_vertex_count_is_refused() {
    let bound = bound();
    let err = fit_au(&bound, &[Vec3::ZERO; 5]).unwrap_err();
    assert!(err.to_string().contains("5 vertices"), "{err}");
}
