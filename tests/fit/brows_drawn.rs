//! Fitted heads without brow groups get their brows from the landmarks beside their mesh when
//! the rig is loaded, so the editor, `render` and `export` draw the same brows.

/// A fitted MediaPipe mask (no brow groups of its own) loads with a brow over each eye:
/// mirrored, above the lids' landmarks, off the midline.
#[test]
fn a_fitted_head_loads_with_brows_from_its_landmarks() {
    let Some((_dir, loaded, landmarks)) = crate::fitted_mediapipe() else {
        return;
    };
    let mesh = &loaded.mesh;
    let marks = landmarks.positions(mesh).unwrap();
    let frame = grimace::landmarks::FaceFrame::of(&marks).unwrap();
    let height = |p: glam::Vec3| p.as_dvec3().dot(frame.up);
    let eye_top = [37, 38, 43, 44]
        .iter()
        .map(|&i| height(marks[i]))
        .fold(f64::MIN, f64::max);
    let mut sizes = Vec::new();
    for side in ["left", "right"] {
        let brow = mesh
            .groups
            .get(&format!("{side}_brow_hair"))
            .unwrap_or_else(|| panic!("no {side} brow"));
        assert!(!brow.is_empty());
        for &v in brow {
            let p = mesh.positions[v as usize];
            assert!(height(p) > eye_top, "{side} brow below the upper lid");
        }
        sizes.push(brow.len());
    }
    assert!(
        sizes[0].abs_diff(sizes[1]) * 5 <= sizes[0].max(sizes[1]),
        "{sizes:?}"
    );
}

/// A MediaPipe face mesh needs no landmark file: fitted with its topology kept (the rig
/// names the user's own mesh, with nothing beside it), it loads with MediaPipe's numbering
/// as its landmarks, and its brows are marked from the same points the view is framed by.
#[test]
fn a_mediapipe_mesh_without_a_landmark_file_gets_brows_from_its_numbering() {
    let Some((path, _, _)) = crate::shared_mediapipe() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    crate::fit_mediapipe_in(dir.path(), &path, &["--keep-lips", "--keep-eyes"]);
    let loaded = grimace::io::load::load_rig(&dir.path().join("mp.rig.ron")).unwrap();
    let mesh_file = loaded
        .mesh_path
        .as_ref()
        .expect("the rig names a mesh file");
    assert!(
        !grimace::io::landmarks::beside(mesh_file).exists(),
        "this test needs a mesh with no landmark file beside it"
    );
    let points = loaded
        .landmark_points()
        .unwrap()
        .expect("MediaPipe's numbering gives the landmarks");
    assert_eq!(points.len(), 68);
    for side in ["left", "right"] {
        let brow = loaded.mesh.groups.get(&format!("{side}_brow_hair"));
        assert!(brow.is_some_and(|b| !b.is_empty()), "no {side} brow");
    }
}
