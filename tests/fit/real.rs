//! Real meshes from ../shared/meshes: MediaPipe's canonical face (closed mouth, 468
//! vertices, centimetres) and MakeHuman's whole-body base mesh (quads, helper geometry,
//! decimetres). Both fit, validate, and show AU 12, 26 and 45 moving the right regions in the
//! right directions; MakeHuman's eyes and helpers stay still under the skin muscles and its
//! lashes close with their lids.

use crate::common;

use std::f32::consts::FRAC_PI_2;
use std::path::Path;

use glam::{DVec3, Vec3};
use grimace::fit::{Fitted, Part};
use grimace::io::obj;
use grimace::landmarks::{FaceFrame, Landmarks};
use grimace::model::{BoundRig, Mesh};

/// Displacements of every vertex for an AU of the built-in table.
fn au(bound: &BoundRig, key: &str) -> Vec<Vec3> {
    let out = crate::positions_at_au(bound, key);
    out.iter().zip(bound.rest()).map(|(a, b)| *a - *b).collect()
}

/// The checks both meshes share. `v` gives each landmark's vertex; `size` is the face's
/// eye-to-mouth distance.
fn check_aus(mesh: &Mesh, fitted: &Fitted, v: &[u32]) {
    let bound = BoundRig::bind(&fitted.rig, mesh).unwrap();
    let points: Vec<Vec3> = v.iter().map(|&i| mesh.positions[i as usize]).collect();
    let frame = FaceFrame::of(&points).unwrap();
    let size = frame.eyes_to_mouth;
    let at = |d: &[Vec3], i: usize| d[v[i] as usize].as_dvec3();
    let up = |d: DVec3| d.dot(frame.up) / size;
    let across = |d: DVec3| d.dot(frame.lateral) / size;

    // AU 12: both mouth corners up and outward.
    let smile = au(&bound, "12");
    for (corner, outward) in [(48, -1.0), (54, 1.0)] {
        let d = at(&smile, corner);
        assert!(up(d) > 0.03, "AU 12: corner {corner} rises {:.3}", up(d));
        assert!(
            outward * across(d) > 0.01,
            "AU 12: corner {corner} across {:.3}",
            across(d)
        );
    }
    // AU 26: the chin and lower lip go down, the upper lip stays.
    let open = au(&bound, "26");
    let chin = up(at(&open, 8));
    assert!(chin < -0.05, "AU 26: chin moves {chin:.3}");
    for lower in [57, 66] {
        assert!(up(at(&open, lower)) < -0.03, "AU 26: lower lip {lower}");
    }
    for upper in [51, 62] {
        let u = at(&open, upper).length() / size;
        assert!(
            u < 0.1 * chin.abs(),
            "AU 26: upper lip {upper} moves {u:.3}"
        );
    }
    // The mouth opens: the inner lip points part.
    let gap = up(at(&open, 62) - at(&open, 66));
    assert!(gap > 0.03, "AU 26: lips part by {gap:.3}");
    // AU 45: upper lids come down, lower lids do not, and the lid landmarks come at least
    // 0.35 of their opening together, and the lids close: under 10% of the opening shows
    // between them as `grimace check` measures it (at the free edges where the landmarks are
    // not on them). MakeHuman's lid landmarks lie on the lid's back, 4 to 5 mm beyond the
    // free edges, and come 0.39 to 0.47 of their opening together when the lids meet.
    let blink = au(&bound, "45");
    let gap = crate::lid_gap_at(&bound, mesh, v, "45");
    assert!(gap < 0.10, "AU 45: the lids leave {gap:.3} of the opening");
    for (upper, lower) in [(37, 41), (38, 40), (43, 47), (44, 46)] {
        let (u, l) = (up(at(&blink, upper)), up(at(&blink, lower)));
        let opening = up(points[upper].as_dvec3() - points[lower].as_dvec3());
        assert!(u < -0.02, "AU 45: upper lid {upper} moves {u:.3}");
        assert!(l > -0.01, "AU 45: lower lid {lower} moves {l:.3}");
        assert!(
            u - l < -0.35 * opening,
            "AU 45: lids {upper}, {lower} close by {:.3} of {opening:.3}",
            l - u
        );
    }
    // Nothing far from the face moves under the mouth and eye AUs.
    for d in [&smile, &blink] {
        let far = mesh
            .positions
            .iter()
            .zip(d.iter())
            .filter(|(p, _)| (p.as_dvec3() - points[30].as_dvec3()).length() > 2.0 * size)
            .map(|(_, d)| d.length())
            .fold(0.0f32, f32::max);
        assert!(f64::from(far) < 1e-3 * size, "a far vertex moved {far}");
    }
}

