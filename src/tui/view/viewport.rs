//! The viewport: the deformed face, drawn by the core renderer ([`crate::render`]) and copied
//! cell by cell into the ratatui buffer.

use glam::Vec2;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::widgets::{Block, Borders, Widget};

use super::theme::Theme;
use crate::render::{
    muscle_overlays, nearest_ansi16, Camera, CellGrid, ColorMode, DotCanvas, Overlay, Palette,
    Renderer, Rgb, Scene,
};
use crate::tui::app::{App, Colors, Row};

/// The renderer and its buffers, kept between frames so drawing allocates nothing.
#[derive(Debug, Clone, Default)]
pub struct RenderCache {
    /// What the grid shows; the face is drawn again only when this changes.
    key: Option<CacheKey>,
    renderer: Option<Renderer>,
    canvas: Option<DotCanvas>,
    grid: CellGrid,
    overlays: Vec<Overlay>,
}

/// Everything the picture depends on.
#[derive(Debug, Clone, PartialEq)]
struct CacheKey {
    generation: u64,
    view: crate::tui::app::View,
    area: Rect,
    selected: Option<usize>,
}

/// The camera for the view settings: angles in degrees, pan as a fraction of the face's size.
pub fn camera(app: &App) -> Camera {
    let (lo, hi) = app.doc.scene.mesh().bounds();
    let extent = (hi - lo).truncate().max_element().max(f32::EPSILON);
    Camera {
        yaw: app.view.yaw.to_radians(),
        pitch: app.view.pitch.to_radians(),
        zoom: app.view.zoom,
        pan: Vec2::new(app.view.pan.0, app.view.pan.1) * extent,
    }
}

fn color_mode(colors: Colors) -> ColorMode {
    match colors {
        Colors::None => ColorMode::None,
        Colors::Ansi16 => ColorMode::Ansi16,
        Colors::TrueColor => ColorMode::TrueColor,
    }
}

/// A renderer colour as a terminal colour: named ANSI colours on 16-colour terminals.
fn to_color(rgb: Rgb, colors: Colors) -> Option<Color> {
    const NAMED: [Color; 16] = [
        Color::Black,
        Color::Red,
        Color::Green,
        Color::Yellow,
        Color::Blue,
        Color::Magenta,
        Color::Cyan,
        Color::Gray,
        Color::DarkGray,
        Color::LightRed,
        Color::LightGreen,
        Color::LightYellow,
        Color::LightBlue,
        Color::LightMagenta,
        Color::LightCyan,
        Color::White,
    ];
    match colors {
        Colors::None => None,
        Colors::Ansi16 => Some(NAMED[usize::from(nearest_ansi16(rgb)) & 15]),
        Colors::TrueColor => Some(Color::Rgb(rgb.0, rgb.1, rgb.2)),
    }
}

/// Draws the viewport panel, reusing the buffers in `cache`.
pub fn draw(app: &App, cache: &mut RenderCache, theme: &Theme, area: Rect, buf: &mut Buffer) {
    let title = format!(
        " Face  {}  yaw {:.0} pitch {:.0} zoom {:.2} ",
        app.view.style.name(),
        app.view.yaw,
        app.view.pitch,
        app.view.zoom
    );
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border(false))
        .title(title);
    let inner = block.inner(area);
    block.render(area, buf);
    if inner.is_empty() {
        return;
    }
    let selected = match app.selected_row() {
        Row::Muscle(i) => Some(i),
        Row::Jaw => None,
    };
    let key = CacheKey {
        generation: app.doc.scene.generation(),
        view: app.view.clone(),
        area: inner,
        selected: selected.filter(|_| app.view.show_muscles),
    };
    let fresh = cache.key.as_ref() == Some(&key);
    if !fresh {
        render_face(app, cache, inner, selected);
        cache.key = Some(key);
    }
    copy_cells(app, theme, &cache.grid, inner, buf);
}

/// Renders the face into the cache's cell grid.
fn render_face(app: &App, cache: &mut RenderCache, inner: Rect, selected: Option<usize>) {
    let RenderCache {
        key: _,
        renderer,
        canvas,
        grid,
        overlays,
    } = &mut *cache;
    let mesh = app.doc.scene.mesh();
    let renderer = renderer.get_or_insert_with(|| Renderer::new(mesh));
    let canvas = canvas.get_or_insert_with(|| DotCanvas::new(0, 0));
    let mode = app.view.cells;
    mode.prepare(canvas, usize::from(inner.width), usize::from(inner.height));
    overlays.clear();
    let palette = Palette::default();
    if app.view.show_muscles {
        muscle_overlays(app.rig(), selected, &palette, overlays);
    }
    let mut scene = Scene::new(mesh, app.doc.scene.positions()).with_overlays(overlays);
    scene.ghost = app.view.show_ghost;
    scene.displacement = app.view.show_displacement;
    renderer.render(&scene, &camera(app), app.view.style, canvas);
    grid.fill(canvas, mode, color_mode(app.view.colors));
}

/// Copies the cell grid into the ratatui buffer.
fn copy_cells(app: &App, theme: &Theme, grid: &CellGrid, inner: Rect, buf: &mut Buffer) {
    for row in 0..grid.height.min(usize::from(inner.height)) {
        for (col, cell) in grid
            .row(row)
            .iter()
            .enumerate()
            .take(usize::from(inner.width))
        {
            if cell.ch == ' ' && cell.bg.is_none() {
                continue;
            }
            let Some(target) = buf.cell_mut((inner.x + col as u16, inner.y + row as u16)) else {
                continue;
            };
            target.set_char(cell.ch);
            match cell.fg.and_then(|c| to_color(c, app.view.colors)) {
                Some(fg) => {
                    target.set_fg(fg);
                }
                None => {
                    target.set_style(theme.face());
                }
            }
            if let Some(bg) = cell.bg.and_then(|c| to_color(c, app.view.colors)) {
                target.set_bg(bg);
            }
        }
    }
}
