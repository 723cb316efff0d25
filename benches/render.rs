//! One editor frame on a 200x60 terminal on the default face: deform, project, rasterize
//! with hidden-line removal, and fill the braille cell grid.
//!
//! Run: `cargo bench --bench render -- --warm-up-time 1 --measurement-time 3`. The CPU time
//! per frame is printed first (set `GRIMACE_BENCH_CPU_ONLY=1` to print only that); with
//! `GRIMACE_SHARED` set, the classic face is measured too. For profiling,
//! `GRIMACE_BENCH_ONLY=frame_lines` keeps only the measurements whose name contains it and
//! `GRIMACE_BENCH_RUNS=N` sets the frames in each of the five batches the CPU time is
//! measured over (2000).

use std::path::PathBuf;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::Vec3;
use grimace::io::builtin;
use grimace::model::{BoundRig, Mesh};
use grimace::render::{Camera, CellGrid, CellMode, ColorMode, Framing, Renderer, Scene, Style};

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

fn frame(c: &mut Criterion) {
    let cpu_only = std::env::var_os("GRIMACE_BENCH_CPU_ONLY").is_some();
    // The default face deformed by an expression, every frame (as the editor does).
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let table = builtin::default_table();
    let bound = BoundRig::bind(&rig, &mesh).expect("default rig binds");
    let act = table
        .expression_activations("happiness", &rig)
        .expect("default table has happiness");
    let mut positions = Vec::new();
    let mut renderer = Renderer::new(&mesh);
    let mut canvas = CellMode::Braille.canvas(COLS, ROWS);
    let mut grid = CellGrid::default();
    let camera = Camera::three_quarter();
    for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
        if !selected(&format!("frame_{style}")) {
            continue;
        }
        let mut one = || {
            bound.deform(&act, &mut positions).expect("in range");
            let scene = Scene::new(&mesh, &positions).with_rest(&mesh.positions);
            renderer.render(&scene, black_box(&camera), style, &mut canvas);
            grid.fill(&canvas, CellMode::Braille, ColorMode::TrueColor);
            black_box(&grid);
        };
        // On a shared machine wall time includes waiting for a core; the thread's own CPU
        // time per frame is printed too.
        print_cpu_time(
            &format!("frame_{COLS}x{ROWS}_face_{style}"),
            "deform + render + cells; ",
            &mut one,
        );
        if !cpu_only {
            c.bench_function(&format!("frame_{COLS}x{ROWS}_face_{style}"), |b| {
                b.iter(&mut one)
            });
        }
    }
    // Rendering alone, without the deformation.
    for style in [Style::Lines, Style::Shaded] {
        if !selected(&format!("render_only_{style}")) {
            continue;
        }
        let mut one = || {
            let scene = Scene::new(&mesh, &mesh.positions);
            renderer.render(&scene, black_box(&camera), style, &mut canvas);
            grid.fill(&canvas, CellMode::Braille, ColorMode::TrueColor);
            black_box(&grid);
        };
        print_cpu_time(
            &format!("render_only_{COLS}x{ROWS}_face_{style}"),
            "",
            &mut one,
        );
        if !cpu_only {
            c.bench_function(&format!("render_only_{COLS}x{ROWS}_face_{style}"), |b| {
                b.iter(&mut one)
            });
        }
    }
    // Blank eyes: the default face without its iris and pupil groups, shaded with the irises
    // its landmarks place painted on (`raster::iris`) and without them, the cost of the
    // painting per frame.
    if selected("blank_eyes") {
        let mut blank = mesh.clone();
        blank
            .groups
            .retain(|name, _| !name.contains("iris") && !name.contains("pupil"));
        let points = builtin::landmarks("default")
            .expect("landmarks")
            .positions(&blank)
            .expect("on the face");
        let framing = Framing::of_face(None, &blank, Some(&points), None);
        let mut none = framing.clone();
        none.irises.clear();
        let mut renderer = Renderer::new(&blank);
        for (name, framing) in [("painted", &framing), ("blank", &none)] {
            let mut one = || {
                bound.deform(&act, &mut positions).expect("in range");
                let scene = Scene::new(&blank, &positions)
                    .with_rest(&blank.positions)
                    .with_framing(framing);
                renderer.render(&scene, black_box(&camera), Style::Shaded, &mut canvas);
                grid.fill(&canvas, CellMode::Braille, ColorMode::TrueColor);
                black_box(&grid);
            };
            print_cpu_time(
                &format!("frame_{COLS}x{ROWS}_blank_eyes_{name}_shaded"),
                "",
                &mut one,
            );
        }
    }
    if let Some(classic) = classic_face().filter(|_| selected("classic_lines")) {
        let mut renderer = Renderer::new(&classic);
        let mut one = || {
            let scene = Scene::new(&classic, &classic.positions);
            renderer.render(&scene, black_box(&camera), Style::Lines, &mut canvas);
            grid.fill(&canvas, CellMode::Braille, ColorMode::TrueColor);
            black_box(&grid);
        };
        print_cpu_time(
            &format!("render_only_{COLS}x{ROWS}_classic_lines"),
            "",
            &mut one,
        );
    }
}

/// Prints the thread's CPU time per frame of `one` (median and minimum over five batches),
/// `what` saying what a frame holds beyond rendering.
fn print_cpu_time(name: &str, what: &str, one: &mut impl FnMut()) {
    if let Some((median, min)) = cpu_time_per_frame(one) {
        eprintln!(
            "{name}: {:.1} us CPU per frame ({what}min {:.1})",
            median / 1000.0,
            min / 1000.0
        );
    }
}

/// Whether the measurement `name` runs: all of them, or those whose name contains
/// `GRIMACE_BENCH_ONLY` (for profiling one style).
fn selected(name: &str) -> bool {
    std::env::var("GRIMACE_BENCH_ONLY").map_or(true, |only| name.contains(&only))
}

/// On-CPU time of `f` per run, from the kernel's per-thread scheduler statistics (Linux
/// only; `None` elsewhere): the median over `BATCHES` batches of many runs, and the
/// smallest batch.
///
/// The kernel brings a running thread's counter up to date only at scheduler ticks and
/// switches, so each batch runs long enough (hundreds of milliseconds) for that to be a
/// small error; the median keeps a burst of other work on a shared machine from skewing
/// the result.
fn cpu_time_per_frame(f: &mut impl FnMut()) -> Option<(f64, f64)> {
    const BATCHES: usize = 5;
    let read = || -> Option<u64> {
        let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
        text.split_whitespace().next()?.parse().ok()
    };
    for _ in 0..50 {
        f();
    }
    let runs: u32 = std::env::var("GRIMACE_BENCH_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2000)
        .max(1);
    let mut batches = Vec::with_capacity(BATCHES);
    for _ in 0..BATCHES {
        let start = read()?;
        for _ in 0..runs {
            f();
        }
        batches.push((read()? - start) as f64 / runs as f64);
    }
    batches.sort_by(f64::total_cmp);
    Some((batches[BATCHES / 2], batches[0]))
}

criterion_group!(benches, frame);
criterion_main!(benches);
