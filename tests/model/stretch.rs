//! The stretch limit (`docs/model.md`, "The stretch limit"): a linear or sheet muscle's pull
//! changes along the skin no faster than the limit allows, whatever the mesh's resolution.

use grimace::io::builtin;
use grimace::model::{BoundRig, Mesh, MuscleKind, Rig, SkinRules};

use crate::spread::{carry_masks, subdivide};

/// Largest stretch of an edge of `mesh` moved to `moved`.
fn worst_edge(mesh: &Mesh, moved: &[glam::Vec3]) -> f32 {
    mesh.edges()
        .iter()
        .map(|&[a, b]| {
            let (a, b) = (a as usize, b as usize);
            moved[a].distance(moved[b]) / mesh.positions[a].distance(mesh.positions[b])
        })
        .fold(1.0f32, f32::max)
}

/// The built-in face and its rig, coarse and cut in sixteen (a quarter of the edge length;
/// masks and the jaw's weights carried to the new vertices).
fn faces() -> [(&'static str, Rig, Mesh); 2] {
    let coarse = builtin::default_mesh();
    let (once, parents) = subdivide(&coarse);
    let rig = carry_masks(&builtin::default_rig(), &parents);
    let (fine, parents) = subdivide(&once);
    let fine_rig = carry_masks(&rig, &parents);
    [
        ("coarse", builtin::default_rig(), coarse),
        ("fine", fine_rig, fine),
    ]
}

/// The paper's deformation with the skin's stretch limit and nothing else.
const LIMITED: SkinRules = SkinRules {
    stretch: 2.0,
    ..SkinRules::PAPER
};

/// Largest stretch of an edge of `mesh` when muscles `group`'s fields move it at 2.0.
fn largest_stretch(bound: &BoundRig, mesh: &Mesh, group: &[usize]) -> f32 {
    let mut moved = mesh.positions.clone();
    for &m in group {
        let field = bound.field(m).expect("a field per muscle");
        for (&v, &d) in field.vertices.iter().zip(&field.displacements) {
            moved[v as usize] += 2.0 * d;
        }
    }
    worst_edge(mesh, &moved)
}

/// The largest stretch at 2.0 with `skin` of each linear and sheet muscle: alone, and
/// with its mirror partner at 2.0 too (the limit caps a muscle only as far as both need it:
/// the two sides of the levator labii fade into each other at the midline, the two
/// mentalis overlap on the chin), the less of the two, by name.
fn stretches(rig: &Rig, mesh: &Mesh, skin: SkinRules) -> Vec<(String, f32)> {
    let bound = BoundRig::bind_with(rig, mesh, skin).expect("binds");
    rig.muscles
        .iter()
        .enumerate()
        .filter(|(_, m)| !matches!(m.kind, MuscleKind::Sphincter(_)))
        .map(|(i, m)| {
            let alone = largest_stretch(&bound, mesh, &[i]);
            let pair = rig
                .mirror_of(i)
                .map_or(alone, |j| largest_stretch(&bound, mesh, &[i, j]));
            (m.name.clone(), alone.min(pair))
        })
        .collect()
}

/// On the built-in face cut in sixteen (a quarter of the edge length), where the falloff's
/// slope is resolved, the muscles' own fields stretch edges beyond 2.5 times their length at
/// 2.0; limited, no field (alone or with its mirror partner, the less of the two) stretches
/// any edge beyond the limit (2.0), on the coarse face or the fine one. Without the limit
/// the first assertion holds and the last fails (the medial frontalis 3.12x).
#[test]
fn no_muscle_alone_stretches_the_skin_beyond_the_limit_at_any_resolution() {
    let [coarse, (_, fine_rig, fine)] = faces();
    let own = stretches(&fine_rig, &fine, SkinRules::PAPER);
    let worst = own.iter().map(|s| s.1).fold(1.0f32, f32::max);
    println!("own fields on the fine face: up to {worst:.2}x {own:?}");
    assert!(worst > 2.5, "the fine face resolves the falloff: {worst}");
    for (name, rig, mesh) in [coarse, ("fine", fine_rig, fine)] {
        let limited = stretches(&rig, &mesh, LIMITED);
        println!("limited on the {name} face: {limited:?}");
        for (muscle, stretch) in limited {
            // the levator labii's midline fade into its partner is kept (its pair's sum is
            // smooth there) and is held by its range, under the tear's 2.5
            let bound = match muscle.as_str() {
                "L_Labii_Nasi" | "R_Labii_Nasi" => 2.5,
                _ => 2.01,
            };
            assert!(stretch < bound, "{name} face, {muscle}: {stretch}");
        }
    }
}

/// The largest stretch of an edge of `mesh` with the jaw alone at 4.0, bound with `skin`.
fn jaw_stretch(rig: &Rig, mesh: &Mesh, skin: SkinRules) -> f32 {
    let bound = BoundRig::bind_with(rig, mesh, skin).expect("binds");
    let mut act = grimace::model::Activations::zero(rig);
    act.jaw = 4.0;
    let mut moved = Vec::new();
    bound.deform(&act, &mut moved).expect("in range");
    worst_edge(mesh, &moved)
}

/// The jaw's weights are capped the same way, at 2.25 (`stretch.rs`, `JAW_OVER_MUSCLES`):
/// its turn at 4.0 stretches no edge beyond that on the built-in face or on it cut in
/// sixteen, where its own weights stretch one further.
#[test]
fn the_jaw_alone_stretches_the_skin_no_further_than_its_limit() {
    let [coarse, (_, fine_rig, fine)] = faces();
    let own = jaw_stretch(&fine_rig, &fine, SkinRules::PAPER);
    println!("the jaw's own weights on the fine face: {own:.2}x");
    for (name, rig, mesh) in [coarse, ("fine", fine_rig, fine)] {
        let stretch = jaw_stretch(&rig, &mesh, LIMITED);
        println!("limited on the {name} face: {stretch:.3}x");
        assert!(stretch < 2.3, "{name} face: {stretch}");
    }
    assert!(own > 2.3, "the jaw's own weights: {own}");
}
