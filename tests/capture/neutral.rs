//! The neutral the muscles define: a recording made by grimace whose first frame and most of
//! whose frames smile, so that the median of its calm frames smiles too, is solved back
//! from the rest face, the smile's known activations recovered.

use glam::{DVec3, Vec3};
use grimace::capture::synthetic::{self, Motion};
use grimace::capture::{neutral, pose, LandmarkModel, NeutralSource, Regularisation, Session};
use grimace::model::Activations;

use crate::synthetic::{act, face, read, Face};

/// The smile most of the recording holds.
const SMILE: [(&str, f32); 2] = [("L_Zygomatic_Major", 0.6), ("R_Zygomatic_Major", 0.6)];

/// 40 frames: the smile (frames 1-24: the first and the median frame smile), the rest face
/// (25-32), the smile with the inner brows raised (33-40).
fn recording(face: &Face) -> Vec<(Activations, &'static str)> {
    let smile = act(face, &SMILE, 0.0);
    let rest = act(face, &[], 0.0);
    let brows = [
        SMILE[0],
        SMILE[1],
        ("L_Frontalis_Medial", 0.5),
        ("R_Frontalis_Medial", 0.5),
    ];
    let raised = act(face, &brows, 0.0);
    (0..40)
        .map(|k| match k {
            0..24 => (smile.clone(), "smile"),
            24..32 => (rest.clone(), "rest"),
            _ => (raised.clone(), "smile and brows"),
        })
        .collect()
}

/// RMS distance between two landmark sets.
fn rms(a: &[DVec3], b: &[DVec3]) -> f64 {
    (a.iter()
        .zip(b)
        .map(|(p, q)| p.distance_squared(*q))
        .sum::<f64>()
        / a.len() as f64)
        .sqrt()
}

/// The head turned and moved as [`Motion::default`], without the tracker's noise.
fn still() -> Motion {
    Motion {
        noise: 0.0,
        ..Motion::default()
    }
}

/// One pose's landmarks as the tracker would see it at the recording's first frame, no noise.
fn seen(face: &Face, pose: &Activations) -> Vec<Vec3> {
    synthetic::landmarks(&face.bound, &face.vertices, &[Some(pose.clone())], still())
        .remove(0)
        .unwrap()
}

/// A synthetic recording of `acts` (default motion: turned, moved and noised), written as an
/// OpenFace CSV and read back as landmark rows.
fn recorded(face: &Face, acts: &[Option<Activations>]) -> Vec<Vec<Vec3>> {
    read(&synthetic::csv(&synthetic::landmarks(
        &face.bound,
        &face.vertices,
        acts,
        Motion::default(),
    )))
}

/// The recording's calm-frame median and the least-work neutral found from it.
struct Neutrals {
    model: LandmarkModel,
    median: Vec<DVec3>,
    found: Vec<DVec3>,
}

fn neutrals(face: &Face, rows: &[Vec<Vec3>]) -> Neutrals {
    let frames: Vec<&[Vec3]> = rows.iter().map(Vec::as_slice).collect();
    let model = LandmarkModel::new(&face.bound, &face.vertices);
    let (median, _) = pose::estimate_neutral(&frames).unwrap();
    let regularisation = Regularisation::default();
    let (found, _) =
        neutral::least_work(&face.bound, &model, &frames, median.clone(), regularisation).unwrap();
    Neutrals {
        model,
        median,
        found,
    }
}

/// `points` aligned onto `neutral`.
fn at(points: &[Vec3], neutral: &[DVec3]) -> Vec<DVec3> {
    pose::align(points, neutral).unwrap().points
}

#[test]
fn a_recording_that_smiles_throughout_is_solved_from_the_rest_face() {
    let face = face();
    let poses = recording(&face);
    let acts: Vec<Option<Activations>> = poses.iter().map(|(a, _)| Some(a.clone())).collect();
    let rows = recorded(&face, &acts);
    let Neutrals {
        model,
        median,
        found,
    } = neutrals(&face, &rows);
    let regularisation = Regularisation::default();

    // The neutral recovered: the rest face, not the smile the calm-frame median is.
    let rest = seen(&face, &act(&face, &[], 0.0));
    let smile = seen(&face, &act(&face, &SMILE, 0.0));
    let smile_size = rms(&at(&smile, &median), &at(&rest, &median));
    let was = rms(&at(&rest, &median), &median);
    let off = rms(&at(&rest, &found), &found);
    assert!(
        was > 0.5 * smile_size,
        "the calm-frame median smiles (rest {was:.3} mm from it, the smile {smile_size:.3})"
    );
    assert!(
        off < 0.15 * smile_size,
        "the muscle-defined neutral is {off:.3} mm from the rest face (the smile: {smile_size:.3}, the median: {was:.3})"
    );

    // And the smile's activations are solved back from it.
    let source = NeutralSource::FirstFrame(1);
    let mut session = Session::new(&face.bound, &model, found, source, regularisation).unwrap();
    let names = face.names();
    for (k, ((want, what), row)) in poses.iter().zip(&rows).enumerate() {
        let got = session.frame(row).expect("every synthetic frame is usable");
        // The temporal term lags a step change by design: a pose is checked once held.
        if k < 2 || poses[k - 2].1 != *what {
            continue;
        }
        for name in ["L_Zygomatic_Major", "R_Zygomatic_Major"] {
            let i = names.iter().position(|n| *n == name).unwrap();
            let (w, g) = (want.muscles[i], got.activations.muscles[i]);
            assert!(
                (w - g).abs() < 0.05,
                "frame {}: {what}: {name} wanted {w}, solved {g}",
                k + 1
            );
        }
    }
}

