//! Unit tests of the deformation: bit-identical partial updates, the jaw, the sparse layout.

use std::path::PathBuf;

use super::*;
use crate::model::jaw::Jaw;
use crate::model::muscle::{Linear, Muscle, MuscleKind, Side};
use crate::model::rig::RIG_VERSION;

/// Four vertices: two on a linear muscle's axis, one chin-like, one far away.
fn mesh() -> Mesh {
    Mesh::new(
        vec![
            Vec3::new(0.0, 0.0, 0.5),
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(0.0, -8.0, 6.0),
            Vec3::new(50.0, 50.0, 50.0),
        ],
        vec![[0, 1, 2], [1, 2, 3]],
    )
    .expect("valid mesh")
}

fn linear(name: &str) -> Muscle {
    Muscle {
        name: name.into(),
        side: Side::Centre,
        mirror: None,
        kind: MuscleKind::Linear(Linear {
            attachment: Vec3::ZERO,
            insertion: Vec3::Z,
            zone: 60.0,
            falloff_start: 1.0,
            falloff_end: 3.0,
        }),
    }
}

fn rig(muscles: Vec<Muscle>, jaw: Option<Jaw>) -> Rig {
    Rig {
        masks: Vec::new(),
        version: RIG_VERSION,
        mesh: PathBuf::from("test.obj"),
        landmarks: None,
        combine: Combine::Sum,
        muscles,
        jaw,
    }
}

fn jaw(weight: f32) -> Jaw {
    Jaw {
        axis: glam::Vec3::X,
        slide: glam::Vec3::ZERO,
        pivot: Vec3::ZERO,
        degrees_per_unit: 1.0,
        weights: vec![(2, weight)],
    }
}

#[test]
fn jaw_opens_down_and_back() {
    // Chin (0,-8,6) about the origin by 4 degrees:
    // y' = cos4 (-8) - sin4 (6) = -8.399051, z' = sin4 (-8) + cos4 (6) = 5.427333.
    let r = rig(vec![], Some(jaw(1.0)));
    let bound = BoundRig::bind(&r, &mesh()).expect("binds");
    let mut out = Vec::new();
    let act = Activations {
        muscles: vec![],
        jaw: 4.0,
    };
    bound.deform(&act, &mut out).expect("in range");
    let chin = out[2];
    assert!(
        (chin - Vec3::new(0.0, -8.399_051, 5.427_333)).length() < 1e-5,
        "{chin}"
    );
    assert!(
        chin.y < -8.0 && chin.z < 6.0,
        "the chin moves down and back"
    );
    assert_eq!(out[0], mesh().positions[0]);
}

#[test]
fn jaw_weight_blends_and_zero_weight_stays() {
    // Weight 0.5: halfway between rest and the fully turned chin.
    let mut out = Vec::new();
    let act = Activations {
        muscles: vec![],
        jaw: 4.0,
    };
    let half = BoundRig::bind(&rig(vec![], Some(jaw(0.5))), &mesh()).expect("binds");
    half.deform(&act, &mut out).expect("in range");
    let want = (Vec3::new(0.0, -8.399_051, 5.427_333) + Vec3::new(0.0, -8.0, 6.0)) * 0.5;
    assert!((out[2] - want).length() < 1e-5);
    let none = BoundRig::bind(&rig(vec![], Some(jaw(0.0))), &mesh()).expect("binds");
    none.deform(&act, &mut out).expect("in range");
    assert_eq!(out, mesh().positions);
}

#[test]
fn jaw_turns_the_post_muscle_position() {
    // The muscle moves vertex 0 from (0,0,0.5) to (0,0,0) at activation 1 (k = -1, t = 1);
    // a jaw of weight 1 with 90 degrees per unit then turns (0,0,0) about the origin: it
    // stays. Put the pivot at (0,1,0) instead: (0,-1,0) relative turns by 90 degrees to
    // (0,0,-1) relative, i.e. (0,1,-1).
    let mut r = rig(vec![linear("a")], None);
    r.jaw = Some(Jaw {
        axis: glam::Vec3::X,
        slide: glam::Vec3::ZERO,
        pivot: Vec3::Y,
        degrees_per_unit: 90.0,
        weights: vec![(0, 1.0)],
    });
    let bound = BoundRig::bind(&r, &mesh()).expect("binds");
    let mut out = Vec::new();
    let act = Activations {
        muscles: vec![1.0],
        jaw: 1.0,
    };
    bound.deform(&act, &mut out).expect("in range");
    assert!(
        (out[0] - Vec3::new(0.0, 1.0, -1.0)).length() < 1e-6,
        "{}",
        out[0]
    );
}

