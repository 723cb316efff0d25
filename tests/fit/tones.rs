//! Lash lines and lips found from the landmarks on every head (`fit::tones`): on the built-in
//! face where its own lids and lips are, on fitted MediaPipe and MakeHuman heads when their
//! rigs are loaded, moving with the lids; a head without landmarks loads without them.

use glam::Vec3;
use grimace::fit::tones::{LOWER_LID_LINE, UPPER_LID_LINE, VERMILION};
use grimace::landmarks::FaceFrame;
use grimace::model::Mesh;

/// The members of `name`, or a failure naming the head.
fn group<'a>(head: &str, mesh: &'a Mesh, name: &str) -> &'a [u32] {
    mesh.groups
        .get(name)
        .unwrap_or_else(|| panic!("{head}: no {name}"))
}

/// Checks a head's tone groups against its landmarks: each eye's upper line above its lower
/// line, the two sides alike in size, the vermilion between the nose and the chin.
fn check_head(head: &str, mesh: &Mesh, points: &[Vec3]) {
    let frame = FaceFrame::of(points).unwrap();
    let up = |v: u32| mesh.positions[v as usize].as_dvec3().dot(frame.up);
    let mean = |ids: &[u32]| ids.iter().map(|&v| up(v)).sum::<f64>() / ids.len() as f64;
    let mut sizes = Vec::new();
    for side in ["right", "left"] {
        let upper = group(head, mesh, &format!("{side}_{UPPER_LID_LINE}"));
        let lower = group(head, mesh, &format!("{side}_{LOWER_LID_LINE}"));
        println!(
            "{head} {side}: upper {}, lower {}",
            upper.len(),
            lower.len()
        );
        assert!(
            mean(upper) > mean(lower),
            "{head} {side}: upper line below the lower"
        );
        sizes.push(upper.len());
    }
    assert!(
        sizes[0].abs_diff(sizes[1]) * 4 <= sizes[0].max(sizes[1]),
        "{head}: {sizes:?}"
    );
    let lips = group(head, mesh, VERMILION);
    println!("{head}: vermilion {}", lips.len());
    let (nose, chin) = (
        points[33].as_dvec3().dot(frame.up),
        points[8].as_dvec3().dot(frame.up),
    );
    assert!(
        lips.iter().all(|&v| up(v) < nose && up(v) > chin),
        "{head}: lips off the mouth"
    );
}

/// The built-in face's lines lie on its own lid margins and its vermilion on its own lips.
#[test]
fn the_builtin_face_has_lash_lines_on_its_lids_and_vermilion_on_its_lips() {
    let mesh = grimace::io::builtin::default_mesh();
    let points = grimace::io::builtin::landmarks("face")
        .unwrap()
        .positions(&mesh)
        .unwrap();
    check_head("built-in", &mesh, &points);
    for side in ["right", "left"] {
        let own = &mesh.groups[&format!("{side}_upper_lid")];
        let line = group("built-in", &mesh, &format!("{side}_{UPPER_LID_LINE}"));
        let on = own.iter().filter(|v| line.contains(v)).count();
        println!(
            "built-in {side}: {on} of {} margin vertices on the line",
            own.len()
        );
        assert!(on * 10 >= own.len() * 8, "{side}: {on} of {}", own.len());
    }
    let own: Vec<u32> = ["upper_lip", "lower_lip"]
        .iter()
        .flat_map(|n| mesh.groups[*n].iter().copied())
        .collect();
    let lips = group("built-in", &mesh, VERMILION);
    let on = own.iter().filter(|v| lips.contains(v)).count();
    println!(
        "built-in: {on} of {} lip vertices in the vermilion, {} marked",
        own.len(),
        lips.len()
    );
    assert!(on * 10 >= own.len() * 8, "{on} of {}", own.len());
    assert!(lips.len() <= own.len() * 2);
}

