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

/// The lines shown in a panel `height` lines tall. When the list does not fit, the jaw (its
/// heading and row) stays pinned at the bottom and the muscles scroll above it, so the jaw is
/// always in sight.
pub fn visible(app: &App, height: usize) -> Vec<PanelLine> {
    let all = lines(app);
    let jaw = [PanelLine::Heading(Group::Jaw), PanelLine::Row(Row::Jaw)];
    if all.len() <= height || height < 4 || !all.ends_with(&jaw) {
        let offset = scroll(app, &all, height);
        return all.into_iter().skip(offset).take(height).collect();
    }
    let muscles = &all[..all.len() - jaw.len()];
    let room = height - jaw.len();
    let offset = if app.selected_row() == Row::Jaw {
        muscles.len() - room
    } else {
        scroll(app, muscles, room)
    };
    let mut out: Vec<PanelLine> = muscles[offset..offset + room].to_vec();
    out.extend(jaw);
    out
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
    match visible(app, inner.height as usize).get((y - inner.y) as usize)? {
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

/// A muscle name shortened to `width` characters, keeping it readable and telling it apart
/// from its neighbours: words are cut to three letters and a dot from the left
/// (`Orbicularis Oculi Orbital` becomes `Orb. Oculi Orbital`), the last word last, and only
/// then is the end cut with an ellipsis.
pub fn fit_name(name: &str, width: usize) -> String {
    let mut words: Vec<String> = name.split(' ').map(str::to_string).collect();
    let len =
        |words: &[String]| words.iter().map(|w| w.chars().count()).sum::<usize>() + words.len() - 1;
    for i in 0..words.len() {
        if len(&words) <= width {
            return words.join(" ");
        }
        if words[i].chars().count() > 4 {
            words[i] = words[i].chars().take(3).chain(['.']).collect();
        }
    }
    let joined = words.join(" ");
    if joined.chars().count() <= width {
        return joined;
    }
    let mut cut: String = joined.chars().take(width.saturating_sub(1)).collect();
    cut.push('\u{2026}');
    cut
}

/// The widths of a row's name and gauge in a panel `width` cells wide (inside its border):
/// the name gets up to 20 cells before the gauge grows past its smallest (3).
pub fn name_and_gauge(width: usize) -> (usize, usize) {
    // side(1) + space + name + space + gauge + space + value(4) + mark(1)
    let rest = width.saturating_sub(1 + 1 + 1 + 1 + 4 + 1);
    let name = (rest - (rest / 4).clamp(3, 12).min(rest)).max(rest.saturating_sub(3).min(20));
    (name, rest - name)
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
    let shown = visible(app, inner.height as usize);
    let ascii = app.view.cells == CellMode::Ascii;
    let partner = app
        .partner(app.selected_row())
        .filter(|_| app.selection.mirror);
    for (k, line) in shown.iter().enumerate() {
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
    let (name_width, gauge_width) = name_and_gauge(width);
    let name = fit_name(&name, name_width);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tui::app::App;
    use crate::tui::face::Face;

    fn app_on(rig: crate::model::Rig) -> App {
        let scene = Face::new(rig, crate::io::builtin::default_mesh()).unwrap();
        App::new(scene, crate::facs::AuTable::new("builtin:default"), None)
    }

    #[test]
    fn names_fit_and_stay_unique_at_every_width() {
        for rig in [
            crate::io::builtin::default_rig(),
            crate::io::builtin::paper_rig(),
        ] {
            let app = app_on(rig);
            for columns in 60..=220 {
                let area = Rect::new(0, 0, columns, 40);
                let panel = crate::tui::view::layout(area, &app).unwrap().muscles;
                let (width, _) = name_and_gauge(inner(panel).width as usize);
                let mut seen = std::collections::BTreeSet::new();
                for m in &app.rig().muscles {
                    let shown = fit_name(&display_name(&m.name), width);
                    assert!(shown.chars().count() <= width, "{shown} at {columns}");
                    assert!(!shown.ends_with('\u{2026}'), "{} cut at {columns}", m.name);
                    assert!(
                        seen.insert((m.side.letter(), shown.clone())),
                        "{shown} twice at {columns} columns"
                    );
                }
            }
        }
    }

    #[test]
    fn shortening_cuts_words_from_the_left() {
        assert_eq!(
            fit_name("Orbicularis Oculi Orbital", 25),
            "Orbicularis Oculi Orbital"
        );
        assert_eq!(
            fit_name("Orbicularis Oculi Orbital", 20),
            "Orb. Oculi Orbital"
        );
        assert_eq!(
            fit_name("Depressor Labii Inferioris", 20),
            "Dep. Lab. Inferioris"
        );
        assert_eq!(fit_name("Depressor Labii Inferioris", 14), "Dep. Lab. Inf.");
        assert_eq!(fit_name("Depressor Labii Inferioris", 8), "Dep. La\u{2026}");
    }

    #[test]
    fn the_jaw_stays_in_sight_when_the_muscles_scroll() {
        let mut app = app_on(crate::io::builtin::default_rig());
        let rows = app.selection.rows.len();
        for height in [10, 20, 36, 38] {
            for selected in [0, rows / 2, rows - 2, rows - 1] {
                app.selection.selected = selected;
                let shown = visible(&app, height);
                assert_eq!(shown.len(), height.min(lines(&app).len()));
                assert_eq!(shown.last(), Some(&PanelLine::Row(Row::Jaw)));
                assert!(
                    shown.contains(&PanelLine::Row(app.selected_row())),
                    "row {selected} at height {height}"
                );
            }
        }
    }
}
