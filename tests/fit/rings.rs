//! The mouth and eye rings on fitted heads take their frame, size and strength from the lip
//! and lid landmarks: on closed and open mouths the mouth ring keeps the template's size
//! relative to the lip contour, and a pucker (AU18) moves the lips about as far, relative to
//! the face, as on the built-in face.

use crate::common;

use std::path::Path;

use glam::Vec3;
use grimace::fit::quality::{Expect, Eyes, Gauge};
use grimace::fit::regions::{Extent, CONTOURS};
use grimace::io::{builtin, landmarks::load_landmarks, obj};
use grimace::landmarks::{FaceFrame, Landmarks};
use grimace::model::{Activations, BoundRig, Mesh, MuscleKind, Rig, Sphincter};

/// Millimetres per outer canthal distance (36 to 45) on an adult face.
const CANTHAL_MM: f32 = 90.0;

fn ring<'a>(rig: &'a Rig, name: &str) -> &'a Sphincter {
    match &rig.muscles[rig.muscle_index(name).unwrap()].kind {
        MuscleKind::Sphincter(s) => s,
        _ => panic!("{name} is not a sphincter"),
    }
}

/// The mouth ring's semi-axes over the outer lip contour's half-width and half-height.
fn mouth_ratios(rig: &Rig, points: &[Vec3]) -> (f64, f64) {
    let frame = FaceFrame::of(points).unwrap();
    let lips = Extent::of(points, &CONTOURS[0], frame.forward).unwrap();
    let s = ring(rig, "Orbicularis_Oris");
    (
        f64::from(s.semi_major) / lips.half_width,
        f64::from(s.semi_minor) / lips.half_height,
    )
}

/// How far AU18 moves the farthest lip landmark (48-67), in mm for an outer canthal
/// distance of 90 mm.
fn pucker_mm(rig: &Rig, mesh: &Mesh, vertices: &[u32]) -> f32 {
    let bound = BoundRig::bind(rig, mesh).unwrap();
    let act = builtin::default_table()
        .entry_activations(&"18".parse().unwrap(), rig)
        .unwrap();
    let mut moved = Vec::new();
    bound.deform(&act, &mut moved).unwrap();
    let at = |i: usize| vertices[i] as usize;
    let travel = (48..68)
        .map(|i| moved[at(i)].distance(mesh.positions[at(i)]))
        .fold(0.0f32, f32::max);
    let canthal = mesh.positions[at(36)].distance(mesh.positions[at(45)]);
    travel / canthal * CANTHAL_MM
}

/// The built-in face with its lips parted by its own jaw (about 7 degrees), no muscles.
fn open_mouth_face() -> Mesh {
    let mut mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let bound = BoundRig::bind(&rig, &mesh).unwrap();
    let mut act = Activations::zero(&rig);
    let degrees_per_unit = rig.jaw.as_ref().unwrap().degrees_per_unit;
    act.jaw = 7.0 / degrees_per_unit;
    let mut moved = Vec::new();
    bound.deform(&act, &mut moved).unwrap();
    mesh.positions = moved;
    mesh
}

