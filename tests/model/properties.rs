//! Properties of the deformation on a small symmetric synthetic face: identity at rest,
//! finiteness, locality, mirror symmetry, continuity across zone borders, the jaw weights,
//! and the single-muscle update.

use std::path::PathBuf;

use glam::Vec3;
use grimace::model::field::{
    linear_displacement, muscle_displacement, sheet_displacement, sphincter_displacement,
    SphincterShape,
};
use grimace::model::{
    Activations, BoundRig, Combine, Convergence, Frame, Jaw, Linear, Mesh, Muscle, MuscleKind, Rig,
    Sheet, Side, SkinRules, Sphincter, RIG_VERSION,
};
use proptest::prelude::*;

/// Grid half-size and step: x, y in -4..=4 by 0.25 (33 x 33 vertices, exactly symmetric).
const STEPS: usize = 33;
const STEP: f32 = 0.25;

/// A dome-shaped grid symmetric in x: vertex (i, j) mirrors to (STEPS - 1 - i, j).
fn dome() -> Mesh {
    dome_of(STEPS, STEP)
}

/// A dome-shaped grid over x, y in -4..=4 with `steps` vertices a side, its cells split
/// along diagonals that mirror across x = 0 (the skin rules read triangles, so a mirrored
/// mesh needs a mirrored triangulation to deform symmetrically).
fn dome_of(steps: usize, step: f32) -> Mesh {
    let mut positions = Vec::with_capacity(steps * steps);
    for j in 0..steps {
        for i in 0..steps {
            let x = -4.0 + step * i as f32;
            let y = -4.0 + step * j as f32;
            positions.push(Vec3::new(x, y, 5.0 - 0.1 * (x * x + y * y)));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..steps - 1 {
        for i in 0..steps - 1 {
            let v = (j * steps + i) as u32;
            let s = steps as u32;
            if 2 * i + 1 < steps {
                triangles.push([v, v + 1, v + s + 1]);
                triangles.push([v, v + s + 1, v + s]);
            } else {
                triangles.push([v, v + 1, v + s]);
                triangles.push([v + 1, v + s + 1, v + s]);
            }
        }
    }
    Mesh::new(positions, triangles).expect("valid dome")
}

/// The vertex mirroring vertex `v` across x = 0.
fn mirror_vertex(v: usize) -> usize {
    let (j, i) = (v / STEPS, v % STEPS);
    j * STEPS + (STEPS - 1 - i)
}

fn flip(p: Vec3) -> Vec3 {
    Vec3::new(-p.x, p.y, p.z)
}

/// The muscle kind mirrored across x = 0.
fn mirror_kind(kind: &MuscleKind) -> MuscleKind {
    match kind {
        MuscleKind::Linear(m) => MuscleKind::Linear(Linear {
            attachment: flip(m.attachment),
            insertion: flip(m.insertion),
            ..m.clone()
        }),
        MuscleKind::Sphincter(m) => MuscleKind::Sphincter(Sphincter {
            centre: flip(m.centre),
            ..m.clone()
        }),
        MuscleKind::Sheet(m) => MuscleKind::Sheet(Sheet {
            attachment: m.attachment.map(flip),
            insertion: m.insertion.map(flip),
            ..m.clone()
        }),
    }
}

fn left_linear() -> Linear {
    Linear {
        attachment: Vec3::new(-3.0, 2.0, 3.0),
        insertion: Vec3::new(-1.5, -0.5, 4.6),
        zone: 40.0,
        falloff_start: 0.5,
        falloff_end: 4.0,
    }
}

/// Attachment line 2.5 above the insertion line; L - |Ac lc| = 1; W = 2.
fn left_sheet() -> Sheet {
    Sheet {
        attachment: [Vec3::new(-3.0, 4.0, 3.0), Vec3::new(-1.0, 4.0, 3.0)],
        insertion: [Vec3::new(-3.0, 1.5, 3.0), Vec3::new(-1.0, 1.5, 3.0)],
        length: 3.5,
        width: 2.0,
    }
}

fn left_eye() -> Sphincter {
    Sphincter {
        centre: Vec3::new(-2.0, 1.0, 4.5),
        semi_major: 1.2,
        semi_minor: 0.6,
        convergence: Convergence::MajorAxis,
        bulge: 30.0,
        frame: Frame::IDENTITY,
    }
}

fn mouth() -> Sphincter {
    Sphincter {
        centre: Vec3::new(0.0, -2.0, 4.6),
        semi_major: 2.0,
        semi_minor: 0.8,
        convergence: Convergence::Centre,
        bulge: 10.0,
        frame: Frame::IDENTITY,
    }
}

/// A symmetric rig: pairs of linear, sheet and eye muscles, a centred mouth and a jaw whose
/// weights fall from 1 on the midline to 0 at |x| = 3.
fn symmetric_rig(combine: Combine) -> Rig {
    let mut muscles = Vec::new();
    for (name, kind) in [
        ("lin", MuscleKind::Linear(left_linear())),
        ("sheet", MuscleKind::Sheet(left_sheet())),
        ("eye", MuscleKind::Sphincter(left_eye())),
    ] {
        muscles.push(Muscle {
            name: format!("L_{name}"),
            side: Side::Left,
            mirror: Some(format!("R_{name}")),
            kind: kind.clone(),
        });
        muscles.push(Muscle {
            name: format!("R_{name}"),
            side: Side::Right,
            mirror: Some(format!("L_{name}")),
            kind: mirror_kind(&kind),
        });
    }
    muscles.push(Muscle {
        name: "mouth".into(),
        side: Side::Centre,
        mirror: None,
        kind: MuscleKind::Sphincter(mouth()),
    });
    let weights = dome()
        .positions
        .iter()
        .enumerate()
        .filter(|(_, p)| p.y < -1.5)
        .map(|(v, p)| (v as u32, (1.0 - p.x.abs() / 3.0).clamp(0.0, 1.0)))
        .collect();
    Rig {
        masks: Vec::new(),
        version: RIG_VERSION,
        mesh: PathBuf::from("dome.obj"),
        landmarks: None,
        combine,
        muscles,
        jaw: Some(Jaw {
            axis: glam::Vec3::X,
            slide: glam::Vec3::ZERO,
            pivot: Vec3::new(0.0, 1.0, -2.0),
            degrees_per_unit: 3.0,
            weights,
        }),
    }
}

/// Activations for the 7 muscles of [`symmetric_rig`], plus the jaw.
fn activations() -> impl Strategy<Value = Activations> {
    (prop::collection::vec(0.0f32..=2.0, 7), 0.0f32..=4.0)
        .prop_map(|(muscles, jaw)| Activations { muscles, jaw })
}

fn combine() -> impl Strategy<Value = Combine> {
    prop_oneof![Just(Combine::Sum), Just(Combine::Average)]
}

fn deformed(bound: &BoundRig, act: &Activations) -> Vec<Vec3> {
    let mut out = Vec::new();
    bound.deform(act, &mut out).expect("activations in range");
    out
}

#[test]
fn zero_activation_is_the_identity() {
    for combine in [Combine::Sum, Combine::Average] {
        let rig = symmetric_rig(combine);
        let bound = BoundRig::bind(&rig, &dome()).expect("binds");
        assert_eq!(deformed(&bound, &Activations::zero(&rig)), dome().positions);
    }
}

#[test]
fn large_meshes_deform_in_parallel_identically() {
    // 257 x 257 vertices: above the parallel threshold. Building the same state one muscle
    // at a time with the single-threaded updates must give the same bits.
    let mesh = dome_of(257, 8.0 / 256.0);
    assert!(mesh.positions.len() >= grimace::model::deform::PARALLEL_MIN_VERTICES);
    for combine in [Combine::Sum, Combine::Average] {
        let mut rig = symmetric_rig(combine);
        rig.jaw = None;
        let bound = BoundRig::bind_with(&rig, &mesh, SkinRules::DEFAULT).expect("binds");
        let target = Activations {
            muscles: vec![1.0, 0.5, 2.0, 0.0, 0.3, 1.7, 0.9],
            jaw: 0.0,
        };
        let mut stepwise = deformed(&bound, &Activations::zero(&rig));
        let mut act = Activations::zero(&rig);
        for m in 0..rig.muscles.len() {
            act.muscles[m] = target.muscles[m];
            bound
                .update_muscle(&act, m, &mut stepwise)
                .expect("in range");
        }
        let full = deformed(&bound, &target);
        assert!(full
            .iter()
            .zip(&stepwise)
            .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)));
        assert_ne!(full, mesh.positions);
    }
}

