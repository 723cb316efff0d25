//! A head split at its texture seams (each vertex on a seam written once per side, as many
//! exporters write one) fits and moves as the same head in one piece: `fit-rig` joins the
//! seams for the skin, and each copy moves with the vertex it lies on.

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;
use grimace::io::builtin;
use grimace::io::landmarks::save_landmarks;
use grimace::io::load::load_rig;
use grimace::io::obj::write_obj;
use grimace::landmarks::Landmarks;
use grimace::model::{Activations, BoundRig, SkinRules};

use crate::common;

/// `text` (an OBJ file) split at its midline: every vertex on the plane x = 0 gets a copy
/// (appended after the last vertex) that the faces on the right of it (x < 0) use instead.
/// Groups, materials and texture corners are kept. Returns the text and, per copy, the
/// vertex it copies (0-based).
fn split_at_midline(text: &str) -> (String, Vec<(u32, u32)>) {
    let positions: Vec<Vec3> = text
        .lines()
        .filter(|l| l.starts_with("v "))
        .map(|l| {
            let xyz: Vec<f32> = l[2..]
                .split_whitespace()
                .map(|w| w.parse().unwrap())
                .collect();
            Vec3::new(xyz[0], xyz[1], xyz[2])
        })
        .collect();
    let n = positions.len() as u32;
    let index = |corner: &str| corner.split('/').next().unwrap().parse::<u32>().unwrap() - 1;
    let mut copies: HashMap<u32, u32> = HashMap::new();
    let mut order = Vec::new();
    let mut faces = Vec::new();
    for line in text.lines() {
        let Some(rest) = line.strip_prefix("f ") else {
            faces.push(line.to_string());
            continue;
        };
        let corners: Vec<&str> = rest.split_whitespace().collect();
        let centre: Vec3 = corners
            .iter()
            .map(|c| positions[index(c) as usize])
            .sum::<Vec3>()
            / corners.len() as f32;
        let mut words = vec!["f".to_string()];
        for c in &corners {
            let v = index(c);
            let tail = &c[c.find('/').unwrap_or(c.len())..];
            let v = if centre.x < 0.0 && positions[v as usize].x == 0.0 {
                *copies.entry(v).or_insert_with(|| {
                    order.push(v);
                    n + order.len() as u32 - 1
                })
            } else {
                v
            };
            words.push(format!("{}{tail}", v + 1));
        }
        faces.push(words.join(" "));
    }
    let last_v = faces.iter().rposition(|l| l.starts_with("v ")).unwrap();
    let added: Vec<String> = order
        .iter()
        .map(|&v| {
            let p = positions[v as usize];
            format!("v {} {} {}", p.x, p.y, p.z)
        })
        .collect();
    faces.splice(last_v + 1..last_v + 1, added);
    let pairs = order
        .iter()
        .enumerate()
        .map(|(k, &v)| (n + k as u32, v))
        .collect();
    (faces.join("\n") + "\n", pairs)
}

/// Fits the built-in rig to `NAME.obj` in `dir` (its landmarks beside it) with `extra`
/// arguments; returns what `fit-rig` printed.
fn fit(dir: &Path, name: &str, extra: &[&str]) -> String {
    let (obj, out) = (format!("{name}.obj"), format!("{name}.rig.ron"));
    let mut args = vec!["fit-rig", &obj, "--out", &out];
    args.extend_from_slice(extra);
    let fit = common::grimace_in(dir, &args);
    let said = String::from_utf8_lossy(&fit.stdout).into_owned();
    assert!(
        fit.status.success(),
        "{said}{}",
        String::from_utf8_lossy(&fit.stderr)
    );
    said
}

/// Per entry of the built-in table (every AU, then every expression): the largest distance
/// between the whole head's and the split head's vertices of the same number, and between
/// a copy and the vertex it copies on the split head.
fn differences(
    dir: &Path,
    whole: &str,
    split: &str,
    copies: &[(u32, u32)],
) -> Vec<(String, f32, f32)> {
    let table = builtin::default_table();
    let load = |name: &str| {
        let loaded = load_rig(&dir.join(format!("{name}.rig.ron"))).unwrap();
        BoundRig::bind_with(&loaded.rig, &loaded.mesh, SkinRules::DEFAULT).unwrap()
    };
    let (a, b) = (load(whole), load(split));
    let n = copies.iter().map(|c| c.0).min().unwrap() as usize;
    let mut entries: Vec<(String, Activations, Activations)> = Vec::new();
    for key in table.aus.keys() {
        let act = |r: &BoundRig| table.entry_activations(key, r.rig()).unwrap();
        entries.push((format!("AU {key}"), act(&a), act(&b)));
    }
    for name in table.expressions.keys() {
        let act = |r: &BoundRig| table.expression_activations(name, r.rig()).unwrap();
        entries.push((name.clone(), act(&a), act(&b)));
    }
    let (mut pa, mut pb) = (Vec::new(), Vec::new());
    entries
        .into_iter()
        .map(|(label, act_a, act_b)| {
            a.deform(&act_a, &mut pa).unwrap();
            b.deform(&act_b, &mut pb).unwrap();
            let same = (0..n).map(|v| pa[v].distance(pb[v])).fold(0.0f32, f32::max);
            let apart = copies
                .iter()
                .map(|&(c, v)| pb[c as usize].distance(pb[v as usize]))
                .fold(0.0f32, f32::max);
            (label, same, apart)
        })
        .collect()
}

