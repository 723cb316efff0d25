//! Big heads: what a frame, a key press, loading, binding and fitting cost on heads of
//! tens and hundreds of thousands of vertices, drawing the full mesh ("full") against the
//! level of detail the editor and `render --format txt` draw ("lod"), in the same run.
//!
//! The heads are the built-in face with every edge split into `k` parts (new vertices on
//! the flat triangles, old vertices keeping their numbers, so the built-in landmarks still
//! name them), the default rig fitted to each with `fit_rig`. Nothing big is committed: the
//! heads are made here and written to a temporary folder for the load measurement.
//!
//! Run: `cargo bench --bench heads`. `GRIMACE_HEADS=3,10` sets the splits (default 3 and
//! 12: 30 763 and 475 840 vertices); `GRIMACE_BENCH_RUNS=N` the frames per measurement
//! (default 30). `GRIMACE_HEADS_EDITOR_ONLY=1` measures the editor only (for profiling
//! it). `GRIMACE_HEADS_OUT=DIR` only writes the heads and their landmarks there
//! (`head-K.obj`, `head-K.landmarks.ron`) for timing the command line on them. Times are wall-clock medians (and minimums) over the runs, each run on the
//! whole rayon pool as the editor uses it.

use std::collections::HashMap;
use std::time::Instant;

use grimace::fit::{fit_rig, PartOverrides, Template};
use grimace::io::{builtin, obj};
use grimace::model::{Activations, BoundRig, Deformation, Mesh};
use grimace::render::{
    Camera, CellGrid, CellMode, ColorMode, Framing, Lod, Renderer, Scene, Style,
};

const COLS: usize = 200;
const ROWS: usize = 60;

/// The mesh with each edge split into `k` parts and each triangle into `k * k`; old
/// vertices keep their numbers, groups keep the new vertices between their members.
fn split(mesh: &Mesh, k: u32) -> Mesh {
    let mut positions = mesh.positions.clone();
    let mut origin: Vec<Vec<u32>> = Vec::new();
    let mut on_edge: HashMap<(u32, u32, u32), u32> = HashMap::new();
    let mut triangles = Vec::with_capacity(mesh.triangles.len() * (k * k) as usize);
    let kf = k as f32;
    for &[a, b, c] in &mesh.triangles {
        let [pa, pb, pc] = [a, b, c].map(|i| mesh.positions[i as usize]);
        let mut grid = vec![0u32; ((k + 1) * (k + 2) / 2) as usize];
        let slot = |i: u32, j: u32| (j * (k + 1) - j * (j.saturating_sub(1)) / 2 + i) as usize;
        for j in 0..=k {
            for i in 0..=k - j {
                let id = match (i, j) {
                    (0, 0) => a,
                    (i, 0) if i == k => b,
                    (0, j) if j == k => c,
                    _ => {
                        let edge = if j == 0 {
                            Some((a, b, i))
                        } else if i == 0 {
                            Some((a, c, j))
                        } else if i + j == k {
                            Some((b, c, j))
                        } else {
                            None
                        };
                        let p = pa + (pb - pa) * (i as f32 / kf) + (pc - pa) * (j as f32 / kf);
                        let corners = match edge {
                            Some((x, y, _)) => vec![x, y],
                            None => vec![a, b, c],
                        };
                        let mut make = || {
                            positions.push(p);
                            origin.push(corners.clone());
                            positions.len() as u32 - 1
                        };
                        match edge {
                            Some((x, y, t)) => {
                                let key = if x < y { (x, y, t) } else { (y, x, k - t) };
                                *on_edge.entry(key).or_insert_with(make)
                            }
                            None => make(),
                        }
                    }
                };
                grid[slot(i, j)] = id;
            }
        }
        for j in 0..k {
            for i in 0..k - j {
                triangles.push([grid[slot(i, j)], grid[slot(i + 1, j)], grid[slot(i, j + 1)]]);
                if i + j + 1 < k {
                    triangles.push([
                        grid[slot(i + 1, j)],
                        grid[slot(i + 1, j + 1)],
                        grid[slot(i, j + 1)],
                    ]);
                }
            }
        }
    }
    let mut out = Mesh::new(positions, triangles).expect("split mesh");
    let old = mesh.positions.len() as u32;
    for (name, members) in &mesh.groups {
        let mut new = members.clone();
        for (n, corners) in origin.iter().enumerate() {
            if corners.iter().all(|c| members.binary_search(c).is_ok()) {
                new.push(old + n as u32);
            }
        }
        new.sort_unstable();
        out.groups.insert(name.clone(), new);
    }
    out
}

