//! Camera, projection, orientation, hidden-line removal and robustness of the rasterizer,
//! on small synthetic meshes.

use glam::{Vec2, Vec3};
use grimace::model::{Frame, Mesh};
use grimace::render::{
    muscle_overlays, Camera, CellMode, DotCanvas, Layer, Orientation, Overlay, Palette, Renderer,
    Rgb, Scene, Shape, Style,
};
use proptest::prelude::*;

/// A UV sphere of radius 1 whose right-hand normals point outward.
fn sphere(rings: usize, segments: usize) -> Mesh {
    let mut positions = vec![Vec3::Y];
    for r in 1..rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            positions.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ));
        }
    }
    positions.push(-Vec3::Y);
    let bottom = positions.len() as u32 - 1;
    let at = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, at(1, s + 1), at(1, s)]);
        triangles.push([bottom, at(rings - 1, s), at(rings - 1, s + 1)]);
    }
    for r in 1..rings - 1 {
        for s in 0..segments {
            triangles.push([at(r, s), at(r, s + 1), at(r + 1, s + 1)]);
            triangles.push([at(r, s), at(r + 1, s + 1), at(r + 1, s)]);
        }
    }
    Mesh::new(positions, triangles).unwrap()
}

fn flipped(mesh: &Mesh) -> Mesh {
    let triangles = mesh.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
    Mesh::new(mesh.positions.clone(), triangles).unwrap()
}

fn draw(
    mesh: &Mesh,
    positions: &[Vec3],
    camera: &Camera,
    style: Style,
    w: usize,
    h: usize,
) -> DotCanvas {
    let mut canvas = DotCanvas::new(w, h);
    let scene = Scene::new(mesh, positions);
    Renderer::new(mesh).render(&scene, camera, style, &mut canvas);
    canvas
}

fn lit_dots(canvas: &DotCanvas) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for y in 0..canvas.height() {
        for x in 0..canvas.width() {
            if canvas.is_on(x, y) {
                out.push((x, y));
            }
        }
    }
    out
}

const CUBE: (Vec3, Vec3) = (Vec3::splat(-1.0), Vec3::splat(1.0));

#[test]
fn fit_centres_and_scales_the_bounds_with_a_margin() {
    let proj = Camera::front().fit(CUBE, 100, 50, 1.0);
    // The tighter side is the height: 50 dots * 0.94 usable / 2 units.
    assert!((proj.scale_y - 23.5).abs() < 1e-4, "{}", proj.scale_y);
    assert!((proj.scale_x - 23.5).abs() < 1e-4);
    let centre = proj.project(Vec3::ZERO);
    assert!(
        (centre - Vec3::new(50.0, 25.0, 0.0)).length() < 1e-4,
        "{centre}"
    );
    let top = proj.project(Vec3::Y);
    assert!((top.y - 1.5).abs() < 1e-4, "{top}");
    // Nearer the viewer is larger depth, in dot heights.
    assert!((proj.project(Vec3::Z).z - 23.5).abs() < 1e-4);
}

#[test]
fn fit_corrects_for_the_dot_aspect() {
    // Dots half as wide as tall (ASCII cells one dot each): twice as many dots per unit
    // across as down.
    let proj = Camera::front().fit(CUBE, 100, 50, 0.5);
    assert!((proj.scale_y - 23.5).abs() < 1e-4);
    assert!((proj.scale_x - 47.0).abs() < 1e-4);
}

#[test]
fn zoom_and_pan_move_the_view() {
    let mut camera = Camera::front();
    camera.zoom = 2.0;
    camera.pan = Vec2::new(0.5, 0.0);
    let proj = camera.fit(CUBE, 100, 100, 1.0);
    assert!((proj.scale_y - 94.0).abs() < 1e-3);
    // Panning the view right by 0.5 units moves what was at screen-right 0.5 to the centre;
    // screen right is mesh +x.
    let p = proj.project(Vec3::new(0.5, 0.0, 0.0));
    assert!((p.x - 50.0).abs() < 1e-3, "{p}");
}