/// The slide moves the jaw after the turn, in proportion to the angle and blended by the
/// weight; `update_jaw` agrees with `deform` bit for bit; a bad slide is refused.
#[test]
fn jaw_slides_in_proportion_to_its_angle() {
    let slide = Vec3::new(0.0, -0.01, 0.02);
    let sliding = Jaw {
        slide,
        degrees_per_unit: 2.0,
        ..jaw(0.5)
    };
    let bound = BoundRig::bind(&rig(vec![], Some(sliding.clone())), &mesh()).expect("binds");
    let mut out = Vec::new();
    let act = Activations {
        muscles: vec![],
        jaw: 3.0,
    };
    bound.deform(&act, &mut out).expect("in range");
    // vertex 2 at (0, -8, 6), turned by 6 degrees about the origin, moved by 6 x slide,
    // half of that motion kept (weight 0.5)
    let p = Vec3::new(0.0, -8.0, 6.0);
    let (sin, cos) = 6.0f32.to_radians().sin_cos();
    let turned = Vec3::new(0.0, cos * p.y - sin * p.z, sin * p.y + cos * p.z) + 6.0 * slide;
    let want = p + 0.5 * (turned - p);
    assert!((out[2] - want).length() < 1e-5, "{} vs {want}", out[2]);
    let mut partial = mesh().positions;
    bound.update_jaw(&act, &mut partial).expect("in range");
    assert_eq!(partial, out);
    // no slide: exactly the paper's turn
    let pure = BoundRig::bind(
        &rig(
            vec![],
            Some(Jaw {
                slide: Vec3::ZERO,
                ..sliding.clone()
            }),
        ),
        &mesh(),
    )
    .expect("binds");
    let mut turned_only = Vec::new();
    pure.deform(&act, &mut turned_only).expect("in range");
    assert!((out[2] - turned_only[2] - 0.5 * 6.0 * slide).length() < 1e-5);
    let lost = Jaw {
        slide: Vec3::new(f32::NAN, 0.0, 0.0),
        ..sliding
    };
    assert!(matches!(
        BoundRig::bind(&rig(vec![], Some(lost)), &mesh()),
        Err(BindError::JawParameter {
            parameter: "slide",
            ..
        })
    ));
}

#[test]
fn sum_and_average_combine() {
    // Two identical muscles at 1.0 and 0.5: vertex 0 moves by -0.5 z per unit;
    // sum: -0.75; average over the two active muscles: -0.375 (the paper's arithmetic,
    // without the skin rules).
    let mut r = rig(vec![linear("a"), linear("b")], None);
    let act = Activations {
        muscles: vec![1.0, 0.5],
        jaw: 0.0,
    };
    let mut out = Vec::new();
    BoundRig::bind_with(&r, &mesh(), SkinRules::PAPER)
        .unwrap()
        .deform(&act, &mut out)
        .unwrap();
    assert!((out[0].z - (0.5 - 0.75)).abs() < 1e-6);
    r.combine = Combine::Average;
    let bound = BoundRig::bind_with(&r, &mesh(), SkinRules::PAPER).unwrap();
    bound.deform(&act, &mut out).unwrap();
    assert!((out[0].z - (0.5 - 0.375)).abs() < 1e-6);
    // One active muscle: average equals sum (nothing to divide by).
    let one = Activations {
        muscles: vec![0.0, 0.5],
        jaw: 0.0,
    };
    bound.deform(&one, &mut out).unwrap();
    assert!((out[0].z - (0.5 - 0.25)).abs() < 1e-6);
}

