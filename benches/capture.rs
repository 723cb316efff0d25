//! `grimace capture` on a 700-frame recording made by the rig itself (a smile, a brow raise
//! and the jaw coming and going while the head turns), end to end (the process, start-up
//! included: what the 300 frames a second is about), per frame (the library's solve
//! alone) and the start-up's parts (the landmark model, the calm-frame median, the
//! least-work neutral).
//!
//! Run: `cargo bench --bench capture`. Prints the end-to-end median and frames per second.

use std::process::Command;
use std::time::Instant;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::Vec3;
use grimace::capture::synthetic::{self, Motion};
use grimace::capture::{pose, LandmarkModel, NeutralSource, Regularisation, Session};
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig, Deformation};

const FRAMES: usize = 700;

fn rig() -> (BoundRig, Vec<u32>) {
    let mesh = builtin::default_mesh();
    let bound = Deformation::default()
        .bind(&builtin::default_rig(), &mesh)
        .expect("the default rig binds");
    let vertices = builtin::landmarks("default")
        .expect("built-in landmarks")
        .vertices(&mesh);
    (bound, vertices)
}

/// Activations that come and go smoothly over the recording.
fn poses(bound: &BoundRig) -> Vec<Option<Activations>> {
    let rig = bound.rig();
    let index = |name: &str| rig.muscle_index(name).expect("a default-rig muscle");
    let (smile, brow) = (index("L_Zygomatic_Major"), index("R_Frontalis_Inner"));
    (0..FRAMES)
        .map(|k| {
            let t = k as f32 / FRAMES as f32;
            let mut act = Activations::zero(rig);
            act.muscles[smile] = (t * 9.0).sin().max(0.0);
            act.muscles[brow] = (t * 5.0).cos().max(0.0) * 0.8;
            act.jaw = (t * 7.0).sin().max(0.0) * 2.0;
            Some(act)
        })
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn end_to_end(text: &str) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    std::fs::write(dir.path().join("rec.csv"), text).expect("write the recording");
    let times: Vec<f64> = (0..5)
        .map(|_| {
            let start = Instant::now();
            let status = Command::new(env!("CARGO_BIN_EXE_grimace"))
                .args(["capture", "rec.csv", "--out", "acts.csv"])
                .current_dir(dir.path())
                .output()
                .expect("run grimace capture");
            assert!(
                status.status.success(),
                "{}",
                String::from_utf8_lossy(&status.stderr)
            );
            start.elapsed().as_secs_f64()
        })
        .collect();
    let t = median(times);
    println!(
        "capture end to end, {FRAMES} frames: {:.1} ms median, {:.0} frames/s (start-up included)",
        t * 1e3,
        FRAMES as f64 / t
    );
}

fn capture(c: &mut Criterion) {
    let (bound, vertices) = rig();
    let frames = synthetic::landmarks(&bound, &vertices, &poses(&bound), Motion::default());
    end_to_end(&synthetic::csv(&frames));
    let rows: Vec<Vec<Vec3>> = frames.into_iter().flatten().collect();
    let model = LandmarkModel::new(&bound, &vertices);
    let refs: Vec<&[Vec3]> = rows.iter().map(Vec::as_slice).collect();
    let (median, _) = pose::estimate_neutral(&refs).expect("a neutral");
    let regularisation = Regularisation::default();
    let (neutral, _) = grimace::capture::neutral::least_work(
        &bound,
        &model,
        &refs,
        median.clone(),
        regularisation,
    )
    .expect("the least-work neutral");
    c.bench_function("capture: landmark model (start-up)", |b| {
        b.iter(|| LandmarkModel::new(black_box(&bound), &vertices))
    });
    c.bench_function("capture: estimate the neutral (700 frames)", |b| {
        b.iter(|| pose::estimate_neutral(black_box(&refs)))
    });
    c.bench_function("capture: the least-work neutral (700 frames)", |b| {
        b.iter(|| {
            grimace::capture::neutral::least_work(
                &bound,
                &model,
                black_box(&refs),
                median.clone(),
                regularisation,
            )
        })
    });
    let mut session = Session::new(
        &bound,
        &model,
        neutral,
        NeutralSource::Frame(1),
        Regularisation::default(),
    )
    .expect("a session");
    let mut k = 0;
    c.bench_function("capture: one frame", |b| {
        b.iter(|| {
            k = (k + 1) % rows.len();
            session.frame(black_box(&rows[k]))
        })
    });
}

criterion_group!(benches, capture);
criterion_main!(benches);
