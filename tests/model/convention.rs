//! One coordinate convention, glTF's: right-handed, y up, the face toward +z, the subject's
//! left at positive x. A mark on the subject's left is drawn on the viewer's right, `L_`
//! muscles and `L` AUs act at positive x in exported meshes, and version 1 rig files (the
//! subject's left at negative x) are converted on load.

use crate::common;
use grimace::io::load::load_rig;

use std::path::Path;

use glam::Vec3;
use grimace::io::{builtin, obj};
use grimace::model::{Activations, BoundRig, Mesh, MuscleKind, Side, RIG_VERSION};
use grimace::render::{Camera, DotCanvas, Renderer, Scene, Style};

/// A plate facing +z: a band across the whole width (x from -1 to 1, y from -1 to 0) and,
/// on the subject's left only (x from 0.4 to 1), a tab reaching up to y = 1. As a scanner
/// or a glTF asset would have it: the subject's left at positive x.
const ASYMMETRIC_OBJ: &str = "\
v -1 -1 0\nv 1 -1 0\nv 1 0 0\nv -1 0 0\n\
v 0.4 0 0\nv 1 1 0\nv 0.4 1 0\n\
f 1 2 3\nf 1 3 4\nf 5 3 6\nf 5 6 7\n";

fn asymmetric_mesh() -> Mesh {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.obj");
    std::fs::write(&path, ASYMMETRIC_OBJ).unwrap();
    obj::read_obj(&path).unwrap()
}

fn lit_dots(mesh: &Mesh, camera: &Camera) -> (DotCanvas, Vec<(usize, usize)>) {
    let mut canvas = DotCanvas::new(80, 80);
    let scene = Scene::new(mesh, &mesh.positions);
    Renderer::new(mesh).render(&scene, camera, Style::Shaded, &mut canvas);
    let mut dots = Vec::new();
    for y in 0..canvas.height() {
        for x in 0..canvas.width() {
            if canvas.is_on(x, y) {
                dots.push((x, y));
            }
        }
    }
    (canvas, dots)
}

#[test]
fn a_mark_on_the_subjects_left_appears_on_the_viewers_right_in_the_front_view() {
    let mesh = asymmetric_mesh();
    let (canvas, dots) = lit_dots(&mesh, &Camera::front());
    let (w, h) = (canvas.width(), canvas.height());
    // The tab is the upper half of the picture; it is drawn (front faces are not culled)
    // and all of it lies on the viewer's right.
    let tab: Vec<_> = dots.iter().filter(|&&(_, y)| y < h / 2 - 2).collect();
    assert!(tab.len() > 50, "the tab is drawn: {} dots", tab.len());
    assert!(
        tab.iter().all(|&&(x, _)| x > w / 2),
        "the subject's left is on the viewer's right"
    );
    // The band below spans both halves.
    let band = dots.iter().filter(|&&(_, y)| y > h / 2 + 2);
    let (left, right): (Vec<&(usize, usize)>, Vec<_>) = band.partition(|&&(x, _)| x < w / 2);
    assert!(left.len() > 50 && right.len() > 50);
}

#[test]
fn turning_toward_the_subjects_left_brings_positive_x_nearer() {
    let proj = Camera::three_quarter().fit((Vec3::splat(-1.0), Vec3::splat(1.0)), 80, 80, 1.0);
    let left_cheek = proj.project(Vec3::new(1.0, 0.0, 0.0));
    let right_cheek = proj.project(Vec3::new(-1.0, 0.0, 0.0));
    assert!(left_cheek.z > right_cheek.z, "{left_cheek} {right_cheek}");
    // and it stays on the viewer's right, as in the front view
    assert!(left_cheek.x > right_cheek.x);
}

