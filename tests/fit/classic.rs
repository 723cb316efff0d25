//! The classic Waters face's landmarks, written by `grimace import-waters` from the built-in
//! face's by a warp onto the features found in the classic mesh, and a rig fitted with them.

use crate::common;

use std::path::Path;

use glam::Vec3;
use grimace::face::classic::{self, FOUND_IBUG};
use grimace::io::landmarks::load_landmarks;
use grimace::io::obj;
use grimace::landmarks::mirror;

use common::grimace_in;

fn ok(dir: &Path, args: &[&str]) -> String {
    let out = grimace_in(dir, args);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "grimace {args:?}: {stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

#[test]
fn import_waters_writes_landmarks_that_fit_the_default_rig() {
    let Some(shared) = common::shared_with(&["waters-geoface"]) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = shared.join("waters-geoface");
    ok(
        d,
        &["import-waters", data.to_str().unwrap(), "--out", "classic"],
    );
    let mesh_path = d.join("classic/mesh.obj");
    let marks_path = d.join("classic/mesh.landmarks.ron");
    let out = ok(
        d,
        &["validate", "classic/mesh.landmarks.ron", "classic/mesh.obj"],
    );
    assert!(out.contains("68 points"), "{out}");

    let mesh = obj::read_obj(&mesh_path).unwrap();
    let v = load_landmarks(&marks_path).unwrap().vertices(&mesh);
    let at = |i: usize| mesh.positions[v[i] as usize];
    // The points found in the classic mesh are kept exactly.
    let found = classic::found_ibug(&mesh).unwrap();
    for (k, &i) in FOUND_IBUG.iter().enumerate() {
        assert_eq!(v[i], found[k], "landmark {i}");
    }
    // Eye corners and mouth corners are mirror pairs, the subject's right at x < 0.
    let size = mesh.bounds().1 - mesh.bounds().0;
    for i in [36, 39, 48] {
        let (a, b) = (at(i), at(mirror(i)));
        let gap = (a * Vec3::new(-1.0, 1.0, 1.0)).distance(b);
        assert!(a.x < 0.0 && gap < 0.01 * size.y, "{i}: {a} vs {b}");
    }
    // Every landmark is a mirror of its partner within 1% of the face's height.
    let mut worst = 0.0f32;
    for i in 0..68 {
        let (a, b) = (at(i), at(mirror(i)));
        let gap = (a * Vec3::new(-1.0, 1.0, 1.0)).distance(b);
        assert!(gap < 0.01 * size.y, "{i}: {a} vs {b}: {gap}");
        worst = worst.max(gap / size.y);
    }
    eprintln!(
        "largest left-right mismatch: {:.2}% of the face's height",
        100.0 * worst
    );
    // The chin is the lowest landmark; the brows are above the eyes, the nose between eyes
    // and mouth.
    for i in 0..68 {
        assert!(
            at(8).y <= at(i).y,
            "landmark {i} at {} below the chin",
            at(i)
        );
    }
    assert!(at(19).y > at(37).y && at(24).y > at(44).y);
    assert!(at(30).y < at(39).y && at(30).y > at(51).y);

    // The default rig fits to the classic face with them, and AU 12 pulls the mouth corners
    // up and outward.
    let out = ok(
        d,
        &[
            "fit-rig",
            "classic/mesh.obj",
            "--landmarks",
            "classic/mesh.landmarks.ron",
            "--out",
            "classic/fit.rig.ron",
        ],
    );
    assert!(out.contains("478 vertices"), "{out}");
    ok(
        d,
        &[
            "export",
            "--rig",
            "classic/fit.rig.ron",
            "--table",
            "builtin:default",
            "--au",
            "12",
            "--out",
            "smile.obj",
        ],
    );
    let smile = obj::read_obj(&d.join("smile.obj")).unwrap();
    for (i, outward) in [(48, -1.0), (54, 1.0)] {
        let moved = smile.positions[v[i] as usize] - at(i);
        eprintln!("AU 12 moves landmark {i} by {moved}");
        assert!(
            moved.y > 0.01 * size.y && moved.x * outward > 0.01 * size.y,
            "AU 12 moved landmark {i} by {moved}"
        );
    }
}
