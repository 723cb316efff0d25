use glam::{DVec3, Vec3};
use grimace::capture::{pose, FrameSolver, LandmarkModel, Regularisation};
use grimace::io::openface::{OpenFaceReader, RowOutcome};
use grimace::model::Deformation;
use std::io::BufReader;
use std::path::Path;

fn main() {
    let path = std::env::args().nth(1).unwrap();
    let f = std::fs::File::open(&path).unwrap();
    let mut r = OpenFaceReader::with_landmarks(BufReader::new(f), Path::new(&path)).unwrap();
    let mut frames: Vec<Vec<Vec3>> = Vec::new();
    while let Some(o) = r.next_row().unwrap() {
        if let RowOutcome::Row(row) = o {
            if row.success {
                frames.push(row.landmarks);
            }
        }
    }
    let mesh = grimace::io::builtin::default_mesh();
    let rig = grimace::io::builtin::default_rig();
    let bound = Deformation::default().bind(&rig, &mesh).unwrap();
    let lm = grimace::io::builtin::landmarks("default")
        .unwrap()
        .vertices(&mesh);
    let model = LandmarkModel::new(&bound, &lm);
    let refs: Vec<&[Vec3]> = frames.iter().map(|f| f.as_slice()).collect();
    let (neutral, _) = pose::estimate_neutral(&refs).unwrap();
    let to_rig = pose::ToRig::new(&neutral, model.rest()).unwrap();
    println!("scale {}", to_rig.scale);
    println!(
        "rig 0 {:?} 16 {:?} 30 {:?}",
        model.rest()[0],
        model.rest()[16],
        model.rest()[30]
    );
    println!(
        "subj 0 {:?} 16 {:?} 30 {:?} 8 {:?}",
        neutral[0], neutral[16], neutral[30], neutral[8]
    );
    let from: Vec<Vec3> = neutral.iter().map(|p| p.as_vec3()).collect();
    let to: Vec<Vec3> = model.rest().iter().map(|p| p.as_vec3()).collect();
    let w = grimace::fit::Warp::fit(&from, &to).unwrap();
    println!("bend {}", w.bend(&to));
    for i in [8usize, 19, 24, 48, 54, 62, 66, 37, 41] {
        let j = w.jacobian(neutral[i]);
        println!(
            "jac {i} det^(1/3) {:.4} cols {:?}",
            j.determinant().cbrt(),
            j
        );
    }
    let mut solver = FrameSolver::new(&bound, &model, Regularisation::default());
    let mut axis_m = [DVec3::ZERO; 6];
    let mut axis_r = [DVec3::ZERO; 6];
    let mut motion_sum = vec![0.0; 68];
    let mut res_sum = vec![0.0; 68];
    let mut out = Vec::new();
    for f in &frames {
        let a = pose::align(f, &neutral).unwrap();
        let m = to_rig.motion(&a.points, &neutral);
        let s = solver.solve(&m);
        let d = model.displacement(&bound, &s.activations, &mut out);
        for (gi, g) in [
            (0usize, 0..17),
            (1, 17..27),
            (2, 27..36),
            (3, 36..48),
            (4, 48..60),
            (5, 60..68),
        ] {
            for i in g {
                axis_m[gi] += m[i] * m[i];
                axis_r[gi] += (m[i] - d[i]) * (m[i] - d[i]);
            }
        }
        for i in 0..68 {
            motion_sum[i] += m[i].length_squared();
            res_sum[i] += (m[i] - d[i]).length_squared();
        }
    }
    let groups = [
        ("jaw", 0..17),
        ("brows", 17..27),
        ("nose", 27..36),
        ("eyes", 36..48),
        ("outer lip", 48..60),
        ("inner lip", 60..68),
    ];
    for (n, g) in groups {
        let ms: f64 = motion_sum[g.clone()].iter().sum();
        let rs: f64 = res_sum[g].iter().sum();
        println!("{n}: motion {ms:.1} res {rs:.1}");
    }
    for g in 0..6 {
        println!("group {g} motion xyz {:?} res {:?}", axis_m[g], axis_r[g]);
    }
}