/// Writes `text` as `NAME.obj` in `dir` with `landmarks` beside it.
fn write_head(dir: &Path, name: &str, text: &str, landmarks: &[u32]) {
    std::fs::write(dir.join(format!("{name}.obj")), text).unwrap();
    let marks = Landmarks::Vertices(landmarks.to_vec());
    save_landmarks(&dir.join(format!("{name}.landmarks.ron")), &marks).unwrap();
}

/// The built-in face split at its midline moves as the face in one piece, entry for entry
/// of the built-in table, and its seam stays closed; with `--keep-seams` (what every fit did
/// before seams were joined) the two sides drift apart.
#[test]
fn the_built_in_face_split_at_its_midline_moves_as_one_piece() {
    let dir = tempfile::tempdir().unwrap();
    let face = builtin::default_mesh();
    let text = write_obj(&face, &face.positions);
    let landmarks = builtin::landmarks("face").unwrap().vertices(&face);
    let (split, copies) = split_at_midline(&text);
    assert!(copies.len() > 20, "{} midline vertices", copies.len());
    write_head(dir.path(), "whole", &text, &landmarks);
    write_head(dir.path(), "split", &split, &landmarks);
    let said = fit(dir.path(), "whole", &[]);
    assert!(!said.contains("seams"), "the whole face has none: {said}");
    let said = fit(dir.path(), "split", &[]);
    assert!(said.contains("seams: the skin was split"), "{said}");
    let size = {
        let (lo, hi) = face.bounds();
        (hi - lo).length()
    };
    for (label, same, apart) in differences(dir.path(), "whole", "split", &copies) {
        assert!(same <= 1e-5 * size, "{label}: the heads differ by {same}");
        assert_eq!(apart, 0.0, "{label}: the seam opened");
    }
    fit(dir.path(), "split", &["--keep-seams"]);
    let widest = differences(dir.path(), "whole", "split", &copies)
        .into_iter()
        .map(|(_, _, apart)| apart)
        .fold(0.0f32, f32::max);
    assert!(widest > 1e-3 * size, "kept split, the seam opens: {widest}");
}

/// MakeHuman's head split at its midline (as an exporter splitting at a texture seam down the
/// face writes it) has its lips found and moves as the head in one piece. Before seams were
/// joined, `fit-rig` found no inner lip line (the seam crosses it) and the sides drifted
/// apart by up to 2.3 mm (AU9).
#[test]
fn makehuman_split_at_its_midline_moves_as_one_piece() {
    let Some((path, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let landmarks = landmarks.vertices(&mesh);
    let (split, copies) = split_at_midline(&text);
    write_head(dir.path(), "whole", &text, &landmarks);
    write_head(dir.path(), "split", &split, &landmarks);
    let said_whole = fit(dir.path(), "whole", &[]);
    let said = fit(dir.path(), "split", &[]);
    // what was found at the lips (the files and vertex numbers it names differ)
    let lips = |s: &str| {
        let line = s.lines().find(|l| l.contains("lips:")).unwrap_or_default();
        line.split([';', ',']).next().unwrap().to_owned()
    };
    assert_eq!(lips(&said), lips(&said_whole), "{said}");
    for (label, same, apart) in differences(dir.path(), "whole", "split", &copies) {
        assert!(same <= 1e-4, "{label}: the heads differ by {same}");
        assert!(apart <= 1e-4, "{label}: the seam opened by {apart}");
    }
}

/// MediaPipe's face written as separate triangles (every face its own three vertices, as a
/// triangle soup) is joined back into its own surface: its joined lips are found and cut, its
/// covered eyes opened, and it passes `check`. The mesh `fit-rig` opened (lips cut along a
/// line of coincident vertices, a mouth pocket and eyes' insides on the lips' and lids'
/// edges) is joined nowhere when fitted again.
#[test]
fn mediapipe_as_separate_triangles_is_joined_and_an_opened_mesh_is_not() {
    let Some((path, mesh, landmarks)) = crate::shared_mediapipe() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut soup = String::new();
    for p in &mesh.positions {
        soup.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
    }
    for t in &mesh.triangles {
        for v in t {
            let p = mesh.positions[*v as usize];
            soup.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
        }
    }
    let n = mesh.vertex_count();
    for k in 0..mesh.triangles.len() {
        let first = n + 3 * k + 1;
        soup.push_str(&format!("f {} {} {}\n", first, first + 1, first + 2));
    }
    write_head(dir.path(), "soup", &soup, &landmarks.vertices(&mesh));
    let said = fit(dir.path(), "soup", &[]);
    assert!(said.contains("seams: the skin was split"), "{said}");
    assert!(
        said.contains("lips: joined along the inner lip line"),
        "{said}"
    );
    let check = common::grimace_in(dir.path(), &["check", "--rig", "soup.rig.ron"]);
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(check.status.success(), "{report}");

    crate::fit_mediapipe_in(dir.path(), &path, &[]);
    std::fs::copy(
        dir.path().join("mp.opened.obj"),
        dir.path().join("again.obj"),
    )
    .unwrap();
    std::fs::copy(
        dir.path().join("mp.opened.landmarks.ron"),
        dir.path().join("again.landmarks.ron"),
    )
    .unwrap();
    let said = fit(dir.path(), "again", &[]);
    assert!(!said.contains("seam"), "{said}");
}
