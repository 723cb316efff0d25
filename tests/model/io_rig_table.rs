//! Rig and AU table files: exact round trips, semantic checks with positions, loading with
//! the mesh, atomic saves.

use grimace::io::load::load_rig_with;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::Vec3;
use grimace::facs::{AuEntry, AuKey, AuTable, TABLE_VERSION};
use grimace::io::{self, table_file};
use grimace::model::{
    Combine, Convergence, Frame, Jaw, Linear, Mesh, Muscle, MuscleKind, Rig, Sheet, Side,
    Sphincter, RIG_VERSION,
};
use proptest::prelude::*;

fn linear(name: &str, side: Side, mirror: Option<&str>, x: f32) -> Muscle {
    Muscle {
        name: name.into(),
        side,
        mirror: mirror.map(Into::into),
        kind: MuscleKind::Linear(Linear {
            attachment: Vec3::new(x * 3.805, 0.868, 6.6),
            insertion: Vec3::new(x * 1.57, -2.221, 7.82),
            zone: 45.0,
            falloff_start: 0.1,
            falloff_end: 4.8,
        }),
    }
}

fn sample_rig() -> Rig {
    Rig {
        masks: Vec::new(),
        version: RIG_VERSION,
        mesh: PathBuf::from("face.obj"),
        landmarks: None,
        combine: Combine::Average,
        muscles: vec![
            linear(
                "L_Zygomatic_Major",
                Side::Left,
                Some("R_Zygomatic_Major"),
                -1.0,
            ),
            linear(
                "R_Zygomatic_Major",
                Side::Right,
                Some("L_Zygomatic_Major"),
                1.0,
            ),
            Muscle {
                name: "Orbicularis_Oris".into(),
                side: Side::Centre,
                mirror: None,
                kind: MuscleKind::Sphincter(Sphincter {
                    centre: Vec3::new(0.0, -2.3, 8.9),
                    semi_major: 1.6,
                    semi_minor: 0.7,
                    convergence: Convergence::Centre,
                    bulge: 10.0,
                    frame: Frame::IDENTITY,
                }),
            },
            Muscle {
                name: "L_Frontalis".into(),
                side: Side::Left,
                mirror: None,
                kind: MuscleKind::Sheet(Sheet {
                    attachment: [Vec3::new(-2.0, 7.0, 6.0), Vec3::new(-0.2, 7.2, 7.0)],
                    insertion: [Vec3::new(-2.0, 4.0, 7.5), Vec3::new(-0.2, 4.2, 8.4)],
                    length: 3.5,
                    width: 2.0,
                }),
            },
        ],
        jaw: Some(Jaw {
            axis: glam::Vec3::X,
            slide: glam::Vec3::ZERO,
            pivot: Vec3::new(0.0, -1.0, 2.0),
            degrees_per_unit: 1.0,
            weights: (0..14).map(|v| (v, v as f32 / 13.0)).collect(),
        }),
    }
}

fn triangle_mesh(count: usize) -> Mesh {
    let positions = (0..count)
        .map(|i| Vec3::new(i as f32, (i % 3) as f32, 0.0))
        .collect();
    Mesh::new(positions, vec![[0, 1, 2]]).unwrap()
}

fn sample_table() -> AuTable {
    let mut table = AuTable::new("face.rig.ron");
    let mut muscles = BTreeMap::new();
    muscles.insert("L_Zygomatic_Major".to_string(), 1.2);
    muscles.insert("R_Zygomatic_Major".to_string(), 1.2);
    table.aus.insert(
        AuKey::new(12),
        AuEntry {
            name: "Lip Corner Puller".into(),
            muscles,
            jaw: 0.0,
        },
    );
    table.aus.insert(
        "L12".parse().unwrap(),
        AuEntry {
            name: "Lip Corner Puller".into(),
            muscles: [("L_Zygomatic_Major".to_string(), 0.7)].into(),
            jaw: 0.0,
        },
    );
    table.aus.insert(
        AuKey::new(26),
        AuEntry {
            name: "Jaw Drop".into(),
            muscles: BTreeMap::new(),
            jaw: 2.5,
        },
    );
    table.expressions.insert("smile".into(), "12+26B".into());
    table.expressions.insert("smirk".into(), "L12@1.5".into());
    table
}

fn p() -> &'static Path {
    Path::new("t.ron")
}

#[test]
fn rig_round_trips_exactly_and_reads_well() {
    let rig = sample_rig();
    let text = io::rig_to_ron(&rig);
    let back = io::parse_rig(&text, p()).unwrap();
    assert_eq!(back, rig);
    assert_eq!(io::rig_to_ron(&back), text);
    assert!(
        text.contains("            mirror: \"R_Zygomatic_Major\",\n"),
        "{text}"
    );
    assert!(
        text.contains(
            "            kind: Linear(\n                attachment: (-3.805, 0.868, 6.6),\n"
        ),
        "{text}"
    );
    // no slide is written for the paper's pure turn
    assert!(!text.contains("slide"), "{text}");
}

