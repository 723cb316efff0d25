//! The generated default face: topology, symmetry, proportions, and the committed asset.

use std::collections::{BTreeMap, BTreeSet};

use glam::Vec3;
use grimace::face::anthropometry::{units, MM_PER_UNIT};
use grimace::face::topology::boundary_loops;
use grimace::face::{generate, groups};
use grimace::io::presets;
use grimace::model::Mesh;

fn face() -> Mesh {
    generate()
}

fn one(mesh: &Mesh, name: &str) -> Vec3 {
    let members = mesh
        .groups
        .get(name)
        .unwrap_or_else(|| panic!("group {name} missing"));
    assert_eq!(members.len(), 1, "{name} should be one vertex");
    mesh.positions[members[0] as usize]
}

/// Distance in millimetres between two mesh points.
fn mm(a: Vec3, b: Vec3) -> f64 {
    f64::from((a - b).length()) * MM_PER_UNIT
}

#[test]
fn size_is_within_the_brief() {
    let mesh = face();
    let n = mesh.vertex_count();
    assert!((1000..=4500).contains(&n), "{n} vertices");
    mesh.validate().expect("valid mesh");
    let (lo, hi) = mesh.bounds();
    let height = hi.y - lo.y;
    assert!((15.0..17.0).contains(&height), "face height {height} units");
}

#[test]
fn every_edge_is_used_at_most_twice_and_winding_is_consistent() {
    let mesh = face();
    for (edge, (forward, backward)) in mesh.edge_uses() {
        assert!(
            forward <= 1 && backward <= 1,
            "edge {edge:?} used {forward}+{backward} times"
        );
        assert!(forward + backward >= 1);
    }
}

#[test]
fn no_degenerate_or_duplicate_triangles() {
    let mesh = face();
    let mut seen = BTreeSet::new();
    for (i, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        let area = 0.5 * (b - a).cross(c - a).length();
        assert!(area > 1e-4, "triangle {i} has area {area}");
        let mut key = *t;
        key.sort_unstable();
        assert!(seen.insert(key), "triangle {i} repeats {key:?}");
    }
}

#[test]
fn normals_point_out_of_the_face() {
    let mesh = face();
    let normals = mesh.face_normals(&mesh.positions);
    // the head's vertical axis lies about one head depth behind the face
    let axis_z = -units(85.0) as f32;
    let mut inward = 0;
    // the skin's triangles (each eyeball is a closed sphere, facing every way)
    let skin = groups::skin_len(&mesh) as u32;
    for (t, n) in mesh
        .triangles
        .iter()
        .zip(&normals)
        .filter(|(t, _)| t.iter().all(|&v| v < skin))
    {
        let centre = t.iter().map(|&v| mesh.positions[v as usize]).sum::<Vec3>() / 3.0;
        let outward = Vec3::new(centre.x, 0.0, centre.z - axis_z).normalize();
        if n.dot(outward) <= 0.0 {
            inward += 1;
        }
    }
    // the underside of the nose tip faces down and slightly back; nothing else may
    assert!(
        inward * 100 < mesh.triangles.len(),
        "{inward} triangles face inward"
    );
    let front: Vec3 = normals
        .iter()
        .zip(&mesh.triangles)
        .filter(|(_, t)| mesh.positions[t[0] as usize].x.abs() < 2.0)
        .map(|(n, _)| *n)
        .sum();
    assert!(front.z > 0.9 * front.length(), "front normals {front}");
}

#[test]
fn the_only_boundaries_are_the_rim_the_eyes_and_the_mouth() {
    let mesh = face();
    let mut loops = boundary_loops(&mesh);
    assert_eq!(
        loops.len(),
        4,
        "boundary loops: {:?}",
        loops.iter().map(Vec::len).collect::<Vec<_>>()
    );
    loops.sort_by_key(|l| std::cmp::Reverse(l.len()));
    let slit_members = |names: &[&str]| -> BTreeSet<u32> {
        names
            .iter()
            .flat_map(|n| mesh.groups[*n].iter().copied())
            .collect()
    };
    let expected = [
        slit_members(&[
            "left_upper_lid",
            "left_lower_lid",
            "left_inner_eye_corner",
            "left_outer_eye_corner",
        ]),
        slit_members(&[
            "right_upper_lid",
            "right_lower_lid",
            "right_inner_eye_corner",
            "right_outer_eye_corner",
        ]),
    ];
    for lp in &loops[1..] {
        let set: BTreeSet<u32> = lp.iter().copied().collect();
        let is_eye = expected
            .iter()
            .any(|e| e.is_subset(&set) && set.len() == e.len());
        let is_mouth = set.contains(&mesh.groups["left_mouth_corner"][0]);
        assert!(
            is_eye || is_mouth,
            "unexpected hole of {} vertices",
            lp.len()
        );
    }
}

