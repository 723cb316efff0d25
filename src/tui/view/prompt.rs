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
        Mode::Confirm(question) => {
            let line = Line::from(Span::styled(
                question_text(question),
                theme.message(Severity::Warning),
            ));
            frame
                .buffer_mut()
                .set_line(area.x, area.y, &line, area.width);
        }
        _ => {
            if let Some(message) = &app.message {
                let line = Line::from(Span::styled(
                    message.text.clone(),
                    theme.message(message.severity),
                ));
                frame
                    .buffer_mut()
                    .set_line(area.x, area.y, &line, area.width);
            }
        }
    }
}
