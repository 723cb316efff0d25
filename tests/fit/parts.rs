//! A head as users bring them: the default face with eyeballs (named objects, quads) and
//! upper and lower teeth (unnamed pieces), turned z-up and in millimetres. Fitting must keep
//! eyes and teeth out of the skin muscles and turn the lower teeth with the jaw.

use std::fmt::Write as _;
use std::path::Path;

use glam::{Quat, Vec3};
use grimace::fit::{fit_rig, Part, PartOverrides, Template};
use grimace::io::{builtin, obj};
use grimace::landmarks::FaceFrame;
use grimace::model::{Activations, BoundRig, Mesh};

/// A UV sphere of quads (and triangle caps) as OBJ lines, vertices numbered from `first`.
fn sphere(out: &mut String, centre: Vec3, radius: f32, first: usize) -> usize {
    let (rings, segments) = (8, 12);
    let mut count = 0;
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let p = centre
                + radius
                    * Vec3::new(
                        theta.sin() * phi.cos(),
                        theta.cos(),
                        theta.sin() * phi.sin(),
                    );
            let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
            count += 1;
        }
    }
    for r in 0..rings {
        for s in 0..segments {
            let a = first + r * segments + s + 1;
            let b = first + r * segments + (s + 1) % segments + 1;
            let _ = writeln!(out, "f {a} {b} {} {}", b + segments, a + segments);
        }
    }
    count
}