#[test]
fn every_vertex_has_an_exact_mirror_twin() {
    let mesh = face();
    let key = |p: Vec3| (p.y.to_bits(), p.z.to_bits());
    let mut by_yz: BTreeMap<(u32, u32), Vec<f32>> = BTreeMap::new();
    for p in &mesh.positions {
        by_yz.entry(key(*p)).or_default().push(p.x);
    }
    for p in &mesh.positions {
        if p.x.abs() < 1e-6 {
            assert_eq!(p.x, 0.0, "on-plane vertex {p} is not at x = 0 exactly");
        }
        let twins = &by_yz[&key(*p)];
        assert!(
            twins.iter().any(|&x| (x + p.x).abs() <= 1e-6),
            "vertex {p} has no mirror twin"
        );
    }
}

#[test]
fn proportions_follow_farkas_norms() {
    let mesh = face();
    let close = |what: &str, got: f64, want: f64, tol: f64| {
        assert!(
            (got - want).abs() <= tol,
            "{what}: {got:.1} mm, expected {want} +- {tol}"
        );
    };
    let en = mm(
        one(&mesh, "left_inner_eye_corner"),
        one(&mesh, "right_inner_eye_corner"),
    );
    close("en-en", en, 32.0, 3.0);
    let ex = mm(
        one(&mesh, "left_outer_eye_corner"),
        one(&mesh, "right_outer_eye_corner"),
    );
    close("ex-ex", ex, 90.0, 4.0);
    let ch = mm(
        one(&mesh, "left_mouth_corner"),
        one(&mesh, "right_mouth_corner"),
    );
    close("ch-ch", ch, 52.0, 4.0);
    let height = f64::from(one(&mesh, "nasion").y - one(&mesh, "gnathion").y) * MM_PER_UNIT;
    close("n-gn", height, 120.0, 4.0);
    let nose = f64::from(one(&mesh, "nasion").y - one(&mesh, "subnasale").y) * MM_PER_UNIT;
    close("n-sn", nose, 51.0, 4.0);
    let tip = f64::from(one(&mesh, "nose_tip").z - one(&mesh, "subnasale").z) * MM_PER_UNIT;
    assert!(
        tip > 12.0,
        "the nose tip stands only {tip:.1} mm in front of the subnasale"
    );
}

#[test]
fn lids_and_lips_are_separate_and_close() {
    let mesh = face();
    for side in ["left", "right"] {
        let up = one(&mesh, &format!("{side}_upper_lid_centre"));
        let down = one(&mesh, &format!("{side}_lower_lid_centre"));
        let fissure = f64::from(up.y - down.y) * MM_PER_UNIT;
        assert!(
            (7.0..12.0).contains(&fissure),
            "{side} eye fissure {fissure:.1} mm"
        );
        let upper: BTreeSet<u32> = mesh.groups[&format!("{side}_upper_lid")]
            .iter()
            .copied()
            .collect();
        let lower: BTreeSet<u32> = mesh.groups[&format!("{side}_lower_lid")]
            .iter()
            .copied()
            .collect();
        assert!(upper.is_disjoint(&lower));
    }
    let up = one(&mesh, "upper_lip_centre");
    let down = one(&mesh, "lower_lip_centre");
    let gap = mm(up, down);
    assert!(gap > 0.1 && gap < 1.5, "lip gap {gap:.2} mm");
    assert!(up.y > down.y);
}

#[test]
fn groups_are_found_again_after_an_obj_round_trip() {
    let mesh = face();
    let text = presets::mesh_file(&mesh);
    let read = grimace::io::obj::parse_obj(&text, std::path::Path::new("face.obj"))
        .expect("the written face reads back");
    assert_eq!(read.positions, mesh.positions);
    assert_eq!(groups::find_groups_in(&read), mesh.groups);
}

#[test]
fn committed_asset_is_exactly_what_the_generator_writes() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/face.obj");
    let committed = std::fs::read_to_string(&path).expect("assets/face.obj is readable");
    let generated = presets::mesh_file(&face());
    assert!(
        committed == generated,
        "assets/face.obj differs from the generator: run `grimace gen-face --out assets/face.obj`"
    );
}
