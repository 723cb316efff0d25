//! Fitting rigs to other faces by landmarks and AU entries to shapes, in the library and
//! through `grimace fit-rig` / `fit-au`.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;

mod au;
mod beyond;
mod brow_lowering;
mod brows_drawn;
mod classic;
mod cli;
mod eyecut;
mod eyes;
mod finer;
mod framing;
mod lidcorners;
mod lidfold;
mod lids;
mod lipcut;
mod lipmasks;
mod mouth;
mod parts;
mod real;
mod rig;
mod rings;
mod scheme;
mod seams;

use std::path::{Path, PathBuf};

use glam::Vec3;
use grimace::fit::quality::{Expect, Gauge};
use grimace::fit::{fit_rig, Fitted, PartOverrides, Template};
use grimace::io::{builtin, landmarks::load_landmarks, obj};
use grimace::landmarks::Landmarks;
use grimace::model::{BoundRig, Mesh};

/// The built-in rig fitted to `mesh` from `landmarks`, as `fit-rig` fits it.
fn fit_default(mesh: &Mesh, landmarks: &Landmarks) -> Fitted {
    let face = builtin::default_mesh();
    let rig = builtin::default_rig();
    let points = builtin::landmarks("face")
        .unwrap()
        .positions(&face)
        .unwrap();
    fit_rig(
        Template {
            rig: &rig,
            mesh: &face,
            landmarks: &points,
        },
        mesh,
        landmarks,
        "mesh.obj".into(),
        &PartOverrides::default(),
    )
    .unwrap()
}

/// MakeHuman's base mesh from `../shared` (its path, the mesh, and the landmarks picked on it
/// in `tests/fit_data`); `None` where the shared data is absent outside CI.
fn shared_makehuman() -> Option<(PathBuf, Mesh, Landmarks)> {
    let path =
        common::shared_with(&["meshes/makehuman_base.obj"])?.join("meshes/makehuman_base.obj");
    let mesh = obj::read_obj(&path).unwrap();
    let landmarks = load_landmarks(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fit_data/makehuman_base.landmarks.ron"
    )))
    .unwrap();
    Some((path, mesh, landmarks))
}

/// MediaPipe's canonical face from `../shared` (its path, the mesh, its landmarks by
/// MediaPipe's numbering); `None` where the shared data is absent outside CI.
fn shared_mediapipe() -> Option<(PathBuf, Mesh, Landmarks)> {
    let path = common::shared_with(&["meshes/mediapipe_canonical_face.obj"])?
        .join("meshes/mediapipe_canonical_face.obj");
    let mesh = obj::read_obj(&path).unwrap();
    let landmarks = Landmarks::mediapipe(&mesh).unwrap();
    Some((path, mesh, landmarks))
}

/// Runs `grimace fit-rig PATH --landmarks mediapipe --out mp.rig.ron EXTRA...` in `dir`,
/// asserts it succeeded and returns what it printed.
fn fit_mediapipe_in(dir: &Path, path: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "fit-rig",
        path.to_str().unwrap(),
        "--landmarks",
        "mediapipe",
        "--out",
        "mp.rig.ron",
    ];
    args.extend_from_slice(extra);
    let out = common::grimace_in(dir, &args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The shared MediaPipe face fitted by `fit-rig` in a temporary folder and loaded as a user's
/// rig would be: the folder (the files live as long as it does), the rig and its mesh, and
/// the landmarks written beside the mesh. `None` where the shared data is missing (outside CI).
fn fitted_mediapipe() -> Option<(tempfile::TempDir, grimace::io::load::LoadedRig, Landmarks)> {
    let (path, _, _) = shared_mediapipe()?;
    let dir = tempfile::tempdir().unwrap();
    fit_mediapipe_in(dir.path(), &path, &[]);
    let loaded = grimace::io::load::load_rig(&dir.path().join("mp.rig.ron")).unwrap();
    let beside = grimace::io::landmarks::beside(loaded.mesh_path.as_ref().unwrap());
    let landmarks = load_landmarks(&beside).unwrap();
    Some((dir, loaded, landmarks))
}

/// `check`'s failures (each named by head and AU) of `bound` at the built-in table's `aus`
/// at full intensity, measured by `gauge` against `expect`.
fn au_failures(
    name: &str,
    bound: &BoundRig,
    gauge: &Gauge,
    aus: &[&str],
    expect: Expect,
) -> Vec<String> {
    let mut failures = Vec::new();
    for au in aus {
        let quality = gauge.measure(&positions_at_au(bound, au), expect);
        eprintln!("{name} AU{au}: {quality:?}");
        failures.extend(
            quality
                .failures()
                .into_iter()
                .map(|f| format!("{name} AU{au}: {f}")),
        );
    }
    failures
}

/// The share of the rest opening the lids of both eyes leave at AU `key` of the built-in
/// table, as `grimace check` measures it (`marks`: the landmarks' vertices).
fn lid_gap_at(bound: &BoundRig, mesh: &Mesh, marks: &[u32], key: &str) -> f32 {
    let gauge = Gauge::new(mesh, marks, None).unwrap();
    let closing = Expect {
        lids_close: Some(grimace::fit::quality::Eyes::Both),
        jaw_opens: false,
    };
    gauge
        .measure(&positions_at_au(bound, key), closing)
        .lid_gap
        .unwrap()
}

/// Positions of `bound` at an AU of the built-in table, at full intensity.
fn positions_at_au(bound: &BoundRig, key: &str) -> Vec<Vec3> {
    let table = builtin::default_table();
    let act = table
        .entry_activations(&key.parse().unwrap(), bound.rig())
        .unwrap();
    let mut out = Vec::new();
    bound.deform(&act, &mut out).unwrap();
    out
}

/// `mesh` with every vertex moved by a seeded, roughly normal random offset of `sigma_mm`
/// in each coordinate (millimetres at the scale its 68 landmark vertices `marks` give,
/// [`grimace::landmarks::mm_per_unit`]): the unevenness of a scanned surface (the same
/// every run).
fn uneven(mesh: &Mesh, marks: &[u32], sigma_mm: f32, seed: u64) -> Mesh {
    let points: Vec<Vec3> = marks.iter().map(|&v| mesh.positions[v as usize]).collect();
    let sigma = sigma_mm / grimace::landmarks::mm_per_unit(&points).unwrap();
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut uniform = || {
        // xorshift64*: enough for a test's noise
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f32 / (1u64 << 53) as f32
    };
    // the sum of four uniforms, scaled to unit variance: near enough to a normal's shape
    let mut normal = || ((0..4).map(|_| uniform()).sum::<f32>() - 2.0) * 3.0f32.sqrt();
    let mut out = mesh.clone();
    for p in &mut out.positions {
        *p += Vec3::new(normal(), normal(), normal()) * sigma;
    }
    out
}
