//! The cost of one played frame on the built-in default face: an OpenFace row's 17 AU
//! intensities mapped through the default table, the mesh deformed, the face rendered in the
//! default style with displacement colours (as the view draws it) and turned into braille cells, at two terminal sizes. Playback keeps 60 fps
//! while this stays well under 16.7 ms (the view then spends the rest of each frame asleep).
//!
//! Run: `cargo bench --bench play -- --warm-up-time 1 --measurement-time 3`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use grimace::facs::AuKey;
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig};
use grimace::play::source::AuFrames;
use grimace::play::{AuMapper, IntensityScale};
use grimace::render::{Camera, CellGrid, CellMode, ColorMode, DotCanvas, Renderer, Scene, Style};

/// The 17 AUs OpenFace reports, with intensities from a real frame (0-5).
const ROW: [(u8, f32); 17] = [
    (1, 0.50),
    (2, 0.28),
    (4, 0.62),
    (5, 0.10),
    (6, 1.04),
    (7, 1.85),
    (9, 0.11),
    (10, 0.93),
    (12, 1.74),
    (14, 2.23),
    (15, 0.06),
    (17, 1.01),
    (20, 0.47),
    (23, 0.20),
    (25, 0.80),
    (26, 0.37),
    (45, 2.38),
];

fn frames(c: &mut Criterion) {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let table = builtin::default_table();
    let bound = BoundRig::bind(&rig, &mesh).expect("the default rig binds");
    let mut builder = AuFrames::new(
        AuMapper::new(&table, &rig),
        IntensityScale::ZeroToFive,
        "bench",
    );
    let row = || ROW.iter().map(|&(n, v)| (AuKey::new(n), v));

    c.bench_function("play/map_row", |b| {
        b.iter(|| black_box(builder.frame(0.0, None, row())))
    });

    let mut positions = bound.rest().to_vec();
    let act: Activations = builder.frame(0.0, None, row()).activations;
    c.bench_function("play/deform", |b| {
        b.iter(|| bound.deform(black_box(&act), &mut positions).unwrap())
    });

    let mut renderer = Renderer::new(&mesh);
    let mut canvas = DotCanvas::new(0, 0);
    let mut grid = CellGrid::default();
    for (cols, rows) in [(70, 27), (170, 57)] {
        c.bench_function(&format!("play/frame_{cols}x{rows}"), |b| {
            b.iter(|| {
                let frame = builder.frame(0.0, None, row());
                bound.deform(&frame.activations, &mut positions).unwrap();
                CellMode::Braille.prepare(&mut canvas, cols, rows);
                let mut scene = Scene::new(&mesh, &positions).with_rest(bound.rest());
                scene.displacement = true;
                renderer.render(&scene, &Camera::front(), Style::Lines, &mut canvas);
                grid.fill(&canvas, CellMode::Braille, ColorMode::Ansi16);
                black_box(grid.cells.len())
            })
        });
    }
}

criterion_group!(benches, frames);
criterion_main!(benches);