fn save_and_validate(dir: &Path, mesh_file: &Path, fitted: &Fitted) {
    let mut rig = fitted.rig.clone();
    rig.mesh = mesh_file.to_path_buf();
    let out = dir.join("fitted.rig.ron");
    grimace::io::save_rig(&out, &rig).unwrap();
    let result = common::grimace_in(dir, &["validate", "fitted.rig.ron"]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
}

#[test]
fn mediapipe_canonical_face() {
    let Some((path, mesh, landmarks)) = crate::shared_mediapipe() else {
        return;
    };
    let fitted = crate::fit_default(&mesh, &landmarks);
    assert!(fitted.parts.of_vertex.iter().all(|&p| p == Part::Skin));
    check_aus(&mesh, &fitted, &landmarks.vertices(&mesh));
    let dir = tempfile::tempdir().unwrap();
    save_and_validate(dir.path(), &path, &fitted);
}

#[test]
fn makehuman_base_mesh() {
    let Some((path, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let fitted = crate::fit_default(&mesh, &landmarks);
    let parts = &fitted.parts.of_vertex;
    let group = |name: &str| mesh.groups[name].clone();
    let body = group("body");
    for name in [
        "helper-l-eye",
        "helper-r-eye",
        "helper-hair",
        "helper-tights",
    ] {
        assert!(
            group(name).iter().all(|&v| parts[v as usize] != Part::Skin),
            "{name}"
        );
    }
    for name in ["helper-lower-teeth", "helper-tongue"] {
        assert!(
            group(name).iter().all(|&v| parts[v as usize] == Part::Jaw),
            "{name}"
        );
    }
    assert!(group("helper-upper-teeth")
        .iter()
        .all(|&v| parts[v as usize] == Part::Still));
    assert!(group("body")
        .iter()
        .all(|&v| parts[v as usize] == Part::Skin));
    check_aus(&mesh, &fitted, &landmarks.vertices(&mesh));

    // Eyes and helpers never move under the skin muscles.
    let bound = BoundRig::bind(&fitted.rig, &mesh).unwrap();
    let helpers: Vec<u32> = mesh
        .groups
        .iter()
        .filter(|(name, _)| name.starts_with("helper-") && !name.contains("lash"))
        .flat_map(|(_, m)| m.iter().copied())
        .filter(|v| body.binary_search(v).is_err())
        .collect();
    for key in ["12", "45", "6", "1", "4", "9", "17", "24"] {
        let d = au(&bound, key);
        for &v in &helpers {
            assert_eq!(
                d[v as usize],
                Vec3::ZERO,
                "AU {key} moved helper vertex {v}"
            );
        }
    }
    lashes_follow_their_lids(&mesh, &bound, parts, &landmarks.vertices(&mesh));
    let dir = tempfile::tempdir().unwrap();
    save_and_validate(dir.path(), &path, &fitted);
}

/// The eyelash groups are skin and close with their lids: at AU45 a lash vertex moves, on
/// average, within a tenth of the upper lids' travel of the nearest body vertex (the lid's
/// edge it grows from). Still lashes would stay where the open lid was.
fn lashes_follow_their_lids(mesh: &Mesh, bound: &BoundRig, parts: &[Part], marks: &[u32]) {
    let d = au(bound, "45");
    let lid = [37, 38, 43, 44]
        .map(|l| d[marks[l] as usize].length())
        .into_iter()
        .fold(0.0f32, f32::max);
    let body = &mesh.groups["body"];
    for (name, members) in mesh.groups.iter().filter(|(n, _)| n.contains("eyelashes")) {
        assert!(
            members.iter().all(|&v| parts[v as usize] == Part::Skin),
            "{name}"
        );
        let off: f32 = members
            .iter()
            .map(|&v| {
                let p = mesh.positions[v as usize];
                let edge = body
                    .iter()
                    .min_by(|&&a, &&b| {
                        let da = mesh.positions[a as usize].distance_squared(p);
                        da.total_cmp(&mesh.positions[b as usize].distance_squared(p))
                    })
                    .unwrap();
                d[v as usize].distance(d[*edge as usize])
            })
            .sum::<f32>()
            / members.len() as f32;
        println!("{name}: AU45 moves a lash {off} from its lid edge (lid travel {lid})");
        assert!(
            off < 0.1 * lid,
            "{name}: {off} off its lid, lid travel {lid}"
        );
    }
}

/// The same face z-up in millimetres and turned half away: the mouth and eye rings still
/// close the lids and the mouth in the face's own plane.
#[test]
fn mediapipe_canonical_face_z_up_and_turned() {
    let Some(shared) = common::shared_with(&["meshes/mediapipe_canonical_face.obj"]) else {
        return;
    };
    let path = shared.join("meshes/mediapipe_canonical_face.obj");
    let mut mesh = obj::read_obj(&path).unwrap();
    let turn = glam::Quat::from_rotation_z(0.7) * glam::Quat::from_rotation_x(FRAC_PI_2);
    for p in &mut mesh.positions {
        *p = turn * *p * 10.0 + Vec3::new(30.0, -5.0, 1650.0);
    }
    let landmarks = Landmarks::mediapipe(&mesh).unwrap();
    let fitted = crate::fit_default(&mesh, &landmarks);
    check_aus(&mesh, &fitted, &landmarks.vertices(&mesh));
}
