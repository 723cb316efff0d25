//! Drawing the picker: the mesh with the picked points and the cursor, the landmark's name
//! and the progress, the default face with the landmark marked, the status line, and the
//! help and questions over them. Only reads the state.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Widget, Wrap};
use ratatui::Frame;

use super::keys;
use super::layout;
use super::state::{Mode, PickApp, Question};
use crate::landmarks::NAMES;
use crate::render::{
    Camera, CellGrid, CellMode, ColorMode, DotCanvas, Framing, Renderer, Scene, Style as Look,
};
use crate::tui::view::cells::CellGridView;
use crate::tui::view::theme::Theme;
use crate::tui::view::wrap_words;

/// One rendered face, kept until its view changes.
#[derive(Debug, Default)]
struct FaceCache {
    key: Option<(Camera, Rect, CellMode, ColorMode, usize)>,
    renderer: Option<Renderer>,
    canvas: Option<DotCanvas>,
    grid: CellGrid,
}

impl FaceCache {
    /// The face drawn for this view (drawn again only when something changed), fitted as
    /// `framing` says, as the picker's screen is (`None`: the whole mesh).
    fn grid(
        &mut self,
        (mesh, framing): (&crate::model::Mesh, Option<&Framing>),
        camera: Camera,
        area: Rect,
        cells: CellMode,
        colors: ColorMode,
    ) -> &CellGrid {
        let fitted = framing.map_or(mesh.positions.len(), |f| f.frame(mesh).len());
        let key = (camera, area, cells, colors, fitted);
        if self.key != Some(key) {
            let renderer = self.renderer.get_or_insert_with(|| Renderer::new(mesh));
            let canvas = self.canvas.get_or_insert_with(|| DotCanvas::new(0, 0));
            cells.prepare(canvas, usize::from(area.width), usize::from(area.height));
            let scene = Scene::new(mesh, &mesh.positions);
            let scene = match framing {
                Some(framing) => scene.with_framing(framing),
                None => scene,
            };
            renderer.render(&scene, &camera, Look::Lines, canvas);
            self.grid.fill(canvas, cells, colors);
            self.key = Some(key);
        }
        &self.grid
    }
}

/// The two faces' pictures, kept between frames.
#[derive(Debug, Default)]
pub struct PickCache {
    mesh: FaceCache,
    reference: FaceCache,
}

/// The marks drawn over the faces.
fn marks(cells: CellMode) -> (char, char, char) {
    match cells {
        CellMode::Ascii => ('+', 'o', '*'),
        _ => ('✚', '•', '◆'),
    }
}

/// Draws the whole picker.
pub fn draw(app: &PickApp, cache: &mut PickCache, frame: &mut Frame) {
    let area = frame.area();
    let theme = Theme::new(app.colors);
    let parts = layout(area);
    let buf = frame.buffer_mut();
    draw_mesh(app, cache, &theme, parts.mesh, parts.mesh_inner, buf);
    draw_info(app, &theme, parts.info, buf);
    draw_reference(app, cache, &theme, parts.reference, buf);
    draw_status(app, &theme, parts.status, buf);
    match &app.mode {
        Mode::Help => draw_help(&theme, area, buf),
        Mode::Confirm(question) => draw_question(app, question, &theme, area, buf),
        _ => {}
    }
}

fn mark_style(theme: &Theme, color: Color) -> Style {
    match theme.colors {
        ColorMode::None => Style::default().add_modifier(Modifier::BOLD),
        _ => Style::default().fg(color).add_modifier(Modifier::BOLD),
    }
}

