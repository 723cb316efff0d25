//! The paper's extra muscles on the classic Waters face (read from the shared reference
//! folder): each moves the right tissue the right way at 1.0 and 2.0, the jaw opens the mouth
//! without tearing its corners, the rig is mirror-symmetric, and the 18 linear muscles still
//! match the classic reference outputs. Also `grimace import-waters` end to end.

use crate::common;
use grimace::io::load::load_rig;

use std::collections::HashMap;
use std::path::Path;
use std::process::{Command, Output};

use glam::Vec3;
use grimace::face::classic::{self, Landmarks};
use grimace::io::waters::{self, ImportOptions, Imported};
use grimace::model::{Activations, BoundRig, MuscleKind, Side, SkinRules};

/// The classic face with the extras, bound, and its landmarks.
struct Face {
    imported: Imported,
    bound: BoundRig,
    marks: Landmarks,
}

fn face() -> Option<Face> {
    let shared = common::shared()?;
    let options = ImportOptions {
        extras: Some(classic::extra_muscles),
        ..Default::default()
    };
    let imported = waters::import_dir(&shared.join("waters-geoface"), &options).unwrap();
    // the paper's deformation: these tests check its equations on the classic face
    let bound = BoundRig::bind_with(&imported.rig, &imported.mesh, SkinRules::PAPER).unwrap();
    let marks = classic::find_landmarks(&imported.mesh).unwrap();
    Some(Face {
        imported,
        bound,
        marks,
    })
}

impl Face {
    fn rest(&self) -> &[Vec3] {
        &self.imported.mesh.positions
    }

    /// The mesh with one muscle (by name) at `value`, or only the jaw when `name` is "jaw".
    fn pull(&self, name: &str, value: f32) -> Vec<Vec3> {
        let rig = &self.imported.rig;
        let mut act = Activations::zero(rig);
        if name == "jaw" {
            act.jaw = value;
        } else {
            act.muscles[rig.muscle_index(name).unwrap()] = value;
        }
        self.deform(&act)
    }

    fn deform(&self, act: &Activations) -> Vec<Vec3> {
        let mut out = Vec::new();
        self.bound.deform(act, &mut out).unwrap();
        assert!(out.iter().all(|p| p.is_finite()), "a vertex is not finite");
        out
    }

    fn eye(&self, side: Side) -> &classic::Opening {
        match side {
            Side::Left => &self.marks.left_eye,
            _ => &self.marks.right_eye,
        }
    }
}

fn y_range(p: &[Vec3], vs: &[u32]) -> (f32, f32) {
    vs.iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(p[v as usize].y), hi.max(p[v as usize].y))
        })
}

#[test]
fn the_extras_are_the_papers_muscles_with_sides_and_partners() {
    let Some(face) = face() else { return };
    let rig = &face.imported.rig;
    assert_eq!(rig.muscles.len(), 23);
    let extras: Vec<(&str, Side, Option<&str>)> = rig.muscles[18..]
        .iter()
        .map(|m| (m.name.as_str(), m.side, m.mirror.as_deref()))
        .collect();
    assert_eq!(
        extras,
        vec![
            ("L_Frontalis_Sheet", Side::Left, Some("R_Frontalis_Sheet")),
            ("R_Frontalis_Sheet", Side::Right, Some("L_Frontalis_Sheet")),
            ("Orbicularis_Oris", Side::Centre, None),
            (
                "L_Orbicularis_Oculi",
                Side::Left,
                Some("R_Orbicularis_Oculi")
            ),
            (
                "R_Orbicularis_Oculi",
                Side::Right,
                Some("L_Orbicularis_Oculi")
            ),
        ]
    );
    // the same names as the paper's rig on the default face, so AU tables can move over
    let paper = grimace::io::builtin::paper_rig();
    for name in extras.iter().map(|e| e.0) {
        assert!(paper.muscle_index(name).is_some(), "{name}");
    }
    let jaw = rig.jaw.as_ref().unwrap();
    assert!(jaw.degrees_per_unit >= 1.0);
    assert!(jaw.weights.iter().all(|&(_, w)| w > 0.0 && w <= 1.0));
    assert!(jaw.weights.windows(2).all(|w| w[0].0 < w[1].0));
}

