//! The `?` overlay: every binding (from the keymap) and every `:` command.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Widget};

use super::theme::Theme;
use crate::tui::keymap;

/// The overlay's lines.
pub fn lines() -> Vec<(String, String, bool)> {
    let mut out = Vec::new();
    let mut section = "";
    for (keys, description, sec) in keymap::help_lines() {
        if sec != section {
            out.push((sec.to_string(), String::new(), true));
            section = sec;
        }
        out.push((keys, description, false));
    }
    out.push(("other keys".into(), String::new(), true));
    for (keys, description) in keymap::OTHER_KEYS {
        out.push((keys.to_string(), description.to_string(), false));
    }
    out.push(("commands (type : first)".into(), String::new(), true));
    for (command, description) in keymap::COMMANDS {
        out.push((format!(":{command}"), description.to_string(), false));
    }
    out
}

/// Draws the overlay over the middle of the screen.
pub fn draw(theme: &Theme, scroll: u16, area: Rect, buf: &mut Buffer) {
    let width = area.width.saturating_sub(4).min(90);
    let height = area.height.saturating_sub(2);
    let popup = Rect {
        x: area.x + (area.width - width) / 2,
        y: area.y + 1,
        width,
        height,
    };
    Clear.render(popup, buf);
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border(true))
        .title(" Help: j/k scroll, any other key closes ");
    let inner = block.inner(popup);
    block.render(popup, buf);
    let all = lines();
    let max_scroll = all.len().saturating_sub(inner.height as usize);
    let skip = (scroll as usize).min(max_scroll);
    let key_width = 30.min(inner.width as usize / 2);
    for (k, (keys, description, heading)) in all
        .iter()
        .skip(skip)
        .take(inner.height as usize)
        .enumerate()
    {
        let line = if *heading {
            Line::from(Span::styled(keys.clone(), theme.heading()))
        } else {
            Line::from(vec![
                Span::styled(format!("  {keys:<key_width$}"), theme.partner()),
                Span::raw(description.clone()),
            ])
        };
        buf.set_line(inner.x, inner.y + k as u16, &line, inner.width);
    }
}
