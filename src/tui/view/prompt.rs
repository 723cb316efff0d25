//! The bottom line: the input being typed, a question, or the last message.

use ratatui::layout::{Position, Rect};
use ratatui::text::{Line, Span};
use ratatui::Frame;

use super::theme::Theme;
use crate::tui::app::{App, Mode, Severity};
use crate::tui::update::question_text;

/// Draws the line (and places the cursor when typing).
pub fn draw(app: &App, theme: &Theme, area: Rect, frame: &mut Frame) {
    let width = area.width as usize;
    match &app.mode {
        Mode::Input(input) => {
            let prompt = input.kind.prompt();
            let text_width = width.saturating_sub(prompt.chars().count() + 1);
            // Keep the cursor visible in long input by scrolling the text.
            let skip = input.cursor.saturating_sub(text_width);
            let shown: String = input.text.chars().skip(skip).take(text_width).collect();
            let line = Line::from(vec![
                Span::styled(prompt.clone(), theme.heading()),
                Span::raw(shown),
            ]);
            frame
                .buffer_mut()
                .set_line(area.x, area.y, &line, area.width);
            let x = area.x + (prompt.chars().count() + input.cursor - skip) as u16;
            frame.set_cursor_position(Position::new(x.min(area.right().saturating_sub(1)), area.y));
        }
        _ => {
            let Some((text, severity)) = shown_text(app) else {
                return;
            };
            let lines = super::wrap_words(&text, width);
            for (row, part) in lines.into_iter().take(area.height as usize).enumerate() {
                let line = Line::from(Span::styled(part, theme.message(severity)));
                frame
                    .buffer_mut()
                    .set_line(area.x, area.y + row as u16, &line, area.width);
            }
        }
    }
}

/// The most rows the line takes for a long message or question.
pub const MAX_ROWS: u16 = 3;

/// How many rows the line needs at `width` columns: one while typing, else enough for the
/// message or question to wrap (at most [`MAX_ROWS`]), so nothing is cut off at the edge.
pub fn rows(app: &App, width: u16) -> u16 {
    match shown_text(app) {
        Some((text, _)) if !matches!(app.mode, Mode::Input(_)) => {
            let lines = super::wrap_words(&text, width.max(1) as usize).len();
            (lines as u16).clamp(1, MAX_ROWS)
        }
        _ => 1,
    }
}

/// The question being asked, else the last message.
fn shown_text(app: &App) -> Option<(String, Severity)> {
    match &app.mode {
        Mode::Confirm(question) => Some((question_text(question), Severity::Warning)),
        _ => app
            .message
            .as_ref()
            .map(|message| (message.text.clone(), message.severity)),
    }
}