#[test]
fn front_view_puts_the_subjects_left_on_the_viewers_right() {
    let proj = Camera::front().fit(CUBE, 100, 100, 1.0);
    // glTF's convention: the subject's left at positive x
    let subjects_left = proj.project(Vec3::new(0.8, 0.0, 0.0));
    let subjects_right = proj.project(Vec3::new(-0.8, 0.0, 0.0));
    assert!(subjects_left.x > 50.0 && subjects_right.x < 50.0);
    assert!(proj.project(Vec3::new(0.0, 0.8, 0.0)).y < 50.0, "up is up");
}

#[test]
fn side_view_shows_the_left_profile_with_the_nose_to_the_left() {
    let camera = Camera::side();
    let proj = camera.fit(CUBE, 100, 100, 1.0);
    let nose = proj.project(Vec3::new(0.0, 0.0, 1.0));
    assert!(nose.x < 50.0 - 40.0, "nose at {nose}");
    let left_cheek = proj.project(Vec3::new(1.0, 0.0, 0.0));
    let right_cheek = proj.project(Vec3::new(-1.0, 0.0, 0.0));
    assert!(
        left_cheek.z > right_cheek.z,
        "the subject's left cheek is nearer"
    );
    assert!((camera.toward_viewer() - Vec3::X).length() < 1e-5);
    assert!((Camera::front().toward_viewer() - Vec3::Z).length() < 1e-6);
}

#[test]
fn positive_pitch_looks_down_from_above() {
    let camera = Camera {
        pitch: 0.5,
        ..Camera::front()
    };
    assert!(camera.toward_viewer().y > 0.4);
    let three = Camera::three_quarter().toward_viewer();
    assert!(three.x > 0.0 && three.y > 0.0 && three.z > 0.0, "{three}");
}

#[test]
fn a_drawn_triangle_lands_on_the_correct_side() {
    // A small triangle on the subject's left (x > 0) facing the viewer, plus a far one to
    // widen the bounds.
    let mesh = Mesh::new(
        vec![
            Vec3::new(1.0, -0.1, 0.0),
            Vec3::new(0.8, -0.1, 0.0),
            Vec3::new(0.9, 0.1, 0.0),
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-0.99, 0.0, -1.0),
        ],
        vec![[0, 1, 2], [3, 5, 4]],
    )
    .unwrap();
    let canvas = draw(
        &mesh,
        &mesh.positions,
        &Camera::front(),
        Style::Shaded,
        80,
        80,
    );
    let dots = lit_dots(&canvas);
    assert!(!dots.is_empty());
    assert!(
        dots.iter().all(|&(x, _)| x > 40),
        "every lit dot on the right half"
    );
}

#[test]
fn the_depth_buffer_hides_a_line_behind_a_surface() {
    // A large quad at z = 1 facing the viewer, and a small triangle behind it at z = 0.
    let quad = [
        Vec3::new(-1.0, -1.0, 1.0),
        Vec3::new(1.0, -1.0, 1.0),
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(-1.0, 1.0, 1.0),
    ];
    let small = [
        Vec3::new(-0.5, -0.5, 0.0),
        Vec3::new(0.5, -0.5, 0.0),
        Vec3::new(0.0, 0.5, 0.0),
    ];
    let mut positions = quad.to_vec();
    positions.extend(small);
    // Right-hand normals toward +z (the viewer); the quad winding is counter-clockwise seen
    // from +z.
    let both = Mesh::new(positions.clone(), vec![[0, 1, 2], [0, 2, 3], [4, 5, 6]]).unwrap();
    let front_only = Mesh::new(positions.clone(), vec![[0, 1, 2], [0, 2, 3]]).unwrap();
    let back_only = Mesh::new(positions, vec![[4, 5, 6]]).unwrap();
    let camera = Camera::front();
    for style in [Style::Wireframe, Style::Lines] {
        let with_back = draw(&both, &both.positions, &camera, style, 60, 60);
        let without = draw(&front_only, &front_only.positions, &camera, style, 60, 60);
        let alone = draw(&back_only, &back_only.positions, &camera, style, 60, 60);
        assert!(
            alone.count_on() > 40,
            "{style}: the back triangle alone is visible"
        );
        assert_eq!(
            lit_dots(&with_back),
            lit_dots(&without),
            "{style}: the back triangle is hidden"
        );
    }
}

