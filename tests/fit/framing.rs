//! Views frame a fitted head from its landmarks: the camera stays where it is when fitting
//! moves a muscle, and a body's face fills the view, upright.

use glam::{Mat3, Vec2, Vec3};
use grimace::landmarks::CHIN;
use grimace::model::MuscleKind;
use grimace::render::{Camera, Framing};

/// Every muscle point of a fitted MediaPipe face moved (attachments and insertions by a
/// tenth of the face, the rings' frames turned by 29 degrees) leaves its framing as it was: the view
/// comes from the landmarks beside the mesh, not from the rig.
#[test]
fn a_fitted_heads_framing_does_not_move_with_its_muscles() {
    let Some((_dir, loaded, _)) = crate::fitted_mediapipe() else {
        return;
    };
    let (framing, warning) = Framing::of_loaded(&loaded, None);
    assert_eq!(warning, None);
    let mut moved = loaded.clone();
    let (lo, hi) = moved.mesh.bounds();
    let shift = (hi - lo) * Vec3::new(0.1, -0.1, 0.05);
    // Past the 20 degrees within which axes are snapped to the mesh's.
    let turn = Mat3::from_rotation_z(0.5);
    for muscle in &mut moved.rig.muscles {
        match &mut muscle.kind {
            MuscleKind::Linear(l) => {
                l.attachment += shift;
                l.insertion -= shift;
            }
            MuscleKind::Sphincter(s) => {
                s.centre += shift;
                s.frame.x = turn * s.frame.x;
                s.frame.y = turn * s.frame.y;
            }
            MuscleKind::Sheet(s) => {
                for p in s.attachment.iter_mut().chain(&mut s.insertion) {
                    *p += shift;
                }
            }
        }
    }
    assert_eq!(Framing::of_loaded(&moved, None), (framing.clone(), None));
    // Without the landmarks the moved rig would have moved the view.
    assert_ne!(
        Framing::of_rig(&moved.rig, &moved.mesh),
        Framing::of_rig(&loaded.rig, &loaded.mesh)
    );
}

/// MakeHuman's whole body, framed by its landmarks: the face region is the head, and brows
/// to chin fill more than half of a square picture, eyes level and above the mouth; the
/// same body stood on z (the face toward -y) is stood up again.
#[test]
fn a_body_frames_its_face_large_and_upright() {
    let Some((_, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let points = landmarks.positions(&mesh).unwrap();
    let framing = Framing::of_face(None, &mesh, Some(&points), None);
    assert_eq!(framing.basis, Mat3::IDENTITY, "MakeHuman stands on y");
    assert_face_fills_the_view(&framing, &points);

    let stand_on_z = |p: Vec3| Vec3::new(p.x, -p.z, p.y);
    let mut on_z = mesh.clone();
    on_z.positions.iter_mut().for_each(|p| *p = stand_on_z(*p));
    let points: Vec<Vec3> = points.into_iter().map(stand_on_z).collect();
    let framing = Framing::of_face(None, &on_z, Some(&points), None);
    assert_eq!(framing.basis.row(1), Vec3::Z, "up is the mesh's z");
    assert_eq!(framing.basis.row(2), -Vec3::Y, "the face looks toward -y");
    assert_face_fills_the_view(&framing, &points);
}

/// The face's landmarks seen in a square front view of the framing's focus: eyes level,
/// the subject's left on the right, eyes above the mouth above the chin, brows to chin over
/// half the height, the landmarks across over half the width.
fn assert_face_fills_the_view(framing: &Framing, points: &[Vec3]) {
    let focus = framing.focus.as_deref().expect("the face, not the body");
    let size = 200;
    let projection = Camera::front()
        .with_basis(framing.basis)
        .fit_points(focus, size, size, 1.0);
    let at = |ids: std::ops::RangeInclusive<usize>| {
        let n = ids.clone().count() as f32;
        ids.map(|i| projection.project(points[i]).truncate())
            .sum::<Vec2>()
            / n
    };
    let (right_eye, left_eye, mouth) = (at(36..=41), at(42..=47), at(48..=59));
    let (chin, brows) = (at(CHIN..=CHIN), at(17..=26));
    let h = size as f32;
    assert!(
        (right_eye.y - left_eye.y).abs() < 0.02 * h,
        "{right_eye} {left_eye}"
    );
    assert!(right_eye.x < left_eye.x, "{right_eye} {left_eye}");
    assert!(
        left_eye.y < mouth.y && mouth.y < chin.y,
        "{left_eye} {mouth} {chin}"
    );
    assert!(chin.y - brows.y > 0.5 * h, "brows {brows} chin {chin}");
    let across = at(16..=16).x - at(0..=0).x;
    assert!(across > 0.5 * h, "jaw line {across} dots across");
    // Centred: the eyes' middle within a tenth of the picture of its middle, across.
    assert!(((right_eye.x + left_eye.x) / 2.0 - h / 2.0).abs() < 0.1 * h);
}

/// MakeHuman's whole body with no landmarks yet (the picker opens on it so): the framing
/// found from the mesh's shape fits the head above the neck, not the body, whichever axis
/// the body stands on. The face fills a good part of a square view and every landmark is on
/// it.
#[test]
fn a_body_without_landmarks_opens_on_its_head() {
    let Some((_, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let points = landmarks.positions(&mesh).unwrap();
    let stand_on_z = |p: Vec3| Vec3::new(p.x, -p.z, p.y);
    let mut on_z = mesh.clone();
    on_z.positions.iter_mut().for_each(|p| *p = stand_on_z(*p));
    let on_z_points: Vec<Vec3> = points.iter().map(|p| stand_on_z(*p)).collect();
    for (mesh, points) in [(&mesh, &points), (&on_z, &on_z_points)] {
        let framing = Framing::of_mesh(mesh);
        let head = framing.focus.as_deref().expect("the head, not the body");
        let up = |p: &Vec3| framing.basis.row(1).dot(*p);
        let (lo, hi) = mesh.bounds();
        let height = framing.basis.row(1).dot(hi - lo).abs();
        let head_height = head.iter().map(up).fold(f32::MIN, f32::max)
            - head.iter().map(up).fold(f32::MAX, f32::min);
        assert!(
            head_height < 0.2 * height,
            "the head is {head_height} of a body {height} tall"
        );
        let size = 200;
        let projection = Camera::front()
            .with_basis(framing.basis)
            .fit_points(head, size, size, 1.0);
        let on_view: Vec<Vec2> = points
            .iter()
            .map(|p| projection.project(*p).truncate())
            .collect();
        assert!(
            on_view
                .iter()
                .all(|p| p.x >= 0.0 && p.y >= 0.0 && p.x < size as f32 && p.y < size as f32),
            "every landmark on the view"
        );
        let span = on_view[CHIN].y - on_view[19].y;
        assert!(
            span > 0.3 * size as f32,
            "brow to chin {span} of {size} dots"
        );
    }
}
