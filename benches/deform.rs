//! Benchmarks of the deformation against a naive baseline.
//!
//! The face is the classic Waters face from `../shared/golden` (or `$GRIMACE_SHARED/golden`);
//! without it the benchmark prints why and measures nothing. Sizes: the classic face with its
//! 18 linear muscles at 1.0, then the same face subdivided 1-to-4 to about 28k, 113k and 450k
//! vertices with every muscle kind active (2 sheets, 3 sphincters and a jaw placed here for
//! this geometry). The naive baseline visits every vertex for every muscle and recomputes the
//! muscle's geometry each time, as the classic program does.
//!
//! Run: `GRIMACE_SHARED=/work/shared cargo bench --bench deform`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use grimace::model::field::muscle_displacement;
use grimace::model::{
    Activations, BoundRig, Combine, Convergence, Frame, Jaw, Linear, Mesh, Muscle, MuscleKind, Rig,
    Sheet, Side, SkinRules, Sphincter, RIG_VERSION,
};

fn golden_dir() -> PathBuf {
    std::env::var_os("GRIMACE_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"))
        .join("golden")
}

fn rows(path: &Path) -> Option<Vec<Vec<String>>> {
    let text = std::fs::read_to_string(path).ok()?;
    Some(
        text.lines()
            .skip(1)
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split(',').map(|s| s.trim().to_string()).collect())
            .collect(),
    )
}

fn num(s: &str) -> f32 {
    s.parse().unwrap_or(f32::NAN)
}

fn vec3(r: &[String], at: usize) -> Vec3 {
    Vec3::new(num(&r[at]), num(&r[at + 1]), num(&r[at + 2]))
}

/// The classic face and its 18 linear muscles, or `None` when the data is missing.
fn classic() -> Option<(Mesh, Vec<Muscle>)> {
    let dir = golden_dir();
    let positions = rows(&dir.join("waters-vertices.csv"))?
        .iter()
        .map(|r| vec3(r, 1))
        .collect();
    let triangles = rows(&dir.join("waters-triangles.csv"))?
        .iter()
        .map(|r| [1, 2, 3].map(|i| r[i].parse().unwrap_or(u32::MAX)))
        .collect();
    let mesh = Mesh::new(positions, triangles).ok()?;
    let muscles = rows(&dir.join("waters-muscles.csv"))?
        .iter()
        .map(|r| Muscle {
            name: r[1].clone(),
            side: Side::Centre,
            mirror: None,
            kind: MuscleKind::Linear(Linear {
                insertion: vec3(r, 2),
                attachment: vec3(r, 5),
                falloff_start: num(&r[8]),
                falloff_end: num(&r[9]),
                zone: num(&r[10]),
            }),
        })
        .collect();
    Some((mesh, muscles))
}

