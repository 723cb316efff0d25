//! The built-in default face rendered in every style, view and size: the features come out
//! where they belong, and deformation shows.

use crate::common;

use grimace::io::builtin;
use grimace::model::{Activations, BoundRig};
use grimace::render::{
    muscle_overlays, render_text, Camera, CellGrid, CellMode, ColorMode, DotCanvas, Orientation,
    Palette, Renderer, Scene, Style,
};

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
    common::render_every_view(&mesh, "face", |canvas, proj, style, view, what| {
        features_are_drawn(&mesh, canvas, proj, style, view, what);
    });
}

/// The face's features show where their vertices land. The eye and mouth corners lie on the
/// mesh's borders, which the line styles always draw where they face the viewer: both sides
/// from the front, the subject's left (turned toward the viewer) in the side and
/// three-quarter views. The shaded style lights the nose tip, which faces the light.
fn features_are_drawn(
    mesh: &grimace::model::Mesh,
    canvas: &DotCanvas,
    proj: &grimace::render::Projection,
    style: Style,
    view: &str,
    what: &str,
) {
    let at = |name: &str| {
        let v = mesh
            .groups
            .get(name)
            .unwrap_or_else(|| panic!("no group {name}"))[0];
        proj.project(mesh.positions[v as usize]).truncate()
    };
    let sides: &[&str] = if view == "front" {
        &["left", "right"]
    } else {
        &["left"]
    };
    let mut features = vec![];
    if style == Style::Shaded {
        features.push("nose_tip".to_string());
    } else {
        for side in sides {
            for part in ["outer_eye_corner", "inner_eye_corner", "mouth_corner"] {
                features.push(format!("{side}_{part}"));
            }
        }
    }
    for name in &features {
        let p = at(name);
        assert!(
            common::lit_near(canvas, p, 1.5),
            "{what}: nothing drawn at {name} {p}"
        );
    }
    // Photograph orientation: the subject's left eye on the viewer's right, above the mouth.
    if view == "front" {
        assert!(at("left_outer_eye_corner").x > at("right_outer_eye_corner").x);
        assert!(at("left_outer_eye_corner").y < at("left_mouth_corner").y);
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
    common::dump("face-open-mouth-80x24.txt", &open);
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
