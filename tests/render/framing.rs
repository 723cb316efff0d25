//! Framing on a head the user brings: a z-up bust (the face toward -y, a body below it)
//! fitted with `fit-rig` opens upright, facing the viewer, with the face filling the view
//! (framed by the landmarks beside its mesh); glTF export stands it up in y-up viewers.

use std::fmt::Write as _;
use std::path::Path;

use glam::{Vec2, Vec3};
use grimace::io::builtin;
use grimace::render::{Camera, Framing};

use crate::common::grimace_in;

/// The built-in face stood on z (mesh y -> z, mesh z -> -y), with a wide box below it.
fn write_bust(path: &Path) {
    let mesh = builtin::default_mesh();
    let turn = |p: Vec3| Vec3::new(p.x, -p.z, p.y);
    let mut text = String::from("o face\n");
    for p in &mesh.positions {
        let q = turn(*p);
        let _ = writeln!(text, "v {} {} {}", q.x, q.y, q.z);
    }
    let (lo, hi) = mesh.bounds();
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    let n = mesh.positions.len();
    // Shoulders and chest: a box four faces wide and three faces tall under the chin.
    let (x0, x1, y0, y1) = (-2.0 * w, 2.0 * w, lo.z - 1.0 * w, hi.z + 0.2 * w);
    let (z0, z1) = (lo.y - 3.0 * h, lo.y - 0.3 * h);
    for &(x, y, z) in &[
        (x0, y0, z0),
        (x1, y0, z0),
        (x1, y1, z0),
        (x0, y1, z0),
        (x0, y0, z1),
        (x1, y0, z1),
        (x1, y1, z1),
        (x0, y1, z1),
    ] {
        let _ = writeln!(text, "v {x} {y} {z}");
    }
    for [a, b, c] in &mesh.triangles {
        let _ = writeln!(text, "f {} {} {}", a + 1, b + 1, c + 1);
    }
    text.push_str("o body\n");
    let box_faces = [
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [2, 3, 7],
        [2, 7, 6],
        [1, 2, 6],
        [1, 6, 5],
        [3, 0, 4],
        [3, 4, 7],
    ];
    for [a, b, c] in box_faces {
        let _ = writeln!(text, "f {} {} {}", n + a + 1, n + b + 1, n + c + 1);
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn a_fitted_z_up_bust_opens_upright_with_its_face_filling_the_view() {
    let dir = tempfile::tempdir().unwrap();
    write_bust(&dir.path().join("bust.obj"));
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/default.landmarks.ron"),
        dir.path().join("bust.landmarks.ron"),
    )
    .unwrap();
    let fit = grimace_in(
        dir.path(),
        &[
            "fit-rig",
            "bust.obj",
            "--landmarks",
            "bust.landmarks.ron",
            "--out",
            "bust.rig.ron",
        ],
    );
    assert!(
        fit.status.success(),
        "{}",
        String::from_utf8_lossy(&fit.stderr)
    );
    let loaded = grimace::io::load::load_rig(&dir.path().join("bust.rig.ron")).unwrap();
    let (framing, warning) = Framing::of_loaded(&loaded, None);
    assert_eq!(warning, None, "the landmarks beside the mesh are read");
    assert_eq!(framing.basis.row(1), Vec3::Z, "up is the mesh's z");
    assert_eq!(framing.basis.row(2), -Vec3::Y, "the face looks toward -y");
    let focus = framing
        .focus
        .as_deref()
        .expect("the face is framed, not the bust");

    let marks = builtin::landmarks("default")
        .unwrap()
        .vertices(&loaded.mesh);
    let camera = Camera::front().with_basis(framing.basis);
    let (w, h) = (160, 96);
    let projection = camera.fit_points(focus, w, h, 1.0);
    let at = |ids: std::ops::RangeInclusive<usize>| {
        let n = ids.clone().count() as f32;
        ids.map(|i| {
            projection
                .project(loaded.mesh.positions[marks[i] as usize])
                .truncate()
        })
        .sum::<Vec2>()
            / n
    };
    let (right_eye, left_eye, mouth) = (at(36..=41), at(42..=47), at(48..=59));
    let chin = at(8..=8);
    let brows = at(17..=26);
    // Upright and facing: the eyes level, the subject's left on the viewer's right, the
    // eyes above the mouth (screen y grows downward).
    assert!(
        (right_eye.y - left_eye.y).abs() < 0.02 * h as f32,
        "{right_eye} {left_eye}"
    );
    assert!(right_eye.x < left_eye.x, "{right_eye} {left_eye}");
    assert!(
        left_eye.y < mouth.y && mouth.y < chin.y,
        "{left_eye} {mouth} {chin}"
    );
    // Brows to chin fill more than half of the picture's height.
    assert!(
        chin.y - brows.y > 0.5 * h as f32,
        "brows {brows} chin {chin}"
    );

    // glTF stands the bust up in y-up viewers: the node turns mesh z to y.
    let glb = grimace_in(
        dir.path(),
        &[
            "export",
            "--gltf",
            "bust.glb",
            "--rig",
            "bust.rig.ron",
            "--table",
            "builtin:default",
        ],
    );
    assert!(
        glb.status.success(),
        "{}",
        String::from_utf8_lossy(&glb.stderr)
    );
    let doc = gltf::Gltf::from_slice(&std::fs::read(dir.path().join("bust.glb")).unwrap()).unwrap();
    let node = doc.nodes().next().unwrap();
    let (_, rotation, _) = node.transform().decomposed();
    let turned = glam::Quat::from_array(rotation) * Vec3::Z;
    assert!((turned - Vec3::Y).length() < 1e-5, "{turned}");
    let kept = grimace_in(
        dir.path(),
        &[
            "export",
            "--gltf",
            "kept.glb",
            "--keep-axes",
            "--rig",
            "bust.rig.ron",
            "--table",
            "builtin:default",
        ],
    );
    assert!(
        kept.status.success(),
        "{}",
        String::from_utf8_lossy(&kept.stderr)
    );
    let doc = gltf::Gltf::from_slice(&std::fs::read(dir.path().join("kept.glb")).unwrap()).unwrap();
    let (_, rotation, _) = doc.nodes().next().unwrap().transform().decomposed();
    assert_eq!(rotation, [0.0, 0.0, 0.0, 1.0]);

    // A landmark file that no longer reads frames the face from the rig, with a warning:
    // the command still draws.
    std::fs::write(
        dir.path().join("bust.landmarks.ron"),
        "(version: 1, vertices: [1, 2])",
    )
    .unwrap();
    let loaded = grimace::io::load::load_rig(&dir.path().join("bust.rig.ron")).unwrap();
    let (by_rig, warning) = Framing::of_loaded(&loaded, None);
    assert!(warning.is_some_and(|w| w.contains("without the landmarks")));
    assert_eq!(by_rig, Framing::of_rig(&loaded.rig, &loaded.mesh));
    let drawn = grimace_in(dir.path(), &["render", "--rig", "bust.rig.ron"]);
    assert!(drawn.status.success());
    let said = String::from_utf8_lossy(&drawn.stderr);
    assert!(
        said.contains("warning:") && said.contains("bust.landmarks.ron"),
        "{said}"
    );
}

#[test]
fn up_and_front_turn_render_and_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| grimace_in(dir.path(), args);
    // The built-in face told it stands on z: the view turns (the text changes), and back on y
    // it is the default view.
    let default = run(&["render"]);
    let on_y = run(&["render", "--up", "y", "--front", "z"]);
    let on_z = run(&["render", "--up", "z"]);
    assert!(default.status.success() && on_y.status.success() && on_z.status.success());
    assert_eq!(default.stdout, on_y.stdout);
    assert_ne!(default.stdout, on_z.stdout);
    let bad = run(&["render", "--up", "z", "--front", "-z"]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("at right angles"));
    let not_an_axis = run(&["render", "--up", "w"]);
    assert_eq!(not_an_axis.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&not_an_axis.stderr).contains("is not an axis"));
}