/// Writes the head split `k` times as `DIR/head-K.obj` with its landmarks beside it
/// (`head-K.landmarks.ron`, the built-in face's: old vertices keep their numbers), for
/// timing the command line (`grimace fit-rig`, `render`) on it.
fn write_head(k: u32, dir: &std::path::Path) {
    let mesh = split(&builtin::default_mesh(), k);
    let landmarks = builtin::landmarks("face").expect("built-in landmarks");
    let obj_path = dir.join(format!("head-{k}.obj"));
    std::fs::write(&obj_path, obj::write_obj(&mesh, &mesh.positions)).expect("write obj");
    grimace::io::landmarks::save_landmarks(
        &dir.join(format!("head-{k}.landmarks.ron")),
        &landmarks,
    )
    .expect("write landmarks");
    eprintln!("{}: {} vertices", obj_path.display(), mesh.vertex_count());
}

/// Median and minimum wall-clock milliseconds of `runs` calls of `f`.
fn time(runs: usize, mut f: impl FnMut()) -> (f64, f64) {
    f();
    let mut t: Vec<f64> = (0..runs.max(1))
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    (t[t.len() / 2], t[0])
}

fn report(what: &str, (median, min): (f64, f64)) {
    eprintln!("  {what}: {median:.3} ms (min {min:.3})");
}

fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// One head: fit, load, bind, level of detail, deform, frames.
fn head(k: u32, runs: usize) {
    let face = builtin::default_mesh();
    let rig = builtin::default_rig();
    let landmarks = builtin::landmarks("face").expect("built-in landmarks");
    let points = landmarks.positions(&face).expect("landmarks on the face");
    let mesh = split(&face, k);
    let n = mesh.vertex_count();
    eprintln!(
        "head k={k}: {n} vertices, {} triangles",
        mesh.triangles.len()
    );
    let start = Instant::now();
    let fitted = fit_rig(
        Template {
            rig: &rig,
            mesh: &face,
            landmarks: &points,
        },
        &mesh,
        &landmarks,
        "head.obj".into(),
        &PartOverrides::default(),
    )
    .expect("fits");
    eprintln!("  fit_rig: {:.0} ms", start.elapsed().as_secs_f64() * 1e3);
    let dir = tempfile::tempdir().expect("temporary folder");
    let path = dir.path().join("head.obj");
    std::fs::write(&path, obj::write_obj(&mesh, &mesh.positions)).expect("write obj");
    report(
        "load OBJ",
        time(3, || drop(obj::read_obj(&path).expect("reads"))),
    );
    let start = Instant::now();
    let bound = Deformation::Skin.bind(&fitted.rig, &mesh).expect("binds");
    eprintln!(
        "  bind (skin): {:.0} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    bind_cache(&fitted.rig, &mesh, &bound);
    let framing = Framing::of_rig(&fitted.rig, &mesh);
    let start = Instant::now();
    let lod = Lod::of_rig(&fitted.rig, &mesh, &framing);
    eprintln!(
        "  level of detail built: {:.0} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    for level in lod.levels() {
        eprintln!(
            "    level: {} vertices, {} triangles",
            level.source.len(),
            level.mesh.triangles.len()
        );
    }
    let act = builtin::default_table()
        .expression_activations("happiness", &fitted.rig)
        .expect("happiness");
    if let Ok(what) = std::env::var("GRIMACE_HEADS_PROFILE") {
        profile(&what, &mesh, &bound, &framing, &lod, &act, runs);
        return;
    }
    if std::env::var_os("GRIMACE_HEADS_EDITOR_ONLY").is_none() {
        frames(&mesh, &bound, &framing, &lod, &act, runs);
    }
    drop((bound, lod));
    editor_start(&fitted.rig, &mesh);
    editor(fitted.rig, mesh, runs);
    eprintln!("  peak RSS so far: {:.0} MB", peak_rss_mb());
}

/// The bind cache (`io::bind_cache`) in a temporary folder: a bind that writes it, then
/// binds read from it (checked equal to the fresh bind), and the file's size.
fn bind_cache(rig: &grimace::model::Rig, mesh: &Mesh, fresh: &BoundRig) {
    use grimace::io::bind_cache::BindCache;
    let dir = tempfile::tempdir().expect("temporary folder");
    let cache = BindCache::at(dir.path());
    let start = Instant::now();
    let cold = cache.bind(Deformation::Skin, rig, mesh).expect("binds");
    assert!(!cold.from_cache && cold.warnings.is_empty());
    let ms = start.elapsed().as_secs_f64() * 1e3;
    let path = cache.path(Deformation::Skin, rig, mesh).expect("a cache");
    let size = std::fs::metadata(&path).map_or(0, |m| m.len());
    eprintln!(
        "  bind (skin) and write the bind cache: {ms:.0} ms, file {:.1} MB",
        size as f64 / (1u64 << 20) as f64
    );
    let start = Instant::now();
    let key = grimace::io::bind_cache::key(Deformation::Skin.skin(), rig, mesh);
    eprintln!(
        "  bind cache key (hash of rig, mesh, rules, code): {:.1} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    std::hint::black_box(key);
    let warm = cache.bind(Deformation::Skin, rig, mesh).expect("binds");
    assert!(
        warm.from_cache && warm.bound == *fresh,
        "the cached bind is the fresh one"
    );
    drop((cold, warm));
    report(
        "bind (skin) from the bind cache",
        time(3, || {
            drop(cache.bind(Deformation::Skin, rig, mesh).expect("binds"));
        }),
    );
}

/// A writer that only counts bytes, standing in for the terminal.
#[derive(Clone, Default)]
struct Counter(std::sync::Arc<std::sync::atomic::AtomicUsize>);

impl std::io::Write for Counter {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0
            .fetch_add(buf.len(), std::sync::atomic::Ordering::Relaxed);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// The editor on the head at 200x60: its first screen, then a key press (a fine step of
/// the selected muscle: update, the level's deformation, the face drawn, every panel,
/// ratatui's diff and the bytes written), split into its parts.
fn editor(rig: grimace::model::Rig, mesh: Mesh, runs: usize) {
    use grimace::tui::action::Action;
    use grimace::tui::app::{App, ColorMode};
    use grimace::tui::face::Face;
    use grimace::tui::update::update;
    use ratatui::backend::CrosstermBackend;
    use ratatui::layout::Rect;
    use ratatui::{Terminal, TerminalOptions, Viewport};
    let (cols, rows) = (COLS as u16, ROWS as u16);
    let mut term = Terminal::with_options(
        CrosstermBackend::new(Counter::default()),
        TerminalOptions {
            viewport: Viewport::Fixed(Rect::new(0, 0, cols, rows)),
        },
    )
    .expect("a terminal on a counting writer");
    let mesh_count = mesh.vertex_count();
    let start = Instant::now();
    let face = Face::new(rig, mesh).expect("the rig binds");
    let mut app = App::new(face, builtin::default_table(), None);
    app.view.colors = ColorMode::Ansi16;
    update(&mut app, Action::Resize(cols, rows));
    let mut cache = Default::default();
    grimace::tui::draw(&mut term, &app, &mut cache).expect("draws");
    eprintln!(
        "  editor: bound and first screen: {:.0} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    app.doc.face.wait_for_lod();
    eprintln!(
        "  editor: levels of detail ready: {:.0} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    let mut flip = 1;
    let mut press = |app: &mut App| {
        flip = -flip;
        update(app, Action::StepFine(flip));
    };
    report(
        "editor key press 200x60 (update + draw + diff)",
        time(runs, || {
            press(&mut app);
            grimace::tui::draw(&mut term, &app, &mut cache).expect("draws");
        }),
    );
    report(
        "editor key press: update alone",
        time(runs, || press(&mut app)),
    );
    // The viewport's cells at 200x60 (the wide layout: muscles, face, table panels).
    let camera = app.camera();
    let canvas = app.view.drawn_cells().canvas(126, 56);
    let drawn = app
        .doc
        .face
        .lod()
        .choose(&camera, canvas.width(), canvas.height(), canvas.dot_aspect)
        .map_or(mesh_count, |l| l.source.len());
    eprintln!("  editor: the viewport draws {drawn} vertices");
    let mut level_positions = Vec::new();
    let levels = app.doc.face.lod().levels().len();
    for l in 0..levels {
        let count = app.doc.face.lod().levels()[l].source.len();
        report(
            &format!("editor key press: update + the deformation of the {count}-vertex level"),
            time(runs, || {
                press(&mut app);
                let level = &app.doc.face.lod().levels()[l];
                app.doc.face.sample(level, &mut level_positions);
            }),
        );
    }
    let mut draw_times = Vec::new();
    for _ in 0..runs {
        press(&mut app);
        let camera = app.camera();
        if let Some(level) =
            app.doc
                .face
                .lod()
                .choose(&camera, canvas.width(), canvas.height(), canvas.dot_aspect)
        {
            app.doc.face.sample(level, &mut level_positions);
        }
        let start = Instant::now();
        grimace::tui::draw(&mut term, &app, &mut cache).expect("draws");
        draw_times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    draw_times.sort_by(f64::total_cmp);
    report(
        "editor key press: the draw alone (face, panels, diff)",
        (draw_times[runs / 2], draw_times[0]),
    );
    report(
        "editor: draw, nothing changed (panels + diff)",
        time(runs, || {
            grimace::tui::draw(&mut term, &app, &mut cache).expect("draws")
        }),
    );
}

/// The editor's start on the head written as files (`grimace edit --rig R --mesh OBJ`
/// in process, up to its first screen at 200x60), as it is now (the rig bound on a thread
/// while the rest pose is shown) and as it was (loaded, bound, then drawn), in this run.
fn editor_start(rig: &grimace::model::Rig, mesh: &Mesh) {
    use grimace::cli::edit::{prepare, EditArgs};
    use grimace::io::load::load_rig_ref;
    use grimace::tui::face::Face;
    let dir = tempfile::tempdir().expect("temporary folder");
    let (obj_path, rig_path) = (dir.path().join("head.obj"), dir.path().join("head.rig.ron"));
    std::fs::write(&obj_path, obj::write_obj(mesh, &mesh.positions)).expect("write obj");
    let on_file = grimace::io::reference::rig_for_file(&rig_path, rig);
    std::fs::write(&rig_path, grimace::io::rig_to_ron(&on_file)).expect("write rig");
    let args = EditArgs {
        // A table that does not exist yet: its lock and recovery files stay in the folder.
        file: Some(dir.path().join("head.au.ron")),
        rig: Some(rig_path.clone()),
        mesh: Some(obj_path.clone()),
        ..EditArgs::default()
    };
    let ms = |start: Instant| start.elapsed().as_secs_f64() * 1e3;
    for _ in 0..2 {
        let start = Instant::now();
        let (mut app, session) = prepare(&args).expect("the editor starts");
        let loaded = ms(start);
        let drawn = first_screen(&mut app);
        let shown = ms(start);
        app.doc.face.wait_for_bind().expect("binds");
        eprintln!(
            "  editor start, now: files read {loaded:.0} ms, first screen {shown:.0} ms \
             (drawing {drawn:.0} ms), bound {:.0} ms",
            ms(start)
        );
        drop((app, session));
        let start = Instant::now();
        let loaded = load_rig_ref(&rig_path, Some(&obj_path)).expect("loads");
        let read = ms(start);
        let face = Face::new(loaded.rig, loaded.mesh).expect("binds");
        let bound = ms(start);
        let mut app = grimace::tui::app::App::new(face, builtin::default_table(), None);
        first_screen(&mut app);
        eprintln!(
            "  editor start, bound first: files read {read:.0} ms, bound {bound:.0} ms, \
             first screen {:.0} ms",
            ms(start)
        );
    }
}

/// Draws the editor's first screen at 200x60 into a counting writer; its milliseconds.
fn first_screen(app: &mut grimace::tui::app::App) -> f64 {
    use grimace::tui::action::Action;
    use ratatui::backend::CrosstermBackend;
    use ratatui::layout::Rect;
    use ratatui::{Terminal, TerminalOptions, Viewport};
    let start = Instant::now();
    let mut term = Terminal::with_options(
        CrosstermBackend::new(Counter::default()),
        TerminalOptions {
            viewport: Viewport::Fixed(Rect::new(0, 0, COLS as u16, ROWS as u16)),
        },
    )
    .expect("a terminal on a counting writer");
    app.view.colors = grimace::tui::app::ColorMode::Ansi16;
    grimace::tui::update::update(app, Action::Resize(COLS as u16, ROWS as u16));
    let mut cache = Default::default();
    grimace::tui::draw(&mut term, app, &mut cache).expect("draws");
    start.elapsed().as_secs_f64() * 1e3
}

/// One measurement alone, for `perf record` (`GRIMACE_HEADS_PROFILE=deform`, `lines` or
/// `shaded`: the whole mesh's deformation, or the drawn level's frame), `runs` times.
fn profile(
    what: &str,
    mesh: &Mesh,
    bound: &BoundRig,
    framing: &Framing,
    lod: &Lod,
    act: &Activations,
    runs: usize,
) {
    let mut camera = Camera::three_quarter();
    camera.basis = framing.basis;
    let mode = CellMode::Braille;
    let mut canvas = mode.canvas(COLS, ROWS);
    let mut full = Vec::new();
    bound.deform(act, &mut full).expect("deforms");
    if what == "deform" {
        report(
            &format!("deform the whole {}-vertex mesh", mesh.vertex_count()),
            time(runs, || bound.deform(act, &mut full).expect("deforms")),
        );
        return;
    }
    let style = if what == "shaded" {
        Style::Shaded
    } else {
        Style::Lines
    };
    let level = lod.choose(&camera, canvas.width(), canvas.height(), canvas.dot_aspect);
    let (drawn, positions) = match level {
        Some(level) => {
            let mut positions = Vec::new();
            level.gather(&full, &mut positions);
            (&level.mesh, positions)
        }
        None => (mesh, full.clone()),
    };
    let mut renderer = Renderer::new(drawn);
    let mut grid = CellGrid::default();
    report(
        &format!(
            "frame {COLS}x{ROWS} {style}, {} vertices",
            drawn.vertex_count()
        ),
        time(runs, || {
            let mut scene = Scene::new(drawn, &positions).with_rest(&drawn.positions);
            scene.focus = level.map(|l| &l.frame[..]);
            renderer.render(&scene, &camera, style, &mut canvas);
            grid.fill(&canvas, mode, ColorMode::TrueColor);
        }),
    );
}

/// Deform and draw at 200x60, full mesh against the level of detail.
fn frames(
    mesh: &Mesh,
    bound: &BoundRig,
    framing: &Framing,
    lod: &Lod,
    act: &Activations,
    runs: usize,
) {
    let mut camera = Camera::three_quarter();
    camera.basis = framing.basis;
    let mode = CellMode::Braille;
    let mut canvas = mode.canvas(COLS, ROWS);
    let level = lod.choose(&camera, canvas.width(), canvas.height(), canvas.dot_aspect);
    for l in lod.levels() {
        let proj = camera.fit_points(&l.frame, canvas.width(), canvas.height(), canvas.dot_aspect);
        eprintln!(
            "    level of {} vertices: cell {:.2} dots",
            l.source.len(),
            l.cell * proj.scale_x.max(proj.scale_y)
        );
    }
    let mut full = Vec::new();
    report(
        "deform full",
        time(runs, || bound.deform(act, &mut full).expect("deforms")),
    );
    let mut grid = CellGrid::default();
    let mut renderer = Renderer::new(mesh);
    for style in [Style::Lines, Style::Shaded] {
        let scene = Scene::new(mesh, &full)
            .with_rest(&mesh.positions)
            .with_framing(framing);
        report(
            &format!("frame {COLS}x{ROWS} {style}, full mesh, drawn only"),
            time(runs, || {
                renderer.render(&scene, &camera, style, &mut canvas);
                grid.fill(&canvas, mode, ColorMode::TrueColor);
            }),
        );
    }
    let Some(level) = level else {
        eprintln!("  no level of detail at this size: the full mesh is drawn");
        return;
    };
    let mut positions = Vec::new();
    let start = Instant::now();
    let sampler = bound.sampler(&level.source).expect("level vertices");
    eprintln!(
        "  sampler for the level: {:.1} ms ({} vertices read)",
        start.elapsed().as_secs_f64() * 1e3,
        sampler.reads()
    );
    report(
        &format!("deform the level ({} vertices)", level.source.len()),
        time(runs, || {
            bound
                .deform_sampled(act, &sampler, &mut positions)
                .expect("deforms")
        }),
    );
    for other in lod.levels() {
        let mut renderer = Renderer::new(&other.mesh);
        let mut scene = Scene::new(&other.mesh, &other.mesh.positions);
        scene.focus = Some(&other.frame);
        report(
            &format!(
                "frame {COLS}x{ROWS} shaded, the {}-vertex level at rest",
                other.source.len()
            ),
            time(runs, || {
                renderer.render(&scene, &camera, Style::Shaded, &mut canvas);
                grid.fill(&canvas, mode, ColorMode::TrueColor);
            }),
        );
    }
    let mut renderer = Renderer::new(&level.mesh);
    for style in [Style::Lines, Style::Shaded] {
        report(
            &format!("frame {COLS}x{ROWS} {style}, level, drawn only"),
            time(runs, || {
                let mut scene =
                    Scene::new(&level.mesh, &positions).with_rest(&level.mesh.positions);
                scene.focus = Some(&level.frame);
                renderer.render(&scene, &camera, style, &mut canvas);
                grid.fill(&canvas, mode, ColorMode::TrueColor);
            }),
        );
        report(
            &format!("key press {COLS}x{ROWS} {style}: deform the level + draw"),
            time(runs, || {
                bound
                    .deform_sampled(act, &sampler, &mut positions)
                    .expect("deforms");
                let mut scene =
                    Scene::new(&level.mesh, &positions).with_rest(&level.mesh.positions);
                scene.focus = Some(&level.frame);
                renderer.render(&scene, &camera, style, &mut canvas);
                grid.fill(&canvas, mode, ColorMode::TrueColor);
            }),
        );
    }
}

fn main() {
    if std::env::args().any(|a| a == "--list") {
        return;
    }
    let splits: Vec<u32> = std::env::var("GRIMACE_HEADS")
        .ok()
        .map(|s| s.split(',').filter_map(|k| k.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![3, 10]);
    let runs = std::env::var("GRIMACE_BENCH_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(30);
    // The editor's binds go through the user's bind cache: a folder of this run's own, so
    // the first start is measured cold (bound and written) and the second warm (read).
    let cache = tempfile::tempdir().expect("temporary folder");
    std::env::set_var("GRIMACE_CACHE_DIR", cache.path());
    if let Ok(dir) = std::env::var("GRIMACE_HEADS_OUT") {
        for k in splits {
            write_head(k, std::path::Path::new(&dir));
        }
        return;
    }
    for k in splits {
        head(k, runs);
    }
}
