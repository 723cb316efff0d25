//! The viewport: the deformed face, drawn by the core renderer ([`crate::render`]) and copied
//! cell by cell into the ratatui buffer.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::widgets::{Block, Borders, Widget};

use super::cells::CellGridView;
use super::theme::Theme;
use crate::render::{
    muscle_overlays, CellGrid, DisplacementLegend, DotCanvas, Overlay, Palette, Renderer, Scene,
};
use crate::tui::app::{App, Row};

/// The renderer and its buffers, kept between frames so drawing allocates nothing.
#[derive(Debug, Clone, Default)]
pub struct RenderCache {
    /// What the grid shows; the face is drawn again only when this changes.
    key: Option<CacheKey>,
    renderer: Option<Renderer>,
    canvas: Option<DotCanvas>,
    grid: CellGrid,
    overlays: Vec<Overlay>,
    /// The deformed positions of the level of detail drawn (a big mesh's).
    sampled: Vec<glam::Vec3>,
    /// The vertex and triangle counts of the mesh `renderer` was made for: a renderer
    /// made for a big mesh's full size is dropped, not kept with its buffers, when a level
    /// of detail replaces it.
    drawn: (usize, usize),
}

/// Everything the picture depends on.
#[derive(Debug, Clone, PartialEq)]
struct CacheKey {
    generation: u64,
    view: crate::tui::app::View,
    area: Rect,
    selected: Option<usize>,
    /// Rig mode's selected point, while rig mode is on.
    rig: Option<usize>,
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
        generation: app.doc.face.generation(),
        view: app.view.clone(),
        area: inner,
        selected: selected.filter(|_| app.view.show_muscles),
        rig: app.rig_edit.on.then_some(app.rig_edit.point),
    };
    let fresh = cache.key.as_ref() == Some(&key);
    if !fresh {
        render_face(app, cache, inner, selected);
        cache.key = Some(key);
    }
    CellGridView {
        grid: &cache.grid,
        colors: app.view.colors,
        plain: theme.face(),
    }
    .render(inner, buf);
    if app.view.show_displacement && inner.height > 2 {
        // The colour scale, on the viewport's last row.
        let mesh = app.doc.face.mesh();
        let legend = DisplacementLegend::of(&Scene {
            mm_per_unit: app.doc.face.mm_per_unit(),
            ..Scene::new(mesh, &mesh.positions)
        });
        let row = Rect {
            y: inner.bottom() - 1,
            height: 1,
            ..inner
        };
        for x in row.left()..row.right() {
            if let Some(cell) = buf.cell_mut((x, row.y)) {
                cell.reset();
            }
        }
        CellGridView {
            grid: &legend.row(usize::from(row.width), app.view.colors),
            colors: app.view.colors,
            plain: theme.face(),
        }
        .render(row, buf);
    }
}

/// Renders the face into the cache's cell grid.
fn render_face(app: &App, cache: &mut RenderCache, inner: Rect, selected: Option<usize>) {
    let RenderCache {
        key: _,
        renderer,
        canvas,
        grid,
        overlays,
        sampled,
        drawn,
    } = &mut *cache;
    let mesh = app.doc.face.mesh();
    let canvas = canvas.get_or_insert_with(|| DotCanvas::new(0, 0));
    let mode = app.view.drawn_cells();
    mode.prepare(canvas, usize::from(inner.width), usize::from(inner.height));
    overlays.clear();
    let palette = Palette::default();
    if app.view.show_muscles {
        muscle_overlays(app.rig(), selected, &palette, overlays);
    }
    if app.rig_edit.on {
        super::rig::zone_overlays(app, overlays);
    }
    let camera = app.camera();
    let level =
        app.doc
            .face
            .lod()
            .choose(&camera, canvas.width(), canvas.height(), canvas.dot_aspect);
    // A big mesh is drawn from the level of detail this view needs, only its vertices
    // deformed; a small one (or a close zoom) whole.
    let mut scene = match level {
        Some(level) => {
            app.doc.face.sample(level, sampled);
            Scene {
                focus: Some(&level.frame),
                irises: &app.doc.face.framing().irises,
                ..Scene::new(&level.mesh, sampled)
            }
        }
        None => Scene::new(mesh, app.doc.face.positions()).with_framing(app.doc.face.framing()),
    }
    .with_overlays(overlays);
    scene.ghost = app.view.show_ghost;
    scene.displacement = app.view.show_displacement;
    let size = (scene.mesh.positions.len(), scene.mesh.triangles.len());
    if *drawn != size {
        *drawn = size;
        *renderer = None;
    }
    let renderer = renderer.get_or_insert_with(|| Renderer::new(scene.mesh));
    renderer.render(&scene, &camera, app.view.style, canvas);
    grid.fill(canvas, mode, app.view.colors);
}
