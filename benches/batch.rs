//! `grimace batch` throughput: PNG images per second per core, and where the time goes.
//!
//! Faces: the built-in face (3,995 vertices); MakeHuman's base mesh fitted from its landmarks
//! (19,158 vertices, a whole body framed on its face; read from `../shared/meshes`, or
//! `$GRIMACE_SHARED/meshes`, skipped with a reason when missing); and the built-in face split
//! twice 1-to-4 and fitted (54,913 vertices). A ~26k-vertex head lies between the last two.
//! Every AU of the built-in table at E, shaded, 256x256, from the front: one deformation per
//! image (a plan with several views or styles per state deforms once for all of them).
//!
//! Run: `cargo bench --bench batch`. One thread, timed by its CPU time, so the
//! figures are per core even on a busy machine (shards and `--jobs` run items
//! independently). File writes are not included (see BENCHMARKS.md for
//! the end-to-end run).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::Vec3;
use grimace::batch::items::sha256_hex;
use grimace::batch::{Batch, Face, Plan};
use grimace::fit::{fit_rig, PartOverrides, Template};
use grimace::io::obj::MovedObj;
use grimace::io::{builtin, LoadedRig};
use grimace::landmarks::Landmarks;
use grimace::model::{BoundRig, Mesh, Rig};
use grimace::render::{png, svg, Camera, DotCanvas, Framing, Scene, Style};

const PLAN: &str = r#"(
    version: 1,
    faces: [(name: "face", rig: "builtin:default")],
    show: [AllAus],
    intensities: ["E"],
    size: (256, 256),
    outputs: [Png],
)"#;

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

/// The default rig fitted to a mesh from its landmarks.
fn fitted(mesh: &Mesh, landmarks: &Landmarks) -> Rig {
    let face = builtin::default_mesh();
    let rig = builtin::default_rig();
    let points = builtin::landmarks("face")
        .unwrap()
        .positions(&face)
        .unwrap();
    let template = Template {
        rig: &rig,
        mesh: &face,
        landmarks: &points,
    };
    fit_rig(
        template,
        mesh,
        landmarks,
        "head.obj".into(),
        &PartOverrides::default(),
    )
    .expect("fits")
    .rig
}

