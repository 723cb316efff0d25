//! The skin spread keeps the deformation's promises (`docs/model.md`, "The skin spread"):
//! zero activation is the rest mesh, a mirrored pose of the symmetric built-in face is the
//! mirrored mesh, a one-muscle update equals a full deform bit for bit, a rebind equals a
//! fresh bind, and the pull reaches past the muscle's own zone but dies out within reach.

use glam::Vec3;
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig, MuscleKind, SkinRules};

fn bound() -> BoundRig {
    let mesh = builtin::default_mesh();
    BoundRig::bind_with(&builtin::default_rig(), &mesh, SkinRules::TISSUE).expect("binds")
}

fn deformed(bound: &BoundRig, act: &Activations) -> Vec<Vec3> {
    let mut out = Vec::new();
    bound.deform(act, &mut out).expect("in range");
    out
}

#[test]
fn zero_activation_is_the_rest_mesh_bit_for_bit() {
    let bound = bound();
    let out = deformed(&bound, &Activations::zero(bound.rig()));
    for (p, r) in out.iter().zip(bound.rest()) {
        assert_eq!(
            p.to_array().map(f32::to_bits),
            r.to_array().map(f32::to_bits)
        );
    }
}

#[test]
fn a_mirrored_pose_gives_the_mirrored_face() {
    let bound = bound();
    let rig = bound.rig();
    let rest = bound.rest();
    // the built-in face is symmetric: each vertex has a partner at (-x, y, z)
    let key = |p: Vec3| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
    let index: std::collections::HashMap<_, usize> =
        rest.iter().enumerate().map(|(i, p)| (key(*p), i)).collect();
    let flip = |p: Vec3| Vec3::new(-p.x, p.y, p.z);
    let partner: Vec<usize> = rest
        .iter()
        .map(|p| {
            index
                .get(&key(flip(*p) + Vec3::ZERO))
                .copied()
                .expect("mirror vertex")
        })
        .collect();
    let mut act = Activations::zero(rig);
    for (m, a) in act.muscles.iter_mut().enumerate() {
        *a = [0.0, 0.4, 1.3, 2.0][m % 4];
    }
    let mut swapped = act.clone();
    for m in 0..rig.muscles.len() {
        swapped.muscles[rig.mirror_of(m).unwrap_or(m)] = act.muscles[m];
    }
    let out = deformed(&bound, &act);
    let mirrored = deformed(&bound, &swapped);
    let worst = (0..out.len())
        .map(|v| (mirrored[v] - flip(out[partner[v]])).abs().max_element())
        .fold(0.0f32, f32::max);
    assert!(worst <= 1e-5, "mirrored pose differs by {worst}");
}

#[test]
fn a_one_muscle_update_equals_a_full_deform() {
    let bound = bound();
    let rig = bound.rig();
    let mut act = Activations::zero(rig);
    act.muscles.iter_mut().for_each(|a| *a = 0.7);
    act.jaw = 1.5;
    let mut out = deformed(&bound, &act);
    for m in 0..rig.muscles.len() {
        act.muscles[m] = 1.9;
        bound.update_muscle(&act, m, &mut out).expect("in range");
        assert_eq!(out, deformed(&bound, &act), "after muscle {m}");
    }
}

#[test]
fn a_rebind_equals_a_fresh_bind() {
    let mesh = builtin::default_mesh();
    let mut rig = builtin::default_rig();
    let mut bound = BoundRig::bind_with(&rig, &mesh, SkinRules::TISSUE).expect("binds");
    // a small move (the spread length stays) and a large one (the rig's box grows)
    for shift in [Vec3::new(0.0, 0.01, 0.0), Vec3::new(0.0, 3.0, 0.0)] {
        let m = rig
            .muscles
            .iter()
            .position(|m| matches!(m.kind, MuscleKind::Linear(_)))
            .expect("a linear muscle");
        let MuscleKind::Linear(mut linear) = rig.muscles[m].kind.clone() else {
            unreachable!()
        };
        linear.attachment += shift;
        linear.insertion += shift;
        rig.muscles[m].kind = MuscleKind::Linear(linear.clone());
        bound
            .rebind_muscle(m, MuscleKind::Linear(linear))
            .expect("rebinds");
        let fresh = BoundRig::bind_with(&rig, &mesh, SkinRules::TISSUE).expect("binds");
        assert!(bound == fresh, "rebind after a shift of {shift}");
    }
}