/// The brow lowerer's sheets (the orbital orbicularis's upper fibres) at half of AU4's entry.
const SHEETS: [(&str, f32); 2] = [
    ("L_Orbicularis_Oculi_Superior", 0.875),
    ("R_Orbicularis_Oculi_Superior", 0.875),
];

/// RMS distance over the brows' ten landmarks (17-26).
fn brow_rms(a: &[DVec3], b: &[DVec3]) -> f64 {
    rms(&a[17..27], &b[17..27])
}

/// The recording's frames (tracker coordinates) at `along` times the sheets' motion from
/// rest: each frame's rest landmarks plus `along` times the sheets' motion in that frame's
/// pose. Below 0 the brows rise along the sheets' own line: a subject's brow raise that
/// the rig's frontalis does not make exactly, so the signed reading sees the sheets working
/// less than in the neutral, as on real recordings.
fn along_sheets(face: &Face, along: &[f32]) -> Vec<Vec<Vec3>> {
    let make = |a: &Activations| {
        let poses = vec![Some(a.clone()); along.len()];
        synthetic::landmarks(&face.bound, &face.vertices, &poses, still())
    };
    let (rest, sheets) = (make(&act(face, &[], 0.0)), make(&act(face, &SHEETS, 0.0)));
    let mut jitter = 0x5eed_u64;
    rest.iter()
        .zip(&sheets)
        .zip(along)
        .map(|((r, s), &t)| {
            r.as_ref()
                .unwrap()
                .iter()
                .zip(s.as_ref().unwrap())
                .map(|(r, s)| {
                    // 0.02 mm of tracker noise, as the other synthetic recordings have.
                    jitter = jitter.wrapping_mul(6364136223846793005).wrapping_add(1);
                    let n = ((jitter >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.04;
                    *r + (*s - *r) * t + Vec3::splat(n)
                })
                .collect()
        })
        .collect()
}

#[test]
fn brows_lowered_and_raised_along_antagonists_leave_the_neutral_at_rest() {
    let face = face();
    // Lowered first (the first frame is not the neutral), then at rest, then raised, then
    // lowered again: the brows spend as long below their rest as above it.
    let along: Vec<f32> = (0..48)
        .map(|k| match k {
            0..8 | 40..48 => 1.0,
            8..24 => 0.0,
            _ => -1.0,
        })
        .collect();
    let rows = along_sheets(&face, &along);
    let found = neutrals(&face, &rows).found;
    let ends = along_sheets(&face, &[0.0, 1.0]);
    let (rest, lowered) = (at(&ends[0], &found), at(&ends[1], &found));
    let lowering = brow_rms(&lowered, &rest);
    let off = brow_rms(&rest, &found);
    eprintln!("brows: the neutral is {off:.3} mm from rest; the lowering {lowering:.3}");
    assert!(
        off < 0.15 * lowering,
        "the neutral's brows are {off:.3} mm from rest (the lowering: {lowering:.3} mm)"
    );
}

/// RMS distance over the mouth's twenty landmarks (48-67).
fn mouth_rms(a: &[DVec3], b: &[DVec3]) -> f64 {
    rms(&a[48..68], &b[48..68])
}

#[test]
fn brows_that_rest_only_while_the_mouth_smiles_leave_the_neutral_at_rest() {
    let face = face();
    // No frame rests as a whole: the mouth smiles while the brows rest (24 frames), the
    // brows rise while the mouth rests (16). One set of least-working frames for the whole
    // face takes one or the other; the brows' own frames and the rest of the face's own
    // frames each find their rest.
    let smile = act(&face, &SMILE, 0.0);
    let brows = [("L_Frontalis_Medial", 0.6), ("R_Frontalis_Medial", 0.6)];
    let raised = act(&face, &brows, 0.0);
    let acts: Vec<Option<Activations>> = (0..40)
        .map(|k| {
            Some(
                if (12..28).contains(&k) {
                    &raised
                } else {
                    &smile
                }
                .clone(),
            )
        })
        .collect();
    let rows = recorded(&face, &acts);
    let found = neutrals(&face, &rows).found;
    let rest = at(&seen(&face, &act(&face, &[], 0.0)), &found);
    let smiled = at(&seen(&face, &smile), &found);
    let lifted = at(&seen(&face, &raised), &found);
    let (smile_size, raise_size) = (mouth_rms(&smiled, &rest), brow_rms(&lifted, &rest));
    let (mouth_off, brows_off) = (mouth_rms(&rest, &found), brow_rms(&rest, &found));
    eprintln!(
        "mouth {mouth_off:.3} mm from rest (the smile {smile_size:.3}); brows {brows_off:.3} (the raise {raise_size:.3})"
    );
    assert!(
        mouth_off < 0.15 * smile_size,
        "the neutral's mouth is {mouth_off:.3} mm from rest (the smile: {smile_size:.3} mm)"
    );
    assert!(
        brows_off < 0.15 * raise_size,
        "the neutral's brows are {brows_off:.3} mm from rest (the raise: {raise_size:.3} mm)"
    );
}