fn draw_mesh(
    app: &PickApp,
    cache: &mut PickCache,
    theme: &Theme,
    outer: Rect,
    inner: Rect,
    buf: &mut Buffer,
) {
    let name = app
        .mesh_path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let title = format!(
        " {}  yaw {:.0} pitch {:.0} zoom {:.2} ",
        name,
        app.camera.yaw.to_degrees(),
        app.camera.pitch.to_degrees(),
        app.camera.zoom
    );
    Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border(true))
        .title(title)
        .render(outer, buf);
    let Some(screen) = &app.screen else {
        return;
    };
    if inner.is_empty() {
        return;
    }
    let grid = cache.mesh.grid(
        (&app.mesh, Some(&app.framing)),
        app.camera,
        inner,
        app.cells,
        app.colors,
    );
    CellGridView {
        grid,
        colors: app.colors,
        plain: theme.face(),
    }
    .render(inner, buf);
    let (cursor, picked, _) = marks(app.cells);
    let put = |buf: &mut Buffer, at: glam::Vec2, c: char, style: Style| {
        if let Some((col, row)) = screen.cell_of(at) {
            if let Some(cell) = buf.cell_mut((inner.x + col, inner.y + row)) {
                cell.set_char(c).set_style(style);
            }
        }
    };
    for v in app.picks.iter().flatten() {
        if screen.visible[*v as usize] {
            if let Some(at) = screen.dot_of(*v) {
                put(buf, at, picked, mark_style(theme, Color::LightGreen));
            }
        }
    }
    let at = app
        .snapped
        .and_then(|v| screen.dot_of(v))
        .unwrap_or(app.cursor);
    let style = match theme.colors {
        ColorMode::None => Style::default().add_modifier(Modifier::REVERSED | Modifier::BOLD),
        _ => Style::default()
            .fg(Color::Black)
            .bg(Color::Yellow)
            .add_modifier(Modifier::BOLD),
    };
    put(buf, at, cursor, style);
}

/// The info panel's lines.
pub fn info_lines(app: &PickApp) -> Vec<String> {
    let mut lines = Vec::new();
    let picked = app.picked();
    match app.current {
        Some(l) => {
            lines.push(format!("Landmark {l}: {}", NAMES[l]));
            let step = app.step_number().unwrap_or(0);
            let set = if step <= 17 { " (minimal set)" } else { "" };
            lines.push(format!("step {step} of 68{set}, {picked} of 68 picked"));
            let state = if let Some(v) = app.picks[l] {
                format!("picked: vertex {v}; Enter keeps the cursor's vertex")
            } else if let Some((v, source)) = app.proposals[l] {
                format!(
                    "{} (vertex {v}): Enter confirms, arrows nudge",
                    source.describe()
                )
            } else if app.skipped[l] {
                "skipped before: pick it now, or Tab again".to_string()
            } else {
                "find it on your mesh: move the cursor, then Enter".to_string()
            };
            lines.push(state);
        }
        None => {
            lines.push(format!("All 68 landmarks picked ({picked} of 68)"));
            lines.push(":w saves them; n and p go through them to correct one".to_string());
        }
    }
    lines.push(match app.snapped {
        Some(v) => format!("cursor: vertex {v}"),
        None => "cursor: no visible vertex here".to_string(),
    });
    lines
}

fn draw_info(app: &PickApp, theme: &Theme, area: Rect, buf: &mut Buffer) {
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border(false))
        .title(" Landmark ");
    let inner = block.inner(area);
    block.render(area, buf);
    let width = usize::from(inner.width.max(1));
    let mut text: Vec<Line> = Vec::new();
    for (i, line) in info_lines(app).into_iter().enumerate() {
        let style = if i == 0 {
            theme.heading()
        } else {
            theme.text()
        };
        for piece in wrap_words(&line, width) {
            text.push(Line::from(Span::styled(piece, style)));
        }
    }
    Paragraph::new(text).render(inner, buf);
}

fn draw_reference(
    app: &PickApp,
    cache: &mut PickCache,
    theme: &Theme,
    area: Rect,
    buf: &mut Buffer,
) {
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border(false))
        .title(" on the default face ");
    let inner = block.inner(area);
    block.render(area, buf);
    if inner.is_empty() {
        return;
    }
    let camera = Camera {
        yaw: app.camera.yaw,
        pitch: app.camera.pitch,
        ..Camera::front()
    };
    let reference = &app.reference;
    let grid = cache.reference.grid(
        (&reference.mesh, None),
        camera,
        inner,
        app.cells,
        app.colors,
    );
    CellGridView {
        grid,
        colors: app.colors,
        plain: theme.dim(),
    }
    .render(inner, buf);
    let Some(l) = app.current else {
        return;
    };
    let Some(&point) = reference.points.get(l) else {
        return;
    };
    let (dx, dy) = app.cells.dots_per_cell();
    let (w, h) = (
        usize::from(inner.width) * dx,
        usize::from(inner.height) * dy,
    );
    let projection = camera.fit_points(&reference.mesh.positions, w, h, app.cells.dot_aspect(0.5));
    let p = projection.project(point);
    if p.x >= 0.0 && p.y >= 0.0 && (p.x as usize) < w && (p.y as usize) < h {
        let (col, row) = ((p.x as usize / dx) as u16, (p.y as usize / dy) as u16);
        if let Some(cell) = buf.cell_mut((inner.x + col, inner.y + row)) {
            cell.set_char(marks(app.cells).2)
                .set_style(mark_style(theme, Color::LightRed));
        }
    }
}

