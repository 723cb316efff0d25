//! AU4 on a fitted head brings the whole brow down over a lid that stays, as on the built-in
//! face (tests/model/brow_hair.rs): the brow's tail as well as its head.

use grimace::io::builtin;
use grimace::landmarks::FaceFrame;
use grimace::model::Deformation;

/// The fitted MediaPipe mask (its brows drawn from its landmarks when loaded) at AU4: the
/// drawn brow's half toward the head and the half toward the tail each come down at least
/// 0.15 of the eye's width along the face's up (now 0.45 and 0.29), and the upper lid
/// landmarks (37, 38, 43, 44) move under 0.04 of it. Before the orbital fibres' sheet the
/// head half came down about 0.2 and the tail half not at all.
#[test]
fn a_fitted_head_lowers_the_whole_brow_at_au4() {
    let Some((_dir, loaded, landmarks)) = crate::fitted_mediapipe() else {
        return;
    };
    let (rig, mesh) = (&loaded.rig, &loaded.mesh);
    let marks = landmarks.positions(mesh).unwrap();
    let vertices = landmarks.vertices(mesh);
    let frame = FaceFrame::of(&marks).unwrap();
    let eye = 0.5 * (marks[36].distance(marks[39]) + marks[42].distance(marks[45]));
    let bound = Deformation::Skin.bind(rig, mesh).unwrap();
    let act = builtin::default_table()
        .entry_activations(&"4".parse().unwrap(), rig)
        .unwrap();
    let mut moved = Vec::new();
    bound.deform(&act, &mut moved).unwrap();
    let rest = &mesh.positions;
    let down = |v: usize| ((rest[v] - moved[v]).as_dvec3().dot(frame.up)) as f32 / eye;
    let across = |v: usize| rest[v].as_dvec3().dot(frame.lateral);
    let mut failures = Vec::new();
    for (side, head, tail) in [("left", 22, 26), ("right", 21, 17)] {
        let hair = &mesh.groups[&format!("{side}_brow_hair")];
        let (a, b) = (
            marks[head].as_dvec3().dot(frame.lateral),
            marks[tail].as_dvec3().dot(frame.lateral),
        );
        let half = |toward_tail: bool| {
            let members: Vec<usize> = hair
                .iter()
                .map(|&v| v as usize)
                .filter(|&v| (((across(v) - a) / (b - a)) > 0.5) == toward_tail)
                .collect();
            members.iter().map(|&v| down(v)).sum::<f32>() / members.len() as f32
        };
        let (medial, lateral) = (half(false), half(true));
        println!(
            "{side} brow at AU4: down {medial:.3} (head half), {lateral:.3} (tail half) eye widths"
        );
        if medial < 0.15 || lateral < 0.15 {
            failures.push(format!("{side} brow down {medial:.3} / {lateral:.3}"));
        }
    }
    let lid = [37, 38, 43, 44]
        .iter()
        .map(|&l| {
            let v = vertices[l] as usize;
            moved[v].distance(rest[v]) / eye
        })
        .fold(0.0f32, f32::max);
    println!("upper lids at AU4: moved {lid:.3} eye widths");
    if lid >= 0.04 {
        failures.push(format!("upper lid moved {lid:.3}"));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