#[test]
fn landmarks_are_found_by_geometry() {
    let Some(face) = face() else { return };
    let p = face.rest();
    let m = &face.marks;
    // The mouth slit: its two lips are only thousandths apart, yet split by their triangles.
    let [l, r] = m.mouth.corners.map(|v| p[v as usize]);
    assert_eq!(l.x, -r.x);
    let (upper, lower) = m.mouth.centres(p).unwrap();
    assert_eq!((upper.x, lower.x), (0.0, 0.0));
    assert!(
        upper.y > lower.y && upper.y - lower.y < 0.01,
        "{upper} {lower}"
    );
    // Each lip's neighbours lie on its own side: the vertex just above the upper lip's
    // middle is higher than the one just below the lower lip's.
    // glTF's convention, as the import converts to: the subject's left eye at x > 0
    for (eye, sign) in [(&m.left_eye, 1.0), (&m.right_eye, -1.0)] {
        assert!(eye.corners.iter().all(|&v| p[v as usize].x * sign > 0.0));
        let (lo_u, hi_u) = y_range(p, &eye.upper);
        let (lo_l, hi_l) = y_range(p, &eye.lower);
        assert!(hi_u > hi_l && lo_u > lo_l, "{eye:?}");
    }
    assert_eq!(
        m.left_eye.upper.len() + m.left_eye.lower.len(),
        m.right_eye.upper.len() + m.right_eye.lower.len()
    );
    assert!(m.chin.y < lower.y && m.chin.x == 0.0);
    assert!(m.top.y > p[m.left_eye.corners[0] as usize].y);
}

#[test]
fn frontalis_raises_its_own_brow() {
    let Some(face) = face() else { return };
    let p = face.rest();
    for (name, side) in [
        ("L_Frontalis_Sheet", Side::Left),
        ("R_Frontalis_Sheet", Side::Right),
    ] {
        let eye = face.eye(side);
        let [a, b] = eye.corners.map(|v| p[v as usize].x);
        let (x0, x1) = (a.min(b), a.max(b));
        let (_, lid_top) = y_range(p, &eye.upper);
        let (lid_bottom, _) = y_range(p, &eye.lower);
        let opening = lid_top - lid_bottom;
        // the brow: above the lid, over the eye
        let brow: Vec<usize> = (0..p.len())
            .filter(|&i| {
                p[i].x > x0 && p[i].x < x1 && p[i].y > lid_top + 0.3 * opening && {
                    p[i].y < lid_top + 1.2 * opening
                }
            })
            .collect();
        // the same place on the other side
        let other: Vec<usize> = (0..p.len())
            .filter(|&i| {
                brow.iter()
                    .any(|&b| p[b] == Vec3::new(-p[i].x, p[i].y, p[i].z))
            })
            .collect();
        assert!(brow.len() >= 4, "{name}: {brow:?}");
        for k in [1.0f32, 2.0] {
            let out = face.pull(name, k);
            let rises: Vec<f32> = brow.iter().map(|&i| out[i].y - p[i].y).collect();
            assert!(rises.iter().all(|&d| d > 0.0), "{name} {k}: {rises:?}");
            let mean = rises.iter().sum::<f32>() / rises.len() as f32;
            assert!(mean > 0.3 * k, "{name} {k}: mean rise {mean}");
            for &i in &other {
                assert_eq!(out[i], p[i], "{name} moves the other brow");
            }
            // the pull fades out above the lid margin, which the eye sphincter owns
            for &v in eye.upper.iter().chain(&eye.lower) {
                let d = out[v as usize] - p[v as usize];
                assert!(
                    d.length() < 0.05 * k,
                    "{name} {k}: lid vertex {v} moves {d}"
                );
            }
            // and the forehead does not fold: vertices over the eye keep their order in y
            let mut column: Vec<usize> = brow
                .iter()
                .copied()
                .filter(|&i| (p[i].x - 0.5 * (x0 + x1)).abs() < 0.3)
                .collect();
            column.sort_by(|&i, &j| p[i].y.total_cmp(&p[j].y));
            for w in column.windows(2) {
                assert!(out[w[0]].y < out[w[1]].y, "{name} {k}: fold");
            }
        }
    }
}

