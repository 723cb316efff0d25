//! The AU table panel: recorded AUs (number, name, a mark on the loaded one), then expressions.

use ratatui::buffer::Buffer;
use ratatui::layout::{Position, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Widget};

use super::theme::Theme;
use crate::facs::MAX_AUS;
use crate::tui::app::{App, CellMode, Focus, TableItem};

/// A line of the panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PanelLine {
    Heading(&'static str),
    Item(usize),
    Empty(&'static str),
}

fn lines(app: &App, items: &[TableItem]) -> Vec<PanelLine> {
    let aus = items
        .iter()
        .filter(|i| matches!(i, TableItem::Au(_)))
        .count();
    let mut out = Vec::with_capacity(items.len() + 2);
    if aus == 0 {
        out.push(PanelLine::Empty("no AUs yet: r records one"));
    }
    out.extend((0..aus).map(PanelLine::Item));
    if aus < items.len() || !app.doc.table.expressions.is_empty() {
        out.push(PanelLine::Heading("expressions"));
        out.extend((aus..items.len()).map(PanelLine::Item));
    }
    out
}

fn scroll(app: &App, lines: &[PanelLine], height: usize) -> usize {
    let at = lines
        .iter()
        .position(|l| *l == PanelLine::Item(app.selection.table_selected))
        .unwrap_or(0);
    if lines.len() <= height {
        return 0;
    }
    at.saturating_sub(height / 2).min(lines.len() - height)
}

/// The table item under a screen position, for mouse clicks.
pub fn item_at(app: &App, area: Rect, x: u16, y: u16) -> Option<usize> {
    let inner = Block::default().borders(Borders::ALL).inner(area);
    if !inner.contains(Position { x, y }) {
        return None;
    }
    let items = app.table_items();
    let lines = lines(app, &items);
    let offset = scroll(app, &lines, inner.height as usize);
    match lines.get(offset + (y - inner.y) as usize)? {
        PanelLine::Item(i) => Some(*i),
        _ => None,
    }
}

/// "AU table 48 AUs, 7 expr", and "(full)" when no more AUs fit.
fn title(app: &App) -> String {
    let aus = app.doc.table.aus.len();
    let full = if aus >= MAX_AUS { " (full)" } else { "" };
    let plural = if aus == 1 { "" } else { "s" };
    format!(
        " AU table {aus} AU{plural}{full}, {} expr ",
        app.doc.table.expressions.len()
    )
}

/// Draws the panel.
pub fn draw(app: &App, theme: &Theme, area: Rect, buf: &mut Buffer) {
    let focused = app.selection.focus == Focus::Table;
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border(focused))
        .title(title(app));
    let inner = block.inner(area);
    block.render(area, buf);
    let items = app.table_items();
    let lines = lines(app, &items);
    let offset = scroll(app, &lines, inner.height as usize);
    let ascii = app.view.cells == CellMode::Ascii;
    let width = inner.width as usize;
    for (k, line) in lines
        .iter()
        .skip(offset)
        .take(inner.height as usize)
        .enumerate()
    {
        let y = inner.y + k as u16;
        let rendered = match line {
            PanelLine::Heading(text) => Line::from(Span::styled(*text, theme.heading())),
            PanelLine::Empty(text) => Line::from(Span::styled(*text, theme.dim())),
            PanelLine::Item(i) => {
                let style = if *i == app.selection.table_selected {
                    theme.selected(focused)
                } else {
                    theme.text()
                };
                let text = match &items[*i] {
                    TableItem::Au(key) => {
                        let loaded = app.doc.loaded == Some(*key);
                        let mark = match (loaded, ascii) {
                            (true, false) => '\u{25cf}',
                            (true, true) => '*',
                            _ => ' ',
                        };
                        let name = app.doc.table.aus.get(key).map_or("", |e| e.name.as_str());
                        format!("{mark}{:>4} {name}", key.to_string())
                    }
                    TableItem::Expression(name) => {
                        let combo = app
                            .doc
                            .table
                            .expressions
                            .get(name)
                            .map_or("", |c| c.as_str());
                        format!(" {name} = {combo}")
                    }
                };
                let text: String = text.chars().take(width).collect();
                Line::from(Span::styled(format!("{text:<width$}"), style))
            }
        };
        buf.set_line(inner.x, y, &rendered, inner.width);
    }
}

#[cfg(test)]
mod tests {
    use super::title;
    use crate::facs::{AuKey, MAX_AUS};
    use crate::tui::fixture;

    #[test]
    fn the_title_counts_aus_and_expressions_and_says_when_full() {
        let mut app = fixture::app();
        app.doc.table.expressions.clear();
        let entry = app.doc.table.aus.values().next().unwrap().clone();
        app.doc.table.aus.clear();
        assert_eq!(title(&app), " AU table 0 AUs, 0 expr ");
        app.doc.table.aus.insert(AuKey::new(1), entry.clone());
        app.doc.table.expressions.insert("brows".into(), "1".into());
        assert_eq!(title(&app), " AU table 1 AU, 1 expr ");
        for n in 1..=MAX_AUS as u8 {
            app.doc.table.aus.insert(AuKey::new(n), entry.clone());
        }
        assert_eq!(
            title(&app),
            format!(" AU table {MAX_AUS} AUs (full), 1 expr ")
        );
    }
}
