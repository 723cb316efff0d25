//! Eyebrows drawn per dot: on a coarse mesh the brow's tone has a sharp edge inside big
//! triangles, and the brow moves with the skin.

use glam::Vec3;
use grimace::model::Mesh;
use grimace::render::{Camera, DotCanvas, Renderer, Scene, Style};

/// A flat sheet facing +z: columns at `x` = -4 to 4, one unit apart, rows at `ys`, each
/// quad split in two; with the index of the vertex in column `i`, row `j`.
fn sheet(ys: &[f32]) -> (Mesh, impl Fn(usize, usize) -> u32) {
    wide_sheet(4, ys)
}

/// A sheet like [`sheet`] with columns at `x` = -`reach` to `reach`.
fn wide_sheet(reach: i32, ys: &[f32]) -> (Mesh, impl Fn(usize, usize) -> u32) {
    let columns = (2 * reach + 1) as usize;
    let positions = ys
        .iter()
        .flat_map(|&y| (-reach..=reach).map(move |x| Vec3::new(x as f32, y, 0.0)))
        .collect();
    let at = move |i: usize, j: usize| (j * columns + i) as u32;
    let mut triangles = Vec::new();
    for j in 0..ys.len() - 1 {
        for i in 0..columns - 1 {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    (Mesh::new(positions, triangles).expect("a valid sheet"), at)
}

/// A flat sheet facing +z, 8 x 4 units in triangles 1 unit wide and 2 tall, whose brows are
/// one row of vertices each (as on a coarse mask whose brow group is the landmarks along
/// the brow's upper edge): `x` 1 to 3 on the subject's left (+x), -1 to -3 on the right, at
/// `y = 0`.
fn coarse_sheet() -> Mesh {
    let (mut mesh, at) = sheet(&[-2.0, 0.0, 2.0]);
    mesh.groups
        .insert("left_brow_hair".into(), (5..=7).map(|i| at(i, 1)).collect());
    mesh.groups.insert(
        "right_brow_hair".into(),
        (1..=3).map(|i| at(i, 1)).collect(),
    );
    mesh
}

/// A sheet like [`coarse_sheet`] with a second row of vertices 0.1 below the first, whose
/// brows are both rows (a dense group covering triangles of its own, thinner than a brow's
/// minimum height for a single row, 0.1 of its length at the head: 0.2 here).
fn thin_dense_sheet() -> Mesh {
    let (mut mesh, at) = sheet(&[-2.0, -0.1, 0.0, 2.0]);
    let rows = |range: std::ops::RangeInclusive<usize>| {
        range
            .flat_map(|i| [at(i, 1), at(i, 2)])
            .collect::<Vec<u32>>()
    };
    mesh.groups.insert("left_brow_hair".into(), rows(5..=7));
    mesh.groups.insert("right_brow_hair".into(), rows(1..=3));
    mesh
}

/// The brightness (0 to 1) of the surface along a column of dots through `x`, from `y_top`
/// down to `y_bottom` (mesh units), with each dot's height in mesh units; front view,
/// undithered.
fn column(
    mesh: &Mesh,
    positions: &[Vec3],
    x: f32,
    (y_top, y_bottom): (f32, f32),
) -> Vec<(f32, f32)> {
    let mut canvas = DotCanvas::new(240, 120);
    canvas.dither = false;
    let scene = Scene::new(mesh, positions);
    let camera = Camera::front();
    Renderer::new(mesh).render(&scene, &camera, Style::Shaded, &mut canvas);
    let proj = camera.fit_points(
        &mesh.positions,
        canvas.width(),
        canvas.height(),
        canvas.dot_aspect,
    );
    let top = proj.project(Vec3::new(x, y_top, 0.0));
    let bottom = proj.project(Vec3::new(x, y_bottom, 0.0));
    let per_unit = (bottom.y - top.y) / (y_top - y_bottom);
    let dx = top.x as usize;
    (top.y.ceil() as usize..bottom.y as usize)
        .filter_map(|dy| {
            let c = canvas.color(dx, dy)?;
            canvas.is_on(dx, dy).then_some(())?;
            let y = y_top - (dy as f32 + 0.5 - top.y) / per_unit;
            Some((y, c.0 as f32 / 255.0))
        })
        .collect()
}

/// The heights of the dots drawn darker than half the sheet's own brightness.
fn dark(col: &[(f32, f32)]) -> Vec<f32> {
    let skin = col.iter().map(|c| c.1).fold(0.0, f32::max);
    col.iter()
        .filter(|c| c.1 < 0.5 * skin)
        .map(|c| c.0)
        .collect()
}

/// Across a brow two units below and above its vertex row, the tone jumps from skin to
/// brow between neighbouring dots: no dot is drawn in between (a tone per vertex spread
/// it over the whole triangle, half-tones over many dots), and the dark dots lie within a
/// brow's height below the row, not on the forehead or toward the eye.
#[test]
fn a_coarse_brow_has_a_sharp_edge() {
    let mesh = coarse_sheet();
    for x in [-2.0f32, 2.0] {
        let col = column(&mesh, &mesh.positions, x, (1.5, -1.5));
        let skin = col.iter().map(|c| c.1).fold(0.0, f32::max);
        let between = col
            .iter()
            .filter(|c| c.1 > 0.4 * skin && c.1 < 0.9 * skin)
            .count();
        let dark = dark(&col);
        println!(
            "x {x}: {} dots, {} dark, {between} between",
            col.len(),
            dark.len()
        );
        assert!(col.len() > 40, "the column crosses the sheet");
        assert!(!dark.is_empty(), "x {x}: the brow is drawn");
        assert!(between <= 2, "x {x}: {between} dots between skin and brow");
        for y in dark {
            assert!((-0.35..=0.05).contains(&y), "x {x}: brow dot at {y}");
        }
    }
}

/// The band is carried by the skin: with the sheet moved up by half a unit, the brow is
/// drawn half a unit higher.
#[test]
fn the_brow_moves_with_the_skin() {
    let mesh = coarse_sheet();
    let lift = Vec3::new(0.0, 0.5, 0.0);
    let moved: Vec<Vec3> = mesh.positions.iter().map(|&p| p + lift).collect();
    let mean = |v: Vec<f32>| v.iter().sum::<f32>() / v.len().max(1) as f32;
    let at_rest = mean(dark(&column(&mesh, &mesh.positions, 2.0, (1.5, -1.5))));
    let lifted = mean(dark(&column(&mesh, &moved, 2.0, (1.5, -1.5))));
    assert!(
        (lifted - at_rest - 0.5).abs() < 0.1,
        "{at_rest} -> {lifted}"
    );
}

/// A dense brow group is drawn as its own extent: near the brow's head, where a single row
/// would be given 0.2 below it, the brow ends at the group's lower row, 0.1 below.
#[test]
fn a_dense_brow_is_drawn_as_its_own_extent() {
    let mesh = thin_dense_sheet();
    for x in [-1.25f32, 1.25] {
        let dark = dark(&column(&mesh, &mesh.positions, x, (1.5, -1.5)));
        println!("x {x}: dark from {:?} to {:?}", dark.first(), dark.last());
        assert!(!dark.is_empty(), "x {x}: the brow is drawn");
        for y in dark {
            assert!((-0.14..=0.04).contains(&y), "x {x}: brow dot at {y}");
        }
    }
}

/// A brow group marked in two pieces along the brow: one row at `y = 0`, `x` 1 and 2 and
/// then 6 and 7 on the subject's left, mirrored on the right. The gap (four units where the
/// pieces' members are one apart) is left bare: each piece is drawn, and no bar bridges
/// them.
#[test]
fn a_brow_in_two_pieces_is_drawn_as_its_pieces() {
    let (mut mesh, at) = wide_sheet(8, &[-2.0, 0.0, 2.0]);
    // Column `i` is at `x = i - 8`.
    let row = |columns: [usize; 4]| columns.iter().map(|&i| at(i, 1)).collect::<Vec<u32>>();
    mesh.groups
        .insert("left_brow_hair".into(), row([9, 10, 14, 15]));
    mesh.groups
        .insert("right_brow_hair".into(), row([7, 6, 2, 1]));
    for sign in [1.0f32, -1.0] {
        for x in [1.5f32, 6.5] {
            let dark = dark(&column(&mesh, &mesh.positions, sign * x, (1.5, -1.5)));
            assert!(!dark.is_empty(), "x {}: the piece is drawn", sign * x);
        }
        for x in [3.0f32, 4.0, 5.0] {
            let dark = dark(&column(&mesh, &mesh.positions, sign * x, (1.5, -1.5)));
            assert!(
                dark.is_empty(),
                "x {}: {} brow dots in the gap, down to {:?}",
                sign * x,
                dark.len(),
                dark.last()
            );
        }
    }
}
