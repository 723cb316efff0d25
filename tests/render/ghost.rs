//! The rest-pose ghost stays visible under the live lines: where it lies under live dots,
//! braille and ASCII cells get its dim colour as their background.

use grimace::io::builtin;
use grimace::model::BoundRig;
use grimace::render::{
    Camera, CellGrid, CellMode, ColorMode, Palette, Renderer, Rgb, Scene, Style, GHOST_UNDER_DIM,
};

fn grid(ghost: bool, style: Style, colors: ColorMode, smile: bool) -> CellGrid {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let mut positions = mesh.positions.clone();
    if smile {
        let act = builtin::default_table()
            .expression_activations("happiness", &rig)
            .unwrap();
        BoundRig::bind(&rig, &mesh)
            .unwrap()
            .deform(&act, &mut positions)
            .unwrap();
    }
    let mut scene = Scene::new(&mesh, &positions).with_rest(&mesh.positions);
    scene.ghost = ghost;
    let mut canvas = CellMode::Braille.canvas(80, 36);
    Renderer::new(&mesh).render(&scene, &Camera::front(), style, &mut canvas);
    let mut grid = CellGrid::default();
    grid.fill(&canvas, CellMode::Braille, colors);
    grid
}

#[test]
fn the_ghost_shows_as_a_dim_background_under_live_lines() {
    let ghost = Palette::default().ghost.mix(Rgb(0, 0, 0), GHOST_UNDER_DIM);
    for style in [Style::Lines, Style::Shaded] {
        for smile in [false, true] {
            let on = grid(true, style, ColorMode::TrueColor, smile);
            let under: Vec<_> = on.cells.iter().filter(|c| c.bg.is_some()).collect();
            assert!(
                under.len() > 40,
                "{style} smile {smile}: {} cells with the ghost under live dots",
                under.len()
            );
            for cell in &under {
                assert_eq!(cell.bg, Some(ghost));
                assert_ne!(cell.fg, Some(Palette::default().ghost), "live dots on top");
            }
            let off = grid(false, style, ColorMode::TrueColor, smile);
            assert!(
                off.cells.iter().all(|c| c.bg.is_none()),
                "no ghost, no background"
            );
        }
    }
    let plain = grid(true, Style::Lines, ColorMode::None, false);
    assert!(plain.cells.iter().all(|c| c.bg.is_none() && c.fg.is_none()));
}
