//! The classic Waters linear muscle, one call from rest, against the reference outputs in
//! `../shared/golden` (whole positions, unlisted vertices at rest, 1e-5 per coordinate).
//!
//! Every reference point is converted to grimace's convention as it is read, exactly as the
//! import converts the classic files (`waters::from_classic`, x negated), so the comparison
//! is in grimace's frame.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::Vec3;
use grimace::io::waters::from_classic;
use grimace::model::field::linear_displacement;
use grimace::model::{
    Activations, BoundRig, Combine, Linear, Mesh, Muscle, MuscleKind, Rig, Side, SkinRules,
    RIG_VERSION,
};

const TOLERANCE: f32 = 1e-5;
const ACTIVATIONS: [f32; 5] = [0.25, 0.5, 1.0, 2.0, -0.5];

/// The golden folder, or `None` (with a printed reason) when it is absent outside CI.
fn golden_dir() -> Option<PathBuf> {
    common::shared_with(&["golden/waters-linear.csv"]).map(|shared| shared.join("golden"))
}

/// The data rows of a CSV file, split on commas, header dropped.
fn rows(dir: &Path, name: &str) -> Vec<Vec<String>> {
    let path = dir.join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|s| s.trim().to_string()).collect())
        .collect()
}

fn num(s: &str) -> f32 {
    s.parse()
        .unwrap_or_else(|e| panic!("bad number `{s}`: {e}"))
}

/// A reference point, converted from the classic convention.
fn vec3(row: &[String], at: usize) -> Vec3 {
    from_classic(Vec3::new(
        num(&row[at]),
        num(&row[at + 1]),
        num(&row[at + 2]),
    ))
}

struct Golden {
    mesh: Mesh,
    muscles: Vec<Muscle>,
    /// (muscle, activation bits) -> moved vertex -> position.
    moved: BTreeMap<(usize, u32), BTreeMap<u32, Vec3>>,
}

fn load(dir: &Path) -> Golden {
    let positions: Vec<Vec3> = rows(dir, "waters-vertices.csv")
        .iter()
        .enumerate()
        .map(|(i, r)| {
            assert_eq!(r[0], i.to_string(), "vertices must be numbered in order");
            vec3(r, 1)
        })
        .collect();
    let triangles: Vec<[u32; 3]> = rows(dir, "waters-triangles.csv")
        .iter()
        .map(|r| [1, 2, 3].map(|i| r[i].parse().expect("triangle index")))
        .collect();
    let mesh = Mesh::new(positions, triangles).expect("golden mesh is valid");
    let muscles: Vec<Muscle> = rows(dir, "waters-muscles.csv")
        .iter()
        .map(|r| Muscle {
            name: r[1].clone(),
            side: if r[1].starts_with("L_") {
                Side::Left
            } else {
                Side::Right
            },
            mirror: None,
            kind: MuscleKind::Linear(Linear {
                insertion: vec3(r, 2),
                attachment: vec3(r, 5),
                falloff_start: num(&r[8]),
                falloff_end: num(&r[9]),
                zone: num(&r[10]),
            }),
        })
        .collect();
    assert_eq!(muscles.len(), 18);
    let mut moved: BTreeMap<(usize, u32), BTreeMap<u32, Vec3>> = BTreeMap::new();
    for r in rows(dir, "waters-linear.csv") {
        let muscle: usize = r[0].parse().expect("muscle index");
        let activation = num(&r[2]);
        let vertex: u32 = r[3].parse().expect("vertex");
        moved
            .entry((muscle, activation.to_bits()))
            .or_default()
            .insert(vertex, vec3(&r, 4));
    }
    Golden {
        mesh,
        muscles,
        moved,
    }
}

fn rig_of(g: &Golden) -> Rig {
    Rig {
        masks: Vec::new(),
        version: RIG_VERSION,
        mesh: PathBuf::from("golden"),
        landmarks: None,
        combine: Combine::Sum,
        muscles: g.muscles.clone(),
        jaw: None,
    }
}

/// The largest coordinate difference between `got` and the golden positions of one run.
fn max_error(g: &Golden, muscle: usize, activation: f32, got: &[Vec3]) -> f32 {
    let moved = &g.moved[&(muscle, activation.to_bits())];
    let mut worst = 0.0f32;
    for (v, p) in got.iter().enumerate() {
        let expected = moved
            .get(&(v as u32))
            .copied()
            .unwrap_or(g.mesh.positions[v]);
        worst = worst.max((*p - expected).abs().max_element());
    }
    worst
}

