//! Where a pose tears a fitted head: the skin edges stretched most and the triangles turned
//! over, each with its vertices' nearest landmark, their group in the OBJ, how far the
//! deformation moved them and which muscles' fields pull them (activation times field).
//!
//!     cargo run --release --example worst_edges -- RIG LANDMARKS ENTRY...
//!
//! RIG is a `*.rig.ron` (its mesh is read as `grimace check` reads it), LANDMARKS a
//! `*.landmarks.ron` or `mediapipe`, ENTRY an AU key of the built-in table (`10`, `L12`) or
//! one of its expressions (`disgust`).

use std::path::Path;

use glam::Vec3;
use grimace::facs::combo::parse_combo;
use grimace::facs::{AuKey, AuMapper};
use grimace::io::builtin;
use grimace::io::landmarks::load_landmarks;
use grimace::io::load::load_rig_ref;
use grimace::landmarks::Landmarks;
use grimace::model::{Activations, BoundRig, Deformation, Mesh};

/// Muscles (by part of the name) reported at vertices where their field is zero.
static MUSCLE: std::sync::LazyLock<String> =
    std::sync::LazyLock::new(|| std::env::var("MUSCLE").unwrap_or_else(|_| "\u{0}".into()));

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [rig_path, marks, entries @ ..] = args.as_slice() else {
        anyhow::bail!("usage: worst_edges RIG LANDMARKS ENTRY...");
    };
    let loaded = load_rig_ref(Path::new(rig_path), None)?;
    let landmarks = match marks.as_str() {
        "mediapipe" => Landmarks::mediapipe(&loaded.mesh)?,
        file => load_landmarks(Path::new(file))?,
    };
    let marks = landmarks.vertices(&loaded.mesh);
    let table = builtin::default_table();
    let mapper = AuMapper::new(&table, &loaded.rig);
    let bound = Deformation::default().bind(&loaded.rig, &loaded.mesh)?;
    let skin = skin_piece(&loaded.mesh, &marks);
    let mut out = Vec::new();
    for entry in entries {
        let mut act = Activations::zero(&loaded.rig);
        match table.expressions.get(entry) {
            Some(combo) => {
                let combo = parse_combo(combo).map_err(|e| anyhow::anyhow!("{e}"))?;
                mapper.map(
                    combo.terms.iter().map(|t| (t.key, t.intensity.factor())),
                    &mut act,
                );
            }
            None => mapper.map([(entry.parse::<AuKey>()?, 1.0)], &mut act),
        }
        bound.deform(&act, &mut out)?;
        println!("== {entry}");
        report(&bound, &loaded.mesh, &marks, &skin, &act, &out);
    }
    Ok(())
}

/// Which vertices are on the piece holding the landmarks (what `check` calls skin).
fn skin_piece(mesh: &Mesh, marks: &[u32]) -> Vec<bool> {
    let n = mesh.positions.len();
    let mut adjacent = vec![Vec::new(); n];
    for t in &mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            adjacent[a as usize].push(b);
            adjacent[b as usize].push(a);
        }
    }
    let mut on = vec![false; n];
    let mut stack: Vec<u32> = marks.to_vec();
    while let Some(v) = stack.pop() {
        if !std::mem::replace(&mut on[v as usize], true) {
            stack.extend(adjacent[v as usize].iter().copied());
        }
    }
    on
}

fn report(
    bound: &BoundRig,
    mesh: &Mesh,
    marks: &[u32],
    skin: &[bool],
    act: &Activations,
    out: &[Vec3],
) {
    let rest = &mesh.positions;
    let mut edges: Vec<(f32, u32, u32)> = Vec::new();
    let mut turned = Vec::new();
    for t in mesh.triangles.iter().filter(|t| skin[t[0] as usize]) {
        let n0 = (rest[t[1] as usize] - rest[t[0] as usize])
            .cross(rest[t[2] as usize] - rest[t[0] as usize]);
        let n1 = (out[t[1] as usize] - out[t[0] as usize])
            .cross(out[t[2] as usize] - out[t[0] as usize]);
        if n0.dot(n1) < 0.0 {
            turned.push(*t);
        }
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let l0 = rest[a as usize].distance(rest[b as usize]);
            if l0 > 0.0 && a < b {
                edges.push((out[a as usize].distance(out[b as usize]) / l0, a, b));
            }
        }
    }
    edges.sort_by(|x, y| y.0.total_cmp(&x.0));
    edges.dedup_by_key(|e| (e.1, e.2));
    for &(s, a, b) in edges.iter().take(6) {
        println!(
            "edge {a}-{b} stretch {s:.2}x rest length {:.4}",
            rest[a as usize].distance(rest[b as usize])
        );
        for v in [a, b] {
            vertex(bound, mesh, marks, act, out, v);
        }
    }
    println!("{} triangles turned over", turned.len());
    for t in turned.iter().take(4) {
        println!("triangle {t:?}");
        for &v in t {
            vertex(bound, mesh, marks, act, out, v);
        }
    }
}

/// The masks of muscle `name` that list vertex `v`: each as its muscle count and weight.
fn masks_at(bound: &BoundRig, name: &String, v: u32) -> String {
    let masks: Vec<String> = bound
        .rig()
        .masks
        .iter()
        .filter(|k| k.muscles.contains(name))
        .filter_map(|k| {
            let i = k.weights.binary_search_by_key(&v, |&(u, _)| u).ok()?;
            Some(format!("#{} {:.2}", k.muscles.len(), k.weights[i].1))
        })
        .collect();
    masks.join(" ")
}

/// One vertex: position, nearest landmark, group, travel, and the muscles pulling it.
fn vertex(bound: &BoundRig, mesh: &Mesh, marks: &[u32], act: &Activations, out: &[Vec3], v: u32) {
    let p = mesh.positions[v as usize];
    let (mark, d) = marks
        .iter()
        .enumerate()
        .map(|(i, &m)| (i, mesh.positions[m as usize].distance(p)))
        .fold((0, f32::INFINITY), |b, x| if x.1 < b.1 { x } else { b });
    let group = mesh
        .groups
        .iter()
        .find(|(_, members)| members.binary_search(&v).is_ok())
        .map_or("-", |(name, _)| name.as_str());
    let moved = out[v as usize] - p;
    let mut raw = Vec3::ZERO;
    let mut pulls = Vec::new();
    for m in 0..bound.muscle_count() {
        let a = act.muscles[m];
        let Some(field) = bound.field(m) else {
            continue;
        };
        if a == 0.0 {
            continue;
        }
        let name = &bound.rig().muscles[m].name;
        if field.vertices.binary_search(&v).is_err() && name.contains(MUSCLE.as_str()) {
            pulls.push(format!("{name} none, masks [{}]", masks_at(bound, name, v)));
        }
        if let Ok(i) = field.vertices.binary_search(&v) {
            let d = field.displacements[i] * a;
            raw += d;
            pulls.push(format!(
                "{name} {:.3} masks [{}]",
                d.length(),
                masks_at(bound, name, v)
            ));
        }
    }
    println!(
        "  v{v} at {p:.3} near landmark {mark} ({d:.3}) group {group}: moved {:.3} {moved:.3}, \
         fields {:.3} {raw:.3}: {}",
        moved.length(),
        raw.length(),
        pulls.join(", ")
    );
}