#[test]
fn the_default_face_has_its_left_features_at_positive_x() {
    let mesh = builtin::default_mesh();
    for (left, right) in [
        ("left_mouth_corner", "right_mouth_corner"),
        ("left_upper_lid_centre", "right_upper_lid_centre"),
        ("left_cheekbone", "right_cheekbone"),
    ] {
        let at = |name: &str| mesh.positions[mesh.groups[name][0] as usize];
        assert!(at(left).x > 0.0 && at(right).x < 0.0, "{left} {right}");
    }
    let rig = builtin::default_rig();
    for muscle in &rig.muscles {
        let x = match &muscle.kind {
            MuscleKind::Linear(m) => m.insertion.x,
            MuscleKind::Sphincter(m) => m.centre.x,
            MuscleKind::Sheet(m) => m.insertion[0].x + m.insertion[1].x,
        };
        match muscle.side {
            Side::Left => assert!(x > 0.0, "{} at x = {x}", muscle.name),
            Side::Right => assert!(x < 0.0, "{} at x = {x}", muscle.name),
            Side::Centre => assert_eq!(x, 0.0, "{}", muscle.name),
        }
    }
}

/// The positions `grimace export` writes for `args` on the built-in face.
fn export(dir: &Path, name: &str, args: &[&str]) -> Vec<Vec3> {
    let out = dir.join(name);
    let mut all = vec!["export"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", out.to_str().unwrap()]);
    let result = common::grimace_in(dir, &all);
    assert_eq!(
        result.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    obj::read_obj(&out).unwrap().positions
}

#[test]
fn an_exported_l12_moves_vertices_at_positive_x() {
    let dir = tempfile::tempdir().unwrap();
    let rest = export(dir.path(), "rest.obj", &[]);
    let mesh = builtin::default_mesh();
    let corner = |name: &str| mesh.groups[name][0] as usize;
    for (au, sign, own, other) in [
        ("L12", 1.0, "left_mouth_corner", "right_mouth_corner"),
        ("R12", -1.0, "right_mouth_corner", "left_mouth_corner"),
    ] {
        let smile = export(dir.path(), "smile.obj", &["--au", au]);
        let moved = |v: usize| (smile[v] - rest[v]).length();
        // The zygomatic's cone reaches a little over the midline of the upper lip; nearly
        // all of the motion is on the AU's own side.
        let (mut own_side, mut far_side) = (0.0f32, 0.0f32);
        for (v, p) in rest.iter().enumerate() {
            if p.x * sign > 0.0 {
                own_side += moved(v);
            } else {
                far_side += moved(v);
            }
        }
        assert!(
            own_side > 20.0 * far_side,
            "{au}: {own_side} on its side, {far_side} on the other"
        );
        assert!(rest[corner(own)].x * sign > 0.0);
        assert!(moved(corner(own)) > 0.2, "{au} moves the {own}");
        assert_eq!(moved(corner(other)), 0.0, "{au} leaves the {other}");
    }
}

fn pose(rig: &grimace::model::Rig, mesh: &Mesh, act: &Activations) -> Vec<Vec3> {
    let bound = BoundRig::bind(rig, mesh).unwrap();
    let mut out = Vec::new();
    bound.deform(act, &mut out).unwrap();
    out
}

const OLD_DEFAULT: &str = "tests/old_files/default-v1.rig.ron";

#[test]
fn a_version_1_rig_on_the_built_in_face_is_mirrored_on_load() {
    // The default rig as the previous version wrote it, with its `L_` muscles at x < 0.
    let old = load_rig(Path::new(OLD_DEFAULT)).unwrap();
    let notice = old.notice.as_deref().expect("the conversion is reported");
    assert!(notice.contains("rig version 1 converted"), "{notice}");
    assert_eq!(old.rig.version, RIG_VERSION);
    let mut current = builtin::default_rig();
    // the medial frontalis (AU1's sheet, `face::brow`) and the orbital orbicularis's upper
    // fibres (AU4's sheet, `face::brow_lowering`) came later: the file has neither
    let medial = |name: &str| {
        name.ends_with("_Frontalis_Medial") || name.ends_with("_Orbicularis_Oculi_Superior")
    };
    current.muscles.retain(|m| !medial(&m.name));
    current
        .masks
        .retain(|m| !m.muscles.iter().all(|n| medial(n)));
    for mask in &mut current.masks {
        mask.muscles.retain(|n| !medial(n));
    }
    // the mouth sphincter's bulge and the jaw's joint have changed since that file was
    // written (a stronger pucker, a jaw that slides); the conversion is about positions, so
    // compare with the bulge and the jaw's turn the file has
    for (now, then) in current.muscles.iter_mut().zip(&old.rig.muscles) {
        if let (MuscleKind::Sphincter(a), MuscleKind::Sphincter(b)) = (&mut now.kind, &then.kind) {
            a.bulge = b.bulge;
        }
    }
    // and the closing eye rings have since reached up to the brow, tilted along the slit,
    // with a mask of their own: compare with the rings and the mask the file has
    for name in ["L_Orbicularis_Oculi", "R_Orbicularis_Oculi"] {
        let now = current.muscle_index(name).unwrap();
        let then = old.rig.muscle_index(name).unwrap();
        current.muscles[now].kind = old.rig.muscles[then].kind.clone();
    }
    let closing = |m: &grimace::model::Mask| m.muscles.iter().any(|n| n == "L_Orbicularis_Oculi");
    current.masks.retain(|m| !closing(m));
    current
        .masks
        .extend(old.rig.masks.iter().filter(|m| closing(m)).cloned());
    // and the lip masks have since turned about the mouth corners (`face::rigs`,
    // `lip_side_weight`): compare with the file's
    let lip = |m: &grimace::model::Mask| {
        m.muscles.iter().any(|n| {
            ["Labii_Nasi", "Mentalis", "Depressor_Labii_Inferioris"]
                .iter()
                .any(|base| n.ends_with(&format!("_{base}")) && !n.contains("Inner"))
        })
    };
    current.masks.retain(|m| !lip(m));
    current
        .masks
        .extend(old.rig.masks.iter().filter(|m| lip(m)).cloned());
    // and six muscles have since got a range (`face::rigs`, a gain without weights)
    current.masks.retain(|m| !m.weights.is_empty());
    if let (Some(now), Some(then)) = (&mut current.jaw, &old.rig.jaw) {
        (now.pivot, now.degrees_per_unit, now.slide) =
            (then.pivot, then.degrees_per_unit, then.slide);
        // and its skin weights have since been relaxed (`face::rigs`); the weights' own
        // conversion is `a_version_1_jaw_weight_moves_to_the_mirror_vertex`
        now.weights = then.weights.clone();
    }
    let mesh = builtin::default_mesh();
    assert_eq!(old.mesh.positions, mesh.positions);
    let names = |r: &grimace::model::Rig| -> Vec<String> {
        r.muscles.iter().map(|m| m.name.clone()).collect()
    };
    assert_eq!(names(&old.rig), names(&current));
    // Each muscle alone, and the jaw, move exactly the same vertices the same way.
    for m in 0..current.muscles.len() {
        let mut act = Activations::zero(&current);
        act.muscles[m] = 1.5;
        act.jaw = if m % 4 == 0 { 2.0 } else { 0.0 };
        let got = pose(&old.rig, &mesh, &act);
        let want = pose(&current, &mesh, &act);
        // the skin (the eyeballs came later: the old rig has no mask keeping them still)
        let skin = grimace::face::groups::skin_len(&mesh);
        for (v, (g, w)) in got.iter().zip(&want).enumerate().take(skin) {
            assert!(
                (*g - *w).length() < 1e-6,
                "{} vertex {v}: {g} vs {w}",
                current.muscles[m].name
            );
        }
    }
}

#[test]
fn a_version_1_jaw_weight_moves_to_the_mirror_vertex() {
    let mesh = builtin::default_mesh();
    let corner = |name: &str| mesh.groups[name][0];
    // In version 1 the subject's left mouth corner was the vertex now at negative x.
    let text = format!(
        "(version: 1, mesh: \"builtin:face\", muscles: [], jaw: (pivot: (1, -3, -8), \
         degrees_per_unit: 2, weights: [({}, 0.5)]))",
        corner("right_mouth_corner")
    );
    let rig = grimace::io::parse_rig(&text, Path::new("old.rig.ron")).unwrap();
    let jaw = rig.jaw.unwrap();
    assert_eq!(jaw.weights, vec![(corner("left_mouth_corner"), 0.5)]);
    assert_eq!(jaw.pivot, Vec3::new(-1.0, -3.0, -8.0));
    assert_eq!(jaw.axis, Vec3::X, "a turn about x is its own mirror image");
}

#[test]
fn a_version_1_jaw_about_another_axis_still_opens_the_mouth_the_same_way() {
    let mesh = builtin::default_mesh();
    let chin = mesh.groups["chin"][0];
    let text = |version: u32, axis: Vec3| {
        format!(
            "(version: {version}, mesh: \"builtin:face\", muscles: [], jaw: (pivot: (0, -3, -8), \
             degrees_per_unit: 3, weights: [({chin}, 1)], axis: ({}, {}, {})))",
            axis.x, axis.y, axis.z
        )
    };
    // A tilted axis in the old convention, and its conversion.
    let axis = Vec3::new(1.0, 0.2, 0.1);
    let old = grimace::io::parse_rig(&text(1, axis), Path::new("old.rig.ron")).unwrap();
    let jaw = old.jaw.as_ref().unwrap();
    assert_eq!(jaw.axis, Vec3::new(1.0, -0.2, -0.1));
    // The old chin's motion, mirrored, is the new chin's motion.
    let v1 = grimace::io::parse_rig(&text(2, axis), Path::new("v1-as-is.rig.ron")).unwrap();
    let mut act = Activations::zero(&old);
    act.jaw = 3.0;
    let before = pose(&v1, &mesh, &act)[chin as usize] - mesh.positions[chin as usize];
    let after = pose(&old, &mesh, &act)[chin as usize] - mesh.positions[chin as usize];
    let mirrored = Vec3::new(-before.x, before.y, before.z);
    assert!((after - mirrored).length() < 1e-6, "{after} vs {mirrored}");
    assert!(after.y < -0.1, "the chin still moves down: {after}");
}

#[test]
fn the_default_face_landmarks_are_right_handed_like_meshes_users_bring() {
    let mesh = builtin::default_mesh();
    let points = builtin::landmarks("face")
        .unwrap()
        .positions(&mesh)
        .unwrap();
    let frame = grimace::landmarks::FaceFrame::of(&points).unwrap();
    assert!(frame.right_handed);
    // from the subject's right toward the left: +x
    assert!(frame.lateral.x > 0.99, "{}", frame.lateral);
}

#[test]
fn a_version_1_rig_on_a_mesh_file_keeps_its_geometry() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("plate.obj"), ASYMMETRIC_OBJ).unwrap();
    let body = "mesh: \"plate.obj\", muscles: [(name: \"L_pull\", side: Left, \
                kind: Linear(attachment: (-2, 0, 1), insertion: (-0.5, 0, 0.2), zone: 40, \
                falloff_start: 0.5, falloff_end: 3))]";
    std::fs::write(
        dir.path().join("old.rig.ron"),
        format!("(version: 1, {body})"),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("new.rig.ron"),
        format!("(version: 2, {body})"),
    )
    .unwrap();
    let old = load_rig(&dir.path().join("old.rig.ron")).unwrap();
    let new = load_rig(&dir.path().join("new.rig.ron")).unwrap();
    assert_eq!(old.rig, new.rig);
    assert_eq!(old.mesh, new.mesh);
    assert_eq!(new.notice, None);
    let notice = old.notice.expect("the old version is reported");
    assert!(
        notice.contains("rig version 1 read as version 2") && notice.contains("plate.obj"),
        "{notice}"
    );
}

#[test]
fn the_command_line_says_so_once() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = common::grimace_in(root, &["validate", OLD_DEFAULT]);
    assert_eq!(out.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.matches("warning: ").count(), 1, "{stderr}");
    assert!(stderr.contains("default-v1.rig.ron: rig version 1 converted"));
    let dir = tempfile::tempdir().unwrap();
    let out = common::grimace_in(
        root,
        &[
            "export",
            "--rig",
            OLD_DEFAULT,
            "--out",
            dir.path().join("x.obj").to_str().unwrap(),
        ],
    );
    assert_eq!(out.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.matches("rig version 1").count(), 1, "{stderr}");
}