#[test]
fn eye_sphincters_close_the_lids_without_pulling_the_corners_in() {
    let Some(face) = face() else { return };
    let p = face.rest();
    for (name, side) in [
        ("L_Orbicularis_Oculi", Side::Left),
        ("R_Orbicularis_Oculi", Side::Right),
    ] {
        let eye = face.eye(side);
        let (upper, lower) = eye.centres(p).unwrap();
        let find = |q: Vec3| p.iter().position(|&v| v == q).unwrap();
        let (u, l) = (find(upper), find(lower));
        let rest_gap = upper.y - lower.y;
        let mut last_gap = rest_gap;
        for k in [1.0f32, 2.0] {
            let out = face.pull(name, k);
            // nothing moves sideways: the corners stay where they are in x
            for (i, (a, b)) in out.iter().zip(p).enumerate() {
                assert_eq!(a.x, b.x, "{name} {k}: vertex {i} moves in x");
            }
            for &c in &eye.corners {
                let d = out[c as usize] - p[c as usize];
                assert!(d.y.abs() < 0.15 * rest_gap, "{name} {k}: corner moves {d}");
            }
            for &v in &eye.upper {
                assert!(
                    out[v as usize].y <= p[v as usize].y + 0.02,
                    "{name} {k}: {v}"
                );
            }
            for &v in &eye.lower {
                assert!(out[v as usize].y >= p[v as usize].y, "{name} {k}: {v}");
            }
            assert!(out[u].y < upper.y && out[l].y > lower.y);
            let gap = out[u].y - out[l].y;
            assert!(gap < last_gap, "{name} {k}: gap {gap}");
            assert!(gap >= -1e-3, "{name} {k}: the lids cross ({gap})");
            // the lids bulge toward the viewer
            assert!(out[u].z > upper.z && out[l].z > lower.z);
            last_gap = gap;
        }
        // at full activation the lids meet
        assert!(
            last_gap < 0.05 * rest_gap,
            "{name}: gap {last_gap} of {rest_gap}"
        );
    }
}

#[test]
fn the_mouth_sphincter_purses_toward_the_mouth_centre() {
    let Some(face) = face() else { return };
    let p = face.rest();
    let rig = &face.imported.rig;
    let MuscleKind::Sphincter(s) = &rig.muscles[rig.muscle_index("Orbicularis_Oris").unwrap()].kind
    else {
        panic!("not a sphincter")
    };
    let centre = s.centre;
    let mouth = &face.marks.mouth;
    let corners: Vec<u32> = mouth.corners.to_vec();
    for k in [1.0f32, 2.0] {
        let out = face.pull("Orbicularis_Oris", k);
        let mut moved = 0;
        for (i, (a, b)) in out.iter().zip(p).enumerate() {
            let d = *a - *b;
            if d == Vec3::ZERO {
                continue;
            }
            moved += 1;
            // in the x-y plane, never away from the centre; out of it, toward the viewer
            let to_centre = (centre - *b).truncate();
            assert!(d.truncate().dot(to_centre) >= 0.0, "{k}: vertex {i} {d}");
            assert!(d.z > 0.0, "{k}: vertex {i} {d}");
        }
        assert!(moved > 10);
        for &c in &corners {
            let (a, b) = (out[c as usize], p[c as usize]);
            assert!(a.x.abs() < b.x.abs() - 0.05 * k, "{k}: corner {b} -> {a}");
            assert!(a.z > b.z);
        }
        // the middle of the lips is the protected disc: it only bulges
        let (upper, lower) = mouth.centres(p).unwrap();
        for q in [upper, lower] {
            let i = p.iter().position(|&v| v == q).unwrap();
            assert_eq!(out[i].truncate(), q.truncate());
            assert!(out[i].z > q.z);
        }
    }
}

fn normals(mesh: &grimace::model::Mesh, positions: &[Vec3]) -> Vec<Vec3> {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            (b - a).cross(c - a)
        })
        .collect()
}

