//! Fitting a rig to a face: the round trip on the default face, transport to transformed and
//! warped copies, and the parts of a mesh with eyes and teeth.

use glam::{Quat, Vec3};
use grimace::fit::{fit_rig, PartOverrides, Template};
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig, Mesh, MuscleKind, Rig};

fn default_template() -> (Rig, Mesh, Vec<Vec3>) {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let points = builtin::landmarks("face")
        .unwrap()
        .positions(&mesh)
        .unwrap();
    (rig, mesh, points)
}

fn close(a: Vec3, b: Vec3, tol: f32, what: &str) {
    assert!(a.distance(b) <= tol, "{what}: {a} vs {b}");
}

fn closef(a: f32, b: f32, tol: f32, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
}

/// Every muscle parameter and the jaw of `a` equal those of `b` within `tol`.
fn same_rig(a: &Rig, b: &Rig, tol: f32) {
    assert_eq!(a.muscles.len(), b.muscles.len());
    for (m, n) in a.muscles.iter().zip(&b.muscles) {
        assert_eq!(m.name, n.name);
        assert_eq!(m.side, n.side);
        assert_eq!(m.mirror, n.mirror);
        let what = m.name.as_str();
        match (&m.kind, &n.kind) {
            (MuscleKind::Linear(x), MuscleKind::Linear(y)) => {
                close(x.attachment, y.attachment, tol, what);
                close(x.insertion, y.insertion, tol, what);
                closef(x.zone, y.zone, tol, what);
                closef(x.falloff_start, y.falloff_start, tol, what);
                closef(x.falloff_end, y.falloff_end, tol, what);
            }
            (MuscleKind::Sheet(x), MuscleKind::Sheet(y)) => {
                for k in 0..2 {
                    close(x.attachment[k], y.attachment[k], tol, what);
                    close(x.insertion[k], y.insertion[k], tol, what);
                }
                closef(x.length, y.length, tol, what);
                closef(x.width, y.width, tol, what);
            }
            (MuscleKind::Sphincter(x), MuscleKind::Sphincter(y)) => {
                close(x.centre, y.centre, tol, what);
                closef(x.semi_major, y.semi_major, tol, what);
                closef(x.semi_minor, y.semi_minor, tol, what);
                closef(x.bulge, y.bulge, tol, what);
                assert_eq!(x.convergence, y.convergence);
            }
            _ => panic!("{what}: kinds differ"),
        }
    }
    let (ja, jb) = (a.jaw.as_ref().unwrap(), b.jaw.as_ref().unwrap());
    close(ja.pivot, jb.pivot, tol, "jaw pivot");
    close(ja.axis, jb.axis, tol, "jaw axis");
    closef(ja.degrees_per_unit, jb.degrees_per_unit, tol, "jaw degrees");
    assert_eq!(ja.weights.len(), jb.weights.len(), "jaw weight count");
    for (x, y) in ja.weights.iter().zip(&jb.weights) {
        assert_eq!(x.0, y.0);
        closef(x.1, y.1, tol, "jaw weight");
    }
}

#[test]
fn the_default_landmarks_follow_the_face_and_its_rig() {
    let (rig, _, points) = default_template();
    let centre = |name: &str| match &rig.muscles[rig.muscle_index(name).unwrap()].kind {
        MuscleKind::Sphincter(s) => s.centre,
        _ => panic!("{name} is not a sphincter"),
    };
    // The subject's right eye (36-41) is the R_ eye sphincter's, the left (42-47) the L_'s.
    let eye = |ids: std::ops::Range<usize>| ids.map(|i| points[i]).sum::<Vec3>() / 6.0;
    let (right, left) = (eye(36..42), eye(42..48));
    assert!(
        right.distance(centre("R_Orbicularis_Oculi"))
            < right.distance(centre("L_Orbicularis_Oculi"))
    );
    assert!(
        left.distance(centre("L_Orbicularis_Oculi")) < left.distance(centre("R_Orbicularis_Oculi"))
    );
    // Mirror partners are mirror images; the chin is the lowest point, the nose tip the
    // most forward.
    for i in 0..68 {
        let (p, q) = (points[i], points[grimace::landmarks::mirror(i)]);
        assert!(
            (p.x + q.x).abs() < 1e-3 && (p.y - q.y).abs() < 1e-3,
            "landmark {i}"
        );
    }
    assert!(points.iter().all(|p| p.y >= points[8].y));
    assert!(points.iter().all(|p| p.z <= points[30].z));
}

