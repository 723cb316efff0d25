//! The rigs on the default face: each muscle alone moves the right tissue the right way.

use std::collections::HashMap;

use glam::Vec3;
use grimace::face::{generate, rigs};
use grimace::model::{Activations, BoundRig, Mesh, MuscleKind, Rig};

struct Face {
    mesh: Mesh,
    rig: Rig,
    bound: BoundRig,
}

fn face() -> Face {
    let mesh = generate();
    let rig = rigs::default_rig(&mesh).expect("default rig places");
    let bound = BoundRig::bind(&rig, &mesh).expect("default rig binds");
    Face { mesh, rig, bound }
}

impl Face {
    /// Positions with the named muscles (or `jaw`) at the given activations.
    fn pose(&self, pairs: &[(&str, f32)]) -> Vec<Vec3> {
        let mut act = Activations::zero(&self.rig);
        for &(name, value) in pairs {
            if name == "jaw" {
                act.jaw = value;
            } else {
                let i = self
                    .rig
                    .muscle_index(name)
                    .unwrap_or_else(|| panic!("no muscle {name}"));
                act.muscles[i] = value;
            }
        }
        let mut out = Vec::new();
        self.bound
            .deform(&act, &mut out)
            .expect("valid activations");
        assert!(out.iter().all(|p| p.is_finite()), "non-finite position");
        out
    }

    fn vertex(&self, name: &str) -> usize {
        match self.mesh.groups.get(name).map(Vec::as_slice) {
            Some([v]) => *v as usize,
            _ => panic!("no landmark {name}"),
        }
    }

    /// Displacement of a landmark with one muscle at an activation.
    fn moved(&self, muscle: &str, activation: f32, landmark: &str) -> Vec3 {
        let v = self.vertex(landmark);
        self.pose(&[(muscle, activation)])[v] - self.mesh.positions[v]
    }

    /// Mean displacement of a group's members on one side (the subject's right at x < 0),
    /// for one muscle.
    fn group_moved(&self, muscle: &str, activation: f32, group: &str, right: bool) -> Vec3 {
        let pose = self.pose(&[(muscle, activation)]);
        let members: Vec<usize> = self.mesh.groups[group]
            .iter()
            .map(|&v| v as usize)
            .filter(|&v| (self.mesh.positions[v].x < 0.0) == right)
            .collect();
        let sum: Vec3 = members
            .iter()
            .map(|&v| pose[v] - self.mesh.positions[v])
            .sum();
        sum / members.len() as f32
    }
}

/// Checks that a landmark moves in the expected direction at 1.0 and further at 2.0.
fn check(f: &Face, muscle: &str, landmark: &str, rule: impl Fn(Vec3) -> bool, why: &str) {
    let one = f.moved(muscle, 1.0, landmark);
    let two = f.moved(muscle, 2.0, landmark);
    assert!(
        rule(one),
        "{muscle} at 1.0 should {why} {landmark}: moved {one}"
    );
    assert!(
        rule(two),
        "{muscle} at 2.0 should {why} {landmark}: moved {two}"
    );
    assert!(
        two.length() > one.length() * 1.5,
        "{muscle}: 2.0 should move {landmark} further than 1.0 ({two} vs {one})"
    );
}

#[test]
fn zygomatic_major_lifts_the_mouth_corner_toward_the_cheekbone() {
    let f = face();
    for side in ["L", "R"] {
        let corner = if side == "L" {
            "left_mouth_corner"
        } else {
            "right_mouth_corner"
        };
        let cheek = if side == "L" {
            "left_cheekbone"
        } else {
            "right_cheekbone"
        };
        let muscle = format!("{side}_Zygomatic_Major");
        check(&f, &muscle, corner, |d| d.y > 0.1, "lift");
        let c = f.vertex(corner);
        let before = f.mesh.positions[c].distance(f.mesh.positions[f.vertex(cheek)]);
        let after = f.pose(&[(&muscle, 1.0)])[c].distance(f.mesh.positions[f.vertex(cheek)]);
        assert!(
            after < before - 0.1,
            "{muscle}: corner to cheekbone {before} -> {after}"
        );
        // the other corner stays
        let other = if side == "L" {
            "right_mouth_corner"
        } else {
            "left_mouth_corner"
        };
        assert_eq!(f.moved(&muscle, 2.0, other), Vec3::ZERO);
    }
}

