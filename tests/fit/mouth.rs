//! The mouth of fitted heads (`fit::lipsides`, `fit::pocket`): the lips are split by
//! connectivity, so an upper lip that curls below the line between the inner lip landmarks
//! stays with the skull; MakeHuman's separate lips part at AU25-27 without tearing and its
//! lower teeth drop; a mouth whose lips were cut gets a dark pocket behind them that the jaw
//! opens.

use std::collections::BTreeMap;

use glam::Vec3;
use grimace::fit::lipcut::{self, LipCut, Lips};
use grimace::fit::{Fitted, Part};
use grimace::io::builtin;
use grimace::landmarks::{FaceFrame, Landmarks, CANTHAL_MM};
use grimace::model::{BoundRig, Deformation, Mesh};

/// Millimetres per unit of a mesh whose landmark positions are `points`.
fn mm_per_unit(points: &[Vec3]) -> f32 {
    CANTHAL_MM / points[36].distance(points[45])
}

fn jaw_weights(fitted: &Fitted) -> BTreeMap<u32, f32> {
    fitted
        .rig
        .jaw
        .as_ref()
        .unwrap()
        .weights
        .iter()
        .copied()
        .collect()
}

/// The built-in face with the middle of its upper lip's inner edge curled down below the
/// line halfway between the inner lip landmarks and a little forward, over the lower lip (a
/// full upper lip, as MakeHuman's): the inner edge's vertices between the corners that are
/// not landmarks, each moved to a third of the slit's height below the lower lip's edge
/// across from it. Returns the mesh, its landmarks and the moved vertices.
fn curled_upper_lip() -> (Mesh, Vec<u32>, Vec<u32>) {
    let mut face = builtin::default_mesh();
    let marks = builtin::landmarks("face").unwrap().vertices(&face);
    let upper = crate::lipcut::boundary_walk(&face, marks[60], marks[62], marks[64]);
    let lower = crate::lipcut::boundary_walk(&face, marks[60], marks[66], marks[64]);
    assert_eq!(upper.len(), lower.len(), "the slit's rows pair up");
    let rest = face.positions.clone();
    let at = |v: u32| rest[v as usize];
    let gap = at(marks[62]).y - at(marks[66]).y;
    assert!(gap > 0.0, "the built-in mouth is open");
    let mut moved = Vec::new();
    for (&u, &l) in upper.iter().zip(&lower).skip(1) {
        if u == marks[64] || marks.contains(&u) {
            continue;
        }
        let below = at(l) + Vec3::new(0.0, -gap / 3.0, gap / 2.0);
        face.positions[u as usize] = Vec3::new(at(u).x, below.y, below.z);
        moved.push(u);
    }
    let mid = 0.5 * (at(marks[62]).y + at(marks[66]).y);
    assert!(
        moved.iter().all(|&v| face.positions[v as usize].y < mid),
        "the lip dips below the line"
    );
    (face, marks, moved)
}

/// A full upper lip whose edge hangs below the line between the lips stays with the skull:
/// the jaw splits the lips by which lip a vertex is reached from, not by its height (before,
/// the curled edge took the lower lip's weights, about 0.9, and tore off the lip at AU26).
#[test]
fn an_upper_lip_curled_below_the_line_stays_with_the_skull() {
    let (face, marks, moved) = curled_upper_lip();
    let fitted = crate::fit_default(&face, &Landmarks::Vertices(marks.clone()));
    let weights = jaw_weights(&fitted);
    // the middle of the mouth, where the split is whole (it fades out at the corners)
    let half = face.positions[marks[64] as usize].x.abs();
    let middle: Vec<u32> = moved
        .iter()
        .copied()
        .filter(|&v| face.positions[v as usize].x.abs() < 0.5 * half)
        .collect();
    assert!(
        middle.len() >= 3,
        "{} curled vertices in the middle",
        middle.len()
    );
    for v in middle {
        let w = weights.get(&v).copied().unwrap_or(0.0);
        assert!(
            w <= 0.05,
            "upper lip vertex {v} turns with the jaw by {w:.2}"
        );
    }
    // and the lower lip below it still follows the jaw
    let w = weights.get(&marks[66]).copied().unwrap_or(0.0);
    assert!(w >= 0.9, "the lower lip's middle has jaw weight {w:.2}");
}

