//! The built-in face's jaw and mouth: the jaw turns about the condyles and slides forward,
//! the lower incisors drop and the lips part by adult amounts, the lower teeth, gum and
//! tongue turn with the jaw while the upper ones stay, and every mouth part is closed and
//! lies behind the lips.

use glam::Vec3;
use grimace::face::anthropometry::MM_PER_UNIT;
use grimace::face::groups;
use grimace::face::mouth::MouthPart;
use grimace::facs::combo::parse_combo;
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig, Mesh, Rig, SkinRules};

/// Sizes are judged against an outer canthal distance of 90 mm (the brief's adult head).
fn mm_scale(mesh: &Mesh) -> f64 {
    let ex = |name: &str| mesh.positions[mesh.groups[name][0] as usize];
    let canthal = ex("left_outer_eye_corner").distance(ex("right_outer_eye_corner"));
    90.0 / f64::from(canthal)
}

/// The face deformed by AU `key` at full intensity (E), as the editor and `render` show it.
fn deformed(mesh: &Mesh, rig: &Rig, key: &str) -> Vec<Vec3> {
    let table = builtin::default_table();
    let combo = parse_combo(&format!("{key}E")).expect("AU parses");
    let act: Activations = table.evaluate(&combo, rig).expect("AU evaluates");
    let bound = BoundRig::bind_with(rig, mesh, SkinRules::DEFAULT).expect("rig binds");
    let mut out = Vec::new();
    bound.deform(&act, &mut out).expect("deforms");
    out
}

/// The lower incisors' edge: the highest front vertex of the lower teeth on the midline.
fn lower_incisor(mesh: &Mesh) -> u32 {
    let teeth = &mesh.groups[MouthPart::LowerTeeth.group()];
    *teeth
        .iter()
        .filter(|&&v| mesh.positions[v as usize].x == 0.0)
        .max_by(|&&a, &&b| {
            let (p, q) = (mesh.positions[a as usize], mesh.positions[b as usize]);
            (p.y + p.z).total_cmp(&(q.y + q.z))
        })
        .expect("lower teeth on the midline")
}

/// The two lip margins on the midline: the mouth slit's upper and lower copy at x = 0.
fn stomion_pair(mesh: &Mesh) -> (u32, u32) {
    let at_midline = |name: &str| {
        *mesh.groups[name]
            .iter()
            .filter(|&&v| mesh.positions[v as usize].x == 0.0)
            .min_by(|&&a, &&b| {
                // the margin is the copy nearest the other lip
                let (p, q) = (mesh.positions[a as usize], mesh.positions[b as usize]);
                let sign = if name == "upper_lip" { 1.0 } else { -1.0 };
                (sign * p.y).total_cmp(&(sign * q.y))
            })
            .expect("lip margin on the midline")
    };
    (at_midline("upper_lip"), at_midline("lower_lip"))
}

/// Incisor drop, lip opening and the chin's motion (down, back) in mm at AU `key`.
fn jaw_numbers(key: &str) -> (f64, f64, f64, f64) {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let out = deformed(&mesh, &rig, key);
    let s = mm_scale(&mesh);
    let incisor = lower_incisor(&mesh) as usize;
    let drop = f64::from(mesh.positions[incisor].y - out[incisor].y) * s;
    let (up, low) = stomion_pair(&mesh);
    let opening = f64::from(out[up as usize].y - out[low as usize].y) * s;
    let chin = mesh.groups["chin"][0] as usize;
    let moved = out[chin] - mesh.positions[chin];
    (
        drop,
        opening,
        -f64::from(moved.y) * s,
        -f64::from(moved.z) * s,
    )
}

#[test]
fn au26_drops_the_lower_incisors_at_least_15_mm() {
    let (drop, opening, down, back) = jaw_numbers("26");
    println!("AU26: incisors drop {drop:.1} mm, lips open {opening:.1} mm, chin {down:.1} down {back:.1} back");
    assert!(drop >= 15.0, "AU26 drops the lower incisors {drop:.1} mm");
    assert!(
        down > 1.5 * back.abs(),
        "AU26 moves the chin {down:.1} mm down, {back:.1} mm back"
    );
}

#[test]
fn au27_opens_the_mouth_35_to_50_mm() {
    let (drop, opening, down, back) = jaw_numbers("27");
    println!("AU27: incisors drop {drop:.1} mm, lips open {opening:.1} mm, chin {down:.1} down {back:.1} back");
    assert!(
        (35.0..=50.0).contains(&opening),
        "AU27 opens the lips {opening:.1} mm"
    );
    assert!(
        down > 1.5 * back.abs(),
        "AU27 moves the chin {down:.1} mm down, {back:.1} mm back"
    );
}