fn draw_status(app: &PickApp, theme: &Theme, area: Rect, buf: &mut Buffer) {
    if area.is_empty() {
        return;
    }
    buf.set_style(area, theme.status());
    let dirty = if app.dirty { " [+]" } else { "" };
    let left = " PICK ".to_string();
    let file = format!(" {}{dirty} ", app.out.display());
    let room = usize::from(area.width).saturating_sub(left.chars().count() + file.chars().count());
    let (right, style) = match (&app.mode, &app.message) {
        (Mode::Command(line), _) => (format!(":{line}"), theme.status()),
        (_, Some(message)) => (
            message.text.clone(),
            theme
                .message(message.severity)
                .patch(theme.status().remove_modifier(Modifier::REVERSED)),
        ),
        _ => {
            let mut hints = String::new();
            for (key, hint) in keys::hints() {
                let piece = format!("{key} {hint}  ");
                if hints.chars().count() + piece.chars().count() > room {
                    break;
                }
                hints.push_str(&piece);
            }
            (format!("{hints:>room$}"), theme.status())
        }
    };
    let right: String = right.chars().take(room).collect();
    let line = Line::from(vec![
        Span::styled(left, theme.mode()),
        Span::styled(file, theme.status()),
        Span::styled(right, style),
    ]);
    buf.set_line(area.x, area.y, &line, area.width);
}

/// A box in the middle of `area`.
fn centred(area: Rect, width: u16, height: u16) -> Rect {
    let w = width.min(area.width);
    let h = height.min(area.height);
    Rect::new(
        area.x + (area.width - w) / 2,
        area.y + (area.height - h) / 2,
        w,
        h,
    )
}

fn draw_help(theme: &Theme, area: Rect, buf: &mut Buffer) {
    let mut lines: Vec<Line> = vec![Line::from(Span::styled("Keys", theme.heading()))];
    let width = keys::help_lines()
        .iter()
        .map(|(k, _)| k.chars().count())
        .max()
        .unwrap_or(0);
    for (key, description) in keys::help_lines() {
        lines.push(Line::from(format!("{key:<width$}  {description}")));
    }
    lines.push(Line::from(Span::styled("Mouse", theme.heading())));
    for (what, description) in keys::MOUSE {
        lines.push(Line::from(format!("{what:<width$}  {description}")));
    }
    lines.push(Line::from(Span::styled("any key closes this", theme.dim())));
    let height = lines.len() as u16 + 2;
    let rect = centred(area, 100, height);
    Clear.render(rect, buf);
    Paragraph::new(lines)
        .block(
            Block::default()
                .borders(Borders::ALL)
                .title(" Picking landmarks "),
        )
        .wrap(Wrap { trim: false })
        .render(rect, buf);
}

fn draw_question(app: &PickApp, question: &Question, theme: &Theme, area: Rect, buf: &mut Buffer) {
    let text = match question {
        Question::Quit => format!(
            "{} picks are not saved. Quit anyway? (y/n)",
            app.picked()
        ),
        Question::Overwrite { .. } => format!(
            "{} changed on disk since it was opened. Overwrite it? (y/n)",
            crate::io::printable::printable(&app.out.display().to_string())
        ),
        Question::Recover { picks, when, .. } => format!(
            "{} picked landmarks were kept from a picking session that stopped ({when}). Take them back? (y/n)",
            picks.iter().flatten().count()
        ),
    };
    let rect = centred(area, 64, 5);
    Clear.render(rect, buf);
    Paragraph::new(text)
        .style(theme.text())
        .block(Block::default().borders(Borders::ALL).title(" Question "))
        .wrap(Wrap { trim: true })
        .render(rect, buf);
}
