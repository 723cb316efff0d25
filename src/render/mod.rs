//! Rendering to an abstract dot canvas (no terminal dependency): camera, depth-buffered
//! rasterizer, and conversion to braille, ASCII or half-block cells, SVG and PNG.
//!
//! # Orientation: what appears where on screen
//!
//! Mesh coordinates follow glTF's convention: right-handed, y up, z out of the face toward
//! the viewer, and the subject's **left** at **positive x** (as in meshes from scanners,
//! MakeHuman, MediaPipe and glTF assets). A person facing the subject sees the subject's left
//! on *their* right. grimace draws the face that way, like a photograph of the subject, not
//! like a mirror:
//!
//! * Front view ([`Camera::front`]): screen right is mesh **+x**, screen up is +y, and the
//!   viewer looks along -z. So the subject's left eye (x > 0) is on the right half of the
//!   screen, and a muscle named `L_...` acts on the viewer's right. FACS coders read faces
//!   this way.
//! * [`Camera::side`] (yaw +90 degrees) shows the subject's left profile, nose pointing to the
//!   screen's left. Positive yaw turns the subject's left cheek toward the viewer; positive
//!   pitch looks down from above.
//!
//! The view matrix is a rotation (no mirror); back-face culling uses the signed screen area
//! (screen y runs down), and each mesh's winding is detected (see [`Orientation`]): the
//! built-in face's and the imported classic face's right-hand normals point out of the head,
//! a mesh wound the other way renders the same.
//!
//! # Pipeline
//!
//! [`Renderer::render`] projects the current positions with a [`Camera`] fitted to the rest
//! pose ([`Camera::fit_points`]) and culls triangles facing away. For the line styles it gathers
//! the [`Style`]'s lines first, marks the dots they pass through, and rasterizes into the
//! canvas's depth buffer (at dot resolution) only the front faces over marked dots: the
//! depth test reads nothing else, so hidden lines are removed exactly as with a full fill.
//! The lines are then drawn with that depth test and a small slope-scaled bias (or, for
//! [`Style::Shaded`], every front face is filled with lit and dithered dots); the rest-pose
//! ghost and the [`Overlay`]s go on top. [`CellGrid::fill`] turns the dots into
//! braille, ASCII or half-block [`Cell`]s; [`svg`] and [`png`] write files.
//!
//! # Styles
//!
//! [`Style::Lines`] (feature lines) is the default. At terminal resolution (160x96 dots in
//! 80x24) every-edge wireframe of the 6600-triangle default face fills in to a solid blot;
//! the shaded surface reads, but its nose and mouth are only a change in dot density. Feature
//! lines keep eyes, nose and mouth distinct at 80x24 and at 200x60 and leave flat cheeks
//! empty, so deformation stands out. They are:
//!
//! * silhouette edges (between a front- and a back-facing triangle) and mesh borders (eye
//!   openings, mouth slit, outer rim), depth-tested;
//! * creases: edges whose faces meet at more than [`Scene::crease_degrees`] (40);
//! * facing contours ([`Scene::facing_contours`], default one at 0.5): where the smoothed
//!   surface turns 60 degrees from the viewer. On a smooth mesh this outlines the sides of
//!   the nose, the cheeks and the chin, which are neither creases nor silhouette. Faces next
//!   to a crease are skipped (a box's averaged corner normals would draw a line across a
//!   flat side);
//! * optional iso-depth contours ([`Scene::contours`], default none: on the faces tried,
//!   they drew rings that read as a muzzle rather than as shape).
//!
//! [`Style::Shaded`] reads well too and suits half-block colour output and PNG. A mesh
//! whose named vertex groups say `iris` or `pupil` (the default face's eyes) shades them
//! darker: mid grey and nearly black, so the eye reads against its white.
//!
//! ```
//! use grimace::model::Mesh;
//! use grimace::render::{Camera, CellGrid, CellMode, ColorMode, Renderer, Scene, Style};
//! use glam::Vec3;
//!
//! let mesh = Mesh::new(
//!     vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)],
//!     vec![[0, 1, 2]],
//! )
//! .unwrap();
//! let mut renderer = Renderer::new(&mesh);
//! let mut canvas = CellMode::Braille.canvas(20, 10);
//! let scene = Scene::new(&mesh, &mesh.positions);
//! renderer.render(&scene, &Camera::front(), Style::Wireframe, &mut canvas);
//! let mut grid = CellGrid::default();
//! grid.fill(&canvas, CellMode::Braille, ColorMode::None);
//! assert!(grimace::render::to_text(&grid).contains(|c: char| c > '\u{2800}'));
//! ```

pub mod camera;
pub mod canvas;
pub mod cells;
pub mod framing;
pub mod legend;
pub mod lod;
pub mod png;
pub mod raster;
pub mod scene;
pub mod svg;

pub use camera::{Camera, Projection};
pub use canvas::{DotCanvas, Layer, Rgb};
pub use cells::{
    ansi256_rgb, ascii_char, braille_bit, braille_char, dither_256, nearest_ansi16,
    nearest_ansi256, reduce, to_ansi, to_text, Cell, CellGrid, CellMode, ColorMode, ANSI16,
    GHOST_UNDER_DIM,
};
pub use framing::Framing;
pub use legend::DisplacementLegend;
pub use lod::{Level, Lod};
pub use raster::{render, LitTriangle, Renderer, Run};
pub use scene::{
    displacement_ramp, muscle_overlays, Orientation, Overlay, Palette, Scene, Shape, Style,
};

/// Renders a scene straight to text: `cols` x `rows` cells in `mode`, no colour.
pub fn render_text(
    scene: &Scene,
    camera: &Camera,
    style: Style,
    mode: CellMode,
    cols: usize,
    rows: usize,
) -> String {
    let mut canvas = mode.canvas(cols, rows);
    render(scene, camera, style, &mut canvas);
    let mut grid = CellGrid::default();
    grid.fill(&canvas, mode, ColorMode::None);
    to_text(&grid)
}
