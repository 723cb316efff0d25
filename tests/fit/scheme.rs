//! Every landmark set grimace ships follows the iBUG 68 scheme: the built-in face's
//! (`presets/default.landmarks.ron`), the classic Waters face's (written by `import-waters`)
//! and the MediaPipe index table. Each point lies on its side of the face and each contour
//! runs in the scheme's order (`landmarks::order_problems`).

use crate::common;

use glam::Vec3;
use grimace::face::classic;
use grimace::io::waters::{self, ImportOptions};
use grimace::io::{builtin, obj};
use grimace::landmarks::{order_problems, FaceFrame, Landmarks};
use grimace::model::Mesh;

/// The set follows the scheme, and is right-handed (the subject's left at `+lateral` when
/// up and out of the face make a right-handed frame, as in every shipped mesh).
fn follows_the_scheme(what: &str, mesh: &Mesh, landmarks: &Landmarks) {
    let points = landmarks.positions(mesh).unwrap();
    let problems = order_problems(&points);
    assert!(problems.is_empty(), "{what}:\n{}", problems.join("\n"));
    assert!(FaceFrame::of(&points).unwrap().right_handed, "{what}");
}

#[test]
fn the_built_in_landmarks_follow_the_scheme() {
    let mesh = builtin::default_mesh();
    let landmarks = builtin::landmarks("face").unwrap();
    follows_the_scheme("built-in face", &mesh, &landmarks);
    // On the built-in face the subject's left is +x (docs/face.md).
    let points = landmarks.positions(&mesh).unwrap();
    for (i, p) in points.iter().enumerate() {
        let side = f32::from(grimace::landmarks::side(i));
        assert!(side * p.x >= 0.0, "landmark {i} at {p}");
    }
}

#[test]
fn the_classic_landmarks_follow_the_scheme() {
    let Some(shared) = common::shared_with(&["waters-geoface"]) else {
        return;
    };
    let options = ImportOptions {
        drop_duplicate_triangles: false,
        extras: Some(classic::extra_muscles as waters::ExtraMuscles),
    };
    let imported = waters::import_dir(&shared.join("waters-geoface"), &options).unwrap();
    let template = builtin::default_mesh();
    let template_marks = builtin::landmarks("face").unwrap().vertices(&template);
    let marks = classic::ibug_landmarks(&imported.mesh, &template, &template_marks).unwrap();
    follows_the_scheme(
        "classic Waters face",
        &imported.mesh,
        &Landmarks::Vertices(marks),
    );
}

#[test]
fn the_mediapipe_table_follows_the_scheme() {
    let Some(shared) = common::shared_with(&["meshes/mediapipe_canonical_face.obj"]) else {
        return;
    };
    let mesh = obj::read_obj(&shared.join("meshes/mediapipe_canonical_face.obj")).unwrap();
    follows_the_scheme(
        "MediaPipe table",
        &mesh,
        &Landmarks::mediapipe(&mesh).unwrap(),
    );
}

#[test]
fn a_lower_lip_listed_backwards_is_found() {
    let mesh = builtin::default_mesh();
    let mut points = builtin::landmarks("face")
        .unwrap()
        .positions(&mesh)
        .unwrap();
    points[55..60].reverse();
    let problems = order_problems(&points);
    assert!(
        problems.iter().any(|p| p.contains("outer lip line")),
        "{problems:?}"
    );
    assert!(
        problems.iter().any(|p| p.starts_with("landmark 55 ")),
        "{problems:?}"
    );
    // A jaw line given from the left ear to the right is found too.
    let mut points: Vec<Vec3> = builtin::landmarks("face")
        .unwrap()
        .positions(&mesh)
        .unwrap();
    points[0..17].reverse();
    assert!(
        order_problems(&points)
            .iter()
            .any(|p| p.contains("jaw line")),
        "jaw line reversed"
    );
}
