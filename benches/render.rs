//! One editor frame on a 200x60 terminal: project, rasterize with hidden-line removal, and
//! fill the braille cell grid (plus the deformation once the engine provides it).
//!
//! Run: `cargo bench --bench render -- --warm-up-time 1 --measurement-time 3`
//! (set `GRIMACE_SHARED` to use the classic face from the shared reference folder).

use std::path::PathBuf;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::Vec3;
use grimace::model::Mesh;
use grimace::render::{Camera, CellGrid, CellMode, ColorMode, Renderer, Scene, Style};

/// The terminal the benchmark draws for.
const COLS: usize = 200;
const ROWS: usize = 60;

fn classic_face() -> Option<Mesh> {
    let dir = std::env::var_os("GRIMACE_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"))
        .join("golden");
    let rows = |name: &str| -> Option<Vec<Vec<f64>>> {
        let text = std::fs::read_to_string(dir.join(name)).ok()?;
        Some(
            text.lines()
                .skip(1)
                .filter(|l| !l.trim().is_empty())
                .map(|l| l.split(',').filter_map(|f| f.trim().parse().ok()).collect())
                .collect(),
        )
    };
    let positions = rows("waters-vertices.csv")?
        .iter()
        .map(|r| Vec3::new(r[1] as f32, r[2] as f32, r[3] as f32))
        .collect();
    let triangles = rows("waters-triangles.csv")?
        .iter()
        .map(|r| [r[1] as u32, r[2] as u32, r[3] as u32])
        .collect();
    Mesh::new(positions, triangles).ok()
}

/// A dense UV sphere standing in when no face is available (about 4k triangles).
fn sphere() -> Mesh {
    let (rings, segments) = (40usize, 52usize);
    let mut positions = vec![Vec3::Y];
    for r in 1..rings {
        let t = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let p = std::f32::consts::TAU * s as f32 / segments as f32;
            positions.push(Vec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin()));
        }
    }
    positions.push(-Vec3::Y);
    let last = positions.len() as u32 - 1;
    let at = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, at(1, s + 1), at(1, s)]);
        triangles.push([last, at(rings - 1, s), at(rings - 1, s + 1)]);
    }
    for r in 1..rings - 1 {
        for s in 0..segments {
            triangles.push([at(r, s), at(r, s + 1), at(r + 1, s + 1)]);
            triangles.push([at(r, s), at(r + 1, s + 1), at(r + 1, s)]);
        }
    }
    Mesh::new(positions, triangles).expect("valid sphere")
}

fn frame(c: &mut Criterion) {
    let meshes = [("classic", classic_face()), ("sphere4k", Some(sphere()))];
    for (name, mesh) in meshes {
        let Some(mesh) = mesh else {
            eprintln!("{name}: not available, skipped");
            continue;
        };
        let mut renderer = Renderer::new(&mesh);
        let mut canvas = CellMode::Braille.canvas(COLS, ROWS);
        let mut grid = CellGrid::default();
        let camera = Camera::three_quarter();
        for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
            // On a shared machine wall time includes waiting for a core; the thread's own
            // CPU time per frame is printed too.
            if let Some(ns) = cpu_time_per_frame(|| {
                let scene = Scene::new(&mesh, &mesh.positions);
                renderer.render(&scene, &camera, style, &mut canvas);
                grid.fill(&canvas, CellMode::Braille, ColorMode::TrueColor);
                black_box(&grid);
            }) {
                eprintln!(
                    "frame_{COLS}x{ROWS}_{name}_{style}: {:.1} us CPU per frame",
                    ns / 1000.0
                );
            }
            c.bench_function(&format!("frame_{COLS}x{ROWS}_{name}_{style}"), |b| {
                b.iter(|| {
                    let scene = Scene::new(&mesh, &mesh.positions);
                    renderer.render(&scene, black_box(&camera), style, &mut canvas);
                    grid.fill(&canvas, CellMode::Braille, ColorMode::TrueColor);
                    black_box(&grid);
                })
            });
        }
    }
}

/// Mean on-CPU time of `f` over many runs, from the kernel's per-thread scheduler
/// statistics (Linux only; `None` elsewhere).
fn cpu_time_per_frame(mut f: impl FnMut()) -> Option<f64> {
    let read = || -> Option<u64> {
        let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
        text.split_whitespace().next()?.parse().ok()
    };
    for _ in 0..50 {
        f();
    }
    const RUNS: u32 = 1000;
    let start = read()?;
    for _ in 0..RUNS {
        f();
    }
    Some((read()? - start) as f64 / RUNS as f64)
}

criterion_group!(benches, frame);
criterion_main!(benches);