#[test]
fn every_muscle_of_the_synthetic_rig_moves_something() {
    let rig = symmetric_rig(Combine::Sum);
    let bound = BoundRig::bind(&rig, &dome()).expect("binds");
    for m in 0..rig.muscles.len() {
        let n = bound.field(m).expect("field").len();
        assert!(n >= 8, "{} moves only {n} vertices", rig.muscles[m].name);
    }
}

#[test]
fn frontalis_sheet_raises_the_brow() {
    let rig = symmetric_rig(Combine::Sum);
    let bound = BoundRig::bind(&rig, &dome()).expect("binds");
    let field = bound.field(2).expect("L_sheet");
    assert!(field.displacements.iter().all(|d| d.y > 0.0 && d.x == 0.0));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn deformation_is_finite_for_activations_in_range(act in activations(), c in combine()) {
        let bound = BoundRig::bind(&symmetric_rig(c), &dome()).expect("binds");
        prop_assert!(deformed(&bound, &act).iter().all(|p| p.is_finite()));
    }

    #[test]
    fn random_valid_muscles_stay_finite_and_rest_at_zero(
        zone in 1.0f32..89.0,
        fs in 0.0f32..3.0,
        reach in 0.01f32..6.0,
        lx in 0.01f32..5.0,
        ly in 0.01f32..5.0,
        bulge in 0.01f32..50.0,
        extra in 0.01f32..5.0,
        width in 0.01f32..8.0,
        a in 0.0f32..=2.0,
        jaw in 0.0f32..=4.0,
    ) {
        let mesh = dome();
        let kinds = [
            MuscleKind::Linear(Linear { zone, falloff_start: fs, falloff_end: fs + reach, ..left_linear() }),
            MuscleKind::Sphincter(Sphincter { semi_major: lx, semi_minor: ly, bulge, ..mouth() }),
            MuscleKind::Sphincter(Sphincter { semi_major: lx, semi_minor: ly, bulge, ..left_eye() }),
            MuscleKind::Sheet(Sheet { length: 2.5 + extra, width, ..left_sheet() }),
        ];
        let muscles: Vec<Muscle> = kinds.iter().enumerate().map(|(i, kind)| Muscle {
            name: format!("m{i}"), side: Side::Centre, mirror: None, kind: kind.clone(),
        }).collect();
        let rig = Rig { muscles, ..symmetric_rig(Combine::Sum) };
        let bound = BoundRig::bind(&rig, &mesh).expect("valid parameters bind");
        let act = Activations { muscles: vec![a; 4], jaw };
        prop_assert!(deformed(&bound, &act).iter().all(|p| p.is_finite()));
        // Zero activation is the identity whatever the parameters.
        let rest = Activations { muscles: vec![0.0; 4], jaw: 0.0 };
        prop_assert_eq!(deformed(&bound, &rest), mesh.positions);
    }

    #[test]
    fn vertices_outside_every_zone_never_move(act in activations(), c in combine()) {
        let rig = symmetric_rig(c);
        let bound = BoundRig::bind(&rig, &dome()).expect("binds");
        let jaw = rig.jaw.as_ref().expect("jaw");
        let out = deformed(&bound, &act);
        let rest = dome().positions;
        let mut untouched = 0;
        for v in 0..rest.len() {
            let in_field = (0..rig.muscles.len())
                .any(|m| bound.field(m).expect("field").vertices.contains(&(v as u32)));
            let in_jaw = jaw.weights.iter().any(|&(j, w)| j as usize == v && w > 0.0);
            if !in_field && !in_jaw {
                prop_assert_eq!(out[v], rest[v]);
                untouched += 1;
            }
        }
        prop_assert!(untouched > 100);
    }

    #[test]
    fn points_outside_a_linear_cone_or_reach_never_move(
        x in -8.0f32..8.0, y in -8.0f32..8.0, z in -8.0f32..8.0, a in 0.0f32..=2.0,
    ) {
        let m = left_linear();
        let p = Vec3::new(x, y, z);
        let d = (p - m.attachment).as_dvec3();
        let axis = (m.insertion - m.attachment).as_dvec3().normalize();
        let cos_a = axis.dot(d) / d.length();
        // Margins keep the test's own rounding away from the borders.
        if d.length() > m.falloff_end as f64 + 1e-4
            || cos_a < (m.zone as f64).to_radians().cos() - 1e-6
        {
            prop_assert_eq!(linear_displacement(&m, p, a), Vec3::ZERO);
        }
    }

    #[test]
    fn points_outside_an_ellipse_or_sheet_never_move(
        x in -8.0f32..8.0, y in -8.0f32..8.0, z in -8.0f32..8.0, a in 0.0f32..=2.0,
    ) {
        let p = Vec3::new(x, y, z);
        for s in [mouth(), left_eye()] {
            let e = ((p.x - s.centre.x) / s.semi_major).hypot((p.y - s.centre.y) / s.semi_minor);
            if e > 1.0 + 1e-5 {
                prop_assert_eq!(sphincter_displacement(&s, p, a), Vec3::ZERO);
            }
        }
        // The left sheet covers x in -3..-1 (width 2 around x = -2) and y in 4 down to 0.5.
        let s = left_sheet();
        if !(-3.0 - 1e-4..=-1.0 + 1e-4).contains(&p.x) || !(0.5 - 1e-4..=4.0 + 1e-4).contains(&p.y) {
            prop_assert_eq!(sheet_displacement(&s, p, a), Vec3::ZERO);
        }
    }

    #[test]
    fn mirrored_activations_give_a_mirrored_mesh(act in activations(), c in combine()) {
        let rig = symmetric_rig(c);
        let bound = BoundRig::bind_with(&rig, &dome(), SkinRules::DEFAULT).expect("binds");
        let mut swapped = act.clone();
        for m in 0..rig.muscles.len() {
            let partner = rig.mirror_of(m).unwrap_or(m);
            swapped.muscles[partner] = act.muscles[m];
        }
        let out = deformed(&bound, &act);
        let mirrored = deformed(&bound, &swapped);
        for v in 0..out.len() {
            let want = flip(out[mirror_vertex(v)]);
            prop_assert!(
                (mirrored[v] - want).abs().max_element() <= 1e-5,
                "vertex {v}: {} vs mirrored {}", mirrored[v], want
            );
        }
    }

    #[test]
    fn jaw_weight_zero_means_no_jaw_movement(act in activations(), c in combine()) {
        let rig = symmetric_rig(c);
        let bound = BoundRig::bind(&rig, &dome()).expect("binds");
        let jaw = rig.jaw.as_ref().expect("jaw");
        let still = Activations { jaw: 0.0, ..act.clone() };
        let with_jaw = deformed(&bound, &act);
        let without = deformed(&bound, &still);
        let mut moved = 0;
        for v in 0..with_jaw.len() {
            let weight = jaw.weights.iter().find(|&&(j, _)| j as usize == v).map_or(0.0, |w| w.1);
            if weight == 0.0 {
                prop_assert_eq!(with_jaw[v], without[v]);
            } else if act.jaw > 0.5 && with_jaw[v] != without[v] {
                moved += 1;
            }
        }
        if act.jaw > 0.5 {
            prop_assert!(moved > 10, "only {moved} jaw vertices moved");
        }
    }

    #[test]
    fn update_muscle_equals_a_full_deform(
        before in activations(), m in 0usize..7, value in 0.0f32..=2.0, c in combine(),
    ) {
        let bound = BoundRig::bind_with(&symmetric_rig(c), &dome(), SkinRules::DEFAULT).expect("binds");
        let mut out = deformed(&bound, &before);
        let mut after = before.clone();
        after.muscles[m] = value;
        bound.update_muscle(&after, m, &mut out).expect("in range");
        let full = deformed(&bound, &after);
        for (v, (a, b)) in out.iter().zip(&full).enumerate() {
            prop_assert_eq!(a.to_array().map(f32::to_bits), b.to_array().map(f32::to_bits), "vertex {}", v);
        }
    }

    #[test]
    fn update_jaw_equals_a_full_deform(before in activations(), jaw in 0.0f32..=4.0, c in combine()) {
        let bound = BoundRig::bind_with(&symmetric_rig(c), &dome(), SkinRules::DEFAULT).expect("binds");
        let mut out = deformed(&bound, &before);
        let after = Activations { jaw, ..before.clone() };
        bound.update_jaw(&after, &mut out).expect("in range");
        let full = deformed(&bound, &after);
        for (v, (a, b)) in out.iter().zip(&full).enumerate() {
            prop_assert_eq!(a.to_array().map(f32::to_bits), b.to_array().map(f32::to_bits), "vertex {}", v);
        }
    }

    #[test]
    fn deform_equals_pure_displacements_summed_then_the_jaw(act in activations()) {
        // An independent evaluation: each muscle's pure function at each rest vertex,
        // summed (Sum mode), then eqs. 16-19 written out here (the paper's deformation,
        // without the skin rules).
        let rig = symmetric_rig(Combine::Sum);
        let bound = BoundRig::bind_with(&rig, &dome(), SkinRules::PAPER).expect("binds");
        let out = deformed(&bound, &act);
        let jaw = rig.jaw.as_ref().expect("jaw");
        let theta = (act.jaw as f64 * jaw.degrees_per_unit as f64).to_radians();
        for (v, rest) in dome().positions.iter().enumerate() {
            let mut p = *rest;
            for (m, &a) in rig.muscles.iter().zip(&act.muscles) {
                p += muscle_displacement(&m.kind, *rest, a);
            }
            if let Some(&(_, w)) = jaw.weights.iter().find(|&&(j, _)| j as usize == v) {
                let (y, z) = ((p.y - jaw.pivot.y) as f64, (p.z - jaw.pivot.z) as f64);
                let ry = jaw.pivot.y as f64 + theta.cos() * y - theta.sin() * z;
                let rz = jaw.pivot.z as f64 + theta.sin() * y + theta.cos() * z;
                let w = w as f64;
                p.y = (w * ry + (1.0 - w) * p.y as f64) as f32;
                p.z = (w * rz + (1.0 - w) * p.z as f64) as f32;
            }
            prop_assert!((out[v] - p).abs().max_element() <= 1e-5, "vertex {}: {} vs {}", v, out[v], p);
        }
    }

    #[test]
    fn each_kind_is_linear_in_its_activation(
        x in -4.0f32..4.0, y in -4.0f32..4.0, a in -2.0f32..=2.0,
    ) {
        let p = Vec3::new(x, y, 5.0 - 0.1 * (x * x + y * y));
        for kind in symmetric_rig(Combine::Sum).muscles.iter().map(|m| &m.kind) {
            let unit = muscle_displacement(kind, p, 1.0);
            prop_assert_eq!(muscle_displacement(kind, p, a), unit * a);
        }
    }
}