#[test]
fn the_jaw_opens_the_mouth_without_tearing_its_corners() {
    let Some(face) = face() else { return };
    let p = face.rest();
    let mesh = &face.imported.mesh;
    let mouth = &face.marks.mouth;
    let chin = p.iter().position(|&v| v == face.marks.chin).unwrap();
    let (_, lower) = mouth.centres(p).unwrap();
    let lower = p.iter().position(|&v| v == lower).unwrap();
    let rest_normals = normals(mesh, p);
    let corner_points: Vec<Vec3> = mouth.corners.iter().map(|&c| p[c as usize]).collect();
    let mut last_drop = 0.0;
    for k in [1.0f32, 2.0, 4.0] {
        let out = face.pull("jaw", k);
        // the chin goes down and back
        let d = out[chin] - p[chin];
        assert!(d.y < 0.0 && d.z < 0.0, "{k}: chin {d}");
        // the lower lip drops, more with more activation
        let drop = p[lower].y - out[lower].y;
        assert!(drop > last_drop, "{k}: lower lip drop {drop}");
        last_drop = drop;
        // the upper lip and the corners stay put, and so does all above the mouth
        for &v in mouth.upper.iter().chain(&mouth.corners) {
            assert_eq!(out[v as usize], p[v as usize], "{k}: vertex {v} moves");
        }
        // (the classic lower lip rises a little above its corners)
        let top_of_mouth = mouth
            .upper
            .iter()
            .chain(&mouth.lower)
            .chain(&mouth.corners)
            .map(|&v| p[v as usize].y)
            .fold(f32::MIN, f32::max);
        for (i, (a, b)) in out.iter().zip(p).enumerate() {
            if b.y > top_of_mouth + 0.01 {
                assert_eq!(a, b, "{k}: vertex {i} above the mouth moves");
            }
        }
        // no triangle near the corners turns over
        let now = normals(mesh, &out);
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let near = tri.iter().any(|&v| {
                corner_points
                    .iter()
                    .any(|c| c.distance(p[v as usize]) < 1.0)
            });
            if near {
                assert!(
                    now[t].dot(rest_normals[t]) > 0.0,
                    "{k}: triangle {t} {tri:?} flips near a mouth corner"
                );
            }
        }
    }
    // K = 4 opens the lips by a visible amount (about a centimetre at this face's scale)
    assert!(last_drop > 0.8, "lower lip drop {last_drop}");
}

#[test]
fn the_full_rig_is_mirror_symmetric_and_finite() {
    let Some(face) = face() else { return };
    let p = face.rest();
    let rig = &face.imported.rig;
    let index: HashMap<[u32; 3], usize> = p
        .iter()
        .enumerate()
        .map(|(i, v)| (v.to_array().map(f32::to_bits), i))
        .collect();
    let twin: Vec<usize> = p
        .iter()
        .map(|v| {
            let m = Vec3::new(-v.x, v.y, v.z) + Vec3::ZERO;
            index[&m.to_array().map(f32::to_bits)]
        })
        .collect();
    let mut act = Activations::zero(rig);
    for (i, a) in act.muscles.iter_mut().enumerate() {
        *a = 0.1 + (i as f32 * 0.37) % 1.9;
    }
    act.jaw = 2.7;
    let mut mirrored = act.clone();
    for i in 0..rig.muscles.len() {
        let j = rig.mirror_of(i).unwrap_or(i);
        mirrored.muscles[j] = act.muscles[i];
    }
    let a = face.deform(&act);
    let b = face.deform(&mirrored);
    for (i, q) in a.iter().enumerate() {
        let m = Vec3::new(-q.x, q.y, q.z);
        let got = b[twin[i]];
        assert!(
            (m - got).abs().max_element() <= 1e-5,
            "vertex {i}: {q} mirrored is {m}, twin {} is at {got}",
            twin[i]
        );
    }
    // everything at full strength stays finite
    let mut full = Activations::zero(rig);
    full.muscles.fill(2.0);
    full.jaw = 4.0;
    face.deform(&full);
}

