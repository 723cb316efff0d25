//! What an engine loses by blending AU morph targets linearly: for each expression of the
//! built-in table, the face an engine shows (rest plus each AU target's displacement times
//! the AU's intensity factor) against grimace's own deformation of the expression, in
//! millimetres of the built-in face (1 unit = 11.5 mm), with the deformation grimace exports
//! (the skin rules) and with the paper's linear model. docs/gltf.md quotes the printed tables
//! (`cargo test --test cli gltf_blending -- --nocapture`).

use std::path::Path;

use glam::Vec3;
use grimace::facs::combo::parse_combo;
use grimace::io::arkit::ArkitMap;
use grimace::io::morph::{morph_targets, target_states, TargetSet};
use grimace::io::{load_rig, load_table};
use grimace::model::Deformation;

const MM_PER_UNIT: f32 = 11.5;

/// (max, rms over the vertices grimace moves) of |linear - grimace| in mm.
fn blend_error(model: Deformation, expression: &str) -> (f32, f32) {
    let table = load_table(Path::new("presets/default.au.ron")).unwrap();
    let loaded = load_rig(Path::new("presets/default.rig.ron")).unwrap();
    let (rig, mesh) = (&loaded.rig, &loaded.mesh);
    let bound = model.bind(rig, mesh).unwrap();
    let aus = target_states(TargetSet::Aus, rig, &table, &ArkitMap::builtin()).unwrap();
    let targets = morph_targets(&bound, &aus.states).unwrap();
    let combo = parse_combo(&table.expressions[expression]).unwrap();
    let mut linear = mesh.positions.clone();
    for term in &combo.terms {
        let name = grimace::io::morph::au_target_name(&term.key);
        let target = targets.iter().find(|t| t.name == name).unwrap();
        let factor = term.intensity.factor();
        for ((p, t), r) in linear
            .iter_mut()
            .zip(&target.positions)
            .zip(&mesh.positions)
        {
            *p += (*t - *r) * factor;
        }
    }
    let act = table.expression_activations(expression, rig).unwrap();
    let mut own: Vec<Vec3> = Vec::new();
    bound.deform(&act, &mut own).unwrap();
    let (mut max, mut sum, mut moved) = (0.0f32, 0.0f64, 0usize);
    for ((l, g), r) in linear.iter().zip(&own).zip(&mesh.positions) {
        let error = l.distance(*g) * MM_PER_UNIT;
        max = max.max(error);
        if g.distance(*r) > 1e-6 {
            sum += f64::from(error * error);
            moved += 1;
        }
    }
    (max, (sum / moved.max(1) as f64).sqrt() as f32)
}

const EXPRESSIONS: [&str; 7] = [
    "anger",
    "contempt",
    "disgust",
    "fear",
    "happiness",
    "sadness",
    "surprise",
];

/// Prints the table of one deformation; returns the largest error.
fn table(model: Deformation) -> f32 {
    println!("{model}:\n| expression | max error (mm) | RMS over moved vertices (mm) |");
    println!("|---|---|---|");
    let mut worst = 0.0f32;
    for name in EXPRESSIONS {
        let (max, rms) = blend_error(model, name);
        println!("| {name} | {max:.3} | {rms:.3} |");
        assert!(max.is_finite() && rms <= max);
        worst = worst.max(max);
    }
    worst
}

#[test]
fn linear_blending_error_of_the_exported_targets() {
    // The skin rules are not linear in the activations: blends approximate, within a few mm.
    let worst = table(Deformation::Skin);
    assert!(worst < 5.0, "{worst} mm");
}

#[test]
fn linear_blending_error_of_the_paper_model() {
    let worst = table(Deformation::Paper);
    let blend_error = |name| blend_error(Deformation::Paper, name);
    // Muscles are linear in their activation and none of these sums clamps: without the
    // jaw the blend is exact (float rounding only).
    for name in ["anger", "contempt", "disgust", "happiness", "sadness"] {
        assert!(blend_error(name).0 < 1e-3, "{name}");
    }
    // AU 26 turns the jaw: a rotation at a fraction of its angle is not that fraction of
    // the full turn's displacement, and fear (26B) and surprise (26C) show it.
    for name in ["fear", "surprise"] {
        assert!(blend_error(name).0 > 0.1, "{name}");
    }
    assert!(worst < 1.0, "{worst} mm");
}
