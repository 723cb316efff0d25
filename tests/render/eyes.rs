//! The default face's eyes: the iris and pupil read in every style.

use crate::common;

use glam::{Vec2, Vec3};
use grimace::face::anthropometry::{units, y_units};
use grimace::face::generator::EYEBALL;
use grimace::face::groups::skin_len;
use grimace::face::rigs::skin_under;
use grimace::io::builtin;
use grimace::model::Mesh;
use grimace::render::{Camera, CellMode, DotCanvas, Framing, Projection, Renderer, Scene, Style};

const COLS: usize = 200;
const ROWS: usize = 60;

/// The face without its eyeballs: the skin vertices and the triangles on them.
fn skin_only(mesh: &Mesh) -> Mesh {
    let n = skin_len(mesh);
    let triangles = mesh
        .triangles
        .iter()
        .filter(|t| t.iter().all(|&v| (v as usize) < n))
        .copied()
        .collect();
    Mesh::new(mesh.positions[..n].to_vec(), triangles).expect("the skin is a valid mesh")
}

/// A point on the front of an eye at `rho` mm from its axis, at angle `a`, at the depth of
/// the limbus (`sign` 1 for the subject's left eye).
fn on_eye(sign: f32, rho: f64, a: f64) -> Vec3 {
    let [cx, cy, cz] = EYEBALL.centre;
    let front = (EYEBALL.radius.powi(2) - EYEBALL.iris_radius.powi(2)).sqrt();
    Vec3::new(
        sign * units(cx + rho * a.cos()) as f32,
        y_units(cy + rho * a.sin()) as f32,
        units(cz + front) as f32,
    )
}

/// Whether the open eye shows the point: no skin lies over it, nor 1.5 mm above or below it
/// (so a lid margin's own line does not count).
fn in_the_opening(skin: &Mesh, p: Vec3) -> bool {
    let d = units(1.5) as f32;
    [-d, 0.0, d]
        .iter()
        .all(|dy| skin_under(skin, p.x, p.y + dy).is_none())
}

fn render(mesh: &Mesh, style: Style) -> (DotCanvas, Projection) {
    let mut canvas = CellMode::Braille.canvas(COLS, ROWS);
    let scene = Scene::new(mesh, &mesh.positions);
    let camera = Camera::front();
    Renderer::new(mesh).render(&scene, &camera, style, &mut canvas);
    let proj = camera.fit_points(
        &mesh.positions,
        canvas.width(),
        canvas.height(),
        canvas.dot_aspect,
    );
    (canvas, proj)
}

#[test]
fn the_iris_is_a_circle_line_inside_the_open_eye() {
    let mesh = builtin::default_mesh();
    let skin = skin_only(&mesh);
    let (canvas, proj) = render(&mesh, Style::Lines);
    let (bare, bare_proj) = render(&skin, Style::Lines);
    for sign in [1.0f32, -1.0] {
        let mut shown = 0;
        let mut drawn = 0;
        let mut drawn_bare = 0;
        for k in 0..48 {
            let a = std::f64::consts::TAU * f64::from(k) / 48.0;
            let p = on_eye(sign, EYEBALL.iris_radius, a);
            if !in_the_opening(&skin, p) {
                continue;
            }
            shown += 1;
            if common::lit_near(&canvas, proj.project(p).truncate(), 1.0) {
                drawn += 1;
            }
            if common::lit_near(&bare, bare_proj.project(p).truncate(), 1.0) {
                drawn_bare += 1;
            }
        }
        // the sides of the iris show between the lids; its top and bottom are under them
        assert!(shown >= 12, "only {shown} points of the iris's rim show");
        assert!(
            drawn * 10 >= shown * 9,
            "eye {sign}: {drawn} of {shown} points of the iris's rim are drawn"
        );
        assert!(
            drawn_bare * 4 < shown,
            "eye {sign}: without eyeballs {drawn_bare} of {shown} are drawn too"
        );
        // the pupil's rim is drawn as well
        let pupil = (0..16)
            .map(|k| {
                on_eye(
                    sign,
                    EYEBALL.pupil_radius,
                    std::f64::consts::TAU * k as f64 / 16.0,
                )
            })
            .filter(|p| common::lit_near(&canvas, proj.project(*p).truncate(), 1.0))
            .count();
        assert!(
            pupil >= 14,
            "eye {sign}: {pupil} of 16 points of the pupil's rim drawn"
        );
    }
}

