//! The skin stays on the face (`docs/model.md`, "Keeping the skin on the face"): displaced
//! skin slides along the rest surface instead of sinking behind it, and no triangle
//! collapses. Measured on the default face against the paper's deformation.

use glam::Vec3;
use grimace::model::{Activations, BoundRig, SkinRules};

use super::au_shapes::{face, Face, MM};

/// Closest point to `q` on the triangle `abc` (Ericson, Real-Time Collision Detection 5.1.5).
fn closest_on_triangle(q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, q - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = q - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = q - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

impl Face {
    /// How far (mm) vertex `v` of `pose` lies behind the rest surface: its distance to the
    /// nearest rest triangle when it is on the inner side of it, else 0.
    fn sink(&self, pose: &[Vec3], v: usize) -> f32 {
        let rest = &self.mesh.positions;
        let q = pose[v];
        let (mut best, mut inside) = (f32::INFINITY, false);
        for t in &self.mesh.triangles {
            let [a, b, c] = t.map(|i| rest[i as usize]);
            let p = closest_on_triangle(q, a, b, c);
            let d = (q - p).length();
            if d < best {
                best = d;
                // the default face's triangles wind counter-clockwise seen from outside
                inside = (q - p).dot((b - a).cross(c - a)) < 0.0;
            }
        }
        if inside {
            best * MM
        } else {
            0.0
        }
    }

    /// The smallest ratio of a triangle's area (projected on its rest normal) to its rest
    /// area, over the face.
    fn smallest_area(&self, pose: &[Vec3]) -> f32 {
        let rest = &self.mesh.positions;
        self.mesh
            .triangles
            .iter()
            .filter_map(|t| {
                let [a, b, c] = t.map(|i| rest[i as usize]);
                let n = (b - a).cross(c - a);
                let a0 = n.length();
                (a0 > 0.0).then(|| {
                    let [p, q, r] = t.map(|i| pose[i as usize]);
                    (q - p).cross(r - p).dot(n / a0) / a0
                })
            })
            .fold(f32::INFINITY, f32::min)
    }

    fn paper(&self) -> BoundRig {
        BoundRig::bind_with(&self.rig, &self.mesh, SkinRules::PAPER).expect("binds")
    }

    fn combo_with(&self, bound: &BoundRig, text: &str) -> Vec<Vec3> {
        let combo = grimace::facs::combo::parse_combo(text).expect("parses");
        let act = self.table.evaluate(&combo, &self.rig).expect("evaluates");
        let mut out = Vec::new();
        bound.deform(&act, &mut out).expect("in range");
        out
    }

    fn everything(&self) -> Activations {
        let mut all = Activations::zero(&self.rig);
        all.muscles.iter_mut().for_each(|a| *a = 2.0);
        all.jaw = 4.0;
        all
    }
}

/// The left and right mouth corners sink behind the rest surface at AU12, 14 and 20 (mm):
/// the paper's deformation against the skin rules.
#[test]
fn mouth_corners_slide_along_the_face_instead_of_sinking() {
    let f = face();
    let paper = f.paper();
    // (AU, sink with the paper's deformation at least, with the skin rules at most), mm
    for (au, before, after) in [("12", 3.2, 0.5), ("14", 3.3, 1.5), ("20", 4.3, 1.0)] {
        for corner in ["left_mouth_corner", "right_mouth_corner"] {
            let v = f.vertex(corner);
            let was = f.sink(&f.combo_with(&paper, au), v);
            let now = f.sink(&f.combo(au), v);
            println!("AU{au} {corner}: {was:.2} mm behind the rest surface before, {now:.2} now");
            assert!(was >= before, "AU{au} {corner}: the paper's sink {was} mm");
            assert!(
                now <= after,
                "AU{au} {corner}: still {now} mm behind the surface"
            );
        }
        // the corner still travels: the slide keeps the pull along the face
        let p = f.combo(au);
        let moved = f.moved(&p, "left_mouth_corner");
        let was = (f.combo_with(&paper, au)[f.vertex("left_mouth_corner")]
            - f.mesh.positions[f.vertex("left_mouth_corner")])
            * MM;
        let along = |m: Vec3| Vec3::new(m.x, m.y, 0.0).length();
        assert!(
            along(moved) >= 0.9 * along(was),
            "AU{au}: the corner's travel across the face fell from {was} to {moved} mm"
        );
    }
}

/// No AU of the table shrinks a triangle below 12 % of its rest area (projected on its rest
/// normal) or turns one over; with every muscle at 2 and the jaw at 4, fewer triangles turn
/// over than with the paper's deformation.
#[test]
fn triangles_keep_their_area() {
    let f = face();
    let paper = f.paper();
    let (mut worst, mut worst_paper) = (f32::INFINITY, f32::INFINITY);
    for k in f.table.aus.keys() {
        let p = f.combo(&k.to_string());
        let smallest = f.smallest_area(&p);
        assert!(
            smallest >= 0.12,
            "AU{k}: a triangle keeps {smallest} of its area"
        );
        assert_eq!(f.flips(&p), 0, "AU{k} flips triangles");
        worst = worst.min(smallest);
        let before = f.smallest_area(&f.combo_with(&paper, &k.to_string()));
        worst_paper = worst_paper.min(before);
    }
    println!(
        "smallest area kept at any AU: {worst:.3} ({worst_paper:.3} with the paper's deformation)"
    );
    let mut out = Vec::new();
    f.bound.deform(&f.everything(), &mut out).expect("in range");
    let now = f.flips(&out);
    f.paper()
        .deform(&f.everything(), &mut out)
        .expect("in range");
    let before = f.flips(&out);
    println!("every muscle at 2, jaw 4: {now} of {} triangles flip ({before} with the paper's deformation)", f.mesh.triangles.len());
    assert!(
        now < before,
        "{now} flips with the skin rules, {before} without"
    );
}

/// The skin rules keep partial updates bit-identical to a full deformation on the default
/// face (the area bound reads neighbours, so this checks its halos).
#[test]
fn partial_updates_match_a_full_deformation_on_the_default_face() {
    let f = face();
    let mut act = f.everything();
    act.muscles
        .iter_mut()
        .enumerate()
        .for_each(|(i, a)| *a = (i % 5) as f32 * 0.4);
    act.jaw = 1.5;
    let mut out = Vec::new();
    f.bound.deform(&act, &mut out).expect("in range");
    for m in 0..act.muscles.len() {
        act.muscles[m] = 2.0 - act.muscles[m];
        f.bound.update_muscle(&act, m, &mut out).expect("in range");
    }
    act.jaw = 3.5;
    f.bound.update_jaw(&act, &mut out).expect("in range");
    let full = f.deform(&act);
    for (v, (a, b)) in out.iter().zip(&full).enumerate() {
        assert_eq!(
            a.to_array().map(f32::to_bits),
            b.to_array().map(f32::to_bits),
            "vertex {v}"
        );
    }
}