/// A box of six quads as OBJ lines.
fn block(out: &mut String, lo: Vec3, hi: Vec3, first: usize) -> usize {
    for i in 0..8 {
        let p = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    for f in [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ] {
        let _ = writeln!(
            out,
            "f {}",
            f.map(|v| (first + v + 1).to_string()).join(" ")
        );
    }
    8
}

/// The head in the default face's own frame, with its landmark positions, then moved.
fn head(moved: impl Fn(Vec3) -> Vec3) -> (Mesh, Vec<usize>, Vec<usize>, Vec<usize>) {
    let face = builtin::default_mesh();
    let marks = builtin::landmarks("face")
        .unwrap()
        .positions(&face)
        .unwrap();
    let frame = FaceFrame::of(&marks).unwrap();
    let fwd = frame.forward.as_vec3();
    let mut text = String::from("o Face\n");
    for p in &face.positions {
        let _ = writeln!(text, "v {} {} {}", p.x, p.y, p.z);
    }
    for t in &face.triangles {
        let _ = writeln!(text, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    let mut n = face.positions.len();
    let mean = |ids: std::ops::Range<usize>| {
        let len = ids.len() as f32;
        ids.map(|i| marks[i]).sum::<Vec3>() / len
    };
    let mut eyes = Vec::new();
    for (name, ids) in [("EyeBall.R", 36..42), ("EyeBall.L", 42..48)] {
        let width = marks[ids.start].distance(marks[ids.start + 3]);
        let radius = 0.5 * width;
        let centre = mean(ids) - fwd * (radius * 1.05);
        let _ = writeln!(text, "o {name}");
        let count = sphere(&mut text, centre, radius, n);
        eyes.extend(n..n + count);
        n += count;
    }
    // Teeth: flat blocks behind the lips, above and below the inner lip line.
    let mouth = mean(60..68);
    let half = 0.4 * marks[48].distance(marks[54]);
    let up = frame.up.as_vec3();
    let across = frame.lateral.as_vec3();
    let _ = writeln!(text, "o Cube.001");
    let mut upper = Vec::new();
    let mut lower = Vec::new();
    for (list, dy) in [(&mut upper, 0.25), (&mut lower, -0.25)] {
        let c = mouth - fwd * (0.35 * half) + up * (dy * half);
        let e = across.abs() * half + up.abs() * (0.2 * half) + fwd.abs() * (0.1 * half);
        let count = block(&mut text, c - e, c + e, n);
        list.extend(n..n + count);
        n += count;
    }
    let mut mesh = obj::parse_obj(&text, Path::new("head.obj")).unwrap();
    for p in &mut mesh.positions {
        *p = moved(*p);
    }
    (mesh, eyes, upper, lower)
}

#[test]
fn eyes_and_teeth_stay_out_of_the_skin_muscles_and_lower_teeth_turn_with_the_jaw() {
    let turn = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let moved = |p: Vec3| turn * p * 11.5 + Vec3::new(0.0, 30.0, 1650.0);
    let (mesh, eyes, upper, lower) = head(moved);
    let template_mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let landmarks = builtin::landmarks("face").unwrap();
    let points = landmarks.positions(&template_mesh).unwrap();
    let fitted = fit_rig(
        Template {
            rig: &rig,
            mesh: &template_mesh,
            landmarks: &points,
        },
        &mesh,
        &landmarks,
        "head.obj".into(),
        &PartOverrides::default(),
    )
    .unwrap();
    let parts = &fitted.parts.of_vertex;
    assert!(
        eyes.iter().all(|&v| parts[v] == Part::Still),
        "{:?}",
        fitted.parts.choices
    );
    assert!(
        upper.iter().all(|&v| parts[v] == Part::Still),
        "{:?}",
        fitted.parts.choices
    );
    assert!(
        lower.iter().all(|&v| parts[v] == Part::Jaw),
        "{:?}",
        fitted.parts.choices
    );
    // the face's own eyeballs and upper teeth, after its skin, are still parts too; its lower
    // teeth, lower gum and tongue (unnamed pieces below the lip line) turn with the jaw
    let skin = grimace::face::groups::skin_len(&template_mesh);
    assert!((0..skin).all(|v| parts[v] == Part::Skin));
    let jaw_parts = grimace::face::groups::jaw_parts(&template_mesh);
    for (v, part) in parts
        .iter()
        .enumerate()
        .take(template_mesh.vertex_count())
        .skip(skin)
    {
        let expected = if jaw_parts.contains(&(v as u32)) {
            Part::Jaw
        } else {
            Part::Still
        };
        assert_eq!(*part, expected, "vertex {v}: {:?}", fitted.parts.choices);
    }

    let bound = BoundRig::bind(&fitted.rig, &mesh).unwrap();
    let table = builtin::default_table();
    let mut out = Vec::new();
    for au in ["45", "6", "12", "1", "4", "10", "17", "24"] {
        let act = table
            .entry_activations(&au.parse().unwrap(), &fitted.rig)
            .unwrap();
        bound.deform(&act, &mut out).unwrap();
        for &v in eyes.iter().chain(&upper).chain(&lower) {
            assert_eq!(out[v], mesh.positions[v], "AU {au} moved rigid vertex {v}");
        }
        let skin_moved =
            (0..template_mesh.vertex_count()).any(|v| out[v].distance(mesh.positions[v]) > 0.5);
        assert!(skin_moved, "AU {au} moved no skin");
    }
    // The jaw: lower teeth turn rigidly (distances kept) and go down (z is up); upper teeth
    // stay.
    let mut act = Activations::zero(&fitted.rig);
    act.jaw = 3.0;
    bound.deform(&act, &mut out).unwrap();
    for &v in &upper {
        assert_eq!(out[v], mesh.positions[v]);
    }
    for pair in lower.windows(2) {
        let before = mesh.positions[pair[0]].distance(mesh.positions[pair[1]]);
        let after = out[pair[0]].distance(out[pair[1]]);
        assert!(
            (before - after).abs() < 1e-3 * before.max(1.0),
            "{before} -> {after}"
        );
    }
    let drop: f32 = lower
        .iter()
        .map(|&v| out[v].z - mesh.positions[v].z)
        .sum::<f32>()
        / lower.len() as f32;
    assert!(drop < -2.0, "lower teeth moved {drop} mm along z");
}

/// A head whose teeth, gums and tongue are one group (one material, as many scans have
/// them): the built-in face in millimetres with its mouth parts merged. Fitting splits the
/// group into pieces and sorts them by the occlusal plane: at AU26 the lower teeth follow the
/// chin down and the upper teeth stay where they are.
#[test]
fn one_group_of_teeth_gums_and_tongue_is_split_at_the_occlusal_plane() {
    use grimace::face::mouth::MouthPart;
    let template_mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let landmarks = builtin::landmarks("face").unwrap();
    let points = landmarks.positions(&template_mesh).unwrap();
    let table = builtin::default_table();
    let group = |part: MouthPart| template_mesh.groups[part.group()].clone();
    let upper = group(MouthPart::UpperTeeth);
    let lower = group(MouthPart::LowerTeeth);
    // the names of one part for all: one says tongue (so all of it turned with the jaw),
    // the other says nothing of a jaw (so all of it stayed still)
    for name in ["TeethGumsTongue", "material:Teeth"] {
        let mut mesh = template_mesh.clone();
        for p in &mut mesh.positions {
            *p *= 11.5;
        }
        let merged: Vec<u32> = MouthPart::ALL
            .into_iter()
            .filter(|p| *p != MouthPart::Interior)
            .flat_map(|p| template_mesh.groups[p.group()].clone())
            .collect();
        let interior = group(MouthPart::Interior);
        let skin_len = grimace::face::groups::skin_len(&template_mesh) as u32;
        mesh.groups = [
            ("Head".to_string(), (0..skin_len).collect::<Vec<u32>>()),
            (
                "Eyes".to_string(),
                grimace::face::groups::still_vertices(&template_mesh),
            ),
            (name.to_string(), merged),
            ("mouth_interior".to_string(), interior),
        ]
        .into_iter()
        .map(|(k, mut v)| {
            v.sort_unstable();
            (k, v)
        })
        .collect();
        let fitted = fit_rig(
            Template {
                rig: &rig,
                mesh: &template_mesh,
                landmarks: &points,
            },
            &mesh,
            &landmarks,
            "head.obj".into(),
            &PartOverrides::default(),
        )
        .unwrap();
        let parts = &fitted.parts.of_vertex;
        let choices = &fitted.parts.choices;
        assert!(
            upper.iter().all(|&v| parts[v as usize] == Part::Still),
            "{name}: {choices:?}"
        );
        assert!(
            lower.iter().all(|&v| parts[v as usize] == Part::Jaw),
            "{name}: {choices:?}"
        );
        assert!(
            choices
                .iter()
                .any(|c| c.name.starts_with(name) && c.reason == "occlusal plane"),
            "{name}: {choices:?}"
        );
        let bound = BoundRig::bind(&fitted.rig, &mesh).unwrap();
        let act = table
            .entry_activations(&"26".parse().unwrap(), &fitted.rig)
            .unwrap();
        let mut out = Vec::new();
        bound.deform(&act, &mut out).unwrap();
        for &v in &upper {
            assert_eq!(
                out[v as usize], mesh.positions[v as usize],
                "{name}: upper tooth {v} moved"
            );
        }
        let chin = template_mesh.groups["chin"][0] as usize;
        let chin_drop = mesh.positions[chin].y - out[chin].y;
        let teeth_drop = lower
            .iter()
            .map(|&v| mesh.positions[v as usize].y - out[v as usize].y)
            .sum::<f32>()
            / lower.len() as f32;
        assert!(chin_drop > 10.0, "{name}: the chin drops {chin_drop} mm");
        assert!(
            teeth_drop > 0.6 * chin_drop,
            "{name}: the lower teeth drop {teeth_drop} mm, the chin {chin_drop} mm"
        );
    }
}