#[test]
fn the_linear_muscles_still_match_the_classic_reference() {
    let Some(face) = face() else { return };
    let shared = common::shared().unwrap();
    let plain =
        waters::import_dir(&shared.join("waters-geoface"), &ImportOptions::default()).unwrap();
    assert_eq!(plain.mesh, face.imported.mesh);
    assert_eq!(plain.rig.muscles[..], face.imported.rig.muscles[..18]);
    let golden = std::fs::read_to_string(shared.join("golden/waters-linear.csv")).unwrap();
    let mut expected: HashMap<(usize, &str), Vec<Vec3>> = HashMap::new();
    for line in golden.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f[2] != "1" && f[2] != "2" {
            continue;
        }
        let muscle: usize = f[0].parse().unwrap();
        let rows = expected
            .entry((muscle, f[2]))
            .or_insert_with(|| face.rest().to_vec());
        let v: usize = f[3].parse().unwrap();
        // the reference is in the classic convention; convert it as the import does
        rows[v] = grimace::io::waters::from_classic(Vec3::new(
            f[4].parse().unwrap(),
            f[5].parse().unwrap(),
            f[6].parse().unwrap(),
        ));
    }
    assert_eq!(expected.len(), 36);
    for ((muscle, k), want) in &expected {
        let name = &face.imported.rig.muscles[*muscle].name;
        let got = face.pull(name, k.parse().unwrap());
        for (v, (g, w)) in got.iter().zip(want).enumerate() {
            assert!(
                (*g - *w).abs().max_element() <= 1e-5,
                "{name} at {k}: vertex {v}: {g} vs {w}"
            );
        }
    }
}

// ---- `grimace import-waters` end to end

fn grimace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(args)
        .output()
        .unwrap()
}

fn import_to(dir: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "import-waters",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    grimace(&args)
}

#[test]
fn import_waters_writes_the_full_rig_unless_linear_only() {
    let Some(shared) = common::shared() else {
        return;
    };
    let data = shared.join("waters-geoface");
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    let result = import_to(&data, &full, &[]);
    assert_eq!(
        result.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    assert!(String::from_utf8_lossy(&result.stdout).contains("(23 muscles and a jaw)"));
    let loaded = load_rig(&full.join("rig.ron")).unwrap();
    let placed = classic::place_extras(&loaded.mesh).unwrap();
    assert_eq!(loaded.rig.muscles.len(), 23);
    assert_eq!(loaded.rig.muscles[18..], placed.0[..]);
    assert_eq!(loaded.rig.jaw.as_ref(), Some(&placed.1));
    BoundRig::bind(&loaded.rig, &loaded.mesh).unwrap();

    let linear = tmp.path().join("linear");
    let result = import_to(&data, &linear, &["--linear-only"]);
    assert_eq!(result.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&result.stdout).contains("(18 muscles)\n"));
    let loaded_linear = load_rig(&linear.join("rig.ron")).unwrap();
    assert_eq!(loaded_linear.rig.muscles[..], loaded.rig.muscles[..18]);
    assert!(loaded_linear.rig.jaw.is_none());
}

#[test]
fn import_waters_explains_a_face_it_cannot_place_the_extras_on() {
    // A closed square of two quads mirrored into a face with no mouth or eyes.
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path();
    std::fs::write(
        data.join("faceline.dat"),
        "6\n0 0 1\n-1 0 1\n-1 1 1\n0 1 1\n-1 2 1\n0 2 1\n",
    )
    .unwrap();
    std::fs::write(data.join("index.dat"), "2\n1 2 3 4\n4 3 5 6\n").unwrap();
    std::fs::write(
        data.join("muscle.dat"),
        "1\nL_m -1 1 1 -1 0 1 0.1 1.5 40 1\n",
    )
    .unwrap();
    let out = tmp.path().join("out");
    let result = import_to(data, &out, &[]);
    assert_ne!(result.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("no mouth opening") && stderr.contains("--linear-only"),
        "{stderr}"
    );
    assert!(!out.join("rig.ron").exists());
    let result = import_to(data, &out, &["--linear-only"]);
    assert_eq!(
        result.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    assert!(out.join("rig.ron").exists());
}