/// The largest stretch of a skin edge of `mesh` between `rest` and `moved`.
fn skin_stretch(mesh: &Mesh, parts: &[Part], moved: &[Vec3]) -> f32 {
    mesh.edges()
        .into_iter()
        .filter(|e| e.iter().all(|&v| parts[v as usize] == Part::Skin))
        .map(|[a, b]| {
            let (a, b) = (a as usize, b as usize);
            let rest = mesh.positions[a].distance(mesh.positions[b]);
            if rest > 0.0 {
                moved[a].distance(moved[b]) / rest
            } else {
                1.0
            }
        })
        .fold(0.0, f32::max)
}

/// MakeHuman's lips are separate surfaces whose upper lip curls below the line between
/// them: split by height, part of it went with the jaw and AU25 stretched an edge 9.1x and
/// AU26 19.9x. Split by connectivity, AU25 and AU26 stay under 2.5x, AU27 opens the mouth
/// 35-50 mm (at a 90 mm canthal scale) and the lower teeth drop at least 15 mm at AU26.
#[test]
fn makehuman_lips_part_without_tearing_and_its_teeth_drop() {
    let Some((_, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let marks = landmarks.vertices(&mesh);
    let fitted = crate::fit_default(&mesh, &landmarks);
    let points: Vec<Vec3> = marks.iter().map(|&v| mesh.positions[v as usize]).collect();
    let (mm, frame) = (mm_per_unit(&points), FaceFrame::of(&points).unwrap());
    let bound = Deformation::default().bind(&fitted.rig, &mesh).unwrap();
    for au in ["25", "26"] {
        let moved = crate::positions_at_au(&bound, au);
        let stretch = skin_stretch(&mesh, &fitted.parts.of_vertex, &moved);
        eprintln!("AU{au}: largest skin stretch {stretch:.2}x");
        assert!(
            stretch <= 2.5,
            "AU{au}: a skin edge stretches {stretch:.2}x"
        );
    }
    let moved = crate::positions_at_au(&bound, "27");
    let gap = |p: &[Vec3]| p[marks[62] as usize].distance(p[marks[66] as usize]);
    let opening = (gap(&moved) - gap(&mesh.positions)) * mm;
    eprintln!("AU27: the mouth opens {opening:.1} mm");
    assert!(
        (35.0..=50.0).contains(&opening),
        "AU27 opens {opening:.1} mm"
    );
    let teeth = &mesh.groups["helper-lower-teeth"];
    let moved = crate::positions_at_au(&bound, "26");
    let up = frame.up.as_vec3();
    let drop = teeth
        .iter()
        .map(|&v| (mesh.positions[v as usize] - moved[v as usize]).dot(up) * mm)
        .fold(0.0f32, f32::max);
    eprintln!("AU26: the lower teeth drop {drop:.1} mm");
    assert!(drop >= 15.0, "AU26: the lower teeth drop {drop:.1} mm");
}

/// Where a ray from `origin` along `dir` first meets a triangle of `mesh` at `positions`:
/// the triangle's number.
pub(crate) fn first_hit(mesh: &Mesh, positions: &[Vec3], origin: Vec3, dir: Vec3) -> Option<usize> {
    let mut best: Option<(f32, usize)> = None;
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|v| positions[v as usize]);
        let (e1, e2) = (b - a, c - a);
        let p = dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-12 {
            continue;
        }
        let s = origin - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = dir.dot(q) / det;
        let d = e2.dot(q) / det;
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && d > 0.0 && best.is_none_or(|(b, _)| d < b) {
            best = Some((d, t));
        }
    }
    best.map(|(_, t)| t)
}

fn opened_mediapipe() -> Option<LipCut> {
    let (_, mesh, landmarks) = crate::shared_mediapipe()?;
    let marks = landmarks.vertices(&mesh);
    match lipcut::find(&mesh, &marks) {
        Lips::Joined(cut) => Some(cut),
        other => panic!("MediaPipe's lips are joined, found {other:?}"),
    }
}

