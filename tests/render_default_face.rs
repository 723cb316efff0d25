//! The built-in default face rendered in every style, view and size: the features come out
//! where they belong, and deformation shows.

use std::path::PathBuf;

use grimace::io::builtin;
use grimace::model::{Activations, BoundRig};
use grimace::render::{
    muscle_overlays, render_text, Camera, CellGrid, CellMode, ColorMode, DotCanvas, Orientation,
    Palette, Renderer, Scene, Style,
};

fn dump(name: &str, text: &str) {
    if let Some(dir) = std::env::var_os("GRIMACE_RENDER_DUMP") {
        std::fs::write(PathBuf::from(dir).join(name), text).unwrap();
    }
}

#[test]
fn default_face_winding_is_outward() {
    let mesh = builtin::default_mesh();
    assert_eq!(
        Renderer::new(&mesh).detected_orientation(),
        Orientation::Outward
    );
}

#[test]
fn default_face_renders_in_every_style_view_and_size() {
    let mesh = builtin::default_mesh();
    let scene = Scene::new(&mesh, &mesh.positions);
    for (cols, rows) in [(80, 24), (200, 60), (50, 38)] {
        for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
            for (view, camera) in [
                ("front", Camera::front()),
                ("side", Camera::side()),
                ("three", Camera::three_quarter()),
            ] {
                let text = render_text(&scene, &camera, style, CellMode::Braille, cols, rows);
                dump(&format!("face-{style}-{view}-{cols}x{rows}.txt"), &text);
                let lit = text
                    .chars()
                    .filter(|&c| c > '\u{2800}' && c <= '\u{28ff}')
                    .count();
                assert!(
                    lit > cols * rows / 40,
                    "{style} {view} {cols}x{rows}: only {lit} cells lit"
                );
            }
            let ascii = render_text(&scene, &Camera::front(), style, CellMode::Ascii, cols, rows);
            dump(&format!("face-{style}-ascii-{cols}x{rows}.txt"), &ascii);
            assert!(ascii.is_ascii());
        }
    }
}

fn deformed(combo: &str) -> (grimace::model::Mesh, Vec<glam::Vec3>, grimace::model::Rig) {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let table = builtin::default_table();
    let combo = grimace::facs::combo::parse_combo(combo).unwrap();
    let act: Activations = table.evaluate(&combo, &rig).unwrap();
    let bound = BoundRig::bind(&rig, &mesh).unwrap();
    let mut positions = Vec::new();
    bound.deform(&act, &mut positions).unwrap();
    (mesh, positions, rig)
}

#[test]
fn an_open_mouth_changes_the_picture_and_shows_as_colour() {
    let (mesh, positions, rig) = deformed("26+27");
    let rest = render_text(
        &Scene::new(&mesh, &mesh.positions),
        &Camera::front(),
        Style::Lines,
        CellMode::Braille,
        80,
        24,
    );
    let mut overlays = Vec::new();
    muscle_overlays(&rig, Some(0), &Palette::default(), &mut overlays);
    let scene = Scene {
        ghost: true,
        displacement: true,
        ..Scene::new(&mesh, &positions).with_rest(&mesh.positions)
    };
    let open = render_text(
        &scene,
        &Camera::front(),
        Style::Lines,
        CellMode::Braille,
        80,
        24,
    );
    dump("face-open-mouth-80x24.txt", &open);
    assert_ne!(rest, open);
    let mut canvas = CellMode::HalfBlock.canvas(80, 24);
    let mut renderer = Renderer::new(&mesh);
    renderer.render(
        &scene.with_overlays(&overlays),
        &Camera::front(),
        Style::Lines,
        &mut canvas,
    );
    let mut grid = CellGrid::default();
    grid.fill(&canvas, CellMode::HalfBlock, ColorMode::TrueColor);
    let palette = Palette::default();
    let colours: std::collections::BTreeSet<_> = grid
        .cells
        .iter()
        .filter_map(|c| c.fg)
        .map(|c| (c.0, c.1, c.2))
        .collect();
    assert!(
        colours.len() > 5,
        "ramp, ghost, overlays: {} colours",
        colours.len()
    );
    let selected = palette.selected;
    assert!(
        grid.cells.iter().any(|c| c.fg == Some(selected)),
        "the selected muscle shows"
    );
    let _ = DotCanvas::new(1, 1);
}
