//! Property tests of the rasterizer's fast paths against their plain references.

use glam::Vec3;
use proptest::prelude::*;

use super::depth::*;
use super::features::{crosses, iso_crossing};
use super::fill::{normalize_or_zero_all, raster_triangle};
use super::grid::{ceil_nonneg, floor_end};
use super::lines::*;
use crate::render::canvas::{DotCanvas, Pen, Rgb};

const W: usize = 40;
const H: usize = 32;

/// A corner a little beyond the canvas on every side, with depth.
fn corner() -> impl Strategy<Value = Vec3> {
    (-6.0f32..46.0, -6.0f32..38.0, -50.0f32..50.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Corners snapped to quarter dots, so that edges through dot centres and shared
/// corners (the cases rounding decides) come up often.
fn snapped_corner() -> impl Strategy<Value = Vec3> {
    (-24i32..184, -24i32..152, -50.0f32..50.0)
        .prop_map(|(x, y, z)| Vec3::new(x as f32 * 0.25, y as f32 * 0.25, z))
}

/// A corner far off the canvas, up to overflowing every integer conversion.
fn far_corner() -> impl Strategy<Value = Vec3> {
    let far = prop_oneof![-1e12f32..1e12, Just(f32::INFINITY), Just(f32::NEG_INFINITY)];
    (far, -6.0f32..38.0, -50.0f32..50.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn any_corner() -> impl Strategy<Value = Vec3> {
    prop_oneof![4 => corner(), 4 => snapped_corner(), 1 => far_corner()]
}

/// A depth buffer with some dots already drawn.
fn depth_buffer() -> impl Strategy<Value = Vec<f32>> {
    proptest::collection::vec(prop_oneof![Just(f32::NEG_INFINITY), -60.0f32..60.0], W * H)
}

/// The general rasterizer keeping the nearer depth, as the depth pass did before it had
/// its own loop.
fn reference_depth(p: [Vec3; 3], depth: &mut [f32]) {
    raster_triangle(p, [0.0; 3], W, H, |i, _, _, z, _| {
        if z > depth[i] {
            depth[i] = z;
        }
    });
}

/// The line stepping as it was before the inside-the-canvas shortcut: always clipped.
fn reference_walk(a: Vec3, b: Vec3, w: usize, h: usize) -> Vec<(usize, usize, Vec3)> {
    let mut out = Vec::new();
    if !a.is_finite() || !b.is_finite() || w == 0 || h == 0 {
        return out;
    }
    let Some((a, b)) = clip(a, b, w as f32, h as f32) else {
        return out;
    };
    let d = b - a;
    let steps = ceil_nonneg(d.x.abs().max(d.y.abs())).max(1);
    let inc = d / steps as f32;
    let mut p = a;
    for _ in 0..=steps {
        out.push(((p.x as usize).min(w - 1), (p.y as usize).min(h - 1), p));
        p += inc;
    }
    out
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|z| z.to_bits()).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The depth pass's own loop lights the same dots with the same depths, bit for
    /// bit, as the general rasterizer.
    #[test]
    fn depth_triangle_matches_the_general_rasterizer(
        a in any_corner(), b in any_corner(), c in any_corner(), start in depth_buffer(),
    ) {
        let mut expected = start.clone();
        reference_depth([a, b, c], &mut expected);
        let mut got = start;
        depth_triangle([a, b, c], W, H, &mut got);
        prop_assert_eq!(bits(&got), bits(&expected));
    }

    /// The branch-free span ends agree with the rasterizer's rounding helpers on any
    /// value, NaN and infinities included.
    #[test]
    fn span_ends_match_the_rounding_helpers(
        v in prop_oneof![
            4 => -50.0f32..500.0,
            2 => (-200i32..2000).prop_map(|k| k as f32 * 0.25),
            1 => proptest::num::f32::ANY,
        ],
        limit in 0usize..400,
    ) {
        let (start, end) = span(v, limit);
        prop_assert_eq!(start as usize, ceil_nonneg(v).min(limit));
        prop_assert_eq!(end as usize, floor_end(v, limit));
    }

    /// The box from the corners' spans is the box the rasterizer computes.
    #[test]
    fn the_box_from_vertex_spans_is_the_rasterizer_box(
        a in any_corner(), b in any_corner(), c in any_corner(),
    ) {
        let got = triangle_box([a, b, c].map(|p| dot_span(p, W, H)));
        let x0 = ceil_nonneg(a.x.min(b.x).min(c.x) - 0.5);
        let x1 = floor_end(a.x.max(b.x).max(c.x) - 0.5, W);
        let y0 = ceil_nonneg(a.y.min(b.y).min(c.y) - 0.5);
        let y1 = floor_end(a.y.max(b.y).max(c.y) - 0.5, H);
        // Starts are clamped to the canvas; a start past it is an empty range either way.
        prop_assert_eq!(got, [x0.min(W), x1, y0.min(H), y1]);
        let mut expected = vec![f32::NEG_INFINITY; W * H];
        depth_triangle([a, b, c], W, H, &mut expected);
        let mut via_spans = vec![f32::NEG_INFINITY; W * H];
        depth_triangle_in([a, b, c], got, W, None, &mut via_spans);
        prop_assert_eq!(bits(&via_spans), bits(&expected));
    }

    /// Hidden-line removal does not change: on every dot a line visits, the depth
    /// buffer filled only under the lines equals the one filled everywhere.
    #[test]
    fn the_depth_under_every_line_dot_is_the_full_depth(
        tris in proptest::collection::vec((any_corner(), any_corner(), any_corner()), 1..40),
        lines in proptest::collection::vec((any_corner(), any_corner()), 1..6),
    ) {
        let mut mask = DotMask::default();
        mask.reset(W, H);
        for &(a, b) in &lines {
            mask.mark_line(a, b, W, H);
        }
        let mut full = vec![f32::NEG_INFINITY; W * H];
        let mut culled = vec![f32::NEG_INFINITY; W * H];
        for &(a, b, c) in &tris {
            depth_triangle([a, b, c], W, H, &mut full);
            let [x0, x1, y0, y1] = triangle_box([a, b, c].map(|p| dot_span(p, W, H)));
            if x0 < x1 && y0 < y1 && mask.any(x0, x1, y0, y1) {
                depth_triangle_in([a, b, c], [x0, x1, y0, y1], W, Some(&mask), &mut culled);
            }
        }
        for &(a, b) in &lines {
            let mut visited = 0;
            walk_line(a, b, W, H, |x, y, _| {
                visited += 1;
                assert_eq!(culled[y * W + x].to_bits(), full[y * W + x].to_bits());
            });
            prop_assert_eq!(visited, reference_walk(a, b, W, H).len());
        }
    }

    /// The mask's box test agrees with looking at every dot of the box.
    #[test]
    fn the_mask_box_test_matches_a_dot_by_dot_scan(
        dots in proptest::collection::vec((0usize..150, 0usize..9), 0..6),
        x0 in 0usize..150, dx in 1usize..80, y0 in 0usize..9, dy in 1usize..4,
    ) {
        let (w, h) = (150, 9);
        let mut mask = DotMask::default();
        mask.reset(w, h);
        for &(x, y) in &dots {
            let p = Vec3::new(x as f32 + 0.5, y as f32 + 0.5, 0.0);
            mask.mark_line(p, p, w, h);
        }
        let (x1, y1) = ((x0 + dx).min(w), (y0 + dy).min(h));
        let brute = dots.iter().any(|&(x, y)| (x0..x1).contains(&x) && (y0..y1).contains(&y));
        prop_assert_eq!(mask.any(x0, x1, y0, y1), brute);
        for y in y0..y1 {
            let last = dots
                .iter()
                .filter(|&&(x, dy)| dy == y && (x0..x1).contains(&x))
                .map(|&(x, _)| x + 1)
                .max();
            prop_assert_eq!(mask.last_set(y, x0, x1), last);
        }
    }

    /// Skipping the clip for lines inside the canvas visits the same dots at the same
    /// points as clipping.
    #[test]
    fn walking_a_line_matches_the_clipped_walk(a in any_corner(), b in any_corner()) {
        let mut got = Vec::new();
        walk_line(a, b, W, H, |x, y, p| got.push((x, y, p)));
        let expected = reference_walk(a, b, W, H);
        prop_assert_eq!(got.len(), expected.len());
        for (g, e) in got.iter().zip(&expected) {
            prop_assert_eq!((g.0, g.1), (e.0, e.1));
            prop_assert_eq!(g.2.to_array().map(f32::to_bits), e.2.to_array().map(f32::to_bits));
        }
    }

    /// Normalizing four at a time gives the same bits as one at a time.
    #[test]
    fn normalizing_in_fours_matches_glam(
        v in proptest::collection::vec(
            proptest::array::uniform3(prop_oneof![
                4 => -10.0f32..10.0,
                1 => Just(0.0f32),
                1 => proptest::num::f32::ANY,
                1 => -1e-20f32..1e-20,
            ]),
            0..11,
        ),
    ) {
        let v: Vec<Vec3> = v.into_iter().map(Vec3::from_array).collect();
        let mut got = v.clone();
        normalize_or_zero_all(&mut got);
        for (g, n) in got.iter().zip(&v) {
            let e = n.normalize_or_zero();
            prop_assert_eq!(g.to_array().map(f32::to_bits), e.to_array().map(f32::to_bits));
        }
    }

    /// Drawing steps walked ahead lights the same dots, in the same colours, and
    /// reports the same visible pieces as drawing the line itself.
    #[test]
    fn drawing_walked_steps_matches_drawing_the_line(
        tris in proptest::collection::vec((any_corner(), any_corner(), any_corner()), 0..12),
        lines in proptest::collection::vec((any_corner(), any_corner(), 0.0f32..4.0), 1..6),
    ) {
        let mut direct = DotCanvas::new(W, H);
        {
            let (depth, _, _, _) = direct.buffers_mut();
            for &(a, b, c) in &tris {
                depth_triangle([a, b, c], W, H, depth);
            }
        }
        let mut walked = direct.clone();
        let color = Rgb(1, 2, 3);
        let (mut direct_runs, mut walked_runs) = (Vec::new(), Vec::new());
        for &(a, b, bias) in &lines {
            let pen = Pen::mesh(color, bias);
            draw_line(&mut direct, Some(&mut direct_runs), a, b, pen);
            let mut dots = Vec::new();
            walk_line(a, b, W, H, |x, y, p| dots.push(LineDot { x: x as u32, y: y as u32, p }));
            draw_walked(&mut walked, Some(&mut walked_runs), &dots, pen);
        }
        prop_assert_eq!(direct_runs, walked_runs);
        for y in 0..H {
            for x in 0..W {
                prop_assert_eq!(direct.color(x, y), walked.color(x, y));
                prop_assert_eq!(direct.layer(x, y), walked.layer(x, y));
            }
        }
    }

    /// The cheap crossing test says yes exactly when the crossing finds a segment.
    #[test]
    fn crosses_agrees_with_iso_crossing(
        f in proptest::array::uniform3(prop_oneof![Just(f32::NAN), Just(0.5f32), -1.0f32..2.0]),
        level in prop_oneof![Just(0.5f32), -1.0f32..2.0],
    ) {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        prop_assert_eq!(crosses(f, level), iso_crossing(p, f, level).is_some());
    }
}

/// The shaded style drawn plainly: each triangle dot by dot, its planes evaluated at each
/// dot centre, each dot lit as a nearer triangle is drawn over it.
fn reference_shaded(
    renderer: &super::Renderer,
    scene: &crate::render::Scene,
    canvas: &mut DotCanvas,
) {
    use super::brow::in_band;
    use super::fill::{float_box, plane_at, reference_light, BROW_TONE};
    use crate::render::canvas::Layer;
    let (w, h, dither) = (canvas.width(), canvas.height(), canvas.dither);
    let base = scene.palette.mesh;
    let (depth, on, color, layer) = canvas.buffers_mut();
    for (t, tri) in renderer.triangles.iter().enumerate() {
        if !renderer.facing[t] {
            continue;
        }
        let p = tri.map(|i| renderer.projected[i as usize]);
        let [a, b, c] = p;
        let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if !area.is_finite() || area.abs() < 1e-9 {
            continue;
        }
        let [wa, wb] = corner_weights(p, area);
        let plane = |v: [f32; 3]| {
            let ((ax, ay, a0), (bx, by, b0)) = (wa, wb);
            (
                ax * (v[0] - v[2]) + bx * (v[1] - v[2]),
                ay * (v[0] - v[2]) + by * (v[1] - v[2]),
                a0 * (v[0] - v[2]) + b0 * (v[1] - v[2]) + v[2],
            )
        };
        let z = plane([a.z, b.z, c.z]);
        let s = plane(tri.map(|i| renderer.vertex_shade[i as usize]));
        // A triangle a brow band's edge crosses: its shade before the brow's tone, and its
        // corners' band coordinates (`brow`).
        let brow = renderer
            .brows
            .binary_search_by_key(&(t as u32), |b| b.triangle)
            .ok()
            .map(|k| {
                let b = renderer.brows[k];
                let untoned = b
                    .corners_in_band()
                    .map(|inside| if inside { BROW_TONE } else { 1.0 });
                let shade = [0, 1, 2].map(|k| renderer.vertex_shade[tri[k] as usize] / untoned[k]);
                (plane(shade), plane(b.along), plane(b.across))
            });
        let k = (!renderer.vertex_heat.is_empty())
            .then(|| plane(tri.map(|i| renderer.vertex_heat[i as usize])));
        let [x0, x1, y0, y1] = float_box(p, w, h);
        for y in y0..y1 {
            for x in x0..x1 {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let (la, lb) = (plane_at(wa, px, py), plane_at(wb, px, py));
                let inside = la >= -1e-5 && lb >= -1e-5 && 1.0 - la - lb >= -1e-5;
                let zi = plane_at(z, px, py);
                let i = y * w + x;
                if inside && zi > depth[i] {
                    depth[i] = zi;
                    let heat = k.map(|k| plane_at(k, px, py));
                    let shade = match brow {
                        Some((untoned, along, across)) => {
                            let inside = in_band(plane_at(along, px, py), plane_at(across, px, py));
                            plane_at(untoned, px, py) * if inside { BROW_TONE } else { 1.0 }
                        }
                        None => plane_at(s, px, py),
                    };
                    let (lit, rgb) = reference_light(base, dither, x, y, shade, heat);
                    on[i] = lit;
                    color[i] = rgb;
                    layer[i] = if lit { Layer::Mesh } else { Layer::Empty };
                }
            }
        }
    }
}

/// The shaded fill (four dots at a time, then lit in a second step) lights the same dots
/// in the same colours, with the same depths, as drawing each triangle dot by dot: the default face at rest and smiling, with
/// and without displacement colours, dithered and not, from several cameras and sizes.
#[test]
fn the_shaded_fill_matches_drawing_dot_by_dot() {
    use crate::io::builtin;
    use crate::model::BoundRig;
    use crate::render::{Camera, CellMode, Scene, Style};
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let table = builtin::default_table();
    let bound = BoundRig::bind(&rig, &mesh).unwrap();
    let act = table.expression_activations("happiness", &rig).unwrap();
    let mut smile = Vec::new();
    bound.deform(&act, &mut smile).unwrap();
    let cameras = [
        Camera::front(),
        Camera::three_quarter(),
        Camera::side(),
        Camera {
            zoom: 3.0,
            pan: glam::Vec2::new(2.0, -1.0),
            ..Camera::three_quarter()
        },
    ];
    let mut renderer = super::Renderer::new(&mesh);
    let mut compared = 0;
    for positions in [&mesh.positions, &smile] {
        for displacement in [false, true] {
            for camera in &cameras {
                for (mode, cols, rows) in [
                    (CellMode::Braille, 80, 24),
                    (CellMode::HalfBlock, 57, 31),
                    (CellMode::Ascii, 200, 60),
                ] {
                    let mut scene = Scene::new(&mesh, positions).with_rest(&mesh.positions);
                    scene.displacement = displacement;
                    let mut fast = mode.canvas(cols, rows);
                    renderer.render(&scene, camera, Style::Shaded, &mut fast);
                    let mut slow = mode.canvas(cols, rows);
                    reference_shaded(&renderer, &scene, &mut slow);
                    for y in 0..fast.height() {
                        for x in 0..fast.width() {
                            assert_eq!(
                                fast.depth(x, y).to_bits(),
                                slow.depth(x, y).to_bits(),
                                "depth at {x},{y}"
                            );
                            assert_eq!(fast.color(x, y), slow.color(x, y), "at {x},{y}");
                            assert_eq!(fast.layer(x, y), slow.layer(x, y), "at {x},{y}");
                        }
                    }
                    compared += fast.count_on();
                }
            }
        }
    }
    assert!(compared > 100_000, "{compared} lit dots compared");
}

/// A renderer kept between frames (its camera fit reused while the camera, canvas and rest
/// pose stay the same) draws every frame as a new renderer does, when any of them changes.
#[test]
fn a_kept_renderer_refits_when_camera_canvas_or_rest_pose_change() {
    use crate::io::builtin;
    use crate::render::{Camera, CellMode, Scene, Style};
    let mesh = builtin::default_mesh();
    let moved: Vec<Vec3> = mesh.positions.iter().map(|p| *p * 1.5 + Vec3::X).collect();
    let mut kept = super::Renderer::new(&mesh);
    let frames = [
        (Camera::front(), &mesh.positions, 80, 24),
        (Camera::front(), &mesh.positions, 80, 24),
        (Camera::three_quarter(), &mesh.positions, 80, 24),
        (Camera::three_quarter(), &moved, 80, 24),
        (Camera::three_quarter(), &moved, 57, 31),
        (Camera::front(), &mesh.positions, 80, 24),
    ];
    for (n, (camera, rest, cols, rows)) in frames.into_iter().enumerate() {
        let scene = Scene::new(&mesh, &mesh.positions).with_rest(rest);
        let mut a = CellMode::Braille.canvas(cols, rows);
        let mut b = CellMode::Braille.canvas(cols, rows);
        kept.render(&scene, &camera, Style::Shaded, &mut a);
        super::Renderer::new(&mesh).render(&scene, &camera, Style::Shaded, &mut b);
        let mut lit = 0;
        for y in 0..a.height() {
            for x in 0..a.width() {
                assert_eq!(a.is_on(x, y), b.is_on(x, y), "frame {n}, dot {x},{y}");
                assert_eq!(a.depth(x, y).to_bits(), b.depth(x, y).to_bits());
                lit += a.is_on(x, y) as usize;
            }
        }
        assert!(lit > 500, "frame {n}: {lit} dots lit");
    }
}

/// The edges as sorting every half edge gives them (the reference of `build_edges`).
fn edges_by_sorting(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<(u32, u32, u32, u32)> {
    let mut half = Vec::new();
    for (t, tri) in triangles.iter().enumerate() {
        if tri.iter().any(|&i| i as usize >= vertex_count) {
            continue;
        }
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let (a, b) = (tri[i].min(tri[j]), tri[i].max(tri[j]));
            if a != b {
                half.push((a, b, t as u32));
            }
        }
    }
    half.sort_unstable();
    let mut edges: Vec<(u32, u32, u32, u32)> = Vec::new();
    for (a, b, t) in half {
        match edges.last_mut() {
            Some(e) if (e.0, e.1) == (a, b) => {
                if e.3 == super::NONE {
                    e.3 = t;
                }
            }
            _ => edges.push((a, b, t, super::NONE)),
        }
    }
    edges
}

proptest! {
    /// Bucketed by vertex, the edges come out as sorting them all gives, with degenerate
    /// triangles, out-of-range indices and edges of three triangles among them.
    #[test]
    fn edges_bucketed_by_vertex_are_the_sorted_edges(
        triangles in prop::collection::vec(prop::array::uniform3(0u32..14), 0..60),
    ) {
        let got: Vec<_> = super::features::build_edges(&triangles, 12)
            .iter()
            .map(|e| (e.a, e.b, e.t0, e.t1))
            .collect();
        prop_assert_eq!(got, edges_by_sorting(&triangles, 12));
    }
}

/// The one pass over the triangles (facing, face normals, vertex normals) gives what the
/// separate passes give, bit for bit: bent and partial poses, three views, both windings.
#[test]
fn facing_and_normals_in_one_pass_are_the_separate_passes() {
    use super::project::Normals;
    use crate::io::builtin;
    use crate::render::scene::Orientation;
    use crate::render::{Camera, CellMode, Scene};
    let mesh = builtin::default_mesh();
    let bent: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| *p + Vec3::new(0.0, 0.1 * p.x * p.x, 0.05 * p.y))
        .collect();
    // a pose missing its last vertices: their triangles face nowhere
    let partial = &mesh.positions[..mesh.positions.len() - 50];
    let bits = |v: &[Vec3]| -> Vec<[u32; 3]> {
        v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
    };
    let canvas = CellMode::Braille.canvas(80, 24);
    let size = (canvas.width(), canvas.height(), canvas.dot_aspect);
    for positions in [&mesh.positions[..], &bent, partial] {
        for camera in [Camera::front(), Camera::three_quarter(), Camera::side()] {
            for orientation in [Orientation::Auto, Orientation::Inward] {
                let mut scene = Scene::new(&mesh, positions);
                scene.orientation = orientation;
                let mut apart = super::Renderer::new(&mesh);
                apart.prepare(&scene, &camera, size, Normals::None).unwrap();
                apart.compute_normals(&scene);
                for want in [Normals::Faces, Normals::Vertices] {
                    let mut one = super::Renderer::new(&mesh);
                    one.prepare(&scene, &camera, size, want).unwrap();
                    assert_eq!(one.facing, apart.facing);
                    assert!(one.facing.contains(&true) && one.facing.contains(&false));
                    assert_eq!(bits(&one.face_normals), bits(&apart.face_normals));
                    one.compute_normals(&scene);
                    assert_eq!(bits(&one.normals), bits(&apart.normals));
                }
            }
        }
    }
}