#[test]
fn the_default_rig_fits_back_onto_its_own_face() {
    let (rig, mesh, points) = default_template();
    let template = Template {
        rig: &rig,
        mesh: &mesh,
        landmarks: &points,
    };
    let landmarks = builtin::landmarks("face").unwrap();
    let fitted = fit_rig(
        template,
        &mesh,
        &landmarks,
        "builtin:face".into(),
        &PartOverrides::default(),
    )
    .unwrap();
    same_rig(&fitted.rig, &rig, 1e-4);
    assert!((fitted.scale - 1.0).abs() < 1e-6);
    // The only masks are the lip and lid sides and the template's own gains: no still parts.
    for mask in &fitted.rig.masks {
        if mask.weights.is_empty() {
            let template_gain: f32 = rig
                .masks
                .iter()
                .filter(|m| mask.muscles.iter().all(|n| m.muscles.contains(n)))
                .map(|m| m.gain)
                .product();
            assert!(
                (mask.gain - template_gain).abs() < 1e-6,
                "{:?}",
                mask.muscles
            );
        } else {
            assert_eq!(mask.gain, 1.0);
            assert!(mask.weights.iter().all(|&(_, w)| w < 1.0));
        }
    }
    BoundRig::bind(&fitted.rig, &mesh).unwrap();
}

/// A similarity after a mild smooth bend of the face, with its Jacobian.
struct Transform {
    rotation: Quat,
    scale: f32,
    shift: Vec3,
    bend: f32,
    size: f32,
}

impl Transform {
    fn bent(&self, p: Vec3) -> Vec3 {
        let s = self.size;
        p + self.bend
            * s
            * Vec3::new(
                (p.y / s * 2.0).sin(),
                (p.x / s * 1.5).cos() * 0.5 + (p.z / s).sin() * 0.3,
                (p.x / s * 2.5).sin() * 0.4,
            )
    }

    fn apply(&self, p: Vec3) -> Vec3 {
        self.rotation * self.bent(p) * self.scale + self.shift
    }

    /// A displacement at `p` on the transformed face, mapped back to the original's frame.
    fn back(&self, p: Vec3, d: Vec3) -> Vec3 {
        let h = 1e-3 * self.size;
        let col = |e: Vec3| (self.bent(p + e * h) - self.bent(p - e * h)) / (2.0 * h);
        let j = glam::Mat3::from_cols(col(Vec3::X), col(Vec3::Y), col(Vec3::Z));
        j.inverse() * (self.rotation.inverse() * d / self.scale)
    }
}

fn fitted_default(mesh: &Mesh) -> Rig {
    let (rig, template_mesh, points) = default_template();
    let template = Template {
        rig: &rig,
        mesh: &template_mesh,
        landmarks: &points,
    };
    fit_rig(
        template,
        mesh,
        &builtin::landmarks("face").unwrap(),
        "moved.obj".into(),
        &PartOverrides::default(),
    )
    .unwrap()
    .rig
}

/// The displacement of every vertex for each AU of the default table.
fn au_fields(rig: &Rig, mesh: &Mesh) -> Vec<(String, Vec<Vec3>)> {
    let bound = BoundRig::bind(rig, mesh).unwrap();
    let table = builtin::default_table();
    let mut out = Vec::new();
    let mut moved = Vec::new();
    for key in table.aus.keys() {
        let act: Activations = table.entry_activations(key, rig).unwrap();
        bound.deform(&act, &mut moved).unwrap();
        let d = moved
            .iter()
            .zip(&mesh.positions)
            .map(|(a, b)| *a - *b)
            .collect();
        out.push((key.to_string(), d));
    }
    out
}

fn cosine(a: &[Vec3], b: &[Vec3]) -> f64 {
    let dot: f64 = a.iter().zip(b).map(|(x, y)| f64::from(x.dot(*y))).sum();
    let na: f64 = a.iter().map(|x| f64::from(x.length_squared())).sum();
    let nb: f64 = b.iter().map(|x| f64::from(x.length_squared())).sum();
    dot / (na.sqrt() * nb.sqrt()).max(1e-300)
}

