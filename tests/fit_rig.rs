//! Fitting a rig to a face: the round trip on the default face, transport to transformed and
//! warped copies, and the parts of a mesh with eyes and teeth.

use glam::Vec3;
use grimace::fit::{fit_rig, PartOverrides, Template};
use grimace::io::builtin;
use grimace::model::{BoundRig, Mesh, MuscleKind, Rig};

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
    // The only masks are the lip and lid sides: no gains, no still parts.
    for mask in &fitted.rig.masks {
        assert_eq!(mask.gain, 1.0);
        assert!(mask.weights.iter().all(|&(_, w)| w < 1.0));
    }
    BoundRig::bind(&fitted.rig, &mesh).unwrap();
}