/// Cut lips open onto a pocket, not onto whatever lies behind a face mask: looking into the
/// middle of MediaPipe's opened mouth at AU26 (before, the view went through to the
/// background), the first thing seen is the pocket (`mouth_interior`, which `shaded` draws
/// nearly black); the muscles leave it still and its lower half turns with the jaw.
#[test]
fn cut_lips_open_onto_a_dark_pocket() {
    let Some(cut) = opened_mediapipe() else {
        return;
    };
    let pocket = cut.pocket.as_ref().expect("a pocket behind the cut lips");
    let mesh = &cut.mesh;
    let members = &mesh.groups[grimace::fit::pocket::GROUP];
    let pocket_vertices: Vec<u32> = (pocket.first..mesh.vertex_count() as u32).collect();
    assert_eq!(members, &pocket_vertices);
    let mut fitted = crate::fit_default(mesh, &Landmarks::Vertices(cut.landmarks.clone()));
    lipcut::weights_by_side(&mut fitted.rig, &cut);
    for &v in members {
        assert_eq!(
            fitted.parts.of_vertex[v as usize],
            Part::Still,
            "vertex {v}"
        );
    }
    let bound: BoundRig = Deformation::default().bind(&fitted.rig, mesh).unwrap();
    let points: Vec<Vec3> = cut
        .landmarks
        .iter()
        .map(|&v| mesh.positions[v as usize])
        .collect();
    let frame = FaceFrame::of(&points).unwrap();
    let forward = frame.forward.as_vec3();
    let smile = crate::positions_at_au(&bound, "12");
    for &v in members {
        assert_eq!(
            smile[v as usize], mesh.positions[v as usize],
            "AU12 moves {v}"
        );
    }
    let moved = crate::positions_at_au(&bound, "26");
    let at = |i: usize| moved[cut.landmarks[i] as usize];
    let middle = 0.5 * (at(62) + at(66));
    let eye = middle + forward * points[36].distance(points[45]);
    let hit = first_hit(mesh, &moved, eye, -forward).expect("the view meets the head");
    let first_pocket_triangle = mesh.triangles.len() - pocket.triangles;
    assert!(
        hit >= first_pocket_triangle,
        "the middle of the open mouth shows triangle {hit}, not the pocket"
    );
    let lower_drop = (mesh.positions[cut.landmarks[66] as usize] - at(66)).length();
    let pocket_drop = members
        .iter()
        .map(|&v| (moved[v as usize] - mesh.positions[v as usize]).length())
        .fold(0.0f32, f32::max);
    assert!(
        pocket_drop >= 0.5 * lower_drop,
        "the pocket's lower half moves {pocket_drop} with a lower lip moving {lower_drop}"
    );
}

/// How far (mm) the mouth corners (iBUG 48 and 54, mean of the two) of `mesh` move down and
/// back at AU15 under `rig`: (down, back) in the frame of the face's landmarks `marks`.
fn corners_at_au15(mesh: &Mesh, rig: &grimace::model::Rig, marks: &[u32]) -> (f32, f32) {
    let points: Vec<Vec3> = marks.iter().map(|&v| mesh.positions[v as usize]).collect();
    let (mm, frame) = (mm_per_unit(&points), FaceFrame::of(&points).unwrap());
    let bound = Deformation::default().bind(rig, mesh).unwrap();
    let moved = crate::positions_at_au(&bound, "15");
    let along = |axis: Vec3| {
        [48, 54]
            .iter()
            .map(|&i| (moved[marks[i] as usize] - mesh.positions[marks[i] as usize]).dot(axis))
            .sum::<f32>()
            * 0.5
            * mm
    };
    (-along(frame.up.as_vec3()), -along(frame.forward.as_vec3()))
}

/// The angular depressor pulls a fitted head's mouth corners down at least as steeply
/// against back as it pulls the built-in face's (5.4 mm down, 4.2 back in its landmarks'
/// frame; `fit::insertion`). Carried by the warp alone, its attachment sank under the skin
/// and MakeHuman's corners went about 4.8 mm down and 5.7 back: the tracker read little
/// frown in sadness. The fitted muscle now leaves the corner at the template's angle to the
/// skin (6.7 down, none back; MediaPipe's 7.0 down, 3.6 back).
#[test]
fn fitted_corners_go_down_more_than_back_at_au15() {
    let face = builtin::default_mesh();
    let face_marks = builtin::landmarks("face").unwrap().vertices(&face);
    let (down, back) = corners_at_au15(&face, &builtin::default_rig(), &face_marks);
    eprintln!("built-in face: corners {down:.1} mm down, {back:.1} mm back at AU15");
    let steepest_back = back / down;
    let heads = [crate::shared_makehuman(), crate::shared_mediapipe()];
    for (path, mesh, landmarks) in heads.into_iter().flatten() {
        let fitted = crate::fit_default(&mesh, &landmarks);
        let marks = landmarks.vertices(&mesh);
        let (down, back) = corners_at_au15(&mesh, &fitted.rig, &marks);
        eprintln!(
            "{}: corners {down:.1} mm down, {back:.1} mm back at AU15",
            path.display()
        );
        assert!(
            down >= 4.0,
            "{}: corners only {down:.1} mm down",
            path.display()
        );
        assert!(
            back <= steepest_back * down,
            "{}: corners {back:.1} mm back for {down:.1} mm down (built-in face: {:.2} back per mm down)",
            path.display(),
            steepest_back
        );
    }
}