#[test]
fn au_fields_survive_similarities_and_a_mild_bend() {
    let mesh = builtin::default_mesh();
    let (lo, hi) = mesh.bounds();
    let size = (hi - lo).max_element();
    let reference = au_fields(&fitted_default(&mesh), &mesh);
    let cases = [
        // z up, millimetres (the face is in units of 11.5 mm)
        Transform {
            rotation: Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
            scale: 11.5,
            shift: Vec3::new(0.0, 0.0, 1700.0),
            bend: 0.03,
            size,
        },
        Transform {
            rotation: Quat::from_euler(glam::EulerRot::XYZ, 0.4, -2.2, 1.1),
            scale: 0.37,
            shift: Vec3::new(-3.0, 8.0, 0.5),
            bend: 0.03,
            size,
        },
        Transform {
            rotation: Quat::from_euler(glam::EulerRot::ZYX, 2.9, 0.3, -0.8),
            scale: 100.0,
            shift: Vec3::new(250.0, -40.0, 1e3),
            bend: 0.02,
            size,
        },
        Transform {
            rotation: Quat::IDENTITY,
            scale: 25.4,
            shift: Vec3::new(-7.0, 300.0, 12.0),
            bend: 0.03,
            size,
        },
    ];
    // Every AU, sphincter ones (18, 23, 24, 43/45, 6, 7) included: a fitted sphincter gets
    // the frame of the face it is placed on.
    let table = builtin::default_table();
    let rig = builtin::default_rig();
    let uses_sphincter = |key: &str| {
        table.aus[&key.parse().unwrap()].muscles.keys().any(|name| {
            matches!(
                rig.muscles[rig.muscle_index(name).unwrap()].kind,
                MuscleKind::Sphincter(_)
            )
        })
    };
    let mut failures = Vec::new();
    let mut sphincter_aus = 0;
    for (n, t) in cases.iter().enumerate() {
        let mut moved = mesh.clone();
        moved.positions = mesh.positions.iter().map(|p| t.apply(*p)).collect();
        let rig = fitted_default(&moved);
        let fields = au_fields(&rig, &moved);
        let mut lowest = (f64::INFINITY, String::new());
        for ((key, want), (_, got)) in reference.iter().zip(&fields) {
            let back: Vec<Vec3> = got
                .iter()
                .zip(&mesh.positions)
                .map(|(d, p)| t.back(*p, *d))
                .collect();
            let c = cosine(want, &back);
            if uses_sphincter(key) {
                sphincter_aus += 1;
                if c < lowest.0 {
                    lowest = (c, key.clone());
                }
            }
            if c < 0.95 {
                failures.push(format!("case {n}, AU {key}: cosine {c:.4}"));
            }
        }
        println!(
            "case {n}: lowest cosine of a sphincter AU {:.4} (AU {})",
            lowest.0, lowest.1
        );
    }
    // 18, 23, 24, 43, 45, 6 and 7 at least, in each of the four cases.
    assert!(sphincter_aus >= 4 * 7, "{sphincter_aus} sphincter AUs");
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Fitting the default rig to the default face itself (scale 1, no bend) gives every AU of
/// the default table back: the template's per-vertex masks are carried with the rig.
#[test]
fn the_identity_fit_gives_every_au_back() {
    let mesh = builtin::default_mesh();
    let want = au_fields(&builtin::default_rig(), &mesh);
    let got = au_fields(&fitted_default(&mesh), &mesh);
    let mut wrong = Vec::new();
    let mut worst = 0.0f32;
    for ((key, a), (_, b)) in want.iter().zip(&got) {
        let err = a
            .iter()
            .zip(b)
            .map(|(x, y)| x.distance(*y))
            .fold(0.0f32, f32::max);
        worst = worst.max(err);
        if err > 1e-4 {
            wrong.push(format!("AU {key}: {err:.4}"));
        }
    }
    println!(
        "identity fit: {} of {} AUs differ, largest difference {worst:.2e}",
        wrong.len(),
        want.len()
    );
    assert!(wrong.is_empty(), "{wrong:#?}");
}