#[test]
fn angular_depressor_pulls_the_mouth_corner_down() {
    let f = face();
    check(
        &f,
        "R_Angular_Depressor",
        "right_mouth_corner",
        |d| d.y < -0.1,
        "lower",
    );
    check(
        &f,
        "L_Angular_Depressor",
        "left_mouth_corner",
        |d| d.y < -0.1,
        "lower",
    );
}

#[test]
fn frontalis_raises_the_brows() {
    let f = face();
    for (muscle, landmark) in [
        ("R_Frontalis_Inner", "right_brow_inner"),
        ("R_Frontalis_Major", "right_brow_centre"),
        ("R_Frontalis_Outer", "right_brow_outer"),
        ("R_Secondary_Frontalis", "right_brow_inner"),
        ("L_Frontalis_Inner", "left_brow_inner"),
        ("L_Frontalis_Outer", "left_brow_outer"),
    ] {
        check(&f, muscle, landmark, |d| d.y > 0.05, "raise");
    }
    // 1.6 at the sheet's range (gain 0.25) is the bare field 0.4
    for landmark in ["right_brow_inner", "right_brow_centre", "right_brow_outer"] {
        let d = f.moved("R_Frontalis_Sheet", 1.6, landmark);
        assert!(
            d.y > 0.1,
            "the right frontalis sheet should raise {landmark}: {d}"
        );
        let lid = f.moved("R_Frontalis_Sheet", 1.6, "right_lower_lid_centre");
        assert_eq!(
            lid,
            Vec3::ZERO,
            "the frontalis must not reach the lower lid"
        );
    }
    check(
        &f,
        "L_Frontalis_Sheet",
        "left_brow_centre",
        |d| d.y > 0.1,
        "raise",
    );
}

#[test]
fn corrugator_and_brow_depressors_pull_the_brows_together_and_down() {
    let f = face();
    check(
        &f,
        "R_Lateral_Corrugator",
        "right_brow_inner",
        |d| d.x > 0.02 && d.y < 0.0,
        "draw in and down",
    );
    check(
        &f,
        "L_Lateral_Corrugator",
        "left_brow_inner",
        |d| d.x < -0.02 && d.y < 0.0,
        "draw in and down",
    );
    check(
        &f,
        "R_Depressor_Supercilii",
        "right_brow_inner",
        |d| d.y < -0.05,
        "lower",
    );
    check(
        &f,
        "Procerus",
        "nasion",
        |d| d.y < -0.02,
        "lower the skin at",
    );
}

#[test]
fn eye_sphincters_close_the_lids_without_pulling_the_corners_in() {
    let f = face();
    for side in ["left", "right"] {
        let muscle = format!(
            "{}_Orbicularis_Oculi",
            if side == "left" { "L" } else { "R" }
        );
        check(
            &f,
            &muscle,
            &format!("{side}_upper_lid_centre"),
            |d| d.y < -0.05,
            "lower",
        );
        check(
            &f,
            &muscle,
            &format!("{side}_lower_lid_centre"),
            // up along the slit's slope, which leans forward: some of the travel is in z
            |d| d.y > 0.0 && d.length() > 0.05,
            "raise",
        );
        for corner in ["inner", "outer"] {
            let d = f.moved(&muscle, 2.0, &format!("{side}_{corner}_eye_corner"));
            assert!(
                d.x.abs() < 1e-6,
                "{muscle} moved the {corner} corner sideways: {d}"
            );
        }
        let pose = f.pose(&[(&muscle, 2.0)]);
        let up = f.vertex(&format!("{side}_upper_lid_centre"));
        let down = f.vertex(&format!("{side}_lower_lid_centre"));
        let rest_gap = f.mesh.positions[up].y - f.mesh.positions[down].y;
        let gap = pose[up].y - pose[down].y;
        assert!(
            gap.abs() < 0.25 * rest_gap,
            "{muscle} at 2.0 leaves the eye open: {gap} of {rest_gap}"
        );
        let squint = f.pose(&[(&muscle, 0.4)]);
        let narrowed = squint[up].y - squint[down].y;
        assert!(
            narrowed < 0.85 * rest_gap,
            "{muscle} at 0.4 should squint visibly"
        );
    }
}

