//! Dots to cells: braille bits, ASCII shapes, half blocks, colour reduction, text.

use glam::Vec3;
use grimace::model::Mesh;
use grimace::render::{
    ascii_char, braille_bit, nearest_ansi16, reduce, render_text, to_ansi, to_text, Camera, Cell,
    CellGrid, CellMode, ColorMode, DotCanvas, Layer, Rgb, Scene, Style, ANSI16,
};

fn grid_of(canvas: &DotCanvas, mode: CellMode, colors: ColorMode) -> CellGrid {
    let mut grid = CellGrid::default();
    grid.fill(canvas, mode, colors);
    grid
}

#[test]
fn braille_bits_follow_unicode_dot_numbering() {
    let expected = [
        ((0, 0), '\u{2801}'),
        ((0, 1), '\u{2802}'),
        ((0, 2), '\u{2804}'),
        ((1, 0), '\u{2808}'),
        ((1, 1), '\u{2810}'),
        ((1, 2), '\u{2820}'),
        ((0, 3), '\u{2840}'),
        ((1, 3), '\u{2880}'),
    ];
    for ((dx, dy), ch) in expected {
        // Put the dot in the second cell of the second row to check the cell addressing too.
        let mut canvas = DotCanvas::new(4, 8);
        canvas.plot(2 + dx, 4 + dy, Rgb(1, 2, 3), Layer::Mesh);
        let grid = grid_of(&canvas, CellMode::Braille, ColorMode::TrueColor);
        assert_eq!((grid.width, grid.height), (2, 2));
        assert_eq!(grid.get(1, 1).unwrap().ch, ch, "dot ({dx}, {dy})");
        assert_eq!(grid.get(1, 1).unwrap().fg, Some(Rgb(1, 2, 3)));
        assert_eq!(grid.get(0, 0).unwrap(), &Cell::BLANK);
        assert_eq!(
            braille_bit(dx as usize, dy as usize) as u32,
            ch as u32 - 0x2800
        );
    }
    let mut full = DotCanvas::new(2, 4);
    for y in 0..4 {
        for x in 0..2 {
            full.plot(x, y, Rgb::default(), Layer::Mesh);
        }
    }
    assert_eq!(
        grid_of(&full, CellMode::Braille, ColorMode::None).cells[0].ch,
        '\u{28FF}'
    );
}

fn pattern(rows: [&str; 4]) -> u8 {
    let mut bits = 0;
    for (dy, row) in rows.iter().enumerate() {
        for (dx, c) in row.chars().enumerate() {
            if c == '#' {
                bits |= braille_bit(dx, dy);
            }
        }
    }
    bits
}

#[test]
fn ascii_picks_the_character_that_looks_like_the_dots() {
    assert_eq!(ascii_char(0), ' ');
    assert_eq!(ascii_char(pattern(["#.", "#.", "#.", "#."])), '|');
    assert_eq!(ascii_char(pattern([".#", ".#", ".#", ".#"])), '|');
    assert_eq!(ascii_char(pattern(["..", "##", "..", ".."])), '-');
    assert_eq!(ascii_char(pattern(["..", "..", "..", "##"])), '_');
    assert_eq!(ascii_char(pattern([".#", ".#", "#.", "#."])), '/');
    assert_eq!(ascii_char(pattern(["#.", "#.", ".#", ".#"])), '\\');
    assert_eq!(ascii_char(pattern(["..", "..", "..", "#."])), '.');
    assert_eq!(ascii_char(pattern(["##", "##", "##", "##"])), '#');
    // A vertical line with one stray dot is still a bar.
    assert_eq!(ascii_char(pattern(["#.", "#.", "#.", "##"])), 'L');
    assert_eq!(ascii_char(pattern(["#.", "#.", "##", "#."])), '|');
    for bits in 1..=255u8 {
        let c = ascii_char(bits);
        assert!(c.is_ascii_graphic(), "pattern {bits:#010b} maps to {c:?}");
    }
}

#[test]
fn half_blocks_carry_top_and_bottom_colours() {
    let mut canvas = DotCanvas::new(3, 2);
    let (red, blue) = (Rgb(200, 0, 0), Rgb(0, 0, 200));
    canvas.plot(0, 0, red, Layer::Mesh);
    canvas.plot(1, 1, blue, Layer::Mesh);
    canvas.plot(2, 0, red, Layer::Mesh);
    canvas.plot(2, 1, blue, Layer::Mesh);
    let grid = grid_of(&canvas, CellMode::HalfBlock, ColorMode::TrueColor);
    assert_eq!((grid.width, grid.height), (3, 1));
    assert_eq!(
        grid.cells[0],
        Cell {
            ch: '▀',
            fg: Some(red),
            bg: None
        }
    );
    assert_eq!(
        grid.cells[1],
        Cell {
            ch: '▄',
            fg: Some(blue),
            bg: None
        }
    );
    assert_eq!(
        grid.cells[2],
        Cell {
            ch: '▀',
            fg: Some(red),
            bg: Some(blue)
        }
    );
    canvas.plot(2, 1, red, Layer::Mesh);
    let grid = grid_of(&canvas, CellMode::HalfBlock, ColorMode::TrueColor);
    assert_eq!(
        grid.cells[2],
        Cell {
            ch: '█',
            fg: Some(red),
            bg: None
        }
    );
}

