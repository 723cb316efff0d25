//! Sphincter frames: the default is the mesh's own axes (old rigs compute what they did), a
//! turned sphincter on a turned mesh moves the skin by the turned displacement, and rig files
//! write, read and check the frame.

use std::path::Path;

use glam::{Quat, Vec3};
use grimace::io::{self, builtin};
use grimace::model::field::{sphincter_displacement, Shape, SphincterShape};
use grimace::model::{Convergence, Frame, MuscleKind, Sphincter};
use proptest::prelude::*;

fn sphincter(convergence: Convergence, frame: Frame) -> Sphincter {
    Sphincter {
        centre: Vec3::new(0.3, -1.2, 4.0),
        semi_major: 2.0,
        semi_minor: 0.9,
        convergence,
        bulge: 10.0,
        frame,
    }
}

fn convergence() -> impl Strategy<Value = Convergence> {
    prop_oneof![Just(Convergence::Centre), Just(Convergence::MajorAxis)]
}

fn unit() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0)
        .prop_filter("not too short", |(x, y, z)| {
            Vec3::new(*x, *y, *z).length() > 0.2
        })
        .prop_map(|(x, y, z)| Vec3::new(x, y, z).normalize())
}

fn rotation() -> impl Strategy<Value = Quat> {
    (unit(), -3.1f32..3.1).prop_map(|(axis, angle)| Quat::from_axis_angle(axis, angle))
}

