//! The default AU table: the AUs and expressions it must hold, and what they do to the face.

use std::collections::HashMap;

use glam::Vec3;
use grimace::facs::combo::parse_combo;
use grimace::facs::{catalogue, AuKey, AuTable, MAX_AUS};
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig, Mesh, Rig, Side};

fn setup() -> (Mesh, Rig, AuTable, BoundRig) {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let table = builtin::default_table();
    let bound = BoundRig::bind(&rig, &mesh).expect("binds");
    (mesh, rig, table, bound)
}

fn pose(bound: &BoundRig, act: &Activations) -> Vec<Vec3> {
    let mut out = Vec::new();
    bound.deform(act, &mut out).expect("valid activations");
    out
}

fn key(text: &str) -> AuKey {
    text.parse().expect("AU key")
}

#[test]
fn holds_the_required_aus_with_their_facs_names() {
    let (_, rig, table, _) = setup();
    assert!(table.aus.len() <= MAX_AUS);
    for n in [
        1, 2, 4, 5, 6, 7, 9, 10, 12, 14, 15, 17, 20, 23, 25, 26, 27, 43, 45, 46,
    ] {
        let entry = table
            .aus
            .get(&AuKey::new(n))
            .unwrap_or_else(|| panic!("AU {n} missing"));
        assert_eq!(
            Some(entry.name.as_str()),
            catalogue::name_of(n),
            "AU {n} name"
        );
    }
    for text in [
        "L12", "R12", "L14", "R14", "L15", "R15", "L20", "R20", "L46", "R46", "L2", "R2",
    ] {
        assert!(table.aus.contains_key(&key(text)), "{text} missing");
    }
    table.check_rig(&rig).expect("table fits the default rig");
}

#[test]
fn every_au_moves_the_face_and_stays_in_range() {
    let (mesh, rig, table, bound) = setup();
    for k in table.aus.keys() {
        let act = table.entry_activations(k, &rig).expect("evaluates");
        act.validate(&rig).expect("activations in range");
        let moved = pose(&bound, &act)
            .iter()
            .zip(&mesh.positions)
            .filter(|(a, b)| (**a - **b).length() > 1e-3)
            .count();
        assert!(moved > 10, "AU {k} moves only {moved} vertices");
    }
}

#[test]
fn unilateral_aus_act_on_their_side_and_mirror_each_other() {
    let (mesh, rig, table, bound) = setup();
    let bits = |p: Vec3| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
    let index: HashMap<_, usize> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| (bits(*p), i))
        .collect();
    let twin = |p: Vec3| index[&bits(Vec3::new(if p.x == 0.0 { 0.0 } else { -p.x }, p.y, p.z))];
    for (k, _) in table.aus.iter().filter(|(k, _)| k.side == Some(Side::Left)) {
        let right = AuKey {
            number: k.number,
            side: Some(Side::Right),
        };
        let l = pose(&bound, &table.entry_activations(k, &rig).expect("L"));
        let r = pose(&bound, &table.entry_activations(&right, &rig).expect("R"));
        let mut left_side = 0.0f32;
        let mut right_side = 0.0f32;
        for (v, rest) in mesh.positions.iter().enumerate() {
            let d = (l[v] - *rest).length();
            // glTF's convention: the subject's left at positive x
            if rest.x > 0.0 {
                left_side += d;
            } else {
                right_side += d;
            }
            let m = r[twin(*rest)];
            assert!(
                (l[v] - Vec3::new(-m.x, m.y, m.z)).length() < 1e-4,
                "{k} and {right} are not mirror images at vertex {v}"
            );
        }
        assert!(
            left_side > 3.0 * right_side,
            "{k} should act on the subject's left"
        );
    }
}

#[test]
fn expressions_are_the_emfacs_prototypes() {
    let (mesh, rig, table, bound) = setup();
    let expected = [
        ("happiness", &[6, 12][..]),
        ("sadness", &[1, 4, 15]),
        ("surprise", &[1, 2, 5, 26]),
        ("fear", &[1, 2, 4, 5, 7, 20, 26]),
        ("anger", &[4, 5, 7, 23]),
        ("disgust", &[9, 15, 16]),
        ("contempt", &[12, 14]),
    ];
    assert_eq!(table.expressions.len(), expected.len());
    for (name, aus) in expected {
        let combo = parse_combo(&table.expressions[name]).expect("parses");
        let mut numbers: Vec<u8> = combo.terms.iter().map(|t| t.key.number).collect();
        numbers.sort_unstable();
        assert_eq!(numbers, aus, "{name}");
        let act = table.evaluate(&combo, &rig).expect("evaluates");
        let moved = pose(&bound, &act)
            .iter()
            .zip(&mesh.positions)
            .filter(|(a, b)| (**a - **b).length() > 1e-3)
            .count();
        assert!(moved > 50, "{name} barely moves the face");
    }
    let contempt = parse_combo(&table.expressions["contempt"]).expect("parses");
    assert!(contempt
        .terms
        .iter()
        .all(|t| t.key.side == Some(Side::Right)));
}

#[test]
fn happiness_lifts_the_mouth_corners_and_sadness_lowers_them() {
    let (mesh, rig, table, bound) = setup();
    let corner = mesh.groups["right_mouth_corner"][0] as usize;
    let brow = mesh.groups["right_brow_inner"][0] as usize;
    let y = |name: &str, v: usize| {
        let act = table.expression_activations(name, &rig).expect("evaluates");
        pose(&bound, &act)[v].y - mesh.positions[v].y
    };
    assert!(y("happiness", corner) > 0.1);
    assert!(y("sadness", corner) < -0.05);
    assert!(y("sadness", brow) > 0.05, "sadness raises the inner brows");
    assert!(y("anger", brow) < -0.05, "anger lowers the brows");
    let lip = mesh.groups["lower_lip_centre"][0] as usize;
    assert!(y("surprise", lip) < -0.2, "surprise drops the jaw");
}