/// At AU26 and AU27 the lower lip follows the jaw and the upper lip stays.
#[test]
fn the_lower_lip_follows_the_jaw_and_the_upper_lip_stays() {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let s = mm_scale(&mesh);
    let (up, low) = stomion_pair(&mesh);
    for key in ["26", "27"] {
        let out = deformed(&mesh, &rig, key);
        let moved = |v: u32| f64::from((out[v as usize] - mesh.positions[v as usize]).length()) * s;
        let incisor = lower_incisor(&mesh);
        assert!(
            moved(up) < 0.15 * moved(low),
            "AU{key}: the upper lip moves {:.1} mm, the lower {:.1} mm",
            moved(up),
            moved(low)
        );
        assert!(
            moved(low) > 0.6 * moved(incisor),
            "AU{key}: the lower lip moves {:.1} mm, the incisors {:.1} mm",
            moved(low),
            moved(incisor)
        );
    }
}

/// The lower teeth, the lower gum and the tongue turn rigidly with the jaw (weight 1); the
/// upper teeth, the upper gum and the back wall stay where they are; no muscle moves any.
#[test]
fn lower_mouth_parts_turn_with_the_jaw_and_upper_ones_stay() {
    let mesh = builtin::default_mesh();
    for rig in [builtin::default_rig(), builtin::paper_rig()] {
        let bound = BoundRig::bind_with(&rig, &mesh, SkinRules::DEFAULT).expect("rig binds");
        let mut all = Activations::zero(&rig);
        all.muscles.iter_mut().for_each(|a| *a = 2.0);
        let mut out = Vec::new();
        bound.deform(&all, &mut out).expect("deforms");
        let rest_with_jaw = {
            let mut jaw_only = Activations::zero(&rig);
            jaw_only.jaw = 4.0;
            let mut o = Vec::new();
            bound.deform(&jaw_only, &mut o).expect("deforms");
            o
        };
        for part in MouthPart::ALL {
            let members = &mesh.groups[part.group()];
            assert!(!members.is_empty(), "no {}", part.group());
            for &v in members {
                let v = v as usize;
                assert_eq!(
                    out[v],
                    mesh.positions[v],
                    "muscles move {} vertex {v}",
                    part.group()
                );
                let travel =
                    f64::from((rest_with_jaw[v] - mesh.positions[v]).length()) * MM_PER_UNIT;
                if part.turns_with_jaw() {
                    assert!(
                        travel > 10.0,
                        "{} vertex {v} moves {travel:.1} mm with the jaw",
                        part.group()
                    );
                } else {
                    assert_eq!(
                        travel,
                        0.0,
                        "{} vertex {v} moves with the jaw",
                        part.group()
                    );
                }
            }
        }
        // rigidly: distances within the lower teeth are kept
        let teeth = &mesh.groups[MouthPart::LowerTeeth.group()];
        let (a, b) = (teeth[0] as usize, teeth[teeth.len() - 1] as usize);
        let before = mesh.positions[a].distance(mesh.positions[b]);
        let after = rest_with_jaw[a].distance(rest_with_jaw[b]);
        assert!(
            (before - after).abs() < 1e-4 * before,
            "{before} -> {after}"
        );
    }
}

/// Each mouth part is closed, lies behind the lips and inside the face's outline, and the
/// groups are found again in the mesh read back from the committed OBJ.
#[test]
fn mouth_parts_are_closed_and_behind_the_lips() {
    let mesh = builtin::default_mesh();
    let boundary: Vec<(u32, u32)> = mesh.boundary_edges();
    let skin = groups::skin_len(&mesh);
    let (up, _) = stomion_pair(&mesh);
    let lips_z = mesh.positions[up as usize].z;
    for part in MouthPart::ALL {
        let members = &mesh.groups[part.group()];
        assert!(members.iter().all(|&v| v as usize >= skin));
        for &(a, b) in &boundary {
            assert!(
                !members.contains(&a) && !members.contains(&b),
                "{} has an open edge {a}-{b}",
                part.group()
            );
        }
        let front = members
            .iter()
            .map(|&v| mesh.positions[v as usize].z)
            .fold(f32::MIN, f32::max);
        assert!(
            f64::from(lips_z - front) * MM_PER_UNIT > 5.0,
            "{} reaches {front} in z, the lips lie at {lips_z}",
            part.group()
        );
    }
    let generated = grimace::face::generate();
    for part in MouthPart::ALL {
        assert_eq!(generated.groups[part.group()], mesh.groups[part.group()]);
    }
}
