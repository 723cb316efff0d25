//! The muscle panel: muscles grouped by kind, each with side, gauge and value; then the jaw.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Widget};

use super::theme::Theme;
use crate::tui::app::{group_of, App, CellMode, Focus, Group, Row};

/// A line of the panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PanelLine {
    /// A group heading.
    Heading(Group),
    /// A muscle or the jaw.
    Row(Row),
}

/// The panel's lines: a heading before each group.
pub fn lines(app: &App) -> Vec<PanelLine> {
    let mut out = Vec::with_capacity(app.selection.rows.len() + 4);
    let mut last = None;
    for &row in &app.selection.rows {
        let group = group_of(app.rig(), row);
        if last != Some(group) {
            out.push(PanelLine::Heading(group));
            last = Some(group);
        }
        out.push(PanelLine::Row(row));
    }
    out
}

/// The first line shown in a panel `height` lines tall: keeps the selection in view, centred
/// when the list does not fit.
pub fn scroll(app: &App, lines: &[PanelLine], height: usize) -> usize {
    let selected = app.selected_row();
    let at = lines
        .iter()
        .position(|l| *l == PanelLine::Row(selected))
        .unwrap_or(0);
    if lines.len() <= height {
        return 0;
    }
    at.saturating_sub(height / 2).min(lines.len() - height)
}

/// The inner area of the panel (inside its border).
pub fn inner(area: Rect) -> Rect {
    Block::default().borders(Borders::ALL).inner(area)
}

/// The row under a screen position, for mouse clicks.
pub fn row_at(app: &App, area: Rect, x: u16, y: u16) -> Option<Row> {
    let inner = inner(area);
    if !inner.contains(ratatui::layout::Position { x, y }) {
        return None;
    }
    let lines = lines(app);
    let offset = scroll(app, &lines, inner.height as usize);
    match lines.get(offset + (y - inner.y) as usize)? {
        PanelLine::Row(row) => Some(*row),
        PanelLine::Heading(_) => None,
    }
}

/// A muscle name as shown: without the side prefix, spaces for underscores.
pub fn display_name(name: &str) -> String {
    let bare = name
        .strip_prefix("L_")
        .or_else(|| name.strip_prefix("R_"))
        .unwrap_or(name);
    bare.replace('_', " ")
}

/// Draws the panel.
pub fn draw(app: &App, theme: &Theme, area: Rect, buf: &mut Buffer) {
    let focused = app.selection.focus == Focus::Muscles;
    let title = format!(
        " Muscles {}/{}{} ",
        app.selection.selected + 1,
        app.selection.rows.len(),
        if app.selection.mirror {
            " [mirror]"
        } else {
            ""
        }
    );
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border(focused))
        .title(title);
    let inner = block.inner(area);
    block.render(area, buf);
    let lines = lines(app);
    let offset = scroll(app, &lines, inner.height as usize);
    let ascii = app.view.cells == CellMode::Ascii;
    let partner = app
        .partner(app.selected_row())
        .filter(|_| app.selection.mirror);
    for (k, line) in lines
        .iter()
        .skip(offset)
        .take(inner.height as usize)
        .enumerate()
    {
        let y = inner.y + k as u16;
        let rendered = match line {
            PanelLine::Heading(group) => {
                Line::from(Span::styled(group.title().to_string(), theme.heading()))
            }
            PanelLine::Row(row) => row_line(app, theme, *row, inner.width, ascii, partner),
        };
        buf.set_line(inner.x, y, &rendered, inner.width);
    }
}

/// One muscle row: marker, side, name, gauge, value, mirror mark.
fn row_line(
    app: &App,
    theme: &Theme,
    row: Row,
    width: u16,
    ascii: bool,
    partner: Option<Row>,
) -> Line<'static> {
    let width = width as usize;
    let selected = row == app.selected_row();
    let (side, name) = match row {
        Row::Muscle(i) => {
            let m = &app.rig().muscles[i];
            (m.side.letter(), display_name(&m.name))
        }
        Row::Jaw => ('C', "jaw".to_string()),
    };
    let value = app.value(row);
    let (_, max) = app.range(row);
    let linked = app.selection.mirror && app.partner(row).is_some();
    let mark = match (partner == Some(row), linked, ascii) {
        (true, _, false) => "\u{25c6}",
        (true, _, true) => "*",
        (false, true, false) => "\u{2194}",
        (false, true, true) => "~",
        _ => " ",
    };
    // side(1) + space + name + space + gauge + space + value(4) + mark(1)
    let fixed = 1 + 1 + 1 + 1 + 4 + 1;
    let rest = width.saturating_sub(fixed);
    let gauge_width = (rest / 4).clamp(3, 12);
    let name_width = rest.saturating_sub(gauge_width);
    let name: String = name.chars().take(name_width).collect();
    let base = if selected {
        theme.selected(app.selection.focus == Focus::Muscles)
    } else {
        theme.text()
    };
    let gauge_style = if selected { base } else { theme.gauge() };
    let mark_style = if partner == Some(row) {
        theme.partner()
    } else {
        base
    };
    Line::from(vec![
        Span::styled(format!("{side} {name:<name_width$} "), base),
        Span::styled(gauge(value / max, gauge_width, ascii), gauge_style),
        Span::styled(format!(" {value:4.2}"), base),
        Span::styled(mark.to_string(), mark_style),
    ])
}

/// A horizontal bar `width` cells wide filled to `fraction`, in eighths when not ASCII.
pub fn gauge(fraction: f32, width: usize, ascii: bool) -> String {
    let fraction = if fraction.is_finite() {
        fraction.clamp(0.0, 1.0)
    } else {
        0.0
    };
    if ascii {
        let filled = (fraction * width as f32).round() as usize;
        return format!("{}{}", "#".repeat(filled), ".".repeat(width - filled));
    }
    const EIGHTHS: [char; 8] = [
        ' ', '\u{258f}', '\u{258e}', '\u{258d}', '\u{258c}', '\u{258b}', '\u{258a}', '\u{2589}',
    ];
    let eighths = (fraction * width as f32 * 8.0).round() as usize;
    let full = eighths / 8;
    let mut out: String = "\u{2588}".repeat(full);
    if full < width {
        let part = eighths % 8;
        out.push(if part == 0 { '\u{b7}' } else { EIGHTHS[part] });
        out.extend(std::iter::repeat_n('\u{b7}', width - full - 1));
    }
    out
}
