//! The closing lids of fitted heads (`src/fit/lids.rs`).

use crate::common;

use std::path::Path;

use glam::Vec3;
use grimace::fit::{fit_rig, Fitted, PartOverrides, Template};
use grimace::io::{builtin, landmarks::load_landmarks, obj};
use grimace::landmarks::Landmarks;
use grimace::model::{BoundRig, Mesh, SkinRules};

fn fit(mesh: &Mesh, landmarks: &Landmarks) -> Fitted {
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

fn makehuman() -> Option<(Mesh, Landmarks)> {
    let shared = common::shared_with(&["meshes/makehuman_base.obj"])?;
    let mesh = obj::read_obj(&shared.join("meshes/makehuman_base.obj")).unwrap();
    let landmarks = load_landmarks(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fit_data/makehuman_base.landmarks.ron"
    )))
    .unwrap();
    Some((mesh, landmarks))
}

fn mediapipe() -> Option<(Mesh, Landmarks)> {
    let shared = common::shared_with(&["meshes/mediapipe_canonical_face.obj"])?;
    let mesh = obj::read_obj(&shared.join("meshes/mediapipe_canonical_face.obj")).unwrap();
    let landmarks = Landmarks::mediapipe(&mesh).unwrap();
    Some((mesh, landmarks))
}

fn normal(p: &[Vec3], t: &[u32; 3]) -> Vec3 {
    let [a, b, c] = t.map(|i| p[i as usize]);
    (b - a).cross(c - a)
}

#[test]
#[ignore]
fn diagnose_makehuman_blink() {
    let Some((mesh, landmarks)) = (if std::env::var("MP").is_ok() {
        mediapipe()
    } else {
        makehuman()
    }) else {
        return;
    };
    let fitted = fit(&mesh, &landmarks);
    let bound = BoundRig::bind_with(&fitted.rig, &mesh, SkinRules::DEFAULT).unwrap();
    let moved = crate::positions_at_au(&bound, "45");
    let paper = BoundRig::bind(&fitted.rig, &mesh).unwrap();
    let moved_paper = crate::positions_at_au(&paper, "45");
    let marks = landmarks.vertices(&mesh);
    let lm = |i: usize| mesh.positions[marks[i] as usize];
    let group_of = |v: u32| {
        mesh.groups
            .iter()
            .filter(|(_, m)| m.binary_search(&v).is_ok())
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join(",")
    };
    let (c, up, inner) = (
        0.5 * (lm(42) + lm(45)),
        (lm(43) + lm(44) - lm(46) - lm(47)) * 0.5,
        lm(42),
    );
    let open = up.length();
    let up = up.normalize();
    let across = (lm(45) - lm(42)).normalize();
    let out = across.cross(up);
    println!(
        "left eye: opening {open}, width {}",
        lm(42).distance(lm(45))
    );
    for i in 42..48 {
        let v = marks[i] as usize;
        println!(
            "landmark {i}: up {:.3} skin {:.3} paper {:.3}",
            (mesh.positions[v] - c).dot(up) / open,
            (moved[v] - mesh.positions[v]).dot(up) / open,
            (moved_paper[v] - mesh.positions[v]).dot(up) / open
        );
    }
    for (u, l) in [(43, 47), (44, 46)] {
        let (u, l) = (marks[u] as usize, marks[l] as usize);
        for (name, p) in [
            ("rest", &mesh.positions),
            ("skin", &moved),
            ("paper", &moved_paper),
        ] {
            let d = p[u] - p[l];
            println!(
                "pair {u}-{l} {name}: across {:.3} up {:.3} out {:.3}",
                d.dot(across) / open,
                d.dot(up) / open,
                d.dot(out) / open
            );
        }
    }
    if let Some(m) = fitted
        .rig
        .muscles
        .iter()
        .find(|m| m.name == "L_Orbicularis_Oculi")
    {
        println!("{:?}", m.kind);
    }
    for m in fitted
        .rig
        .masks
        .iter()
        .filter(|m| m.muscles.iter().any(|n| n == "L_Orbicularis_Oculi"))
    {
        println!(
            "mask {:?} gain {} {} weights",
            m.muscles,
            m.gain,
            m.weights.len()
        );
    }
    let mut n = 0;
    for (k, t) in mesh.triangles.iter().enumerate() {
        let (a, b) = (normal(&mesh.positions, t), normal(&moved, t));
        if a.dot(b) >= 0.0 {
            continue;
        }
        n += 1;
        let centre = t.iter().map(|&i| mesh.positions[i as usize]).sum::<Vec3>() / 3.0;
        if centre.x < c.x - 2.0 * open && centre.x > c.x - 20.0 * open {
            continue; // print the left eye only
        }
        let rel = centre - c;
        let pa = normal(&moved_paper, t).dot(a) < 0.0;
        let travel: Vec<f32> = t
            .iter()
            .map(|&i| (moved[i as usize] - mesh.positions[i as usize]).dot(up) / open)
            .collect();
        println!(
            "tri {k}: {} across {:.2} up {:.2} out {:.2} paper-turned {pa} travel/open {:.2?} inner {:.2}",
            group_of(t[0]),
            rel.dot(across) / open,
            rel.dot(up) / open,
            rel.dot(out) / open,
            travel,
            (centre - inner).length() / open,
        );
    }
    println!("{n} turned");
    for t in &mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let (a, b) = (a as usize, b as usize);
            let r = moved[a].distance(moved[b]) / mesh.positions[a].distance(mesh.positions[b]);
            if r > 2.5 && mesh.positions[a].x > 0.0 {
                let info = |v: usize| {
                    let rel = mesh.positions[v] - c;
                    format!(
                        "({:.2} {:.2} {:.2} travel {:.2})",
                        rel.dot(across) / open,
                        rel.dot(up) / open,
                        rel.dot(out) / open,
                        (moved[v] - mesh.positions[v]).dot(up) / open
                    )
                };
                println!(
                    "edge {a}-{b} stretch {r:.2} {} {} {}",
                    info(a),
                    info(b),
                    group_of(a as u32)
                );
            }
        }
    }
    panic!("diagnostic");
}