fn face(rig: Rig, mesh: Mesh) -> Face {
    let bound = BoundRig::bind(&rig, &mesh).expect("binds");
    Face {
        framing: Framing::of_rig(&rig, &mesh),
        bound,
        table: builtin::default_table(),
        rig: LoadedRig::new(rig, mesh, PathBuf::from("bench"), None),
        metres_per_unit: 0.001,
        obj: MovedObj::default(),
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// This thread's time on a CPU so far, in seconds (`CLOCK_THREAD_CPUTIME_ID`), so a machine
/// shared with other work still gives the cost per core; `None` where it cannot be read.
fn cpu_seconds() -> Option<f64> {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec into the struct passed.
    let ok = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0;
    ok.then_some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
}

/// Milliseconds of CPU (wall clock where CPU time cannot be read) per call of `f` over the
/// batch's items (median of 5 passes).
fn per_item(batch: &Batch, mut f: impl FnMut(usize)) -> f64 {
    let n = batch.expanded.items.len();
    let now = || cpu_seconds().unwrap_or_else(|| EPOCH.with(|e| e.elapsed().as_secs_f64()));
    median(
        (0..5)
            .map(|_| {
                let t = now();
                for i in 0..n {
                    f(i);
                }
                (now() - t) * 1e3 / n as f64
            })
            .collect(),
    )
}

thread_local! {
    static EPOCH: Instant = Instant::now();
}

fn measure(name: &str, face: Face) {
    let (vertices, triangles) = (face.rig.mesh.vertex_count(), face.rig.mesh.triangles.len());
    let plan = Plan::parse(Path::new("bench.plan.ron"), PLAN.to_string()).expect("plan");
    let batch = Batch::new(plan, vec![face]).expect("expands");
    let items = &batch.expanded.items;
    let mut renderers = batch.renderers();
    let mut positions = Vec::new();
    let wall = Instant::now();
    let whole = per_item(&batch, |i| {
        let item = &items[i];
        batch.deform(item.face, item.state, &mut positions).unwrap();
        let bytes = batch.draw(item, &positions, &mut renderers[0]).unwrap();
        black_box(sha256_hex(&bytes));
    });
    let wall = wall.elapsed().as_secs_f64() * 1e3 / (5 * items.len()) as f64;
    let deform = per_item(&batch, |i| {
        let item = &items[i];
        batch.deform(item.face, item.state, &mut positions).unwrap();
        black_box(&positions);
    });
    // Drawing alone, and encoding alone, on the last state's positions.
    let f = &batch.faces[0];
    let mesh = &f.rig.mesh;
    let camera = Camera {
        basis: f.framing.basis,
        ..Camera::front()
    };
    let mut canvas = DotCanvas::new(256, 256);
    canvas.dither = false;
    let draw = per_item(&batch, |_| {
        let scene = Scene::new(mesh, &positions)
            .with_rest(&mesh.positions)
            .with_framing(&f.framing);
        renderers[0].render(&scene, &camera, Style::Shaded, &mut canvas);
        black_box(&canvas);
    });
    let mut size = 0;
    let encode = per_item(&batch, |_| {
        let bytes = png::canvas_to_png(&canvas, 1, svg::BACKGROUND).unwrap();
        size = bytes.len();
        black_box(bytes);
    });
    // The same pixels as an RGB buffer through the png crate, at its default and fast settings.
    let rgb: Vec<u8> = (0..256 * 256)
        .flat_map(|i| {
            let c = canvas.color(i % 256, i / 256).unwrap_or(svg::BACKGROUND);
            [c.0, c.1, c.2]
        })
        .collect();
    let mut sizes = [0; 2];
    let mut encoded = [0.0; 2];
    for (k, compression) in [::png::Compression::Default, ::png::Compression::Fast]
        .into_iter()
        .enumerate()
    {
        encoded[k] = per_item(&batch, |_| {
            let mut out = Vec::new();
            let mut encoder = ::png::Encoder::new(&mut out, 256, 256);
            encoder.set_color(::png::ColorType::Rgb);
            encoder.set_depth(::png::BitDepth::Eight);
            encoder.set_compression(compression);
            let mut writer = encoder.write_header().unwrap();
            writer.write_image_data(&rgb).unwrap();
            writer.finish().unwrap();
            sizes[k] = out.len();
            black_box(out);
        });
    }
    let hash = per_item(&batch, |_| {
        black_box(sha256_hex(&vec![0u8; size]));
    });
    eprintln!(
        "{name}: {vertices} vertices, {triangles} triangles: {:.0} PNG images/s per core ({whole:.3} ms of CPU each, {wall:.3} ms wall clock: deform {deform:.3}, draw {draw:.3}, encode {encode:.3} for {size} bytes; of an RGB buffer alone: {:.3} ms, {} bytes, at the fast setting {:.3} ms, {} bytes; sha256 {hash:.3})",
        1e3 / whole,
        encoded[0],
        sizes[0],
        encoded[1],
        sizes[1]
    );
}

fn shared_meshes() -> Option<PathBuf> {
    let root = std::env::var_os("GRIMACE_SHARED").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared"),
        PathBuf::from,
    );
    let dir = root.join("meshes");
    if dir.join("makehuman_base.obj").is_file() {
        Some(dir)
    } else {
        eprintln!(
            "makehuman: skipped, {} not found (set GRIMACE_SHARED)",
            dir.join("makehuman_base.obj").display()
        );
        None
    }
}

fn batch_bench(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| {
        measure(
            "built-in face",
            face(builtin::default_rig(), builtin::default_mesh()),
        );
        if let Some(dir) = shared_meshes() {
            let mesh = grimace::io::obj::read_obj(&dir.join("makehuman_base.obj")).unwrap();
            let landmarks = grimace::io::landmarks::load_landmarks(
                &Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("tests/fit_data/makehuman_base.landmarks.ron"),
            )
            .unwrap();
            let rig = fitted(&mesh, &landmarks);
            measure("MakeHuman base, fitted", face(rig, mesh));
        }
        let head = split(&split(&builtin::default_mesh()));
        let landmarks = builtin::landmarks("face").unwrap();
        let rig = fitted(&head, &landmarks);
        measure("built-in face split twice, fitted", face(rig, head));
    });
    let plan = Plan::parse(Path::new("bench.plan.ron"), PLAN.to_string()).unwrap();
    let batch = Batch::new(
        plan,
        vec![face(builtin::default_rig(), builtin::default_mesh())],
    )
    .unwrap();
    let item = batch.expanded.items[0].clone();
    let mut renderers = batch.renderers();
    let mut positions = Vec::new();
    c.bench_function("batch_item_png_256", |b| {
        b.iter(|| {
            batch.deform(item.face, item.state, &mut positions).unwrap();
            black_box(batch.draw(&item, &positions, &mut renderers[0]).unwrap())
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = batch_bench
}
criterion_main!(benches);
