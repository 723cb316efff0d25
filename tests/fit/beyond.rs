//! Fitted heads beyond the template's face, which is a mask with no neck, no mouth lining
//! and no crown: the skin under the chin and a mouth's lining take jaw weights that fade
//! along the mesh (`fit::jawfade`), so the fitted shared heads open their jaw at AU26 and
//! AU27 without a turned triangle or a stretch over 2.5x, dropping the jaw at least 15 mm
//! (`grimace check`'s measures); lips that are apart get the dark mouth pocket cut lips get
//! (`fit::lipcut::pocket_behind_apart_lips`); a crown joined to the forehead stays still when
//! the brows rise.

use glam::Vec3;
use grimace::facs::combo::parse_combo;
use grimace::fit::lipcut::{self, Lips};
use grimace::fit::quality::{Expect, Gauge};
use grimace::fit::Part;
use grimace::io::builtin;
use grimace::landmarks::{FaceFrame, Landmarks};
use grimace::model::{Deformation, Mesh};

/// `check`'s verdict on AU26 and AU27 of the built-in rig fitted to `mesh` (its lips cut
/// open first when they are joined, as `fit-rig` does): the failures.
fn jaw_failures(name: &str, mesh: &Mesh, landmarks: &Landmarks) -> Vec<String> {
    let marks = landmarks.vertices(mesh);
    let cut = match lipcut::find(mesh, &marks) {
        Lips::Joined(cut) => Some(cut),
        _ => None,
    };
    let (mesh, marks) = match &cut {
        Some(cut) => (&cut.mesh, cut.landmarks.clone()),
        None => (mesh, marks),
    };
    let mut fitted = crate::fit_default(mesh, &Landmarks::Vertices(marks.clone()));
    if let Some(cut) = &cut {
        lipcut::weights_by_side(&mut fitted.rig, cut);
    }
    let gauge = Gauge::new(mesh, &marks, None).expect("measurable");
    let bound = Deformation::default()
        .bind(&fitted.rig, mesh)
        .expect("binds");
    let expect = Expect {
        jaw_opens: true,
        ..Expect::default()
    };
    crate::au_failures(name, &bound, &gauge, &["26", "27"], expect)
}