/// The share of lit dots over the front-view points of an eye between `inner` and `outer`
/// mm from its axis, where the eye is open.
fn ink(canvas: &DotCanvas, proj: &Projection, skin: &Mesh, inner: f64, outer: f64) -> f64 {
    let (mut lit, mut all) = (0usize, 0usize);
    let mut seen = std::collections::BTreeSet::new();
    for sign in [1.0f32, -1.0] {
        for i in 0..=40 {
            for k in 0..96 {
                let rho = inner + (outer - inner) * f64::from(i) / 40.0;
                let p = on_eye(sign, rho, std::f64::consts::TAU * f64::from(k) / 96.0);
                if skin_under(skin, p.x, p.y).is_some() {
                    continue;
                }
                let d: Vec2 = proj.project(p).truncate();
                let (x, y) = (d.x as usize, d.y as usize);
                if seen.insert((x, y)) {
                    all += 1;
                    lit += usize::from(canvas.is_on(x, y));
                }
            }
        }
    }
    assert!(all >= 20, "only {all} dots between {inner} and {outer} mm");
    lit as f64 / all as f64
}

#[test]
fn shaded_the_iris_is_darker_than_the_white_and_the_pupil_darkest() {
    let mesh = builtin::default_mesh();
    let skin = skin_only(&mesh);
    let (canvas, proj) = render(&mesh, Style::Shaded);
    let sclera = ink(&canvas, &proj, &skin, EYEBALL.iris_radius + 1.0, 10.0);
    let iris = ink(
        &canvas,
        &proj,
        &skin,
        EYEBALL.pupil_radius + 0.7,
        EYEBALL.iris_radius - 0.7,
    );
    let pupil = ink(&canvas, &proj, &skin, 0.0, EYEBALL.pupil_radius - 0.5);
    assert!(
        iris < 0.7 * sclera,
        "iris {iris:.2} of its dots lit, the white {sclera:.2}"
    );
    assert!(pupil < 0.5 * iris, "pupil {pupil:.2}, iris {iris:.2}");
}

/// The default face with its irises and pupils taken away: blank eyeballs.
fn blank_eyed() -> Mesh {
    let mut mesh = builtin::default_mesh();
    mesh.groups
        .retain(|name, _| !name.contains("iris") && !name.contains("pupil"));
    assert!(mesh.groups.keys().any(|name| name.contains("eyeball")));
    mesh
}

/// The luma of the lit dot nearest `p` (within two dots), or `None` where none is lit.
fn luma_near(canvas: &DotCanvas, p: Vec2) -> Option<f32> {
    let mut best: Option<(f32, f32)> = None;
    for dy in -2i32..=2 {
        for dx in -2i32..=2 {
            let (x, y) = (p.x as i32 + dx, p.y as i32 + dy);
            if x < 0 || y < 0 || !canvas.is_on(x as usize, y as usize) {
                continue;
            }
            let d = (dx * dx + dy * dy) as f32;
            let luma = canvas.color(x as usize, y as usize).map(|c| c.luma());
            if let (Some(l), true) = (luma, best.is_none_or(|(bd, _)| d < bd)) {
                best = Some((d, l));
            }
        }
    }
    best.map(|(_, l)| l)
}