#[test]
fn every_muscle_and_activation_matches_the_classic_routine() {
    let Some(dir) = golden_dir() else { return };
    let g = load(&dir);
    assert_eq!(g.moved.len(), 18 * ACTIVATIONS.len());
    let bound =
        BoundRig::bind_with(&rig_of(&g), &g.mesh, SkinRules::PAPER).expect("golden rig binds");
    let mut worst = 0.0f32;
    for (m, muscle) in g.muscles.iter().enumerate() {
        let MuscleKind::Linear(linear) = &muscle.kind else {
            unreachable!()
        };
        let field = bound.field(m).expect("field");
        for a in ACTIVATIONS {
            // Through the pure per-vertex function.
            let pure: Vec<Vec3> = g
                .mesh
                .positions
                .iter()
                .map(|&p| p + linear_displacement(linear, p, a))
                .collect();
            // Through the precomputed field, scaled (works for a = -0.5 too).
            let mut scaled = g.mesh.positions.clone();
            for (&v, &d) in field.vertices.iter().zip(&field.displacements) {
                scaled[v as usize] += d * a;
            }
            let e_pure = max_error(&g, m, a, &pure);
            let e_field = max_error(&g, m, a, &scaled);
            assert!(
                e_pure <= TOLERANCE && e_field <= TOLERANCE,
                "{} at {a}: max error {e_pure} (pure), {e_field} (field)",
                muscle.name
            );
            worst = worst.max(e_pure).max(e_field);
        }
    }
    eprintln!("golden linear: max abs error {worst:e} over 18 muscles x 5 activations");
}

#[test]
fn bound_rig_deform_matches_for_activations_in_range() {
    let Some(dir) = golden_dir() else { return };
    let g = load(&dir);
    let rig = rig_of(&g);
    let bound = BoundRig::bind_with(&rig, &g.mesh, SkinRules::PAPER).expect("golden rig binds");
    let mut out = Vec::new();
    let mut worst = 0.0f32;
    for m in 0..g.muscles.len() {
        for a in ACTIVATIONS.into_iter().filter(|a| *a >= 0.0) {
            let mut act = Activations::zero(&rig);
            act.muscles[m] = a;
            bound.deform(&act, &mut out).expect("in range");
            let e = max_error(&g, m, a, &out);
            assert!(
                e <= TOLERANCE,
                "{} at {a}: max error {e}",
                g.muscles[m].name
            );
            worst = worst.max(e);
        }
    }
    eprintln!("golden linear through BoundRig::deform: max abs error {worst:e}");
}

#[test]
fn moved_vertex_counts_match_the_readme_table() {
    let Some(dir) = golden_dir() else { return };
    let g = load(&dir);
    let bound =
        BoundRig::bind_with(&rig_of(&g), &g.mesh, SkinRules::PAPER).expect("golden rig binds");
    // The golden README's table: 962 moved (muscle, vertex) pairs per activation.
    assert_eq!(bound.pair_count(), 962);
    for m in 0..18 {
        assert_eq!(
            bound.field(m).expect("field").len(),
            g.moved[&(m, 1.0f32.to_bits())].len(),
            "muscle {m}"
        );
    }
}

/// The end-to-end check: import the classic files with `io::waters`, bind the rig it
/// builds, and deform each muscle alone from rest (through `deform` for activations in range,
/// through the scaled field for -0.5).
#[test]
fn imported_classic_face_matches_the_classic_routine() {
    let Some(dir) = golden_dir() else { return };
    let g = load(&dir);
    let classic = dir.join("../waters-geoface");
    let imported = grimace::io::waters::import_dir(&classic, &Default::default())
        .unwrap_or_else(|e| panic!("import of {}: {e}", classic.display()));
    assert_eq!(imported.mesh.positions, g.mesh.positions);
    assert_eq!(imported.mesh.triangles, g.mesh.triangles);
    let rig = &imported.rig;
    assert_eq!(rig.muscles.len(), 18);
    let bound =
        BoundRig::bind_with(rig, &imported.mesh, SkinRules::PAPER).expect("imported rig binds");
    let mut out = Vec::new();
    let mut worst = 0.0f32;
    for (m, muscle) in g.muscles.iter().enumerate() {
        assert_eq!(rig.muscles[m].name, muscle.name);
        for a in ACTIVATIONS {
            if a >= 0.0 {
                let mut act = Activations::zero(rig);
                act.muscles[m] = a;
                bound.deform(&act, &mut out).expect("in range");
            } else {
                let field = bound.field(m).expect("field");
                out = imported.mesh.positions.clone();
                for (&v, &d) in field.vertices.iter().zip(&field.displacements) {
                    out[v as usize] += d * a;
                }
            }
            let e = max_error(&g, m, a, &out);
            assert!(e <= TOLERANCE, "{} at {a}: max error {e}", muscle.name);
            worst = worst.max(e);
        }
    }
    eprintln!("golden linear through import-waters: max abs error {worst:e}");
}