#[test]
fn mouth_sphincter_draws_the_corners_in_and_bulges_the_lips() {
    let f = face();
    check(
        &f,
        "Orbicularis_Oris",
        "right_mouth_corner",
        |d| d.x > 0.05,
        "draw in",
    );
    check(
        &f,
        "Orbicularis_Oris",
        "left_mouth_corner",
        |d| d.x < -0.05,
        "draw in",
    );
    let lip = f.moved("Orbicularis_Oris", 1.0, "upper_lip_centre");
    assert!(lip.z > 0.02, "the lips should bulge forward: {lip}");
}

#[test]
fn jaw_opens_the_mouth_without_tearing_its_corners() {
    let f = face();
    let rest = &f.mesh.positions;
    for k in [1.0, 2.0, 4.0] {
        let pose = f.pose(&[("jaw", k)]);
        let lower = f.vertex("lower_lip_centre");
        let upper = f.vertex("upper_lip_centre");
        let chin = f.vertex("chin");
        let drop = rest[lower].y - pose[lower].y;
        assert!(drop > 0.1 * k, "jaw {k}: lower lip drops");
        let chin_moved = pose[chin] - rest[chin];
        assert!(
            chin_moved.y < 0.0 && chin_moved.z < 0.0 && -chin_moved.y > -1.4 * chin_moved.z,
            "jaw {k}: chin mostly down, a little back: {chin_moved}"
        );
        assert_eq!(pose[upper], rest[upper], "jaw {k}: upper lip stays");
        for corner in ["left_mouth_corner", "right_mouth_corner"] {
            let c = f.vertex(corner);
            let sink = rest[c].y - pose[c].y;
            assert!(
                sink > 0.05 * drop && sink < 0.45 * drop,
                "jaw {k}: {corner} sinks a little: {sink} of {drop}"
            );
            assert_eq!(pose[c].x, rest[c].x, "jaw {k}: {corner} not sideways");
        }
    }
    // at 4.0 the mouth opens as wide as an adult's: 35 to 50 mm at the lips
    let pose = f.pose(&[("jaw", 4.0)]);
    let opening =
        (pose[f.vertex("upper_lip_centre")] - pose[f.vertex("lower_lip_centre")]).length();
    let mm = opening * grimace::face::anthropometry::MM_PER_UNIT as f32;
    assert!((35.0..50.0).contains(&mm), "jaw 4.0 opens the lips {mm} mm");
    // weights: 1 at the lower lip centre and chin; the upper lip moves only near the corners
    let jaw = f.rig.jaw.as_ref().expect("jaw");
    let weight = |v: usize| {
        jaw.weights
            .iter()
            .find(|(i, _)| *i as usize == v)
            .map_or(0.0, |(_, w)| *w)
    };
    assert_eq!(weight(f.vertex("lower_lip_centre")), 1.0);
    assert_eq!(weight(f.vertex("chin")), 1.0);
    let corner_x = rest[f.vertex("left_mouth_corner")].x;
    for &v in &f.mesh.groups["upper_lip"] {
        let v = v as usize;
        let w = weight(v);
        assert!(
            w <= rigs::JAW_CORNER_WEIGHT as f32,
            "upper lip vertex {v} weighs {w}"
        );
        // the corner's weight reaches 12 mm along the upper lip (`face::jaw_skin`)
        if rest[v].x.abs() < 0.5 * corner_x {
            assert_eq!(w, 0.0, "upper lip vertex {v} away from the corners moves");
        }
    }
    // the lower lip's weight falls along a quarter ellipse: still above half at 70 % of the
    // way to the corner, so the opening is an oval, not a crescent
    for &v in &f.mesh.groups["lower_lip"] {
        let v = v as usize;
        let t = rest[v].x.abs() / corner_x;
        if t < 0.7 && rest[v].y < rest[f.vertex("left_mouth_corner")].y {
            assert!(
                weight(v) > 0.5,
                "lower lip vertex {v} at {t} weighs {}",
                weight(v)
            );
        }
    }
}