#[test]
fn blank_eyes_get_irises_where_the_landmarks_put_them() {
    let mesh = blank_eyed();
    let points = builtin::landmarks("default")
        .expect("the default face has landmarks")
        .positions(&mesh)
        .expect("they lie on it");
    let framing = Framing::of_face(None, &mesh, Some(&points), None);
    assert_eq!(framing.irises.len(), 2, "one iris per eye");
    let camera = Camera::front();
    let draw = |scene: Scene| {
        let mut canvas = CellMode::Braille.canvas(COLS, ROWS);
        // Undithered: a dot's colour is its shade.
        canvas.dither = false;
        Renderer::new(&mesh).render(&scene, &camera, Style::Shaded, &mut canvas);
        canvas
    };
    let painted = draw(Scene::new(&mesh, &mesh.positions).with_framing(&framing));
    let blank = draw(Scene::new(&mesh, &mesh.positions));
    let proj = camera.fit_points(
        &mesh.positions,
        painted.width(),
        painted.height(),
        painted.dot_aspect,
    );
    for iris in &framing.irises {
        // The pupil at the centre, the iris half way out, the sclera beyond the iris.
        let at = |r: f32| {
            proj.project(iris.centre + iris.across * iris.radius * r)
                .truncate()
        };
        let luma = |canvas: &DotCanvas, r: f32| {
            luma_near(canvas, at(r)).unwrap_or_else(|| panic!("no dot drawn at {r} iris radii"))
        };
        // The sclera beside the iris, on the side the light comes from (the renderer's
        // light is to the viewer's left, the subject's right).
        let sclera = luma(&painted, -1.5).max(luma(&painted, 1.5));
        for r in [-0.2, 0.0, 0.2] {
            let (p, b) = (luma(&painted, r), luma(&blank, r));
            assert!(
                p < 0.25 * sclera && p < 0.25 * b,
                "pupil at {r}: {p} against the sclera's {sclera} and the blank eye's {b}"
            );
        }
        for r in [-0.7, 0.7] {
            let p = luma(&painted, r);
            assert!(
                (0.25 * sclera..0.75 * sclera).contains(&p),
                "iris at {r}: {p} against the sclera's {sclera}"
            );
        }
    }
    // The face's own irises are left as they are.
    let own = builtin::default_mesh();
    let mut a = CellMode::Braille.canvas(COLS, ROWS);
    let mut b = CellMode::Braille.canvas(COLS, ROWS);
    let scene = Scene::new(&own, &own.positions);
    Renderer::new(&own).render(&scene, &camera, Style::Shaded, &mut a);
    let with = Scene::new(&own, &own.positions).with_framing(&framing);
    Renderer::new(&own).render(&with, &camera, Style::Shaded, &mut b);
    let colors = |c: &DotCanvas| {
        (0..c.height())
            .flat_map(|y| (0..c.width()).map(move |x| (x, y)))
            .map(|(x, y)| c.color(x, y))
            .collect::<Vec<_>>()
    };
    assert!(
        colors(&a) == colors(&b),
        "a face with irises of its own is drawn as it was"
    );
}

/// The shade of the last (nearest) of `triangles` drawn over the dot `p`.
fn top_shade(triangles: &[grimace::render::LitTriangle], p: Vec2) -> Option<f32> {
    let inside = |[a, b, c]: [Vec2; 3]| {
        let s = [(a, b), (b, c), (c, a)].map(|(u, v)| (v - u).perp_dot(p - u));
        let area = (b - a).perp_dot(c - a);
        area != 0.0 && (s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0))
    };
    triangles
        .iter()
        .rev()
        .find(|t| inside(t.corners))
        .map(|t| t.shade)
}

#[test]
fn vector_output_paints_the_same_irises() {
    let mesh = blank_eyed();
    let points = builtin::landmarks("default")
        .unwrap()
        .positions(&mesh)
        .unwrap();
    let framing = Framing::of_face(None, &mesh, Some(&points), None);
    let camera = Camera::front();
    let (w, h) = (400, 400);
    let painted = Renderer::new(&mesh).lit_triangles(
        &Scene::new(&mesh, &mesh.positions).with_framing(&framing),
        &camera,
        w,
        h,
        1.0,
    );
    let blank =
        Renderer::new(&mesh).lit_triangles(&Scene::new(&mesh, &mesh.positions), &camera, w, h, 1.0);
    assert!(painted.len() > blank.len(), "the irises add pieces");
    let proj = camera.fit_points(&mesh.positions, w, h, 1.0);
    for iris in &framing.irises {
        let at = |r: f32| {
            proj.project(iris.centre + iris.across * iris.radius * r)
                .truncate()
        };
        let pupil = top_shade(&painted, at(0.0)).expect("the pupil is drawn");
        let ring = top_shade(&painted, at(0.7)).expect("the iris is drawn");
        let bare = top_shade(&blank, at(0.0)).expect("the blank eye is drawn");
        assert!(
            pupil < 0.2 && pupil < 0.5 * ring,
            "pupil {pupil}, iris {ring}"
        );
        assert!(
            bare > 2.0 * pupil,
            "the blank eye {bare} against the pupil {pupil}"
        );
    }
}