#[test]
fn back_faces_are_culled() {
    let tri = Mesh::new(
        vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let scene = Scene {
        orientation: Orientation::Outward,
        ..Scene::new(&tri, &tri.positions)
    };
    let mut renderer = Renderer::new(&tri);
    let mut canvas = DotCanvas::new(40, 40);
    for style in [Style::Wireframe, Style::Shaded] {
        renderer.render(&scene, &Camera::front(), style, &mut canvas);
        assert!(canvas.count_on() > 20, "{style}: facing the viewer, drawn");
        let behind = Camera {
            yaw: std::f32::consts::PI,
            ..Camera::front()
        };
        renderer.render(&scene, &behind, style, &mut canvas);
        assert_eq!(canvas.count_on(), 0, "{style}: seen from behind, culled");
        let inward = Scene {
            orientation: Orientation::Inward,
            ..scene
        };
        renderer.render(&inward, &Camera::front(), style, &mut canvas);
        assert_eq!(
            canvas.count_on(),
            0,
            "{style}: declared inward, it faces away"
        );
    }
}

#[test]
fn winding_is_detected_and_both_windings_render_alike() {
    let out = sphere(10, 16);
    let inward = flipped(&out);
    assert_eq!(
        Renderer::new(&out).detected_orientation(),
        Orientation::Outward
    );
    assert_eq!(
        Renderer::new(&inward).detected_orientation(),
        Orientation::Inward
    );
    for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
        let a = draw(
            &out,
            &out.positions,
            &Camera::three_quarter(),
            style,
            80,
            80,
        );
        let b = draw(
            &inward,
            &inward.positions,
            &Camera::three_quarter(),
            style,
            80,
            80,
        );
        assert!(a.count_on() > 50);
        assert_eq!(lit_dots(&a), lit_dots(&b), "{style}");
    }
}

#[test]
fn lines_of_a_sphere_are_its_outline_and_a_facing_contour() {
    // A smooth sphere has no borders or creases: its feature lines are the silhouette, a
    // circle of radius 0.94 * 40 = 37.6 dots around the centre, and the facing contour at
    // 0.5, where the surface turns 60 degrees from the viewer: radius 37.6 * sin 60 = 32.6.
    let mesh = sphere(24, 48);
    let radii = |canvas: &DotCanvas| -> Vec<f32> {
        lit_dots(canvas)
            .into_iter()
            .map(|(x, y)| Vec2::new(x as f32 + 0.5 - 40.0, y as f32 + 0.5 - 40.0).length())
            .collect()
    };
    let outline_only = Scene {
        facing_contours: &[],
        ..Scene::new(&mesh, &mesh.positions)
    };
    let mut canvas = DotCanvas::new(80, 80);
    Renderer::new(&mesh).render(&outline_only, &Camera::front(), Style::Lines, &mut canvas);
    let outline = radii(&canvas);
    assert!(outline.len() > 150, "{}", outline.len());
    assert!(
        outline.iter().all(|r| (r - 37.6).abs() < 2.5),
        "{outline:?}"
    );

    let both = Scene {
        facing_contours: &[0.5],
        ..outline_only
    };
    Renderer::new(&mesh).render(&both, &Camera::front(), Style::Lines, &mut canvas);
    let all = radii(&canvas);
    let inner = all.iter().filter(|r| (*r - 32.6).abs() < 2.0).count();
    assert!(inner > 120, "{inner} dots on the facing contour");
    assert!(all
        .iter()
        .all(|r| (r - 37.6).abs() < 2.5 || (r - 32.6).abs() < 2.0));
}