/// A copy of a vertex in no triangle (a split seam's copy, moved with its lead) changes no
/// spread field: it is not on the surface. (Its empty row in the system once made every
/// field it lay in come out empty: a mesh split at its seams lost those muscles.)
#[test]
fn a_copy_in_no_triangle_changes_no_spread_field() {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let whole = bound();
    let mut split = mesh.clone();
    // a copy of every tenth vertex, appended: each lies in some muscle's zone or none
    let copies: Vec<Vec3> = mesh.positions.iter().step_by(10).copied().collect();
    split.positions.extend(copies);
    let with_copies = BoundRig::bind_with(&rig, &split, SkinRules::TISSUE).expect("binds");
    let n = mesh.positions.len() as u32;
    for m in 0..rig.muscles.len() {
        let (a, b) = (whole.field(m).unwrap(), with_copies.field(m).unwrap());
        let kept: Vec<(u32, Vec3)> = b
            .vertices
            .iter()
            .zip(&b.displacements)
            .filter(|(&v, _)| v < n)
            .map(|(&v, &d)| (v, d))
            .collect();
        let own: Vec<(u32, Vec3)> = a
            .vertices
            .iter()
            .copied()
            .zip(a.displacements.iter().copied())
            .collect();
        assert!(!own.is_empty(), "{}: an empty field", rig.muscles[m].name);
        assert_eq!(kept, own, "{}", rig.muscles[m].name);
    }
    // and the copies move with their vertices
    let act = builtin::default_table()
        .expression_activations("happiness", &rig)
        .expect("happiness evaluates");
    let (x, y) = (deformed(&whole, &act), deformed(&with_copies, &act));
    assert_eq!(&y[..x.len()], &x[..]);
    for (k, v) in (0..mesh.positions.len()).step_by(10).enumerate() {
        assert_eq!(y[x.len() + k], x[v]);
    }
}

#[test]
fn the_pull_reaches_past_the_zone_and_dies_out() {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let own = BoundRig::bind_with(&rig, &mesh, SkinRules::DEFAULT).expect("binds");
    let spread = bound();
    let diagonal = {
        let (lo, hi) = mesh.bounds();
        (hi - lo).length()
    };
    for m in 0..rig.muscles.len() {
        let (before, after) = (own.field(m).unwrap(), spread.field(m).unwrap());
        if matches!(rig.muscles[m].kind, MuscleKind::Sphincter(_)) {
            assert_eq!(before, after, "{}: a ring is kept", rig.muscles[m].name);
            continue;
        }
        assert!(
            after.len() > before.len(),
            "{}: {} vertices moved with the spread, {} without",
            rig.muscles[m].name,
            after.len(),
            before.len()
        );
        // every spread vertex lies within reach of the muscle's own zone
        let far = after
            .vertices
            .iter()
            .map(|&v| {
                let p = mesh.positions[v as usize];
                before
                    .vertices
                    .iter()
                    .map(|&u| (mesh.positions[u as usize] - p).length())
                    .fold(f32::INFINITY, f32::min)
            })
            .fold(0.0f32, f32::max);
        assert!(
            far < 0.25 * diagonal,
            "{}: reaches {far}",
            rig.muscles[m].name
        );
    }
}

/// One level of 1-to-4 midpoint subdivision; the old vertices keep their numbers.
pub(crate) fn subdivide(mesh: &grimace::model::Mesh) -> (grimace::model::Mesh, Vec<[u32; 3]>) {
    let mut positions = mesh.positions.clone();
    let mut midpoints = std::collections::HashMap::new();
    let mut parents = Vec::new();
    let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            positions.push((positions[a as usize] + positions[b as usize]) * 0.5);
            let m = (positions.len() - 1) as u32;
            parents.push([m, a, b]);
            m
        })
    };
    let mut triangles = Vec::new();
    for &[a, b, c] in &mesh.triangles {
        let ab = midpoint(a, b, &mut positions);
        let bc = midpoint(b, c, &mut positions);
        let ca = midpoint(c, a, &mut positions);
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    let mesh = grimace::model::Mesh::new(positions, triangles).expect("valid");
    (mesh, parents)
}