#[test]
fn added_muscles_move_their_tissue() {
    let f = face();
    check(
        &f,
        "R_Levator_Palpebrae",
        "right_upper_lid_centre",
        |d| d.y > 0.05,
        "raise",
    );
    assert_eq!(
        f.moved("R_Levator_Palpebrae", 2.0, "right_lower_lid_centre"),
        Vec3::ZERO
    );
    check(
        &f,
        "R_Buccinator",
        "right_mouth_corner",
        |d| d.z < -0.02 && d.x < 0.0,
        "draw back",
    );
    check(
        &f,
        "R_Risorius",
        "right_mouth_corner",
        |d| d.x < -0.03 && -d.x > d.y.abs(),
        "stretch",
    );
    check(&f, "R_Mentalis", "chin", |d| d.y > 0.02, "raise");
    check(&f, "L_Mentalis", "chin", |d| d.y > 0.02, "raise");
    let lip = f.group_moved("R_Depressor_Labii_Inferioris", 1.0, "lower_lip", true);
    assert!(
        lip.y < -0.05,
        "depressor labii should lower the lower lip: {lip}"
    );
    let lip = f.group_moved("R_Labii_Nasi", 1.0, "upper_lip", true);
    assert!(lip.y > 0.05, "labii nasi should raise the upper lip: {lip}");
    let lip = f.group_moved("R_Zygomatic_Minor", 1.0, "upper_lip", true);
    assert!(
        lip.y > 0.02,
        "zygomatic minor should raise the upper lip: {lip}"
    );
    check(
        &f,
        "R_Inner_Labii_Nasi",
        "right_alare",
        |d| d.y > 0.02,
        "raise",
    );
    check(
        &f,
        "R_Orbicularis_Oculi_Orbital",
        "right_cheekbone",
        |d| d.y > 0.02,
        "lift",
    );
    check(
        &f,
        "L_Orbicularis_Oculi_Orbital",
        "left_cheekbone",
        |d| d.y > 0.02,
        "lift",
    );
}

#[test]
fn no_linear_muscle_pulls_skin_past_its_attachment() {
    let f = face();
    for (i, muscle) in f.rig.muscles.iter().enumerate() {
        let MuscleKind::Linear(linear) = &muscle.kind else {
            continue;
        };
        let mut act = Activations::zero(&f.rig);
        act.muscles[i] = 2.0;
        let mut pose = Vec::new();
        f.bound.deform(&act, &mut pose).expect("valid");
        let mut moved = 0;
        for (p, q) in f.mesh.positions.iter().zip(&pose) {
            if p == q {
                continue;
            }
            moved += 1;
            let before = *p - linear.attachment;
            let after = *q - linear.attachment;
            assert!(
                before.dot(after) > 0.0,
                "{} at 2.0 pulls a vertex past its attachment",
                muscle.name
            );
        }
        assert!(moved > 0, "{} moves nothing", muscle.name);
    }
}

#[test]
fn mirrored_muscles_give_mirrored_faces() {
    let f = face();
    let key = |p: Vec3| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
    let index: HashMap<_, usize> = f
        .mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| (key(*p), i))
        .collect();
    let twin: Vec<usize> = f
        .mesh
        .positions
        .iter()
        .map(|p| index[&key(Vec3::new(if p.x == 0.0 { 0.0 } else { -p.x }, p.y, p.z))])
        .collect();
    for (i, muscle) in f.rig.muscles.iter().enumerate() {
        let Some(partner) = f.rig.mirror_of(i) else {
            continue;
        };
        let here = f.pose(&[(&muscle.name, 1.3)]);
        let there = f.pose(&[(&f.rig.muscles[partner].name, 1.3)]);
        for v in 0..here.len() {
            let m = there[twin[v]];
            let mirrored = Vec3::new(-m.x, m.y, m.z);
            assert!(
                (here[v] - mirrored).length() < 1e-4,
                "{} and its mirror differ at vertex {v}: {} vs {}",
                muscle.name,
                here[v],
                mirrored
            );
        }
    }
}

#[test]
fn paper_rig_has_the_papers_muscles() {
    let mesh = generate();
    let rig = rigs::paper_rig(&mesh).expect("paper rig places");
    let count = |label: &str| {
        rig.muscles
            .iter()
            .filter(|m| m.kind.label() == label)
            .count()
    };
    assert_eq!(count("linear"), 18);
    assert_eq!(count("sheet"), 2);
    assert_eq!(count("sphincter"), 3);
    assert!(rig.jaw.is_some());
    for (i, m) in rig.muscles.iter().enumerate() {
        if m.name != "Orbicularis_Oris" {
            let partner = rig
                .mirror_of(i)
                .unwrap_or_else(|| panic!("{} has no mirror", m.name));
            assert_eq!(rig.mirror_of(partner), Some(i));
        }
    }
    BoundRig::bind(&rig, &mesh).expect("paper rig binds");
}