#[test]
fn bind_refuses_bad_rigs() {
    let m = mesh();
    let dup = rig(vec![linear("a"), linear("a")], None);
    assert_eq!(
        BoundRig::bind(&dup, &m),
        Err(BindError::DuplicateMuscle("a".into()))
    );
    let mut lonely = linear("a");
    lonely.mirror = Some("b".into());
    assert!(matches!(
        BoundRig::bind(&rig(vec![lonely], None), &m),
        Err(BindError::MissingMirror { .. })
    ));
    assert!(matches!(
        BoundRig::bind(&rig(vec![], Some(jaw(1.5))), &m),
        Err(BindError::JawWeight { vertex: 2, .. })
    ));
    assert!(matches!(
        BoundRig::bind(&rig(vec![], Some(jaw(f32::NAN))), &m),
        Err(BindError::JawWeight { .. })
    ));
    let far = Jaw {
        weights: vec![(9, 1.0)],
        ..jaw(1.0)
    };
    assert_eq!(
        BoundRig::bind(&rig(vec![], Some(far)), &m),
        Err(BindError::JawVertex {
            vertex: 9,
            count: 4
        })
    );
    let twice = Jaw {
        weights: vec![(2, 1.0), (1, 0.5), (2, 0.2)],
        ..jaw(1.0)
    };
    assert_eq!(
        BoundRig::bind(&rig(vec![], Some(twice)), &m),
        Err(BindError::JawDuplicateVertex(2))
    );
    let lost = Jaw {
        pivot: Vec3::new(f32::NAN, 0.0, 0.0),
        ..jaw(1.0)
    };
    assert!(matches!(
        BoundRig::bind(&rig(vec![], Some(lost)), &m),
        Err(BindError::JawParameter {
            parameter: "pivot",
            ..
        })
    ));
    let spin = Jaw {
        degrees_per_unit: f32::INFINITY,
        ..jaw(1.0)
    };
    assert!(matches!(
        BoundRig::bind(&rig(vec![], Some(spin)), &m),
        Err(BindError::JawParameter {
            parameter: "degrees_per_unit",
            ..
        })
    ));
    let message = BoundRig::bind(&dup, &m).unwrap_err().to_string();
    assert!(message.contains("`a`"), "{message}");
}

#[test]
fn bind_refuses_a_muscle_that_reaches_too_far() {
    // A zone of nearly 90 degrees makes k = 1 - cos_a/cos_zone enormous.
    let mut m = linear("wide");
    if let MuscleKind::Linear(l) = &mut m.kind {
        l.zone = 89.999_99;
        l.falloff_end = 3.0e38;
    }
    let mesh = Mesh::new(
        vec![Vec3::new(0.0, 0.0, 3.0e37), Vec3::Z, Vec3::X],
        vec![[0, 1, 2]],
    )
    .unwrap();
    assert!(matches!(
        BoundRig::bind(&rig(vec![m], None), &mesh),
        Err(BindError::OutOfReach { .. })
    ));
}

#[test]
fn deform_refuses_bad_activations_and_meshes() {
    let r = rig(vec![linear("a")], Some(jaw(1.0)));
    let bound = BoundRig::bind(&r, &mesh()).unwrap();
    let mut out = Vec::new();
    for (muscles, jaw) in [
        (vec![2.5], 0.0),
        (vec![-0.1], 0.0),
        (vec![f32::NAN], 0.0),
        (vec![1.0], 4.5),
        (vec![1.0], f32::INFINITY),
        (vec![], 0.0),
    ] {
        let act = Activations { muscles, jaw };
        assert!(bound.deform(&act, &mut out).is_err(), "{act:?}");
    }
    let act = Activations {
        muscles: vec![1.0],
        jaw: 1.0,
    };
    let mut short = vec![Vec3::ZERO; 2];
    assert_eq!(
        bound.update_muscle(&act, 0, &mut short),
        Err(ActivationError::VertexCount {
            given: 2,
            expected: 4
        })
    );
    let mut full = vec![Vec3::ZERO; 4];
    assert_eq!(
        bound.update_muscle(&act, 3, &mut full),
        Err(ActivationError::NoSuchMuscle { index: 3, count: 1 })
    );
    let other = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
    assert_eq!(
        deform(&other, &bound, &act, &mut out),
        Err(ActivationError::VertexCount {
            given: 3,
            expected: 4
        })
    );
    deform(&mesh(), &bound, &act, &mut out).expect("matching mesh");
}

#[test]
fn deform_does_not_reallocate() {
    let r = rig(vec![linear("a"), linear("b")], Some(jaw(0.7)));
    let bound = BoundRig::bind(&r, &mesh()).unwrap();
    let mut out = Vec::new();
    bound.deform(&Activations::zero(&r), &mut out).unwrap();
    let (ptr, cap) = (out.as_ptr(), out.capacity());
    for step in 0..20 {
        let a = step as f32 * 0.1;
        let act = Activations {
            muscles: vec![a, 2.0 - a],
            jaw: a * 2.0,
        };
        bound.deform(&act, &mut out).unwrap();
        assert_eq!((out.as_ptr(), out.capacity()), (ptr, cap));
    }
}