/// A jaw's slide is written and read back exactly; a file without one (every file written
/// before it existed) reads as the pure turn.
#[test]
fn the_jaw_slide_round_trips_and_defaults_to_none() {
    let mut rig = sample_rig();
    if let Some(jaw) = &mut rig.jaw {
        jaw.slide = Vec3::new(0.0, -0.025, 0.0565);
    }
    let text = io::rig_to_ron(&rig);
    assert!(
        text.contains("        slide: (0.0, -0.025, 0.0565),\n"),
        "{text}"
    );
    let back = io::parse_rig(&text, p()).unwrap();
    assert_eq!(back, rig);
    let old = io::rig_to_ron(&sample_rig());
    let read = io::parse_rig(&old, p()).unwrap();
    assert_eq!(read.jaw.map(|j| j.slide), Some(Vec3::ZERO));
}

/// The landmark file a rig names is written after its mesh and read back; a rig without one
/// writes no such line.
#[test]
fn a_rigs_landmark_file_round_trips() {
    let mut rig = sample_rig();
    rig.landmarks = Some("marks/head.landmarks.ron".into());
    let text = io::rig_to_ron(&rig);
    assert!(
        text.contains("    landmarks: \"marks/head.landmarks.ron\",\n"),
        "{text}"
    );
    assert_eq!(io::parse_rig(&text, p()).unwrap(), rig);
    assert!(!io::rig_to_ron(&sample_rig()).contains("landmarks"));
}

#[test]
fn table_round_trips_exactly_and_reads_well() {
    let table = sample_table();
    let text = io::table_to_ron(&table);
    let back = io::parse_table(&text, p()).unwrap();
    assert_eq!(back, table);
    assert_eq!(io::table_to_ron(&back), text);
    assert!(
        text.contains("        \"L12\": (\n            name: \"Lip Corner Puller\",\n"),
        "{text}"
    );
    assert!(text.contains("        \"smile\": \"12+26B\",\n"), "{text}");
    // AUs in key order: 12 before L12 before 26.
    let at = |s: &str| text.find(s).unwrap();
    assert!(at("\"12\"") < at("\"L12\"") && at("\"L12\"") < at("\"26\""));
}

#[test]
fn hand_written_minimal_files_are_accepted() {
    let rig = "(version: 1, mesh: \"m.obj\", muscles: [(name: \"a\", kind: Linear(attachment: (0, 0, 0), insertion: (1, 0, 0), zone: 40, falloff_start: 0, falloff_end: 3))])";
    let rig = io::parse_rig(rig, p()).unwrap();
    assert_eq!(rig.combine, Combine::Sum);
    assert_eq!(rig.muscles[0].side, Side::Centre);
    assert_eq!(rig.jaw, None);
    let table = io::parse_table("(version: 1, rig: \"r.rig.ron\")", p()).unwrap();
    assert!(table.aus.is_empty() && table.expressions.is_empty());
    assert_eq!(table.version, TABLE_VERSION);
}

fn rig_error(text: &str) -> String {
    io::parse_rig(text, p()).unwrap_err().to_string()
}

#[test]
fn rig_semantic_errors_name_the_muscle_and_place() {
    let good = io::rig_to_ron(&sample_rig());
    let zone = good
        .replacen("zone: 45.0", "zone: 95.0", 2)
        .replacen("zone: 95.0", "zone: 45.0", 1);
    assert_eq!(
        rig_error(&zone),
        "t.ron:26:17: muscle `R_Zygomatic_Major`: zone 95 must lie strictly between 0 and 90 degrees"
    );
    let mirror = good.replace("mirror: \"R_Zygomatic_Major\"", "mirror: \"R_Zygo\"");
    assert_eq!(
        rig_error(&mirror),
        "t.ron:10:13: muscle `L_Zygomatic_Major`: the mirror partner `R_Zygo` is not a muscle of this rig"
    );
    let duplicate = good.replace("\"Orbicularis_Oris\"", "\"L_Frontalis\"");
    assert_eq!(
        rig_error(&duplicate),
        "t.ron:43:13: muscle `L_Frontalis`: the name is used by an earlier muscle; names must be unique"
    );
    let version = good.replace("version: 2", "version: 3");
    assert_eq!(
        rig_error(&version),
        "t.ron:3:5: rig version 3 is not supported; this grimace reads versions 1 and 2"
    );
    let unknown = good.replace("combine: Average", "combine: Average,\n    colour: 3");
    assert!(
        rig_error(&unknown).starts_with("t.ron:6:5: unknown field `colour` in rig; expected one of: version, mesh, landmarks, combine, muscles, jaw"),
        "{}", rig_error(&unknown)
    );
}

