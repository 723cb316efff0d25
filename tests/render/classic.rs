//! Renders the classic Waters face (read from the shared reference folder and converted to
//! glTF's convention as `grimace import-waters` converts it) in every style and checks that
//! the features come out where they belong.

use crate::common;

use std::path::PathBuf;

use glam::Vec3;
use grimace::io::waters::from_classic;
use grimace::model::Mesh;
use grimace::render::{
    Camera, CellGrid, CellMode, ColorMode, DotCanvas, Orientation, Renderer, Scene, Style,
};

fn rows(path: PathBuf) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .map(|f| f.trim().parse::<f64>().unwrap())
                .collect()
        })
        .collect()
}

fn classic_face() -> Option<Mesh> {
    let dir = common::shared_with(&["golden/waters-vertices.csv"])?.join("golden");
    let positions = rows(dir.join("waters-vertices.csv"))
        .iter()
        .map(|r| from_classic(Vec3::new(r[1] as f32, r[2] as f32, r[3] as f32)))
        .collect();
    let triangles = rows(dir.join("waters-triangles.csv"))
        .iter()
        .map(|r| [r[1] as u32, r[2] as u32, r[3] as u32])
        .collect();
    Some(Mesh::new(positions, triangles).expect("classic mesh is valid"))
}

#[test]
fn classic_face_winding_is_detected_as_outward_once_converted() {
    // the classic triangles face into the head; the reflection of the import turns them out
    let Some(mesh) = classic_face() else { return };
    assert_eq!(
        Renderer::new(&mesh).detected_orientation(),
        Orientation::Outward
    );
}

#[test]
fn classic_face_renders_in_every_style_and_size() {
    let Some(mesh) = classic_face() else { return };
    common::render_every_view(&mesh, "classic", |canvas, proj, style, view, what| {
        // The eye openings are mesh borders, drawn by the line styles: from the
        // front both, turned, the subject's left (x > 0), toward the viewer.
        if style != Style::Shaded {
            let sides: &[f32] = if view == "front" {
                &[-1.0, 1.0]
            } else {
                &[1.0]
            };
            for &side in sides {
                for p in eye_border(&mesh, side) {
                    let dot = proj.project(p).truncate();
                    assert!(
                        common::lit_near(canvas, dot, 1.5),
                        "{what}: the eye border at {p} (dot {dot}) is not drawn"
                    );
                }
            }
        }
    });
}

/// Fraction of lit dots inside the bounding box of everything lit.
fn ink_density(canvas: &DotCanvas) -> f32 {
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for y in 0..canvas.height() {
        for x in 0..canvas.width() {
            if canvas.is_on(x, y) {
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            }
        }
    }
    canvas.count_on() as f32 / ((x1 + 1 - x0) * (y1 + 1 - y0)) as f32
}

#[test]
fn feature_lines_leave_the_face_open_where_wireframe_fills_it() {
    let Some(mesh) = classic_face() else { return };
    let scene = Scene::new(&mesh, &mesh.positions);
    let mut renderer = Renderer::new(&mesh);
    let mut canvas = CellMode::Braille.canvas(80, 24);
    let mut density = |style| {
        renderer.render(&scene, &Camera::front(), style, &mut canvas);
        ink_density(&canvas)
    };
    let (lines, wire) = (density(Style::Lines), density(Style::Wireframe));
    eprintln!("ink density: lines {lines:.3}, wireframe {wire:.3}");
    assert!(lines < 0.2, "lines {lines}");
    assert!(wire > 2.0 * lines, "wireframe {wire} vs lines {lines}");
}

#[test]
fn classic_face_eyes_are_open_holes_on_both_sides_of_the_midline() {
    let Some(mesh) = classic_face() else { return };
    let scene = Scene::new(&mesh, &mesh.positions);
    let mut canvas = CellMode::Braille.canvas(80, 24);
    Renderer::new(&mesh).render(&scene, &Camera::front(), Style::Shaded, &mut canvas);
    // The eye openings are holes in the mesh: project each eye's centre (the mean of the
    // border vertices above the nose on that side) and check the dot there is dark while
    // the forehead above it is lit.
    let proj = Camera::front().fit(
        mesh.bounds(),
        canvas.width(),
        canvas.height(),
        canvas.dot_aspect,
    );
    let mut grid = CellGrid::default();
    grid.fill(&canvas, CellMode::Braille, ColorMode::None);
    common::dump("classic-eyes-check.txt", &grimace::render::to_text(&grid));
    for side in [-1.0f32, 1.0] {
        let eye = eye_centre(&mesh, side);
        let p = proj.project(eye);
        let (x, y) = (p.x as usize, p.y as usize);
        let dark = (0..3).all(|d| !canvas.is_on(x, y + d - 1));
        assert!(dark, "eye at {eye} (dot {x},{y}) is dark");
        // Subject's left (x > 0 once imported) on the viewer's right.
        assert_eq!(x > canvas.width() / 2, side > 0.0);
    }
}

/// The centre of the mesh-border loop around one eye.
fn eye_centre(mesh: &Mesh, side: f32) -> Vec3 {
    let pts = eye_border(mesh, side);
    pts.iter().copied().sum::<Vec3>() / pts.len() as f32
}

/// The mesh-border loop around one eye: border vertices with |x| between 15% and 45% of the
/// half-width, 10% to 35% of the height above the middle (below the top rim, above the
/// nostrils).
fn eye_border(mesh: &Mesh, side: f32) -> Vec<Vec3> {
    let (lo, hi) = mesh.bounds();
    let half = (hi.x - lo.x) / 2.0;
    let mid_y = (lo.y + hi.y) / 2.0;
    let height = hi.y - lo.y;
    let mut count = std::collections::HashMap::new();
    for t in &mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let border: std::collections::BTreeSet<u32> = count
        .iter()
        .filter(|(_, &n)| n == 1)
        .flat_map(|(&(a, b), _)| [a, b])
        .collect();
    let pts: Vec<Vec3> = border
        .iter()
        .map(|&i| mesh.positions[i as usize])
        .filter(|p| {
            p.x * side > 0.15 * half
                && p.x * side < 0.45 * half
                && p.y > mid_y + 0.1 * height
                && p.y < mid_y + 0.35 * height
        })
        .collect();
    assert!(pts.len() >= 4, "found an eye border on side {side}");
    pts
}