#[test]
fn rings_follow_the_lip_contour_on_closed_and_open_mouths() {
    let face = builtin::default_mesh();
    let marks = builtin::landmarks("face").unwrap();
    let template = builtin::default_rig();
    let template_points = marks.positions(&face).unwrap();
    let (want_w, want_h) = mouth_ratios(&template, &template_points);
    let want_pucker = pucker_mm(&template, &face, &marks.vertices(&face));
    println!(
        "built-in face: mouth ring {want_w:.2} x the lips' half-width, {want_h:.2} x their \
         half-height; pucker {want_pucker:.2} mm"
    );
    let mut heads: Vec<(&str, Mesh, Landmarks)> = vec![(
        "built-in face, lips parted",
        open_mouth_face(),
        marks.clone(),
    )];
    for (name, mesh, landmarks) in shared_heads() {
        heads.push((name, mesh, landmarks));
    }
    let mut failures = Vec::new();
    for (name, mesh, landmarks) in &heads {
        let fitted = crate::fit_default(mesh, landmarks);
        let points = landmarks.positions(mesh).unwrap();
        let (w, h) = mouth_ratios(&fitted.rig, &points);
        let pucker = pucker_mm(&fitted.rig, mesh, &landmarks.vertices(mesh));
        println!(
            "{name}: mouth ring {w:.2} x the lips' half-width, {h:.2} x their half-height; \
             pucker {pucker:.2} mm"
        );
        for (what, got, want) in [("width", w, want_w), ("height", h, want_h)] {
            if !(0.7..=1.3).contains(&(got / want)) {
                failures.push(format!("{name}: {what} {got:.2}, built-in {want:.2}"));
            }
        }
        if !(0.67..=1.5).contains(&(pucker / want_pucker)) {
            failures.push(format!(
                "{name}: pucker {pucker:.2} mm, built-in {want_pucker:.2} mm"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The default face and the shared heads with their landmarks, when the shared meshes are
/// there.
fn shared_heads() -> Vec<(&'static str, Mesh, Landmarks)> {
    let mut heads = Vec::new();
    if let Some(shared) = common::shared_with(&["meshes/mediapipe_canonical_face.obj"]) {
        let mesh = obj::read_obj(&shared.join("meshes/mediapipe_canonical_face.obj")).unwrap();
        let landmarks = Landmarks::mediapipe(&mesh).unwrap();
        heads.push(("MediaPipe", mesh, landmarks));
    }
    if let Some(shared) = common::shared_with(&["meshes/makehuman_base.obj"]) {
        let mesh = obj::read_obj(&shared.join("meshes/makehuman_base.obj")).unwrap();
        let landmarks = load_landmarks(Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fit_data/makehuman_base.landmarks.ron"
        )))
        .unwrap();
        heads.push(("MakeHuman", mesh, landmarks));
    }
    heads
}

/// The eye rings take their height and strength from the lids: at AU45 the lids of a fitted
/// head close as the built-in face's do, without passing each other. How far they close is
/// `check`'s lid gap: at the lids' free edges where the lid landmarks lie off them
/// (MakeHuman's, on the lid's back, stay apart when the edges meet).
#[test]
fn fitted_lids_close_without_crossing() {
    let mut failures = Vec::new();
    for (name, mesh, landmarks) in shared_heads() {
        let rig = crate::fit_default(&mesh, &landmarks).rig;
        let bound = BoundRig::bind(&rig, &mesh).unwrap();
        let act = builtin::default_table()
            .entry_activations(&"45".parse().unwrap(), &rig)
            .unwrap();
        let mut moved = Vec::new();
        bound.deform(&act, &mut moved).unwrap();
        let v = landmarks.vertices(&mesh);
        let up = FaceFrame::of(&landmarks.positions(&mesh).unwrap())
            .unwrap()
            .up;
        let height = |p: &[Vec3], a: usize, b: usize| {
            (p[v[a] as usize] - p[v[b] as usize]).as_dvec3().dot(up)
        };
        for (upper, lower) in [(37, 41), (38, 40), (43, 47), (44, 46)] {
            let gap = height(&moved, upper, lower) / height(&mesh.positions, upper, lower);
            println!("{name}: lids {upper}/{lower} at AU45: {gap:.2} of the rest opening");
            if gap < 0.0 {
                failures.push(format!("{name}: lids {upper}/{lower} crossed: {gap:.2}"));
            }
        }
        let gauge = Gauge::new(&mesh, &v, None).unwrap();
        let expect = Expect {
            lids_close: Some(Eyes::Both),
            jaw_opens: false,
        };
        let gap = gauge.measure(&moved, expect).lid_gap.unwrap();
        println!("{name}: lid gap at AU45: {gap:.2}");
        if gap > 0.35 {
            failures.push(format!("{name}: lid gap {gap:.2}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// A blink on a fitted head moves the lids and little else: the nose bridge (27-29) and the
/// brows (17-26) under a tenth of the upper lids' travel (37, 38, 43, 44), as on the built-in
/// face (tests/model/regions.rs). A ring carried at the lids' size reaches the brow and the
/// side of the nose on a head whose eyes open wider than the template's unless its reach is
/// kept to the template's.
#[test]
fn fitted_blink_moves_the_lids_and_little_else() {
    let mut failures = Vec::new();
    for (name, mesh, landmarks) in shared_heads() {
        let rig = crate::fit_default(&mesh, &landmarks).rig;
        let bound = BoundRig::bind(&rig, &mesh).unwrap();
        let act = builtin::default_table()
            .entry_activations(&"45".parse().unwrap(), &rig)
            .unwrap();
        let mut moved = Vec::new();
        bound.deform(&act, &mut moved).unwrap();
        let v = landmarks.vertices(&mesh);
        let most = |marks: &mut dyn Iterator<Item = usize>| {
            marks
                .map(|l| moved[v[l] as usize].distance(mesh.positions[v[l] as usize]))
                .fold(0.0f32, f32::max)
        };
        let lid = most(&mut [37, 38, 43, 44].into_iter());
        let bridge = most(&mut (27..=29));
        let brow = most(&mut (17..=26));
        println!("{name}: AU45 lid {lid}, nose bridge {bridge}, brows {brow}");
        if !(lid > 0.0 && bridge < 0.1 * lid && brow < 0.1 * lid) {
            failures.push(format!("{name}: lid {lid}, bridge {bridge}, brows {brow}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
