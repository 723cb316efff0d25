//! Drawing: one file per panel. `draw` only reads the state.

pub mod cells;
pub mod help;
pub mod muscles;
pub mod prompt;
pub mod rig;
pub mod status;
pub mod table;
pub mod theme;
pub mod viewport;

use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Paragraph, Wrap};
use ratatui::Frame;

use super::app::{App, Focus, Mode, MIN_SIZE};
use theme::Theme;

/// Where each panel goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Panels {
    /// The muscle list.
    pub muscles: Rect,
    /// The AU table.
    pub table: Rect,
    /// The face.
    pub viewport: Rect,
    /// The status line.
    pub status: Rect,
    /// The message / input / question line.
    pub line: Rect,
}

/// The panels for a terminal area, or `None` when it is too small to be useful. In narrow
/// terminals the muscle list and the AU table share a column; the focused one gets more of it.
/// The bottom line grows to fit a long message or question (see [`prompt::rows`]).
pub fn layout(area: Rect, app: &App) -> Option<Panels> {
    if area.width < MIN_SIZE.0 || area.height < MIN_SIZE.1 {
        return None;
    }
    let focus = app.selection.focus;
    let [body, status, line] = Layout::vertical([
        Constraint::Min(1),
        Constraint::Length(1),
        Constraint::Length(prompt::rows(app, area.width)),
    ])
    .areas(area);
    if area.width >= 110 {
        // Wide: muscles | face | table.
        let side = (area.width / 6).clamp(28, 40);
        let [muscles, viewport, table] = Layout::horizontal([
            Constraint::Length(side + 6),
            Constraint::Min(20),
            Constraint::Length(side),
        ])
        .areas(body);
        Some(Panels {
            muscles,
            table,
            viewport,
            status,
            line,
        })
    } else {
        // Narrow: muscles above table on the left, face on the right.
        let [left, viewport] =
            Layout::horizontal([Constraint::Length(32), Constraint::Min(20)]).areas(body);
        let table_height = match focus {
            Focus::Muscles => (left.height / 3).max(5),
            Focus::Table => (left.height * 2 / 3).max(5),
        };
        let [muscles, table] =
            Layout::vertical([Constraint::Min(5), Constraint::Length(table_height)]).areas(left);
        Some(Panels {
            muscles,
            table,
            viewport,
            status,
            line,
        })
    }
}

/// Draws the whole screen; `cache` keeps the face's buffers between frames.
pub fn draw(app: &App, cache: &mut viewport::RenderCache, frame: &mut Frame) {
    let area = frame.area();
    let theme = Theme::new(app.view.colors);
    let Some(panels) = layout(area, app) else {
        let text = format!(
            "Terminal too small: {}x{}. grimace needs at least {}x{}. Enlarge the window (q quits).",
            area.width, area.height, MIN_SIZE.0, MIN_SIZE.1
        );
        frame.render_widget(
            Paragraph::new(Line::from(text)).wrap(Wrap { trim: true }),
            area,
        );
        return;
    };
    let buf = frame.buffer_mut();
    viewport::draw(app, cache, &theme, panels.viewport, buf);
    muscles::draw(app, &theme, panels.muscles, buf);
    table::draw(app, &theme, panels.table, buf);
    status::draw(app, &theme, panels.status, buf);
    prompt::draw(app, &theme, panels.line, frame);
    if let Mode::Help(scroll) = app.mode {
        help::draw(&theme, scroll, area, frame.buffer_mut());
    }
}

/// Splits `text` into lines of at most `width` characters, breaking between words (a word
/// longer than `width` is split). Always at least one line.
pub fn wrap_words(text: &str, width: usize) -> Vec<String> {
    let mut out = vec![String::new()];
    for word in text.split_whitespace() {
        let mut word: Vec<char> = word.chars().collect();
        loop {
            let line = out.last_mut().expect("never empty");
            let used = line.chars().count();
            let gap = usize::from(used > 0);
            if used + gap + word.len() <= width {
                if gap == 1 {
                    line.push(' ');
                }
                line.extend(word.iter());
                break;
            }
            if used > 0 {
                out.push(String::new());
                continue;
            }
            let rest = word.split_off(width.min(word.len()));
            line.extend(word.iter());
            out.push(String::new());
            word = rest;
            if word.is_empty() {
                out.pop();
                break;
            }
        }
    }
    out
}