fn near_centre() -> impl Strategy<Value = Vec3> {
    (-2.5f32..2.5, -1.2f32..1.2, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

#[test]
fn the_default_frame_is_the_mesh_axes_and_changes_nothing() {
    assert_eq!(Frame::default(), Frame::IDENTITY);
    assert_eq!(Frame::IDENTITY.x, Vec3::X);
    assert_eq!(Frame::IDENTITY.y, Vec3::Y);
    assert_eq!(Frame::IDENTITY.mirrored_x(), Frame::IDENTITY);
    // Bit for bit the frameless computation, over a grid around both kinds of ellipse.
    for convergence in [Convergence::Centre, Convergence::MajorAxis] {
        let s = sphincter(convergence, Frame::default());
        let frameless = SphincterShape::new(&s);
        let mut moved = 0;
        for i in -30..=30 {
            for j in -15..=15 {
                let p = s.centre + Vec3::new(i as f32 * 0.09, j as f32 * 0.07, (i + j) as f32);
                let d = sphincter_displacement(&s, p, 1.0);
                assert_eq!(d, frameless.unit_displacement(p), "at {p}");
                moved += usize::from(d != Vec3::ZERO);
            }
        }
        assert!(moved > 500, "{moved} points moved");
    }
    assert!(matches!(
        Shape::new(&MuscleKind::Sphincter(sphincter(
            Convergence::Centre,
            Frame::IDENTITY
        ))),
        Shape::Sphincter(_)
    ));
}

#[test]
fn a_frame_turns_the_ellipse_into_its_plane() {
    // A z-up face: the ellipse in the x-z plane, up along +z, bulging toward -y.
    let frame = Frame {
        x: Vec3::X,
        y: Vec3::Z,
    };
    let s = sphincter(Convergence::MajorAxis, frame);
    let flat = sphincter(Convergence::MajorAxis, Frame::IDENTITY);
    // A point 0.5 above the centre (along the frame's y) moves down (-z) and out (-y),
    // exactly as the flat eye moves its point 0.5 above the centre down (-y) and out (+z).
    let d = sphincter_displacement(&s, s.centre + Vec3::new(0.0, 0.0, 0.5), 1.0);
    let want = sphincter_displacement(&flat, flat.centre + Vec3::new(0.0, 0.5, 0.0), 1.0);
    assert!(want.y < 0.0 && want.z > 0.0, "{want}");
    assert!(
        (d - Vec3::new(want.x, -want.z, want.y)).length() < 1e-6,
        "{d} vs {want}"
    );
    // Frames need not be unit or exactly perpendicular: y is made perpendicular to x.
    let loose = sphincter(
        Convergence::MajorAxis,
        Frame {
            x: Vec3::new(3.0, 0.0, 0.0),
            y: Vec3::new(0.5, 0.0, 2.0),
        },
    );
    let p = s.centre + Vec3::new(0.4, 0.3, -0.2);
    let (a, b) = (
        sphincter_displacement(&s, p, 1.0),
        sphincter_displacement(&loose, p, 1.0),
    );
    assert!((a - b).length() < 1e-6, "{a} vs {b}");
}

proptest! {
    /// Turning the mesh and the sphincter (centre and frame) together turns the displacement.
    #[test]
    fn a_turned_sphincter_on_a_turned_mesh_moves_the_skin_turned(
        convergence in convergence(),
        frame_turn in rotation(),
        turn in rotation(),
        offset in near_centre(),
        activation in 0.1f32..2.0,
    ) {
        let frame = Frame { x: frame_turn * Vec3::X, y: frame_turn * Vec3::Y };
        let s = sphincter(convergence, frame);
        let turned = Sphincter {
            centre: turn * s.centre,
            frame: Frame { x: turn * frame.x, y: turn * frame.y },
            ..s.clone()
        };
        let p = s.centre + frame_turn * offset;
        let want = turn * sphincter_displacement(&s, p, activation);
        let got = sphincter_displacement(&turned, turn * p, activation);
        prop_assert!((got - want).length() < 2e-5 * activation.max(1.0), "{got} vs {want}");
        // And a frame turned from the mesh's axes gives the flat displacement turned.
        let flat = sphincter(convergence, Frame::IDENTITY);
        let flat_d = sphincter_displacement(&flat, flat.centre + offset, activation);
        let d = sphincter_displacement(&s, p, activation);
        prop_assert!((d - frame_turn * flat_d).length() < 2e-5 * activation.max(1.0),
            "{d} vs {}", frame_turn * flat_d);
    }

    /// The mirrored frame moves the mirrored point by the mirrored displacement.
    #[test]
    fn a_mirrored_frame_mirrors_the_displacement(
        convergence in convergence(),
        frame_turn in rotation(),
        offset in near_centre(),
    ) {
        let s = sphincter(convergence, Frame { x: frame_turn * Vec3::X, y: frame_turn * Vec3::Y });
        let MuscleKind::Sphincter(m) = MuscleKind::Sphincter(s.clone()).mirrored_x() else {
            unreachable!()
        };
        let flip = |v: Vec3| Vec3::new(-v.x, v.y, v.z);
        let p = s.centre + frame_turn * offset;
        let want = flip(sphincter_displacement(&s, p, 1.0));
        let got = sphincter_displacement(&m, flip(p), 1.0);
        prop_assert!((got - want).length() < 2e-5, "{got} vs {want}");
    }
}

fn p() -> &'static Path {
    Path::new("t.ron")
}

/// The paper's rig (whose rings lie in the mesh's own axes) with the mouth given a frame of
/// its own.
fn framed_rig(frame: Frame) -> grimace::model::Rig {
    let mut rig = builtin::paper_rig();
    let mouth = rig.muscle_index("Orbicularis_Oris").unwrap();
    let MuscleKind::Sphincter(s) = &mut rig.muscles[mouth].kind else {
        panic!("the mouth is not a sphincter")
    };
    s.frame = frame;
    rig
}

#[test]
fn rig_files_keep_a_frame_and_write_none_for_the_default() {
    let plain = io::rig_to_ron(&builtin::paper_rig());
    assert!(!plain.contains("frame"), "{plain}");
    let frame = Frame {
        x: Vec3::new(0.8, 0.0, 0.6),
        y: Vec3::new(0.0, 0.0, 1.0e-7) + Vec3::new(-0.6, 0.0, 0.8).cross(Vec3::X).normalize(),
    };
    let rig = framed_rig(frame);
    let text = io::rig_to_ron(&rig);
    assert_eq!(text.matches("frame: (x: (").count(), 1, "{text}");
    let back = io::parse_rig(&text, p()).unwrap();
    assert_eq!(back, rig);
    assert_eq!(io::rig_to_ron(&back), text);
    // A rig written before frames existed reads with the mesh's own axes.
    let old = io::parse_rig(&plain, p()).unwrap();
    assert_eq!(old, builtin::paper_rig());
}

#[test]
fn bad_frames_are_refused_naming_the_muscle_and_place() {
    let text = io::rig_to_ron(&framed_rig(Frame {
        x: Vec3::new(0.0, 0.0, 1.0),
        y: Vec3::new(0.0, 1.0, 0.0),
    }));
    let line = text.lines().position(|l| l.contains("frame: (x:")).unwrap() + 1;
    let cases = [
        ("(x: (0.0, 0.0, 0.0), y: (0.0, 1.0, 0.0))", "x is zero"),
        (
            "(x: (0.0, 0.0, 1.0), y: (0.0, NaN, 0.0))",
            "y [0, NaN, 0] is not finite",
        ),
        ("(x: (0.0, 0.0, 1.0), y: (0.0, 0.0, -2.0))", "are parallel"),
        (
            "(x: (1.0, 0.0, 0.0), y: (1.0, 0.0001, 0.0))",
            "are parallel",
        ),
    ];
    for (frame, words) in cases {
        let bad = text.replace("(x: (0.0, 0.0, 1.0), y: (0.0, 1.0, 0.0))", frame);
        assert_ne!(bad, text);
        let err = io::parse_rig(&bad, p()).unwrap_err().to_string();
        let at = format!("t.ron:{line}:17: muscle `Orbicularis_Oris`: frame ");
        assert!(err.starts_with(&at), "{err} (want {at})");
        assert!(err.contains(words), "{err} (want {words})");
    }
    // Both directions are needed.
    let half = text.replace(
        "(x: (0.0, 0.0, 1.0), y: (0.0, 1.0, 0.0))",
        "(x: (0.0, 0.0, 1.0))",
    );
    let err = io::parse_rig(&half, p()).unwrap_err().to_string();
    assert!(err.starts_with("t.ron:") && err.contains('y'), "{err}");
}

#[test]
fn the_editor_draws_a_framed_ring_in_its_plane() {
    use grimace::render::{muscle_overlays, Palette, Shape as Drawn};
    let z_up = Frame {
        x: Vec3::X,
        y: Vec3::Z,
    };
    let mut overlays = Vec::new();
    muscle_overlays(&framed_rig(z_up), None, &Palette::default(), &mut overlays);
    let rig = builtin::paper_rig();
    let mouth = rig.muscle_index("Orbicularis_Oris").unwrap();
    let MuscleKind::Sphincter(s) = &rig.muscles[mouth].kind else {
        panic!("the mouth is not a sphincter")
    };
    let Drawn::Ellipse { semi_x, semi_y, .. } = overlays[mouth].shape else {
        panic!("the mouth is not drawn as an ellipse")
    };
    assert_eq!(semi_x, Vec3::X * s.semi_major);
    assert_eq!(semi_y, Vec3::Z * s.semi_minor);
}