#[test]
fn shaded_is_brighter_toward_the_light() {
    let mesh = sphere(24, 48);
    let mut canvas = DotCanvas::new(80, 80);
    canvas.dither = false;
    let scene = Scene::new(&mesh, &mesh.positions);
    Renderer::new(&mesh).render(&scene, &Camera::front(), Style::Shaded, &mut canvas);
    let upper = canvas.color(40, 15).unwrap().luma();
    let lower = canvas.color(40, 68).unwrap().luma();
    assert!(upper > lower + 0.3, "upper {upper} lower {lower}");
    // Dithered, the upper part has more lit dots than the lower part.
    let dithered = draw(
        &mesh,
        &mesh.positions,
        &Camera::front(),
        Style::Shaded,
        80,
        80,
    );
    let count = |y0: usize, y1: usize| {
        (y0..y1)
            .flat_map(|y| (20..60).map(move |x| (x, y)))
            .filter(|&(x, y)| dithered.is_on(x, y))
            .count()
    };
    assert!(count(10, 25) > 2 * count(60, 75));
}

#[test]
fn overlays_are_drawn_on_top_with_their_layers() {
    let mesh = sphere(12, 24);
    let overlays = [
        Overlay {
            shape: Shape::Segment {
                from: Vec3::new(-0.5, 0.0, 0.0),
                to: Vec3::new(0.5, 0.0, 0.0),
            },
            color: Rgb(255, 0, 0),
            selected: false,
        },
        Overlay {
            shape: Shape::Point {
                at: Vec3::new(0.0, -0.5, 0.0),
            },
            color: Rgb(0, 255, 0),
            selected: true,
        },
    ];
    let scene = Scene::new(&mesh, &mesh.positions).with_overlays(&overlays);
    let mut canvas = DotCanvas::new(80, 80);
    Renderer::new(&mesh).render(&scene, &Camera::front(), Style::Shaded, &mut canvas);
    // The segment passes through the centre, inside the sphere, yet is drawn.
    assert_eq!(canvas.color(40, 40), Some(Rgb(255, 0, 0)));
    assert_eq!(canvas.layer(40, 40), Layer::Overlay);
    let pivot_y = 40 + (0.5f32 * 37.6) as usize;
    assert_eq!(canvas.layer(40, pivot_y), Layer::Selected);
}