#[test]
fn inactive_muscles_keep_rest_coordinates_bit_for_bit() {
    // Vertex 0 sits at x = -0.0 on the axis of both muscles; muscle "a" is off and "b"
    // pulls along z only, so x must stay -0.0 (not become +0.0). The skin rules may move a
    // vertex off its muscles' lines, so this is the paper's deformation; with them, zero
    // activation still gives the rest mesh bit for bit.
    let mesh = Mesh::new(
        vec![Vec3::new(-0.0, 0.0, 0.5), Vec3::X * 9.0, Vec3::Y * 9.0],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let r = rig(vec![linear("a"), linear("b")], None);
    let skinned = BoundRig::bind(&r, &mesh).unwrap();
    let mut out = Vec::new();
    skinned.deform(&Activations::zero(&r), &mut out).unwrap();
    assert_eq!(out[0].x.to_bits(), (-0.0f32).to_bits());
    let bound = BoundRig::bind_with(&r, &mesh, SkinRules::PAPER).unwrap();
    for muscles in [vec![0.0, 0.0], vec![0.0, 1.0]] {
        bound
            .deform(&Activations { muscles, jaw: 0.0 }, &mut out)
            .unwrap();
        assert_eq!(out[0].x.to_bits(), (-0.0f32).to_bits());
    }
    assert_eq!(out[0].z, 0.0);
}

#[test]
fn bind_refuses_skin_rules_out_of_range() {
    let r = rig(vec![linear("a")], None);
    for skin in [
        SkinRules {
            slide: 1.5,
            ..SkinRules::DEFAULT
        },
        SkinRules {
            min_area: 1.0,
            ..SkinRules::DEFAULT
        },
        SkinRules {
            patch: 0.0,
            ..SkinRules::DEFAULT
        },
        SkinRules {
            slide: f32::NAN,
            ..SkinRules::DEFAULT
        },
        SkinRules {
            spread: -0.1,
            ..SkinRules::DEFAULT
        },
        SkinRules {
            spread: f32::INFINITY,
            ..SkinRules::DEFAULT
        },
        SkinRules {
            stretch: 0.5,
            ..SkinRules::DEFAULT
        },
        SkinRules {
            stretch: f32::NAN,
            ..SkinRules::DEFAULT
        },
    ] {
        let err = BoundRig::bind_with(&r, &mesh(), skin).unwrap_err();
        assert!(matches!(err, BindError::Skin(_)), "{err}");
    }
}

#[test]
fn layout_matches_the_fields() {
    let r = rig(vec![linear("a"), linear("b")], None);
    let bound = BoundRig::bind(&r, &mesh()).unwrap();
    assert_eq!(bound.muscle_count(), 2);
    assert_eq!(bound.field(0).unwrap().vertices, vec![0, 1]);
    assert_eq!(bound.pair_count(), 4);
    assert!(bound.field(2).is_none());
    assert_eq!(bound.rest(), &mesh().positions[..]);
    assert_eq!(bound.rig(), &r);
}

/// A vertex in no triangle that lies on one of a triangle (a copy at a joined seam) moves
/// with it in every way of deforming: whole, muscle by muscle, the jaw, and sampled. A
/// loose vertex on no vertex is deformed as any other (here out of every reach).
#[test]
fn a_copy_in_no_face_moves_with_the_vertex_it_lies_on() {
    let mut mesh = mesh();
    mesh.positions.push(mesh.positions[1]); // 4: a copy of 1
    mesh.positions.push(mesh.positions[2]); // 5: a copy of the jaw's vertex 2
    mesh.positions.push(Vec3::new(20.0, 0.0, 0.0)); // 6: loose, on no vertex, out of reach
    assert_eq!(mesh.followers(), vec![[4, 1], [5, 2]]);
    let r = rig(vec![linear("a"), linear("b")], Some(jaw(0.7)));
    for skin in [SkinRules::PAPER, SkinRules::DEFAULT] {
        let bound = BoundRig::bind_with(&r, &mesh, skin).unwrap();
        let act = Activations {
            muscles: vec![1.0, 0.5],
            jaw: 2.0,
        };
        let mut out = Vec::new();
        bound.deform(&act, &mut out).unwrap();
        assert_ne!(out[1], mesh.positions[1], "the muscle moves vertex 1");
        assert_eq!(out[4], out[1]);
        assert_eq!(out[5], out[2]);
        assert_eq!(out[6], mesh.positions[6]);
        let mut sampled = Vec::new();
        bound.deform_at(&act, &[4, 5, 6], &mut sampled).unwrap();
        assert_eq!(sampled, vec![out[1], out[2], out[6]]);
        // one muscle, then the jaw, changed on a pose of other activations
        let mut partial = Vec::new();
        let before = Activations {
            muscles: vec![0.0, 0.5],
            jaw: 0.0,
        };
        bound.deform(&before, &mut partial).unwrap();
        let middle = Activations {
            muscles: vec![1.0, 0.5],
            jaw: 0.0,
        };
        bound.update_muscle(&middle, 0, &mut partial).unwrap();
        bound.update_jaw(&act, &mut partial).unwrap();
        assert_eq!(partial, out);
    }
}
