//! The default face's eyeballs: appended after the skin, sized like a real eye, never moved
//! by a muscle or the jaw, always behind the lids.

use std::collections::BTreeSet;

use glam::{Vec2, Vec3};
use grimace::face::anthropometry::{units, y_units, MM_PER_UNIT};
use grimace::face::generator::EYEBALL;
use grimace::face::{generate, groups};
use grimace::facs::combo::parse_combo;
use grimace::fit::parts::{find_parts, Part, PartOverrides};
use grimace::io::builtin;
use grimace::io::presets;
use grimace::model::{Activations, BoundRig, Mesh, Rig};

/// Vertices and triangles of the default face before it had eyeballs.
const SKIN_VERTICES: usize = 3463;
const SKIN_TRIANGLES: usize = 6600;
/// FNV-1a of the OBJ lines of those vertices and triangles, as the face without eyeballs
/// wrote them: the skin, and so every vertex number rigs and landmark files use, is unchanged.
const SKIN_FINGERPRINT: u64 = 0x3a0c_da51_13ba_49b4;

fn fnv1a(lines: &[&str]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for line in lines {
        for b in line.bytes().chain([b'\n']) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

fn eyeball_vertices(mesh: &Mesh) -> Vec<u32> {
    groups::still_vertices(mesh)
}

#[test]
fn the_skin_and_its_vertex_numbers_are_unchanged() {
    let mesh = generate();
    let text = presets::mesh_file(&mesh);
    let v: Vec<&str> = text.lines().filter(|l| l.starts_with("v ")).collect();
    let f: Vec<&str> = text.lines().filter(|l| l.starts_with("f ")).collect();
    assert_eq!(groups::skin_len(&mesh), SKIN_VERTICES);
    let skin: Vec<&str> = v[..SKIN_VERTICES]
        .iter()
        .chain(&f[..SKIN_TRIANGLES])
        .copied()
        .collect();
    assert_eq!(
        fnv1a(&skin),
        SKIN_FINGERPRINT,
        "the first {SKIN_VERTICES} vertices or {SKIN_TRIANGLES} triangles changed"
    );
    let eyes = eyeball_vertices(&mesh);
    assert_eq!(eyes.len(), 2 * EYEBALL.vertex_count());
    assert_eq!(
        eyes[0] as usize, SKIN_VERTICES,
        "eyeballs come after the skin"
    );
    // then the mouth's parts, up to the last vertex
    let rigid = groups::rigid_vertices(&mesh);
    assert_eq!(rigid.len(), mesh.vertex_count() - SKIN_VERTICES);
}

#[test]
fn eyeballs_are_closed_spheres_of_an_adult_size() {
    let mesh = generate();
    let eyes: BTreeSet<u32> = eyeball_vertices(&mesh).into_iter().collect();
    // closed: no boundary edge touches an eyeball
    for (a, b) in mesh.boundary_edges() {
        assert!(
            !eyes.contains(&a) && !eyes.contains(&b),
            "open edge {a}-{b} on an eyeball"
        );
    }
    for (side, sign) in [("left", 1.0f32), ("right", -1.0)] {
        let [cx, cy, cz] = EYEBALL.centre;
        let centre = Vec3::new(
            sign * units(cx) as f32,
            y_units(cy) as f32,
            units(cz) as f32,
        );
        let mm = |v: &u32| f64::from((mesh.positions[*v as usize] - centre).length()) * MM_PER_UNIT;
        let ball = &mesh.groups[&format!("{side}_eyeball")];
        let largest = ball.iter().map(mm).fold(0.0, f64::max);
        assert!(
            (largest - 12.0).abs() < 0.05,
            "{side} eyeball radius {largest} mm"
        );
        // the iris: 11.5 mm across, seen from the front
        let iris = &mesh.groups[&format!("{side}_iris")];
        let pupil = &mesh.groups[&format!("{side}_pupil")];
        assert!(!iris.is_empty() && !pupil.is_empty());
        let across = |members: &Vec<u32>| {
            members
                .iter()
                .map(|v| {
                    let p = mesh.positions[*v as usize];
                    f64::from(Vec2::new(p.x - centre.x, p.y - centre.y).length()) * MM_PER_UNIT
                })
                .fold(0.0, f64::max)
        };
        let (iris_r, pupil_r) = (across(iris), across(pupil));
        assert!(
            (5.0..=5.75).contains(&iris_r),
            "{side} iris reaches {iris_r} mm from the axis"
        );
        assert!(pupil_r < 2.0, "{side} pupil reaches {pupil_r} mm");
        assert!(iris.iter().all(|v| ball.contains(v)));
        // every triangle faces out of the eyeball (the iris and pupil sink in, but still
        // face forward)
        let normals = mesh.face_normals(&mesh.positions);
        for (t, n) in mesh.triangles.iter().zip(&normals) {
            if !ball.contains(&t[0]) {
                continue;
            }
            let mid = t.iter().map(|&v| mesh.positions[v as usize]).sum::<Vec3>() / 3.0;
            let out = (mid - centre).normalize();
            assert!(
                n.dot(out) > 0.0 || n.z > 0.0,
                "{side} eyeball triangle {t:?} faces in"
            );
        }
        assert!(pupil.iter().all(|v| !iris.contains(v)));
    }
}

/// Every rig's AUs at full intensity, each muscle alone at 2.0 and the jaw at 4.0 leave the
/// eyeballs exactly where they were.
#[test]
fn eyeballs_never_move() {
    let mesh = builtin::default_mesh();
    let table = builtin::default_table();
    let eyes = eyeball_vertices(&mesh);
    assert!(!eyes.is_empty(), "the built-in face has no eyeballs");
    for rig in [builtin::default_rig(), builtin::paper_rig()] {
        if let Some(jaw) = &rig.jaw {
            for (v, w) in &jaw.weights {
                assert!(
                    !eyes.contains(v) || *w == 0.0,
                    "eyeball vertex {v} turns with the jaw ({w})"
                );
            }
        }
        let bound = BoundRig::bind(&rig, &mesh).expect("rig binds");
        let mut states = Vec::new();
        for key in table.aus.keys() {
            let combo = parse_combo(&format!("{key}E")).expect("AU parses");
            if let Ok(act) = table.evaluate(&combo, &rig) {
                states.push((format!("AU {key}E"), act));
            }
        }
        for (i, muscle) in rig.muscles.iter().enumerate() {
            let mut act = Activations::zero(&rig);
            act.muscles[i] = 2.0;
            states.push((format!("{} at 2.0", muscle.name), act));
        }
        let mut jaw = Activations::zero(&rig);
        jaw.jaw = 4.0;
        states.push(("jaw at 4.0".into(), jaw));
        let mut all = Activations::zero(&rig);
        all.muscles.iter_mut().for_each(|a| *a = 2.0);
        all.jaw = 4.0;
        states.push(("every muscle at 2.0 and the jaw at 4.0".into(), all));
        let mut out = Vec::new();
        for (what, act) in &states {
            bound.deform(act, &mut out).expect("deforms");
            for &v in &eyes {
                let (p, q) = (mesh.positions[v as usize], out[v as usize]);
                assert!(
                    p.to_array().map(f32::to_bits) == q.to_array().map(f32::to_bits),
                    "{what}: eyeball vertex {v} moved from {p} to {q}"
                );
            }
        }
    }
}

/// The highest skin surface over front-view point `(x, y)` at `positions`, if skin covers it.
fn skin_z(mesh: &Mesh, positions: &[Vec3], skin_triangles: usize, at: Vec2) -> Option<f32> {
    let mut best: Option<f32> = None;
    for t in &mesh.triangles[..skin_triangles] {
        let [a, b, c] = t.map(|v| positions[v as usize]);
        let det = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
        if det.abs() < 1e-12 {
            continue;
        }
        let l0 = ((b.y - c.y) * (at.x - c.x) + (c.x - b.x) * (at.y - c.y)) / det;
        let l1 = ((c.y - a.y) * (at.x - c.x) + (a.x - c.x) * (at.y - c.y)) / det;
        let l2 = 1.0 - l0 - l1;
        if l0 < 0.0 || l1 < 0.0 || l2 < 0.0 {
            continue;
        }
        let z = l0 * a.z + l1 * b.z + l2 * c.z;
        if best.is_none_or(|bz| z > bz) {
            best = Some(z);
        }
    }
    best
}

/// For the front half of both eyeballs at `positions`: how many vertices skin covers in the
/// front view, and the smallest depth (mm) by which the skin lies in front of one it covers.
fn cover(mesh: &Mesh, positions: &[Vec3], members: &[u32]) -> (usize, f64) {
    let mut covered = 0;
    let mut nearest = f64::INFINITY;
    let [_, _, cz] = EYEBALL.centre;
    for &v in members {
        let p = positions[v as usize];
        if f64::from(p.z) < units(cz) {
            continue;
        }
        if let Some(z) = skin_z(mesh, positions, SKIN_TRIANGLES, p.truncate()) {
            covered += 1;
            nearest = nearest.min(f64::from(z - p.z) * MM_PER_UNIT);
        }
    }
    (covered, nearest)
}

fn pose(mesh: &Mesh, rig: &Rig, combo: &str) -> Vec<Vec3> {
    let table = builtin::default_table();
    let act = table
        .evaluate(&parse_combo(combo).expect("combo parses"), rig)
        .expect("combo evaluates");
    let mut out = Vec::new();
    BoundRig::bind(rig, mesh)
        .expect("rig binds")
        .deform(&act, &mut out)
        .expect("deforms");
    out
}

/// At rest, at every blink level, with the eye shut, widened or squeezed, the skin lies in
/// front of the eyeball wherever it covers it: the globe never pokes through a lid.
#[test]
fn lids_lie_in_front_of_the_eyeball_at_every_blink_level() {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let eyes = eyeball_vertices(&mesh);
    let (open, rest_gap) = cover(&mesh, &mesh.positions, &eyes);
    assert!(
        rest_gap > 0.0,
        "at rest the eyeball pokes through by {rest_gap} mm"
    );
    let mut shut = 0;
    for combo in [
        "45A", "45B", "45C", "45D", "45E", "43A", "43C", "43E", "5E", "6E", "7E", "6+7E", "1+2+5E",
        "4+7E", "46E",
    ] {
        let positions = pose(&mesh, &rig, combo);
        let (covered, gap) = cover(&mesh, &positions, &eyes);
        assert!(
            gap > 0.0,
            "{combo}: the eyeball pokes through the lid by {:.2} mm",
            -gap
        );
        if combo == "45E" {
            shut = covered;
        }
    }
    // shut, the lids cover all of the eyeball but a thin seam
    let front = eyes
        .iter()
        .filter(|&&v| f64::from(mesh.positions[v as usize].z) >= units(EYEBALL.centre[2]))
        .count();
    assert!(
        shut * 100 >= 97 * front,
        "45E covers {shut} of {front} front eyeball vertices (open: {open})"
    );
}

/// AU5 raises the upper lid: more of the iris shows than at rest, and at AU45 none of it.
#[test]
fn au5_shows_more_of_the_iris_and_a_blink_hides_it() {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let iris: Vec<u32> = ["left_iris", "right_iris"]
        .iter()
        .flat_map(|n| mesh.groups[*n].iter().copied())
        .collect();
    let shown = |positions: &[Vec3]| {
        let (covered, _) = cover(&mesh, positions, &iris);
        iris.len() - covered
    };
    let rest = shown(&mesh.positions);
    let wide = shown(&pose(&mesh, &rig, "5E"));
    let shut = shown(&pose(&mesh, &rig, "45E"));
    assert!(
        rest * 2 > iris.len(),
        "at rest only {rest} of {} iris vertices show",
        iris.len()
    );
    assert!(wide > rest, "AU5 shows {wide} iris vertices, rest {rest}");
    assert!(
        shut * 20 < iris.len(),
        "AU45 still shows {shut} iris vertices"
    );
}

/// Fitting sees the eyeballs as still parts: by their names, and by their pieces when the
/// mesh comes without names (an OBJ file).
#[test]
fn fitting_keeps_the_eyeballs_still() {
    let mesh = builtin::default_mesh();
    let landmarks = builtin::landmarks("face").expect("default landmarks");
    let vertices = landmarks.vertices(&mesh);
    let points = landmarks.positions(&mesh).expect("landmarks on the mesh");
    let rigid = groups::rigid_vertices(&mesh);
    let jaw = groups::jaw_parts(&mesh);
    let mut unnamed = mesh.clone();
    unnamed.groups.clear();
    for m in [&mesh, &unnamed] {
        let parts = find_parts(m, &vertices, &points, &PartOverrides::default());
        for (v, part) in parts.of_vertex.iter().enumerate() {
            let v32 = v as u32;
            // the mouth's lower parts turn with the jaw, the other rigid parts stay
            let expected = if jaw.contains(&v32) {
                Part::Jaw
            } else if rigid.contains(&v32) {
                Part::Still
            } else {
                Part::Skin
            };
            assert_eq!(*part, expected, "vertex {v} (groups: {})", m.groups.len());
        }
    }
}

/// A rig file for the built-in face written before it had eyeballs carries no mask for them;
/// loading it keeps them still all the same.
#[test]
fn a_rig_file_without_the_eyeball_mask_keeps_them_still() {
    let mesh = builtin::default_mesh();
    let eyes = eyeball_vertices(&mesh);
    let rigid = groups::rigid_vertices(&mesh);
    let mut old = builtin::default_rig();
    old.masks.retain(|m| {
        !m.weights
            .iter()
            .any(|(v, _)| eyes.contains(v) && m.weights.len() == rigid.len())
    });
    assert!(
        old.masks.len() < builtin::default_rig().masks.len(),
        "the eyeball mask was not found to remove"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("old.rig.ron");
    std::fs::write(&path, grimace::io::rig_to_ron(&old)).unwrap();
    let loaded = grimace::io::load_rig(&path).expect("the old rig loads");
    let bound = BoundRig::bind(&loaded.rig, &loaded.mesh).expect("rig binds");
    let mut act = Activations::zero(&loaded.rig);
    act.muscles.iter_mut().for_each(|a| *a = 2.0);
    let mut out = Vec::new();
    bound.deform(&act, &mut out).expect("deforms");
    for &v in &eyes {
        assert_eq!(
            out[v as usize], mesh.positions[v as usize],
            "eyeball vertex {v} moved"
        );
    }
    // The mask is not added twice when a rig that has it is loaded.
    assert_eq!(
        loaded.rig.masks.len(),
        builtin::default_rig().masks.len(),
        "masks after loading"
    );
}