#[test]
fn muscle_overlays_cover_every_muscle_and_the_jaw() {
    use grimace::model::{
        Convergence, Jaw, Linear, Muscle, MuscleKind, Rig, Sheet, Side, Sphincter,
    };
    let linear = Muscle {
        name: "L_Zygomatic_Major".into(),
        side: Side::Left,
        mirror: None,
        kind: MuscleKind::Linear(Linear {
            attachment: Vec3::new(-0.5, 0.2, 0.0),
            insertion: Vec3::new(-0.2, -0.3, 0.5),
            zone: 40.0,
            falloff_start: 0.1,
            falloff_end: 0.6,
        }),
    };
    let sphincter = Muscle {
        name: "Orbicularis_Oris".into(),
        side: Side::Centre,
        mirror: None,
        kind: MuscleKind::Sphincter(Sphincter {
            centre: Vec3::new(0.0, -0.5, 0.5),
            semi_major: 0.3,
            semi_minor: 0.1,
            convergence: Convergence::Centre,
            bulge: 10.0,
            frame: Frame::IDENTITY,
        }),
    };
    let sheet = Muscle {
        name: "Frontalis".into(),
        side: Side::Centre,
        mirror: None,
        kind: MuscleKind::Sheet(Sheet {
            attachment: [Vec3::new(-0.3, 0.9, 0.0), Vec3::new(0.3, 0.9, 0.0)],
            insertion: [Vec3::new(-0.3, 0.5, 0.5), Vec3::new(0.3, 0.5, 0.5)],
            length: 0.5,
            width: 0.6,
        }),
    };
    let rig = Rig {
        masks: Vec::new(),
        version: grimace::model::RIG_VERSION,
        mesh: "builtin:default".into(),
        landmarks: None,
        combine: Default::default(),
        muscles: vec![linear, sphincter, sheet],
        jaw: Some(Jaw {
            axis: glam::Vec3::X,
            slide: glam::Vec3::ZERO,
            pivot: Vec3::new(0.0, -0.2, -0.5),
            degrees_per_unit: 1.0,
            weights: vec![],
        }),
    };
    let palette = Palette::default();
    let mut overlays = Vec::new();
    muscle_overlays(&rig, Some(1), &palette, &mut overlays);
    assert_eq!(overlays.len(), 4);
    assert!(matches!(overlays[0].shape, Shape::Segment { .. }));
    assert!(matches!(overlays[1].shape, Shape::Ellipse { .. }));
    assert!(matches!(overlays[2].shape, Shape::Quad { .. }));
    assert!(matches!(overlays[3].shape, Shape::Point { .. }));
    assert!(overlays[1].selected && overlays[1].color == palette.selected);
    assert_eq!(overlays.iter().filter(|o| o.selected).count(), 1);
}

#[test]
fn ghost_and_displacement_colours_show_motion() {
    let mesh = sphere(12, 24);
    let moved: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| *p + Vec3::new(0.3, 0.0, 0.0))
        .collect();
    let palette = Palette::default();
    let scene = Scene {
        ghost: true,
        displacement: true,
        ..Scene::new(&mesh, &moved).with_rest(&mesh.positions)
    };
    let mut canvas = DotCanvas::new(80, 80);
    Renderer::new(&mesh).render(&scene, &Camera::front(), Style::Lines, &mut canvas);
    let mut ghost = 0;
    let mut hot = 0;
    for (x, y) in lit_dots(&canvas) {
        match canvas.layer(x, y) {
            Layer::Ghost => {
                ghost += 1;
                assert_eq!(canvas.color(x, y), Some(palette.ghost));
            }
            Layer::Mesh => {
                assert_ne!(canvas.color(x, y), Some(palette.mesh), "every vertex moved");
                hot += 1;
            }
            other => panic!("unexpected layer {other:?}"),
        }
    }
    assert!(ghost > 30 && hot > 30, "ghost {ghost} hot {hot}");
}

#[test]
fn degenerate_input_does_not_panic() {
    let empty = Mesh::default();
    let canvas = draw(&empty, &[], &Camera::front(), Style::Lines, 40, 40);
    assert_eq!(canvas.count_on(), 0);
    let mesh = sphere(6, 8);
    for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
        assert_eq!(
            draw(&mesh, &mesh.positions, &Camera::front(), style, 0, 0).count_on(),
            0
        );
        assert_eq!(
            draw(&mesh, &mesh.positions, &Camera::front(), style, 0, 30).count_on(),
            0
        );
        // A NaN vertex: its triangles are skipped, the rest is drawn.
        let mut nan = mesh.positions.clone();
        nan[0] = Vec3::NAN;
        assert!(draw(&mesh, &nan, &Camera::front(), style, 40, 40).count_on() > 10);
        // Too few positions: the missing vertices are skipped.
        assert!(
            draw(
                &mesh,
                &mesh.positions[..10],
                &Camera::front(),
                style,
                40,
                40
            )
            .count_on()
                > 0
        );
        // All vertices at one point; absurd camera values.
        let point = vec![Vec3::ONE; mesh.positions.len()];
        draw(&mesh, &point, &Camera::front(), style, 40, 40);
        let wild = Camera {
            yaw: f32::NAN,
            pitch: 1e30,
            zoom: 1e9,
            pan: Vec2::new(f32::INFINITY, 3.0),
            basis: glam::Mat3::from_cols_array(&[f32::NAN; 9]),
        };
        draw(&mesh, &mesh.positions, &wild, style, 40, 40);
        let huge = Camera {
            zoom: 1e6,
            ..Camera::front()
        };
        draw(&mesh, &mesh.positions, &huge, style, 40, 40);
    }
}