// Continuity across zone borders.
//
// Every field is zero on the outer side of each border and Lipschitz near it (each factor is
// a smooth function of the position that reaches 0 on the border; see docs/model.md). For
// probe points a distance h apart across a border, |difference| <= 2 (activation) x L x h.
// The slopes L for the parameters used here, per unit activation:
// - cone edge: |dk/dangle| r <= tan(zone) = 0.84 (zone 40);
// - falloff end: |k| (pi/2) fe / (fe - fs) <= 0.31 x 1.57 x 4 / 3.5 = 0.55;
// - ellipse rim: |grad f| (1 + 1/Z) <= (1/ly) x 1.1 = 1.8 (eye), 1.4 (mouth);
// - mouth disc edge: f / (lx - ly) <= 1/1.2 = 0.83;
// - sheet ends: (pi/2) / |Ac lc| = 0.63 and (pi/2) / (L - |Ac lc|) = 1.57;
// - sheet side taper: (pi/2) / (taper width 0.25) = 6.3.
// We use L = 7 for all, so the bound is 14 h plus 1e-6 for f32 rounding.
const SLOPE: f32 = 7.0;

fn across(inside: Vec3, outside: Vec3, kind: &MuscleKind, a: f32) -> Result<(), TestCaseError> {
    let h = (inside - outside).length();
    let jump =
        (muscle_displacement(kind, inside, a) - muscle_displacement(kind, outside, a)).length();
    prop_assert!(
        jump <= 2.0 * SLOPE * h + 1e-6,
        "jump {jump} across a border for points {h} apart ({inside} / {outside})"
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn continuous_across_the_cone_edge_and_falloff_end(
        turn in 0.0f64..std::f64::consts::TAU,
        along in 0.3f64..3.7,
        h in 1e-4f64..1e-2,
        a in 0.0f32..=2.0,
    ) {
        let m = left_linear();
        let kind = MuscleKind::Linear(m.clone());
        let origin = m.attachment.as_dvec3();
        let axis = (m.insertion - m.attachment).as_dvec3().normalize();
        let side = axis.any_orthonormal_vector();
        let perp = side * turn.cos() + axis.cross(side) * turn.sin();
        let zone = (m.zone as f64).to_radians();
        // Cone edge: the same distance from the attachment, angles zone -/+ h/(2r).
        let ray = |angle: f64, r: f64| (origin + (axis * angle.cos() + perp * angle.sin()) * r).as_vec3();
        let dt = h / (2.0 * along);
        across(ray(zone - dt, along), ray(zone + dt, along), &kind, a)?;
        // Falloff end: inside the cone, radii fe -/+ h/2.
        let fe = m.falloff_end as f64;
        let angle = zone * (along / 4.0);
        across(ray(angle, fe - h / 2.0), ray(angle, fe + h / 2.0), &kind, a)?;
    }

    #[test]
    fn continuous_across_the_ellipse_rims_and_the_mouth_disc(
        turn in 0.0f64..std::f64::consts::TAU,
        h in 1e-4f64..1e-2,
        a in 0.0f32..=2.0,
    ) {
        for s in [mouth(), left_eye()] {
            let kind = MuscleKind::Sphincter(s.clone());
            let c = s.centre.as_dvec3();
            let (lx, ly) = (s.semi_major as f64, s.semi_minor as f64);
            let at = |scale: f64| {
                (c + glam::DVec3::new(lx * scale * turn.cos(), ly * scale * turn.sin(), 0.0)).as_vec3()
            };
            // Radial scale steps of h / lx move the point by at most h.
            across(at(1.0 - h / (2.0 * lx)), at(1.0 + h / (2.0 * lx)), &kind, a)?;
        }
        // The protected disc's edge (radius ly) of the mouth.
        let s = mouth();
        let kind = MuscleKind::Sphincter(s.clone());
        let ly = s.semi_minor as f64;
        let dir = glam::DVec3::new(turn.cos(), turn.sin(), 0.0);
        let at = |r: f64| (s.centre.as_dvec3() + dir * r).as_vec3();
        across(at(ly - h / 2.0), at(ly + h / 2.0), &kind, a)?;
    }

    #[test]
    fn continuous_across_the_sheet_borders(
        x in -3.0f32..-1.0,
        y in 0.5f32..4.0,
        h in 1e-3f32..1e-2,
        a in 0.0f32..=2.0,
    ) {
        let kind = MuscleKind::Sheet(left_sheet());
        let z = 3.0;
        // Attachment line (y = 4), far end (y = 4 - 3.5 = 0.5), sides (x = -3, x = -1).
        across(Vec3::new(x, 4.0 - h / 2.0, z), Vec3::new(x, 4.0 + h / 2.0, z), &kind, a)?;
        across(Vec3::new(x, 0.5 + h / 2.0, z), Vec3::new(x, 0.5 - h / 2.0, z), &kind, a)?;
        across(Vec3::new(-3.0 + h / 2.0, y, z), Vec3::new(-3.0 - h / 2.0, y, z), &kind, a)?;
        across(Vec3::new(-1.0 - h / 2.0, y, z), Vec3::new(-1.0 + h / 2.0, y, z), &kind, a)?;
        // The insertion line (lambda = 1) is interior: both sides of it are continuous too.
        across(Vec3::new(x, 1.5 + h / 2.0, z), Vec3::new(x, 1.5 - h / 2.0, z), &kind, a)?;
    }
}

/// The paper's eq. 2 read literally (`D = f g` outside the disc, `g = d / lx`) jumps at the
/// disc's edge; the implemented reading `D = f (d - ly)/(lx - ly)` does not. Pinned here.
#[test]
fn mouth_disc_edge_is_continuous_where_the_literal_reading_jumps() {
    let s = mouth();
    let shape = SphincterShape::new(&s);
    let (lx, ly) = (s.semi_major as f64, s.semi_minor as f64);
    // On the major axis just outside the disc, the literal reading gives f g.
    let f = shape.ellipse_factor(ly, 0.0);
    let literal = f * (ly / lx);
    // f = 1 - 0.8/2 = 0.6, g = 0.8/2 = 0.4: a jump of 0.24 per unit activation.
    assert!((literal - 0.24).abs() < 1e-6, "{literal}");
    let just_outside = s.centre + Vec3::new(s.semi_minor + 1e-4, 0.0, 0.0);
    let inplane = sphincter_displacement(&s, just_outside, 1.0)
        .truncate()
        .length() as f64;
    assert!(
        inplane < 1e-4,
        "in-plane pull just outside the disc is {inplane}"
    );
    assert!(literal > 0.2, "the literal reading would jump by {literal}");
}

/// The built-in rigs bind to the built-in face, and the extremes of every range stay finite.
#[test]
fn builtin_rigs_bind_and_stay_finite_at_full_activation() {
    let mesh = grimace::io::builtin::default_mesh();
    for rig in [
        grimace::io::builtin::default_rig(),
        grimace::io::builtin::paper_rig(),
    ] {
        let bound = BoundRig::bind(&rig, &mesh).expect("built-in rig binds");
        let full = Activations {
            muscles: vec![2.0; rig.muscles.len()],
            jaw: 4.0,
        };
        let out = deformed(&bound, &full);
        assert!(out.iter().all(|p| p.is_finite()));
        assert_ne!(out, mesh.positions);
        assert_eq!(deformed(&bound, &Activations::zero(&rig)), mesh.positions);
        for m in 0..rig.muscles.len() {
            assert!(
                !bound.field(m).expect("field").is_empty(),
                "built-in muscle `{}` moves no vertex",
                rig.muscles[m].name
            );
        }
    }
}