/// MakeHuman's chin ends in a floor of skin running back to the neck, and its mouth has a
/// lining behind separate lips; the template has neither. Faded by straight-line distance
/// from the template, the weights fell from 1 to 0 across 11 mm under the chin and from 0.96
/// to 0.02 across the mouth's floor: AU26 turned 42 triangles over, AU27 80 (5.55x).
#[test]
fn fitted_makehuman_opens_its_jaw_without_tearing() {
    let Some((_, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let failures = jaw_failures("MakeHuman", &mesh, &landmarks);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// MediaPipe's face is a mask the template covers: its lips are cut open and its jaw opens
/// without tearing, before and after (the weights along the mesh change nothing there).
#[test]
fn fitted_mediapipe_opens_its_jaw_without_tearing() {
    let Some((_, mesh, landmarks)) = crate::shared_mediapipe() else {
        return;
    };
    let failures = jaw_failures("MediaPipe", &mesh, &landmarks);
    assert!(failures.is_empty(), "{failures:#?}");
}

/// MakeHuman's lips are apart (separate surfaces whose insides meet in a mouth bag of skin,
/// drawn as lit as the cheek: the open mouth rendered grey and the face tracker read a
/// smile). Fitted with a pocket behind the lips, every view into the mouth at AU26 (a grid
/// between the lips) shows the pocket or the mesh's own teeth and tongue, not skin; the
/// pocket's lower half drops with the jaw.
#[test]
fn apart_lips_open_onto_a_dark_pocket() {
    let Some((_, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let marks = landmarks.vertices(&mesh);
    assert_eq!(lipcut::find(&mesh, &marks), Lips::Separate);
    let cut = lipcut::pocket_behind_apart_lips(&mesh, &marks).expect("a pocket behind the lips");
    let pocket = cut.pocket.as_ref().expect("the pocket");
    assert!(
        cut.copies.is_empty() && cut.landmarks == marks,
        "nothing is cut"
    );
    let opened = &cut.mesh;
    assert_eq!(opened.positions[..mesh.vertex_count()], mesh.positions[..]);
    let mut fitted = crate::fit_default(opened, &Landmarks::Vertices(cut.landmarks.clone()));
    lipcut::weights_by_side(&mut fitted.rig, &cut);
    let bound = Deformation::default().bind(&fitted.rig, opened).unwrap();
    let moved = crate::positions_at_au(&bound, "26");
    let points: Vec<Vec3> = marks.iter().map(|&v| mesh.positions[v as usize]).collect();
    let forward = FaceFrame::of(&points).unwrap().forward.as_vec3();
    let at = |i: usize| moved[marks[i] as usize];
    let first_pocket_triangle = opened.triangles.len() - pocket.triangles;
    // a grid of views into the open mouth: the middle half of the way between the inner lips'
    // middles (nearer the lips the view meets their own curled edges), there and a quarter of
    // the inner corners' distance to each side
    let across = (at(64) - at(60)) * 0.25;
    let mut pocket_seen = 0;
    for k in 2..=5 {
        let between = at(62).lerp(at(66), k as f32 / 8.0);
        for side in [-1.0, 0.0, 1.0] {
            let eye = between + across * side + forward * points[36].distance(points[45]);
            let hit = crate::mouth::first_hit(opened, &moved, eye, -forward);
            let Some(hit) = hit else {
                panic!("view {k}/{side} into the open mouth meets nothing");
            };
            let skin = opened.triangles[hit]
                .iter()
                .all(|&v| fitted.parts.of_vertex[v as usize] == Part::Skin);
            assert!(
                hit >= first_pocket_triangle || !skin,
                "view {k}/{side} into the open mouth shows skin (triangle {hit})"
            );
            pocket_seen += usize::from(hit >= first_pocket_triangle);
        }
    }
    eprintln!("the pocket is seen in {pocket_seen} of 12 views into the open mouth");
    assert!(pocket_seen > 0, "the pocket is nowhere in sight");
    let lower_drop = (mesh.positions[marks[66] as usize] - at(66)).length();
    let pocket_drop = (pocket.first as usize..opened.vertex_count())
        .map(|v| (moved[v] - opened.positions[v]).length())
        .fold(0.0f32, f32::max);
    assert!(
        pocket_drop >= 0.5 * lower_drop,
        "the pocket's lower half moves {pocket_drop} with a lower lip moving {lower_drop}"
    );
}

/// Heights along `up` of `points`' brows (17-26, the highest) and the nose's length (27-33).
fn brow_top_and_nose(points: &[Vec3], up: Vec3) -> (f32, f32) {
    let brow = points[17..27]
        .iter()
        .map(|p| p.dot(up))
        .fold(f32::MIN, f32::max);
    (brow, points[27].distance(points[33]))
}

/// A one-piece head with a tall headdress: the built-in face with everything higher than 0.6
/// of the nose's length above the brows stretched to four times its height, one surface with
/// the forehead (no group, no gap). Returns the mesh and its landmark vertices.
fn crowned_face() -> (Mesh, Vec<u32>) {
    let mut face = builtin::default_mesh();
    let marks = builtin::landmarks("face").unwrap().vertices(&face);
    let points: Vec<Vec3> = marks.iter().map(|&v| face.positions[v as usize]).collect();
    let up = FaceFrame::of(&points).unwrap().up.as_vec3();
    let (brow, nose) = brow_top_and_nose(&points, up);
    let base = brow + 0.6 * nose;
    for p in &mut face.positions {
        let h = p.dot(up) - base;
        if h > 0.0 {
            *p += up * 3.0 * h;
        }
    }
    (face, marks)
}

/// A brow raise (AU1+2 at full intensity) moves the brows but no vertex of a headdress above
/// the forehead (more than the nose's length above the brows) by more than 5% of the brows'
/// travel: the frontalis pulls toward its attachment, at the top of the template's forehead,
/// and nothing beyond it (measured: 0; 0.7% at 0.8 of the nose's length).
#[test]
fn a_brow_raise_leaves_a_crown_still() {
    let (mesh, marks) = crowned_face();
    let fitted = crate::fit_default(&mesh, &Landmarks::Vertices(marks.clone()));
    let bound = Deformation::default().bind(&fitted.rig, &mesh).unwrap();
    let table = builtin::default_table();
    let act = table
        .evaluate(&parse_combo("1+2").unwrap(), &fitted.rig)
        .unwrap();
    let mut moved = Vec::new();
    bound.deform(&act, &mut moved).unwrap();
    let points: Vec<Vec3> = marks.iter().map(|&v| mesh.positions[v as usize]).collect();
    let up = FaceFrame::of(&points).unwrap().up.as_vec3();
    let (brow, nose) = brow_top_and_nose(&points, up);
    let travel = |v: usize| moved[v].distance(mesh.positions[v]);
    let brows = marks[17..27]
        .iter()
        .map(|&v| travel(v as usize))
        .fold(0.0, f32::max);
    assert!(brows > 0.0, "the brows rise");
    let crown: Vec<usize> = (0..mesh.vertex_count())
        .filter(|&v| mesh.positions[v].dot(up) > brow + nose)
        .collect();
    assert!(
        crown.len() > 100,
        "the headdress has {} vertices",
        crown.len()
    );
    let worst = crown.iter().map(|&v| travel(v)).fold(0.0, f32::max);
    eprintln!("AU1+2: brows {brows:.3}, crown at most {worst:.4}");
    assert!(
        worst <= 0.05 * brows,
        "the crown moves {worst} with the brows moving {brows}"
    );
}