#[test]
fn the_cell_takes_the_colour_of_its_highest_layer() {
    let mut canvas = DotCanvas::new(2, 4);
    canvas.plot(0, 0, Rgb(9, 9, 9), Layer::Mesh);
    canvas.plot(1, 3, Rgb(200, 0, 0), Layer::Overlay);
    canvas.plot(0, 2, Rgb(1, 1, 1), Layer::Ghost);
    assert_eq!(
        grid_of(&canvas, CellMode::Braille, ColorMode::TrueColor).cells[0].fg,
        Some(Rgb(200, 0, 0))
    );
    // A lower layer does not repaint a dot already lit on a higher one.
    canvas.plot(1, 3, Rgb(5, 5, 5), Layer::Mesh);
    assert_eq!(canvas.color(1, 3), Some(Rgb(200, 0, 0)));
}

#[test]
fn colours_reduce_to_sixteen_and_to_none() {
    for (i, c) in ANSI16.iter().enumerate() {
        assert_eq!(nearest_ansi16(*c) as usize, i);
    }
    assert_eq!(nearest_ansi16(Rgb(250, 10, 10)), 9);
    assert_eq!(nearest_ansi16(Rgb(190, 20, 10)), 1);
    assert_eq!(nearest_ansi16(Rgb(90, 90, 110)), 8);
    assert_eq!(nearest_ansi16(Rgb(225, 225, 225)), 7);
    assert_eq!(reduce(Rgb(250, 10, 10), ColorMode::Ansi16), Some(ANSI16[9]));
    assert_eq!(reduce(Rgb(250, 10, 10), ColorMode::None), None);
    assert_eq!(
        reduce(Rgb(250, 10, 10), ColorMode::TrueColor),
        Some(Rgb(250, 10, 10))
    );
    let mut canvas = DotCanvas::new(2, 4);
    canvas.plot(0, 0, Rgb(250, 10, 10), Layer::Mesh);
    let none = grid_of(&canvas, CellMode::Braille, ColorMode::None);
    assert_eq!(none.cells[0].fg, None);
    assert_eq!(to_ansi(&none, ColorMode::None), "\u{2801}\n");
    let sixteen = grid_of(&canvas, CellMode::Braille, ColorMode::Ansi16);
    assert_eq!(
        to_ansi(&sixteen, ColorMode::Ansi16),
        "\x1b[0m\x1b[91m\u{2801}\x1b[0m\n"
    );
    let full = grid_of(&canvas, CellMode::Braille, ColorMode::TrueColor);
    assert_eq!(
        to_ansi(&full, ColorMode::TrueColor),
        "\x1b[0m\x1b[38;2;250;10;10m\u{2801}\x1b[0m\n"
    );
}

#[test]
fn text_has_one_line_per_row_with_trailing_blanks_trimmed() {
    let mut canvas = DotCanvas::new(6, 8);
    canvas.plot(0, 0, Rgb::default(), Layer::Mesh);
    let grid = grid_of(&canvas, CellMode::Braille, ColorMode::None);
    assert_eq!(to_text(&grid), "\u{2801}\n\n");
    assert_eq!(to_text(&CellGrid::new(0, 0)), "");
}

/// A closed box (cuboid) with outward normals, 2 x 1.4 x 1.
///
/// Its triangulation is not mirror-symmetric, and which diagonal lies where shows in the
/// depth-tested lines. The box is the mirror image (x negated, winding reversed) of the one
/// the snapshots were first drawn with, when the camera mirrored x, so the pictures are
/// unchanged.
fn cuboid() -> Mesh {
    let (x, y, z) = (-1.0, 0.7, 0.5);
    let positions = vec![
        Vec3::new(-x, -y, -z),
        Vec3::new(x, -y, -z),
        Vec3::new(x, y, -z),
        Vec3::new(-x, y, -z),
        Vec3::new(-x, -y, z),
        Vec3::new(x, -y, z),
        Vec3::new(x, y, z),
        Vec3::new(-x, y, z),
    ];
    let quads = [
        [4, 5, 6, 7],
        [1, 0, 3, 2],
        [5, 1, 2, 6],
        [0, 4, 7, 3],
        [7, 6, 2, 3],
        [0, 1, 5, 4],
    ];
    let triangles = quads
        .iter()
        .flat_map(|q| [[q[0], q[2], q[1]], [q[0], q[3], q[2]]])
        .collect();
    Mesh::new(positions, triangles).unwrap()
}

#[test]
fn snapshot_of_a_box_in_three_quarter_view() {
    let mesh = cuboid();
    let scene = Scene::new(&mesh, &mesh.positions);
    let braille = render_text(
        &scene,
        &Camera::three_quarter(),
        Style::Lines,
        CellMode::Braille,
        24,
        8,
    );
    insta::assert_snapshot!("box_three_quarter_braille", braille);
    let ascii = render_text(
        &scene,
        &Camera::three_quarter(),
        Style::Wireframe,
        CellMode::Ascii,
        24,
        8,
    );
    insta::assert_snapshot!("box_three_quarter_ascii", ascii);
}

#[test]
fn snapshot_of_a_box_in_front_view_is_a_rectangle() {
    let mesh = cuboid();
    let scene = Scene::new(&mesh, &mesh.positions);
    // Only the front face is visible; its diagonal is not a feature line (coplanar faces).
    let text = render_text(
        &scene,
        &Camera::front(),
        Style::Lines,
        CellMode::Ascii,
        20,
        6,
    );
    insta::assert_snapshot!("box_front_ascii", text);
}
