//! The rest-pose ghost stays visible under the live lines: where its own dots share a cell
//! with live dots, they are left out of the cell's pattern and the cell gets the ghost's dim
//! colour as its background; where the rest pose and the live pose agree, nothing is marked.

use grimace::io::builtin;
use grimace::model::BoundRig;
use grimace::render::{
    Camera, CellGrid, CellMode, ColorMode, Palette, Renderer, Rgb, Scene, Style, GHOST_UNDER_DIM,
};

/// The built-in face without the parts inside its mouth. The ghost stays behind any surface
/// the lines' depth pass filled; the teeth's edges behind the lips make it fill the whole
/// mouth region, where the smile's ghost lies, so these tests look at the skin alone.
fn face_without_mouth() -> (grimace::model::Mesh, grimace::model::Rig) {
    let mut mesh = builtin::default_mesh();
    let mut rig = builtin::default_rig();
    let mouth: Vec<u32> = grimace::face::groups::rigid_vertices(&mesh)
        .into_iter()
        .filter(|v| !grimace::face::groups::still_vertices(&mesh).contains(v))
        .collect();
    let keep = mouth[0] as usize;
    mesh.positions.truncate(keep);
    mesh.triangles
        .retain(|t| t.iter().all(|&v| (v as usize) < keep));
    for members in mesh.groups.values_mut() {
        members.retain(|&v| (v as usize) < keep);
    }
    mesh.groups.retain(|_, members| !members.is_empty());
    for mask in &mut rig.masks {
        mask.weights.retain(|(v, _)| (*v as usize) < keep);
    }
    if let Some(jaw) = &mut rig.jaw {
        jaw.weights.retain(|(v, _)| (*v as usize) < keep);
    }
    (mesh, rig)
}

fn grid(ghost: bool, style: Style, colors: ColorMode, smile: bool) -> CellGrid {
    let (mesh, rig) = face_without_mouth();
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
fn the_ghost_shows_as_a_dim_background_where_the_face_moved() {
    let ghost = Palette::default().ghost.mix(Rgb(0, 0, 0), GHOST_UNDER_DIM);
    for style in [Style::Lines, Style::Shaded] {
        let marked = |smile: bool| {
            let on = grid(true, style, ColorMode::TrueColor, smile);
            let live = on.cells.iter().filter(|c| c.ch != ' ').count();
            let under: Vec<_> = on
                .cells
                .iter()
                .filter(|c| c.bg.is_some())
                .cloned()
                .collect();
            for cell in &under {
                assert_eq!(cell.bg, Some(ghost));
                assert_ne!(cell.fg, Some(Palette::default().ghost), "live dots on top");
            }
            let off = grid(false, style, ColorMode::TrueColor, smile);
            assert!(
                off.cells.iter().all(|c| c.bg.is_none()),
                "no ghost, no background"
            );
            (under.len(), live)
        };
        let ((rest, live), (smile, _)) = (marked(false), marked(true));
        println!("{style}: {rest} of {live} cells marked at rest, {smile} smiling");
        // At rest only the shaded face's outline, where the silhouette runs through cells
        // half covered, is marked; a moved face adds the cells it left.
        assert!(
            rest * 5 < live,
            "{style}: {rest} of {live} cells marked where nothing moved"
        );
        assert!(
            smile >= rest,
            "{style}: {smile} cells marked in a smile, {rest} at rest"
        );
        if style == Style::Lines {
            // The lines of the rest pose and of the live pose are the same lines at rest.
            assert!(rest <= 2, "lines: {rest} cells marked at rest");
            assert!(smile > 5, "lines: only {smile} cells marked in a smile");
        }
    }
    let plain = grid(true, Style::Lines, ColorMode::None, true);
    assert!(plain.cells.iter().all(|c| c.bg.is_none() && c.fg.is_none()));
}

/// The live pattern of a cell is exactly the live pose's: the ghost adds no dots to it.
#[test]
fn the_ghost_adds_no_dots_to_the_live_lines() {
    let with = grid(true, Style::Lines, ColorMode::TrueColor, true);
    let without = grid(false, Style::Lines, ColorMode::TrueColor, true);
    let mut differ = 0;
    for (a, b) in with.cells.iter().zip(&without.cells) {
        if b.ch != ' ' {
            assert_eq!(a.ch, b.ch, "a cell with live dots changed its pattern");
        } else if a.ch != ' ' {
            differ += 1;
        }
    }
    assert!(differ > 10, "the ghost drew only {differ} cells of its own");
}