#[test]
fn the_canvas_is_reused_between_frames() {
    let mesh = sphere(8, 12);
    let mut renderer = Renderer::new(&mesh);
    let mut canvas = CellMode::Braille.canvas(30, 10);
    let scene = Scene::new(&mesh, &mesh.positions);
    renderer.render(&scene, &Camera::front(), Style::Lines, &mut canvas);
    let first = lit_dots(&canvas);
    renderer.render(&scene, &Camera::side(), Style::Shaded, &mut canvas);
    renderer.render(&scene, &Camera::front(), Style::Lines, &mut canvas);
    assert_eq!(
        lit_dots(&canvas),
        first,
        "no leftovers from the previous frame"
    );
    assert_eq!((canvas.width(), canvas.height()), (60, 40));
}

proptest! {
    #[test]
    fn arbitrary_meshes_and_cameras_never_panic(
        points in prop::collection::vec((-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0), 3..30),
        tris in prop::collection::vec((0u32..40, 0u32..40, 0u32..40), 1..40),
        yaw in -7.0f32..7.0,
        pitch in -7.0f32..7.0,
        zoom in 0.0f32..50.0,
        w in 0usize..50,
        h in 0usize..50,
    ) {
        let positions: Vec<Vec3> = points.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect();
        let n = positions.len() as u32;
        let triangles: Vec<[u32; 3]> = tris.iter().map(|&(a, b, c)| [a % n, b % n, c % n]).collect();
        let mesh = Mesh { positions, triangles, groups: Default::default() };
        let camera = Camera { yaw, pitch, zoom, ..Camera::front() };
        for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
            let scene = Scene { ghost: true, displacement: true, contours: 3, ..Scene::new(&mesh, &mesh.positions) };
            let mut canvas = DotCanvas::new(w, h);
            Renderer::new(&mesh).render(&scene, &camera, style, &mut canvas);
        }
    }
}

/// Fitting points rather than their box centres a turned, one-sided shape (like a face,
/// which has no back) on what is drawn.
#[test]
fn fitting_points_centres_a_turned_one_sided_shape() {
    // A square plate at z = 1; its box below reaches back to z = -3, like a head's.
    let plate = &[
        Vec3::new(-1.0, -1.0, 1.0),
        Vec3::new(1.0, -1.0, 1.0),
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(-1.0, 1.0, 1.0),
    ];
    let camera = Camera::three_quarter();
    let proj = camera.fit_points(plate, 200, 200, 1.0);
    let xs: Vec<f32> = plate.iter().map(|p| proj.project(*p).x).collect();
    let (lo, hi) = xs
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    assert!(((lo + hi) * 0.5 - 100.0).abs() < 1e-3, "{lo}..{hi}");
    // Fitting that deep box instead puts the plate off-centre.
    let boxed = camera.fit(
        (Vec3::new(-1.0, -1.0, -3.0), Vec3::new(1.0, 1.0, 1.0)),
        200,
        200,
        1.0,
    );
    let xs: Vec<f32> = plate.iter().map(|p| boxed.project(*p).x).collect();
    let (lo, hi) = xs
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    assert!(((lo + hi) * 0.5 - 100.0).abs() > 5.0, "{lo}..{hi}");
    // Non-finite points are ignored.
    let mut with_nan = plate.to_vec();
    with_nan.push(Vec3::NAN);
    assert_eq!(camera.fit_points(&with_nan, 200, 200, 1.0), proj);
}