#[test]
fn table_errors_name_the_au_and_place() {
    let good = io::table_to_ron(&sample_table());
    let range = good.replace("\"L_Zygomatic_Major\": 0.7", "\"L_Zygomatic_Major\": 2.5");
    assert_eq!(
        io::parse_table(&range, p()).unwrap_err().to_string(),
        "t.ron:17:17: AU L12: activation of `L_Zygomatic_Major` is 2.5; expected 0 to 2"
    );
    let missing = good.replace("\"12+26B\"", "\"12+26B+4\"");
    assert_eq!(
        io::parse_table(&missing, p()).unwrap_err().to_string(),
        "t.ron:28:9: expression `smile` uses AU 4, which the table does not have"
    );
    let mut rig = sample_rig();
    rig.muscles.remove(0);
    rig.muscles[0].mirror = None;
    let table = io::parse_table(&good, p()).unwrap();
    let err = table_file::check_table_rig(&table, &rig, &good, p()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "t.ron:9:17: AU 12 names muscle `L_Zygomatic_Major`, which the rig does not have"
    );
}

#[test]
fn load_and_save_with_mesh_relative_to_the_rig() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("rigs");
    std::fs::create_dir(&sub).unwrap();
    let mesh = triangle_mesh(14);
    std::fs::write(
        sub.join("face.obj"),
        io::obj::write_obj(&mesh, &mesh.positions),
    )
    .unwrap();
    let rig_path = sub.join("face.rig.ron");
    io::save_rig(&rig_path, &sample_rig()).unwrap();
    let loaded = io::load_rig(&rig_path).unwrap();
    assert_eq!(loaded.rig, sample_rig());
    assert_eq!(loaded.mesh, mesh);
    assert_eq!(loaded.mesh_path, Some(sub.join("face.obj")));

    // A jaw weight beyond the mesh is refused, naming the weights line.
    let small = triangle_mesh(5);
    std::fs::write(
        sub.join("face.obj"),
        io::obj::write_obj(&small, &small.positions),
    )
    .unwrap();
    let err = io::load_rig(&rig_path).unwrap_err();
    assert!(
        err.to_string()
            .ends_with("jaw weight for vertex 5, but the mesh has only 5 vertices"),
        "{err}"
    );
    assert_eq!(err.line, Some(56));

    // A missing mesh file is reported at the rig's mesh field.
    std::fs::remove_file(sub.join("face.obj")).unwrap();
    let err = io::load_rig(&rig_path).unwrap_err();
    assert_eq!(err.line, Some(4));
    assert!(err.message.contains("does not exist"), "{err}");

    // Built-in meshes come from the resolver given.
    let mut rig = sample_rig();
    rig.mesh = PathBuf::from("builtin:test");
    io::save_rig(&rig_path, &rig).unwrap();
    fn resolver(name: &str) -> Option<Mesh> {
        (name == "test").then(|| triangle_mesh(20))
    }
    let loaded = load_rig_with(&rig_path, None, resolver).unwrap();
    assert_eq!(loaded.mesh.vertex_count(), 20);
    assert_eq!(loaded.mesh_path, None);
}

#[test]
fn save_refuses_invalid_and_keeps_the_old_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.au.ron");
    io::save_table(&path, &sample_table()).unwrap();
    let before = std::fs::read(&path).unwrap();
    let mut bad = sample_table();
    bad.aus.get_mut(&AuKey::new(26)).unwrap().jaw = f32::NAN;
    let err = io::save_table(&path, &bad).unwrap_err();
    assert!(
        err.to_string().contains("activation of `jaw` is NaN"),
        "{err}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), before);
}

#[test]
fn read_only_folder_fails_cleanly() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.au.ron");
    io::save_table(&path, &sample_table()).unwrap();
    let before = std::fs::read(&path).unwrap();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o555)).unwrap();
    let probe = dir.path().join("probe");
    if std::fs::write(&probe, b"x").is_ok() {
        // Running as root: permissions do not bind. A folder no one can create files in
        // still exists: /proc. Saving over an existing file there must fail the same way.
        let _ = std::fs::remove_file(&probe);
        std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
        let target = Path::new("/proc/version");
        let Ok(before) = std::fs::read(target) else {
            eprintln!("skipped: running as root and /proc is not available");
            return;
        };
        let err = io::save_table(target, &sample_table()).unwrap_err();
        assert!(
            err.to_string().starts_with("/proc/version: cannot save: "),
            "{err}"
        );
        assert_eq!(std::fs::read(target).unwrap(), before);
        assert!(!Path::new("/proc/version~").exists());
        return;
    }
    let mut changed = sample_table();
    changed.expressions.insert("other".into(), "26".into());
    let err = io::save_table(&path, &changed).unwrap_err();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
    assert!(
        err.to_string().contains("cannot save: permission denied"),
        "{err}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), before);
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 1);
}

fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        -1e6f32..1e6,
        any::<f32>().prop_filter("finite", |v| v.is_finite())
    ]
}

proptest! {
    #[test]
    fn any_valid_linear_muscle_round_trips(
        a in prop::array::uniform3(finite()),
        i in prop::array::uniform3(finite()),
        zone in 0.001f32..89.999,
        fs in 0.0f32..10.0,
        extra in 0.001f32..10.0,
        weights in prop::collection::vec(0.0f32..=1.0, 0..20),
    ) {
        prop_assume!(a != i);
        let mut rig = sample_rig();
        rig.muscles[2] = Muscle {
            name: "x \"quoted\" ü".into(),
            side: Side::Centre,
            mirror: None,
            kind: MuscleKind::Linear(Linear {
                attachment: a.into(), insertion: i.into(), zone,
                falloff_start: fs, falloff_end: fs + extra,
            }),
        };
        rig.jaw.as_mut().unwrap().weights = weights.iter().enumerate().map(|(v, w)| (v as u32 * 3, *w)).collect();
        let text = io::rig_to_ron(&rig);
        let back = io::parse_rig(&text, p()).unwrap();
        prop_assert_eq!(io::rig_to_ron(&back), text);
        prop_assert_eq!(back, rig);
    }

    #[test]
    fn any_valid_table_round_trips(
        entries in prop::collection::btree_map(
            prop::sample::select(grimace::facs::catalogue::CATALOGUE.iter().map(|a| a.number).collect::<Vec<_>>()),
            (prop::collection::btree_map("[A-Za-z_]{1,12}", 0.0f32..=2.0, 0..5), 0.0f32..=4.0),
            0..20),
    ) {
        let mut table = AuTable::new("r.rig.ron");
        for (n, (muscles, jaw)) in entries {
            table.aus.insert(AuKey::new(n), AuEntry { name: format!("AU {n}"), muscles, jaw });
        }
        if let Some(k) = table.aus.keys().next().copied() {
            table.expressions.insert("e".into(), format!("{k}C"));
        }
        let text = io::table_to_ron(&table);
        let back = io::parse_table(&text, p()).unwrap();
        prop_assert_eq!(io::table_to_ron(&back), text);
        prop_assert_eq!(back, table);
    }

    #[test]
    fn random_text_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = io::parse_rig(&text, p());
        let _ = io::parse_table(&text, p());
        let _ = io::obj::parse_obj(&text, p());
    }

    #[test]
    fn mutated_files_never_panic(cut in 0usize..4000, insert in "[ -~]{0,4}") {
        for good in [io::rig_to_ron(&sample_rig()), io::table_to_ron(&sample_table())] {
            let mut at = cut.min(good.len());
            while !good.is_char_boundary(at) { at -= 1; }
            let mutated = format!("{}{}{}", &good[..at], insert, &good[at..]);
            let _ = io::parse_rig(&mutated, p());
            let _ = io::parse_table(&mutated, p());
            let truncated = &good[..at];
            let _ = io::parse_rig(truncated, p());
            let _ = io::parse_table(truncated, p());
        }
    }
}

proptest! {
    #[test]
    fn random_bytes_into_the_classic_parsers_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = io::waters::parse_faceline(&text, p());
        let _ = io::waters::parse_index(&text, p(), 10);
        let _ = io::waters::parse_muscles(&text, p());
    }

    #[test]
    fn number_soup_into_the_classic_parsers_never_panics(s in "[0-9 .\n-]{0,200}|1000[0-9 \n]{0,100}") {
        let _ = io::waters::parse_faceline(&s, p());
        if let Ok(polygons) = io::waters::parse_index(&s, p(), 6) {
            let half: Vec<Vec3> = (0..6).map(|i| Vec3::new(-(i as f32), i as f32, 1.0)).collect();
            let _ = io::waters::build_face(&half, &polygons, true);
        }
        let _ = io::waters::parse_muscles(&format!("1\nm {s}"), p());
    }

    #[test]
    fn random_files_never_panic_the_loaders(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        let dir = tempfile::tempdir().unwrap();
        for name in ["x.rig.ron", "x.au.ron", "x.obj"] {
            let path = dir.path().join(name);
            std::fs::write(&path, &bytes).unwrap();
            let _ = grimace::cli::validate::check(&path);
        }
    }
}
