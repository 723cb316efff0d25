//! No silent wrong output: values that would make a wrong file are refused, and fits that
//! are probably wrong say so.

use std::path::Path;
use std::process::Output;

use crate::common::grimace_in as grimace;

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn gltf_refuses_a_zero_scale_and_a_table_without_targets() {
    let dir = tempfile::tempdir().unwrap();
    let out = grimace(
        dir.path(),
        &["export", "--gltf", "a.glb", "--unit-mm", "1e-45"],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("too small for a node scale"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("a.glb").exists());

    let table = "(version: 1, rig: \"builtin:default\", aus: {}, expressions: {})\n";
    std::fs::write(dir.path().join("empty.au.ron"), table).unwrap();
    let out = grimace(
        dir.path(),
        &["export", "--gltf", "b.glb", "--table", "empty.au.ron"],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("no AUs to export"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("b.glb").exists());
    // Muscle targets need no recorded AU.
    let out = grimace(
        dir.path(),
        &[
            "export",
            "--gltf",
            "c.glb",
            "--table",
            "empty.au.ron",
            "--targets",
            "muscles",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn a_fit_with_a_landmark_on_the_wrong_feature_warns() {
    let dir = tempfile::tempdir().unwrap();
    assert!(grimace(dir.path(), &["export", "--out", "head.obj"])
        .status
        .success());
    let presets = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/default.landmarks.ron");
    let text = std::fs::read_to_string(presets).unwrap();
    std::fs::write(dir.path().join("good.landmarks.ron"), &text).unwrap();
    let good = grimace(
        dir.path(),
        &[
            "fit-rig",
            "head.obj",
            "--landmarks",
            "good.landmarks.ron",
            "--out",
            "a.rig.ron",
        ],
    );
    assert!(good.status.success(), "{}", stderr(&good));
    assert!(!stderr(&good).contains("warning"), "{}", stderr(&good));
    // The fitted rig keeps the template's muscle names: the built-in table drives it.
    let render = grimace(
        dir.path(),
        &[
            "render",
            "--rig",
            "a.rig.ron",
            "--au",
            "L12",
            "--out",
            "s.svg",
        ],
    );
    assert!(render.status.success(), "{}", stderr(&render));
    // Muscle targets need no table at all.
    let muscles = grimace(
        dir.path(),
        &[
            "export",
            "--gltf",
            "m.glb",
            "--rig",
            "builtin:paper",
            "--targets",
            "muscles",
        ],
    );
    assert!(muscles.status.success(), "{}", stderr(&muscles));
    // The chin's vertex given for a point of the right brow (19): a point on the wrong feature.
    let marks = grimace::io::builtin::landmarks("default").unwrap();
    let grimace::landmarks::Landmarks::Vertices(mut v) = marks else {
        panic!("the built-in landmarks are vertex numbers")
    };
    v[19] = v[8];
    let bad = grimace::io::landmarks::landmarks_to_ron(&grimace::landmarks::Landmarks::Vertices(v));
    std::fs::write(dir.path().join("bad.landmarks.ron"), bad).unwrap();
    let out = grimace(
        dir.path(),
        &[
            "fit-rig",
            "head.obj",
            "--landmarks",
            "bad.landmarks.ron",
            "--out",
            "b.rig.ron",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("warning: a landmark bend of"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_folder_or_a_pipe_as_a_target_shape_is_named_for_what_it_is() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("shape.obj")).unwrap();
    let out = grimace(
        dir.path(),
        &[
            "fit-au",
            "shape.obj",
            "--rig",
            "builtin:default",
            "--au",
            "12",
        ],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("is a folder"), "{}", stderr(&out));
    assert!(!stderr(&out).contains("does not exist"), "{}", stderr(&out));
}

/// The built-in landmarks with each point moved to its mirror partner's vertex.
fn swapped_landmarks() -> String {
    let grimace::landmarks::Landmarks::Vertices(v) =
        grimace::io::builtin::landmarks("default").unwrap()
    else {
        panic!("vertex numbers")
    };
    let swapped: Vec<u32> = (0..v.len())
        .map(|i| v[grimace::landmarks::mirror(i)])
        .collect();
    grimace::io::landmarks::landmarks_to_ron(&grimace::landmarks::Landmarks::Vertices(swapped))
}

#[test]
fn a_mirrored_template_is_blamed_on_the_template_and_a_shuffled_set_on_its_order() {
    let dir = tempfile::tempdir().unwrap();
    assert!(grimace(dir.path(), &["export", "--out", "head.obj"])
        .status
        .success());
    let presets = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/default.landmarks.ron");
    std::fs::copy(presets, dir.path().join("head.landmarks.ron")).unwrap();
    std::fs::write(
        dir.path().join("swapped.landmarks.ron"),
        swapped_landmarks(),
    )
    .unwrap();
    let out = grimace(
        dir.path(),
        &[
            "fit-rig",
            "head.obj",
            "--landmarks",
            "head.landmarks.ron",
            "--template-landmarks",
            "swapped.landmarks.ron",
            "--out",
            "a.rig.ron",
        ],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains(
            "swapped.landmarks.ron: the template's landmarks: the landmarks are mirrored"
        ),
        "{}",
        stderr(&out)
    );
    // A set shuffled out of every contour's sequence is named as an order problem.
    let grimace::landmarks::Landmarks::Vertices(v) =
        grimace::io::builtin::landmarks("default").unwrap()
    else {
        panic!("vertex numbers")
    };
    let shuffled: Vec<u32> = (0..v.len())
        .map(|i| v[(grimace::landmarks::mirror(i) * 7) % 68])
        .collect();
    std::fs::write(
        dir.path().join("shuffled.landmarks.ron"),
        grimace::io::landmarks::landmarks_to_ron(&grimace::landmarks::Landmarks::Vertices(
            shuffled,
        )),
    )
    .unwrap();
    let out = grimace(
        dir.path(),
        &[
            "fit-rig",
            "head.obj",
            "--landmarks",
            "shuffled.landmarks.ron",
            "--out",
            "b.rig.ron",
        ],
    );
    // Refused or warned about, the order is named, never a mirror.
    let said = stderr(&out);
    assert!(!said.contains("mirrored"), "{said}");
    assert!(
        said.contains("lies on the subject's") || said.contains("not in the iBUG order"),
        "{said}"
    );
}
