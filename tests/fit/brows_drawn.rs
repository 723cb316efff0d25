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
