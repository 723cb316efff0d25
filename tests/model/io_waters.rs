//! The classic Waters import against the reference outputs in `../shared/golden`: every
//! vertex, triangle and muscle exactly (bit for bit), and the written files read back equal.
//!
//! The import converts the classic data to glTF's convention as it reads it (x negated,
//! `waters::from_classic`); the reference is converted the same way as it is read here, so
//! the comparison is in grimace's frame and still bit for bit.

use crate::common;
use grimace::io::load::load_rig;

use std::path::PathBuf;

use glam::Vec3;
use grimace::io::waters::{self, ImportOptions};
use grimace::io::{obj, rig_file};
use grimace::model::{MuscleKind, Side};

fn csv_rows(path: PathBuf) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|f| f.trim().to_string()).collect())
        .collect()
}

fn f(s: &str) -> f32 {
    s.parse().unwrap()
}

fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

#[test]
fn imported_face_matches_the_reference_exactly() {
    let Some(shared) = common::shared() else {
        return;
    };
    let imported =
        waters::import_dir(&shared.join("waters-geoface"), &ImportOptions::default()).unwrap();
    let mesh = &imported.mesh;

    let vertices = csv_rows(shared.join("golden/waters-vertices.csv"));
    assert_eq!(mesh.vertex_count(), vertices.len());
    assert_eq!(mesh.vertex_count(), 478);
    for (i, row) in vertices.iter().enumerate() {
        assert_eq!(row[0].parse::<usize>().unwrap(), i);
        // merged vertices are stored with -0.0 as 0.0, hence the + 0.0
        let expected = waters::from_classic(Vec3::new(f(&row[1]), f(&row[2]), f(&row[3])));
        assert_eq!(
            bits(mesh.positions[i]),
            bits(expected + Vec3::ZERO),
            "vertex {i}"
        );
    }

    let triangles = csv_rows(shared.join("golden/waters-triangles.csv"));
    assert_eq!(mesh.triangles.len(), 882);
    for (i, row) in triangles.iter().enumerate() {
        let expected: [u32; 3] = [1, 2, 3].map(|c| row[c].parse().unwrap());
        assert_eq!(mesh.triangles[i], expected, "triangle {i}");
    }
}

#[test]
fn imported_muscles_match_the_reference_exactly() {
    let Some(shared) = common::shared() else {
        return;
    };
    let imported =
        waters::import_dir(&shared.join("waters-geoface"), &ImportOptions::default()).unwrap();
    let rows = csv_rows(shared.join("golden/waters-muscles.csv"));
    assert_eq!(imported.rig.muscles.len(), 18);
    for (row, muscle) in rows.iter().zip(&imported.rig.muscles) {
        assert_eq!(muscle.name, row[1]);
        let MuscleKind::Linear(l) = &muscle.kind else {
            panic!("{} is not linear", muscle.name)
        };
        let point =
            |c: usize| waters::from_classic(Vec3::new(f(&row[c]), f(&row[c + 1]), f(&row[c + 2])));
        assert_eq!(bits(l.insertion), bits(point(2)), "{}", muscle.name);
        assert_eq!(bits(l.attachment), bits(point(5)), "{}", muscle.name);
        assert_eq!(l.falloff_start.to_bits(), f(&row[8]).to_bits());
        assert_eq!(l.falloff_end.to_bits(), f(&row[9]).to_bits());
        assert_eq!(l.zone.to_bits(), f(&row[10]).to_bits());
        let name = muscle.name.as_str();
        let (side, partner) = if let Some(stem) = name.strip_prefix("L_") {
            (Side::Left, format!("R_{stem}"))
        } else if let Some(stem) = name.strip_prefix("Left_") {
            (Side::Left, format!("Right_{stem}"))
        } else if let Some(stem) = name.strip_prefix("R_") {
            (Side::Right, format!("L_{stem}"))
        } else if let Some(stem) = name.strip_prefix("Right_") {
            (Side::Right, format!("Left_{stem}"))
        } else {
            panic!("unexpected name {name}")
        };
        assert_eq!(muscle.side, side);
        assert_eq!(muscle.mirror.as_deref(), Some(partner.as_str()));
        // Left muscles lie at x > 0, as glTF's convention says (the classic data has them
        // at x < 0).
        assert_eq!(l.insertion.x > 0.0, side == Side::Left, "{}", muscle.name);
    }
}

#[test]
fn dropping_duplicates_keeps_the_numbering() {
    let Some(shared) = common::shared() else {
        return;
    };
    let dir = shared.join("waters-geoface");
    let kept = waters::import_dir(&dir, &ImportOptions::default()).unwrap();
    let options = ImportOptions {
        drop_duplicate_triangles: true,
        ..Default::default()
    };
    let dropped = waters::import_dir(&dir, &options).unwrap();
    assert_eq!(dropped.mesh.positions, kept.mesh.positions);
    assert_eq!(dropped.mesh.triangles.len(), 876);
    // The golden file lists 504, 505 and 826-829 as the repeats.
    let mut expected = kept.mesh.triangles.clone();
    for i in [829, 828, 827, 826, 505, 504] {
        expected.remove(i);
    }
    assert_eq!(dropped.mesh.triangles, expected);
    // No edge is then shared by more than two triangles.
    let mut uses = std::collections::HashMap::new();
    for t in &dropped.mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    assert_eq!(uses.len(), 1360);
    assert!(uses.values().all(|&n| n <= 2));
}

#[test]
fn written_files_read_back_equal() {
    let Some(shared) = common::shared() else {
        return;
    };
    let imported =
        waters::import_dir(&shared.join("waters-geoface"), &ImportOptions::default()).unwrap();
    let out = tempfile::tempdir().unwrap();
    std::fs::write(
        out.path().join("mesh.obj"),
        obj::write_obj(&imported.mesh, &imported.mesh.positions),
    )
    .unwrap();
    rig_file::save_rig(&out.path().join("rig.ron"), &imported.rig).unwrap();
    let loaded = load_rig(&out.path().join("rig.ron")).unwrap();
    assert_eq!(loaded.rig, imported.rig);
    // The classic face has 478 vertices, as many as a MediaPipe face mesh with irises: read
    // without its landmark file, MediaPipe's numbering on it is no face, so it has no
    // landmarks and no brows are marked from them.
    assert_eq!(loaded.mesh.vertex_count(), 478);
    assert_eq!(loaded.landmark_points().unwrap(), None);
    assert_eq!(loaded.mesh, imported.mesh);
}
