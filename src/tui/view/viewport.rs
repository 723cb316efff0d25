//! The viewport: the deformed face, drawn by the core renderer into the ratatui buffer.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Block, Borders, Widget};

use super::theme::Theme;
use crate::tui::app::App;

/// Draws the viewport panel.
pub fn draw(app: &App, theme: &Theme, area: Rect, buf: &mut Buffer) {
    let title = format!(
        " Face  yaw {:.0} pitch {:.0} zoom {:.2} ",
        app.view.yaw, app.view.pitch, app.view.zoom
    );
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border(false))
        .title(title);
    let inner = block.inner(area);
    block.render(area, buf);
    let text = Line::from("(the face is drawn here once the renderer is built in)");
    buf.set_line(
        inner.x + 1,
        inner.y + inner.height / 2,
        &text,
        inner.width.saturating_sub(2),
    );
}
