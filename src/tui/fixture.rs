//! A small rig on a grid mesh, for the editor's unit tests.

use std::collections::BTreeMap;
use std::path::PathBuf;

use glam::Vec3;

use crate::facs::{AuEntry, AuKey, AuTable};
use crate::model::{
    Combine, Convergence, Frame, Jaw, Linear, Mesh, Muscle, MuscleKind, Rig, Sheet, Side, Sphincter,
};
use crate::tui::app::{App, FileStamp};
use crate::tui::face::Face;

fn linear(name: &str, side: Side, mirror: &str, x: f32) -> Muscle {
    Muscle {
        name: name.into(),
        side,
        mirror: Some(mirror.into()),
        kind: MuscleKind::Linear(Linear {
            attachment: Vec3::new(x, 1.0, -0.5),
            insertion: Vec3::new(x * 0.5, -0.5, 0.0),
            zone: 30.0,
            falloff_start: 0.5,
            falloff_end: 2.0,
        }),
    }
}

/// A small rig: a mirrored linear pair, a sheet, a sphincter and a jaw, on a grid.
pub(crate) fn app() -> App {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            positions.push(Vec3::new(i as f32 - 2.0, j as f32 - 2.0, 0.0));
        }
    }
    for j in 0..4u32 {
        for i in 0..4u32 {
            let v = j * 5 + i;
            triangles.push([v, v + 1, v + 6]);
            triangles.push([v, v + 6, v + 5]);
        }
    }
    let mesh = Mesh::new(positions, triangles).unwrap();
    let rig = Rig {
        masks: Vec::new(),
        version: crate::model::rig::RIG_VERSION,
        mesh: PathBuf::from("grid.obj"),
        landmarks: None,
        combine: Combine::Sum,
        muscles: vec![
            Muscle {
                name: "Orbicularis_Oris".into(),
                side: Side::Centre,
                mirror: None,
                kind: MuscleKind::Sphincter(Sphincter {
                    centre: Vec3::new(0.0, -1.0, 0.0),
                    semi_major: 1.0,
                    semi_minor: 0.5,
                    convergence: Convergence::Centre,
                    bulge: 10.0,
                    frame: Frame::IDENTITY,
                }),
            },
            linear("L_Zygomatic_Major", Side::Left, "R_Zygomatic_Major", -1.5),
            linear("R_Zygomatic_Major", Side::Right, "L_Zygomatic_Major", 1.5),
            Muscle {
                name: "Frontalis".into(),
                side: Side::Centre,
                mirror: None,
                kind: MuscleKind::Sheet(Sheet {
                    attachment: [Vec3::new(-1.0, 2.0, 0.0), Vec3::new(1.0, 2.0, 0.0)],
                    insertion: [Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)],
                    length: 1.5,
                    width: 2.0,
                }),
            },
        ],
        jaw: Some(Jaw {
            axis: glam::Vec3::X,
            slide: glam::Vec3::ZERO,
            pivot: Vec3::new(0.0, 0.0, -1.0),
            degrees_per_unit: 1.0,
            weights: vec![(0, 1.0), (1, 1.0)],
        }),
    };
    let table = AuTable {
        version: 1,
        rig: PathBuf::from("rig.ron"),
        aus: BTreeMap::from([(
            AuKey::new(12),
            AuEntry {
                name: "Lip Corner Puller".into(),
                muscles: BTreeMap::from([
                    ("L_Zygomatic_Major".to_string(), 1.0),
                    ("R_Zygomatic_Major".to_string(), 1.0),
                ]),
                jaw: 0.0,
            },
        )]),
        expressions: BTreeMap::new(),
    };
    let scene = Face::new(rig, mesh).unwrap();
    let mut app = App::new(scene, table, Some(PathBuf::from("t.au.ron")));
    app.doc.file_stamp = Some(FileStamp { len: 1, hash: 1 });
    app
}

/// [`Face::start`] framed by the rig, as the editor frames a rig without landmarks.
pub(crate) fn started(rig: Rig, mesh: Mesh) -> Result<Face, String> {
    let framing = crate::render::Framing::of_rig(&rig, &mesh);
    Face::start(rig, mesh, framing)
}

/// The built-in face with each triangle split into four (old vertices keep their
/// numbers, so the built-in rig binds): big enough for levels of detail.
pub(crate) fn big_face() -> Mesh {
    let face = crate::io::builtin::default_mesh();
    let mut positions = face.positions.clone();
    let mut mid: std::collections::HashMap<(u32, u32), u32> = Default::default();
    let mut triangles = Vec::new();
    for &[a, b, c] in &face.triangles {
        let mut at = |x: u32, y: u32| {
            *mid.entry((x.min(y), x.max(y))).or_insert_with(|| {
                positions.push(0.5 * (positions[x as usize] + positions[y as usize]));
                positions.len() as u32 - 1
            })
        };
        let (ab, bc, ca) = (at(a, b), at(b, c), at(c, a));
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Mesh::new(positions, triangles).unwrap()
}