/// `rig` with each mask and the jaw's weights carried to the midpoints `subdivide` added
/// (`[midpoint, a, b]`): the mean of the ends' weights (1 where a mask does not list a
/// vertex, 0 where the jaw does not), as a fit carries them.
pub(crate) fn carry_masks(rig: &grimace::model::Rig, parents: &[[u32; 3]]) -> grimace::model::Rig {
    let mut rig = rig.clone();
    for mask in &mut rig.masks {
        let listed: std::collections::HashMap<u32, f32> = mask.weights.iter().copied().collect();
        let weight = |v: u32| listed.get(&v).copied().unwrap_or(1.0);
        for &[m, a, b] in parents {
            let w = 0.5 * (weight(a) + weight(b));
            if w < 1.0 {
                mask.weights.push((m, w));
            }
        }
        mask.weights.sort_by_key(|&(v, _)| v);
    }
    if let Some(jaw) = &mut rig.jaw {
        let listed: std::collections::HashMap<u32, f32> = jaw.weights.iter().copied().collect();
        let weight = |v: u32| listed.get(&v).copied().unwrap_or(0.0);
        for &[m, a, b] in parents {
            let w = 0.5 * (weight(a) + weight(b));
            if w > 0.0 {
                jaw.weights.push((m, w));
            }
        }
        jaw.weights.sort_by_key(|&(v, _)| v);
    }
    rig
}

/// The spread is set in face units, not in edges: on the built-in face subdivided once (four
/// times the triangles, half the edge length) every spread field agrees with the coarse one
/// at the shared vertices as closely as the muscles' own fields do, and far closer than the
/// spread changes the field. The masks are carried to the new vertices (the mean of their
/// edge's ends), as a fit carries them; without that the new vertices beside a lip mask
/// moved with the whole pull.
#[test]
fn the_spread_does_not_depend_on_the_resolution() {
    let coarse = builtin::default_mesh();
    let (fine, parents) = subdivide(&coarse);
    let rig = builtin::default_rig();
    let fine_rig = carry_masks(&rig, &parents);
    let on = |rig, mesh, skin| BoundRig::bind_with(rig, mesh, skin).expect("binds");
    let (own, own_fine, spread_coarse, spread_fine) = (
        on(&rig, &coarse, SkinRules::DEFAULT),
        on(&fine_rig, &fine, SkinRules::DEFAULT),
        on(&rig, &coarse, SkinRules::TISSUE),
        on(&fine_rig, &fine, SkinRules::TISSUE),
    );
    let dense = |field: &grimace::model::Field| {
        let mut d = vec![Vec3::ZERO; coarse.positions.len()];
        for (&v, &x) in field.vertices.iter().zip(&field.displacements) {
            if (v as usize) < d.len() {
                d[v as usize] = x;
            }
        }
        d
    };
    let mut gaps = Vec::new();
    for (m, muscle) in rig.muscles.iter().enumerate() {
        if matches!(muscle.kind, MuscleKind::Sphincter(_)) {
            continue;
        }
        let [a, f, b, c] =
            [&own, &own_fine, &spread_coarse, &spread_fine].map(|r| dense(r.field(m).unwrap()));
        let largest = b.iter().map(|d| d.length()).fold(0.0f32, f32::max);
        let gap = |x: &[Vec3], y: &[Vec3]| {
            x.iter()
                .zip(y)
                .map(|(p, q)| (*p - *q).length())
                .fold(0.0f32, f32::max)
                / largest
        };
        let (resolution, spreading, own) = (gap(&b, &c), gap(&a, &b), gap(&a, &f));
        println!(
            "{}: resolution {resolution:.3} (own fields {own:.3}), spread {spreading:.3}",
            muscle.name
        );
        assert!(
            resolution < spreading + own,
            "{}: coarse and fine differ by {resolution} of the largest travel; the spread \
             changes the field by {spreading}",
            muscle.name
        );
        gaps.push((resolution - own, spreading));
    }
    // on the whole, the resolution moves a field a small part of what the spread does
    let mean = |i: usize| gaps.iter().map(|g| [g.0, g.1][i]).sum::<f32>() / gaps.len() as f32;
    println!("mean: resolution {}, spread {}", mean(0), mean(1));
    assert!(
        mean(0) < 0.25 * mean(1),
        "resolution {} against spread {}",
        mean(0),
        mean(1)
    );
}
