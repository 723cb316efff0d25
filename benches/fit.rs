//! Fitting the default rig to a larger head, and the cost per vertex of deforming and drawing
//! the result against the default face's.
//!
//! The head is the default face split twice (each triangle into four, new vertices at edge
//! midpoints): 54,913 vertices, its landmarks the default face's vertex numbers.
//!
//! Run: `cargo bench --bench fit`. Prints wall-clock medians (fit) and per-vertex costs.

use std::collections::HashMap;
use std::time::Instant;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::Vec3;
use grimace::fit::{fit_rig, PartOverrides, Template};
use grimace::io::builtin;
use grimace::model::{BoundRig, Mesh};
use grimace::render::{Camera, CellGrid, CellMode, ColorMode, Renderer, Scene, Style};

/// Each triangle split into four at its edge midpoints; old vertices keep their numbers.
fn split(mesh: &Mesh) -> Mesh {
    let mut positions = mesh.positions.clone();
    let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
    let mut at = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
        *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
            positions.push(0.5 * (positions[a as usize] + positions[b as usize]));
            positions.len() as u32 - 1
        })
    };
    let mut triangles = Vec::with_capacity(mesh.triangles.len() * 4);
    for &[a, b, c] in &mesh.triangles {
        let (ab, bc, ca) = (
            at(a, b, &mut positions),
            at(b, c, &mut positions),
            at(c, a, &mut positions),
        );
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Mesh::new(positions, triangles).expect("split mesh")
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn fit(c: &mut Criterion) {
    let face = builtin::default_mesh();
    let rig = builtin::default_rig();
    let landmarks = builtin::landmarks("face").expect("built-in landmarks");
    let points = landmarks.positions(&face).expect("landmarks on the face");
    let template = Template {
        rig: &rig,
        mesh: &face,
        landmarks: &points,
    };
    let head = split(&split(&face));
    let run = || {
        fit_rig(
            template,
            &head,
            &landmarks,
            "head.obj".into(),
            &PartOverrides::default(),
        )
        .expect("fits")
    };
    let times: Vec<f64> = (0..5)
        .map(|_| {
            let t = Instant::now();
            black_box(run());
            t.elapsed().as_secs_f64()
        })
        .collect();
    let fitted = run();
    eprintln!(
        "fit_rig: {} vertices in {:.3} s (median of 5)",
        head.vertex_count(),
        median(times)
    );

    // Deform and draw: nanoseconds per vertex, default face against the fitted head.
    let table = builtin::default_table();
    let camera = Camera::three_quarter();
    let mut per_vertex = Vec::new();
    for (name, mesh, rig) in [("face", &face, &rig), ("head", &head, &fitted.rig)] {
        let bound = BoundRig::bind(rig, mesh).expect("binds");
        let act = table
            .expression_activations("happiness", rig)
            .expect("happiness");
        let mut out = Vec::new();
        let n = mesh.vertex_count() as f64;
        let runs = (2_000_000.0 / n).ceil() as usize;
        let deform: Vec<f64> = (0..5)
            .map(|_| {
                let t = Instant::now();
                for _ in 0..runs {
                    bound.deform(&act, &mut out).expect("in range");
                    black_box(&out);
                }
                t.elapsed().as_secs_f64() * 1e9 / (runs as f64 * n)
            })
            .collect();
        let mut renderer = Renderer::new(mesh);
        let mut canvas = CellMode::Braille.canvas(200, 60);
        let mut grid = CellGrid::default();
        let draw_runs = (runs / 4).max(2);
        let draw: Vec<f64> = (0..5)
            .map(|_| {
                let t = Instant::now();
                for _ in 0..draw_runs {
                    let scene = Scene::new(mesh, &out).with_rest(&mesh.positions);
                    renderer.render(&scene, &camera, Style::Lines, &mut canvas);
                    grid.fill(&canvas, CellMode::Braille, ColorMode::TrueColor);
                    black_box(&grid);
                }
                t.elapsed().as_secs_f64() * 1e9 / (draw_runs as f64 * n)
            })
            .collect();
        let (d, r) = (median(deform), median(draw));
        eprintln!(
            "{name}: {} vertices, {} (vertex, muscle) pairs: deform {d:.2} ns/vertex, draw {r:.2} ns/vertex",
            mesh.vertex_count(),
            bound.pair_count()
        );
        per_vertex.push((d, r));
    }
    eprintln!(
        "head / face per vertex: deform {:.2}x, draw {:.2}x",
        per_vertex[1].0 / per_vertex[0].0,
        per_vertex[1].1 / per_vertex[0].1
    );
    c.bench_function("fit_rig_split_face", |b| b.iter(|| black_box(run())));
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = fit
}
criterion_main!(benches);