/// One level of 1-to-4 midpoint subdivision (each edge gets one shared midpoint).
fn subdivide(mesh: &Mesh) -> Mesh {
    let mut positions = mesh.positions.clone();
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
        let key = (a.min(b), a.max(b));
        *midpoints.entry(key).or_insert_with(|| {
            positions.push((positions[a as usize] + positions[b as usize]) * 0.5);
            (positions.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(mesh.triangles.len() * 4);
    for &[a, b, c] in &mesh.triangles {
        let ab = midpoint(a, b, &mut positions);
        let bc = midpoint(b, c, &mut positions);
        let ca = midpoint(c, a, &mut positions);
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Mesh::new(positions, triangles).expect("subdivision keeps the mesh valid")
}

/// Sheets, sphincters and a jaw placed for the classic face's geometry (x across, y up,
/// z toward the viewer; the face spans y -8.7..7.5, the mouth corners sit near x = +-1.57,
/// y = -2.22, the brows near y = 3.8).
fn extra_muscles() -> Vec<Muscle> {
    let muscle = |name: &str, kind| Muscle {
        name: name.into(),
        side: Side::Centre,
        mirror: None,
        kind,
    };
    let sheet = |sign: f32| Sheet {
        attachment: [
            Vec3::new(sign * 3.2, 6.3, 7.0),
            Vec3::new(sign * 0.5, 6.3, 7.0),
        ],
        insertion: [
            Vec3::new(sign * 3.2, 3.8, 8.0),
            Vec3::new(sign * 0.5, 3.8, 8.0),
        ],
        length: 3.2,
        width: 2.7,
    };
    let eye = |sign: f32| Sphincter {
        centre: Vec3::new(sign * 1.9, 2.3, 8.0),
        semi_major: 1.3,
        semi_minor: 0.7,
        convergence: Convergence::MajorAxis,
        bulge: 30.0,
        frame: Frame::IDENTITY,
    };
    vec![
        muscle("L_Frontalis_Sheet", MuscleKind::Sheet(sheet(-1.0))),
        muscle("R_Frontalis_Sheet", MuscleKind::Sheet(sheet(1.0))),
        muscle(
            "Orbicularis_Oris",
            MuscleKind::Sphincter(Sphincter {
                centre: Vec3::new(0.0, -2.35, 8.9),
                semi_major: 2.0,
                semi_minor: 0.8,
                convergence: Convergence::Centre,
                bulge: 10.0,
                frame: Frame::IDENTITY,
            }),
        ),
        muscle("L_Orbicularis_Oculi", MuscleKind::Sphincter(eye(-1.0))),
        muscle("R_Orbicularis_Oculi", MuscleKind::Sphincter(eye(1.0))),
    ]
}

/// Jaw weights: 1 on the chin's midline, falling to 0 toward the sides and up to the lips.
fn jaw_for(mesh: &Mesh) -> Jaw {
    let weights = mesh
        .positions
        .iter()
        .enumerate()
        .filter_map(|(v, p)| {
            let w = ((-2.6 - p.y) / 1.0).clamp(0.0, 1.0) * (1.0 - p.x.abs() / 3.5).clamp(0.0, 1.0);
            (w > 0.0).then_some((v as u32, w))
        })
        .collect();
    Jaw {
        axis: glam::Vec3::X,
        slide: glam::Vec3::ZERO,
        pivot: Vec3::new(0.0, -0.5, 2.0),
        degrees_per_unit: 1.0,
        weights,
    }
}

fn rig(muscles: Vec<Muscle>, jaw: Option<Jaw>) -> Rig {
    Rig {
        masks: Vec::new(),
        version: RIG_VERSION,
        mesh: PathBuf::from("classic"),
        landmarks: None,
        combine: Combine::Sum,
        muscles,
        jaw,
    }
}

/// The naive loop: every muscle visits every vertex and recomputes its geometry.
fn naive(rest: &[Vec3], rig: &Rig, act: &Activations, out: &mut Vec<Vec3>) {
    out.clear();
    out.extend_from_slice(rest);
    for (muscle, &a) in rig.muscles.iter().zip(&act.muscles) {
        for (p, r) in out.iter_mut().zip(rest) {
            *p += muscle_displacement(black_box(&muscle.kind), *r, a);
        }
    }
    if let Some(jaw) = &rig.jaw {
        let angle = (act.jaw * jaw.degrees_per_unit).to_radians();
        let (sin, cos) = angle.sin_cos();
        for &(v, w) in &jaw.weights {
            let p = out[v as usize];
            let y = p.y - jaw.pivot.y;
            let z = p.z - jaw.pivot.z;
            let ry = jaw.pivot.y + cos * y - sin * z;
            let rz = jaw.pivot.z + sin * y + cos * z;
            out[v as usize] = Vec3::new(p.x, ry * w + p.y * (1.0 - w), rz * w + p.z * (1.0 - w));
        }
    }
}

fn measure(c: &mut Criterion, label: &str, mesh: &Mesh, rig: &Rig, act: &Activations) {
    let start = std::time::Instant::now();
    let paper = BoundRig::bind_with(rig, mesh, SkinRules::PAPER).expect("bench rig binds");
    let bind_paper = start.elapsed().as_secs_f64();
    let start = std::time::Instant::now();
    let bound = BoundRig::bind_with(rig, mesh, SkinRules::DEFAULT).expect("bench rig binds");
    let bind_skin = start.elapsed().as_secs_f64();
    eprintln!(
        "{label}: bind {:.1} ms without the skin rules, {:.1} ms with them ({} guarded triangles)",
        bind_paper * 1e3,
        bind_skin * 1e3,
        bound.guarded_triangles()
    );
    let mut out = Vec::new();
    // the naive baseline computes the paper's equations: compare it with those
    paper.deform(act, &mut out).expect("in range");
    // The two paths agree before anything is timed.
    let mut check = Vec::new();
    naive(&mesh.positions, rig, act, &mut check);
    let worst = out
        .iter()
        .zip(&check)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "{label}: deform and naive differ by {worst}");
    let paper_min = min_time(200, || {
        paper.deform(black_box(act), &mut out).expect("in range")
    });
    let active: usize = (0..bound.muscle_count())
        .filter(|&m| act.muscles[m] != 0.0)
        .map(|m| bound.field(m).map_or(0, |f| f.len()))
        .sum();
    eprintln!(
        "{label}: {} vertices, {} triangles, {} muscles, {} influenced (vertex, muscle) pairs, {} active",
        mesh.positions.len(),
        mesh.triangles.len(),
        bound.muscle_count(),
        bound.pair_count(),
        active
    );
    // Minimum over many runs: robust against other processes on a shared machine.
    let deform_min = min_time(200, || {
        bound.deform(black_box(act), &mut out).expect("in range")
    });
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let single_min = single.install(|| {
        min_time(200, || {
            bound.deform(black_box(act), &mut out).expect("in range")
        })
    });
    let naive_runs = if mesh.positions.len() > 200_000 {
        5
    } else {
        20
    };
    let naive_min = min_time(naive_runs, || {
        naive(&mesh.positions, rig, black_box(act), &mut check)
    });
    eprintln!(
        "{label}: min deform {:.3} us ({:.2} ns per pair; {:.3} us without the skin rules), on \
         one thread {:.3} us ({:.2} ns per pair), min naive {:.3} us, ratio {:.0}x ({:.0}x on \
         one thread)",
        deform_min * 1e6,
        deform_min * 1e9 / bound.pair_count() as f64,
        paper_min * 1e6,
        single_min * 1e6,
        single_min * 1e9 / bound.pair_count() as f64,
        naive_min * 1e6,
        naive_min / deform_min,
        naive_min / single_min
    );
    let tissue = (mesh.positions.len() < 200_000).then(|| spread(label, mesh, rig, act, &bound));
    let mut group = c.benchmark_group(label);
    group.bench_function("deform", |b| {
        b.iter(|| bound.deform(black_box(act), &mut out).expect("in range"))
    });
    if let Some(tissue) = &tissue {
        group.bench_function("deform_spread", |b| {
            b.iter(|| tissue.deform(black_box(act), &mut out).expect("in range"))
        });
    }
    group.bench_function("deform_paper", |b| {
        b.iter(|| paper.deform(black_box(act), &mut out).expect("in range"))
    });
    group.bench_function("deform_1_thread", |b| {
        single.install(|| b.iter(|| bound.deform(black_box(act), &mut out).expect("in range")))
    });
    let m = 0;
    group.bench_function("update_muscle_0", |b| {
        b.iter(|| {
            bound
                .update_muscle(black_box(act), m, &mut out)
                .expect("in range")
        })
    });
    group.bench_function("naive", |b| {
        b.iter(|| naive(&mesh.positions, rig, black_box(act), &mut check))
    });
    group.finish();
}

/// Binds `rig` with the skin spread ([`SkinRules::TISSUE`]) and prints its bind time, its pairs
/// and its deformation's minimum against the same rig without the spread (`without`).
fn spread(label: &str, mesh: &Mesh, rig: &Rig, act: &Activations, without: &BoundRig) -> BoundRig {
    let start = std::time::Instant::now();
    let tissue = BoundRig::bind_with(rig, mesh, SkinRules::TISSUE).expect("bench rig binds");
    let bind = start.elapsed().as_secs_f64();
    let mut out = Vec::new();
    let with_min = min_time(200, || {
        tissue.deform(black_box(act), &mut out).expect("in range")
    });
    let without_min = min_time(200, || {
        without.deform(black_box(act), &mut out).expect("in range")
    });
    eprintln!(
        "{label}: with the spread: bind {:.1} ms, {} pairs ({} without), min deform {:.3} us \
         ({:.3} us without)",
        bind * 1e3,
        tissue.pair_count(),
        without.pair_count(),
        with_min * 1e6,
        without_min * 1e6
    );
    tissue
}

/// The shortest of `runs` timed calls, in seconds.
fn min_time(runs: usize, mut f: impl FnMut()) -> f64 {
    f();
    (0..runs)
        .map(|_| {
            let start = std::time::Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The default face deformed to "happiness", with and without the skin rules (the editor's
/// case; needs no shared data).
fn default_face(c: &mut Criterion) {
    use grimace::io::builtin;
    let (mesh, rig, table) = (
        builtin::default_mesh(),
        builtin::default_rig(),
        builtin::default_table(),
    );
    let act = table
        .expression_activations("happiness", &rig)
        .expect("happiness evaluates");
    let skin = BoundRig::bind_with(&rig, &mesh, SkinRules::DEFAULT).expect("binds");
    let paper = BoundRig::bind_with(&rig, &mesh, SkinRules::PAPER).expect("binds");
    let tissue = spread("default_face", &mesh, &rig, &act, &skin);
    let mut out = Vec::new();
    let m = rig.muscle_index("L_Zygomatic_Major").expect("zygomatic");
    let mut group = c.benchmark_group("default_face");
    group.bench_function("deform", |b| {
        b.iter(|| skin.deform(black_box(&act), &mut out).expect("in range"))
    });
    group.bench_function("deform_paper", |b| {
        b.iter(|| paper.deform(black_box(&act), &mut out).expect("in range"))
    });
    group.bench_function("deform_spread", |b| {
        b.iter(|| tissue.deform(black_box(&act), &mut out).expect("in range"))
    });
    skin.deform(&act, &mut out).expect("in range");
    group.bench_function("update_muscle_zygomatic", |b| {
        b.iter(|| {
            skin.update_muscle(black_box(&act), m, &mut out)
                .expect("in range")
        })
    });
    paper.deform(&act, &mut out).expect("in range");
    group.bench_function("update_muscle_zygomatic_paper", |b| {
        b.iter(|| {
            paper
                .update_muscle(black_box(&act), m, &mut out)
                .expect("in range")
        })
    });
    group.finish();
}

fn benches(c: &mut Criterion) {
    default_face(c);
    let Some((face, linear)) = classic() else {
        eprintln!(
            "skipping the deform benchmark: classic face not found in {} (set GRIMACE_SHARED)",
            golden_dir().display()
        );
        return;
    };
    let classic_rig = rig(linear.clone(), None);
    let act = Activations {
        muscles: vec![1.0; linear.len()],
        jaw: 0.0,
    };
    measure(c, "classic_478", &face, &classic_rig, &act);

    let mut muscles = linear;
    muscles.extend(extra_muscles());
    let mut act = Activations {
        muscles: vec![1.0; 18],
        jaw: 2.0,
    };
    act.muscles.extend([0.4, 0.4, 0.3, 0.4, 0.4]);
    let mut mesh = face;
    for _ in 0..3 {
        mesh = subdivide(&mesh);
    }
    let head_rig = rig(muscles.clone(), Some(jaw_for(&mesh)));
    measure(c, "subdivided_28k", &mesh, &head_rig, &act);
    mesh = subdivide(&mesh);
    let big_rig = rig(muscles.clone(), Some(jaw_for(&mesh)));
    measure(c, "subdivided_113k", &mesh, &big_rig, &act);
    let mesh = subdivide(&mesh);
    let big_rig = rig(muscles, Some(jaw_for(&mesh)));
    measure(c, "subdivided_450k", &mesh, &big_rig, &act);
}

criterion_group! {
    name = deform;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(10);
    targets = benches
}
criterion_main!(deform);