/// A fitted MediaPipe mask loads with both eyes' lines and its lips.
#[test]
fn a_fitted_mediapipe_head_loads_with_its_tones() {
    let Some((_dir, loaded, landmarks)) = crate::fitted_mediapipe() else {
        return;
    };
    let points = landmarks.positions(&loaded.mesh).unwrap();
    check_head("MediaPipe", &loaded.mesh, &points);
}

/// MakeHuman's base mesh (lids with a thickness, eyeballs, lashes and helper geometry) gets
/// both eyes' lines and its lips from its landmarks.
#[test]
fn makehuman_gets_its_tones_from_its_landmarks() {
    let Some((_, mut mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let points = landmarks.positions(&mesh).unwrap();
    let vertices = landmarks.vertices(&mesh);
    grimace::fit::tones::mark(&mut mesh, &vertices, &points);
    check_head("MakeHuman", &mesh, &points);
}

/// The upper lash line is on the lid that closes: at AU45 its vertices come down by most of
/// the eye's opening, on the built-in face and on a fitted MediaPipe mask.
#[test]
fn the_lash_line_follows_the_lid_when_it_closes() {
    let face = grimace::io::builtin::default_mesh();
    let points = grimace::io::builtin::landmarks("face")
        .unwrap()
        .positions(&face)
        .unwrap();
    let bound =
        grimace::model::BoundRig::bind(&grimace::io::builtin::default_rig(), &face).unwrap();
    closes_with_the_lid("built-in", &face, &points, &bound);
    if let Some((_dir, loaded, landmarks)) = crate::fitted_mediapipe() {
        let points = landmarks.positions(&loaded.mesh).unwrap();
        let bound = grimace::model::BoundRig::bind(&loaded.rig, &loaded.mesh).unwrap();
        closes_with_the_lid("MediaPipe", &loaded.mesh, &points, &bound);
    }
}

/// Checks that each upper lash line comes down at AU45 by at least half the distance between
/// the upper and the lower line at rest.
fn closes_with_the_lid(head: &str, mesh: &Mesh, points: &[Vec3], bound: &grimace::model::BoundRig) {
    let frame = FaceFrame::of(points).unwrap();
    let closed = crate::positions_at_au(bound, "45");
    let up = |p: Vec3| p.as_dvec3().dot(frame.up);
    let mean = |ids: &[u32], at: &[Vec3]| {
        ids.iter().map(|&v| up(at[v as usize])).sum::<f64>() / ids.len() as f64
    };
    for side in ["right", "left"] {
        let upper = group(head, mesh, &format!("{side}_{UPPER_LID_LINE}"));
        let lower = group(head, mesh, &format!("{side}_{LOWER_LID_LINE}"));
        let opening = mean(upper, &mesh.positions) - mean(lower, &mesh.positions);
        let drop = mean(upper, &mesh.positions) - mean(upper, &closed);
        println!("{head} {side}: opening {opening:.4}, the line came down {drop:.4}");
        assert!(drop >= 0.5 * opening, "{head} {side}: {drop} of {opening}");
    }
}

/// A head whose mesh has no landmarks beside it loads with the mesh's own groups only, so it
/// renders as it did before tones were drawn.
#[test]
fn a_head_without_landmarks_loads_without_tones() {
    let Some((_dir, loaded, _)) = crate::fitted_mediapipe() else {
        return;
    };
    let mesh_path = loaded.mesh_path.clone().unwrap();
    std::fs::remove_file(grimace::io::landmarks::beside(&mesh_path)).unwrap();
    let bare = grimace::io::load::load_rig(&loaded.path).unwrap();
    let own = grimace::io::obj::read_obj(&mesh_path).unwrap();
    assert_eq!(bare.mesh.groups, own.groups);
    assert!(!bare
        .mesh
        .groups
        .keys()
        .any(|name| name.contains(UPPER_LID_LINE) || name.contains(VERMILION)));
}
