//! The `?` overlay: every binding (from the keymap) and every `:` command.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Widget};

use super::theme::Theme;
use crate::tui::keymap;
use crate::tui::update::command;

/// The width of the key column, in characters.
const KEY_COLUMN: usize = 18;

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
    out.push(("mouse".into(), String::new(), true));
    for (what, description) in keymap::MOUSE {
        out.push((what.to_string(), description.to_string(), false));
    }
    out.push(("commands (type : first)".into(), String::new(), true));
    for (command, description) in command::help_lines() {
        out.push((command, description, false));
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
    // Wide enough for nearly every key; the few longer ones get a line of their own.
    let key_width = KEY_COLUMN.min(inner.width as usize / 2);
    let text_width = (inner.width as usize).saturating_sub(key_width + 4).max(1);
    let all = wrapped(theme, key_width, text_width);
    let max_scroll = all.len().saturating_sub(inner.height as usize);
    let skip = (scroll as usize).min(max_scroll);
    for (k, line) in all
        .iter()
        .skip(skip)
        .take(inner.height as usize)
        .enumerate()
    {
        buf.set_line(inner.x, inner.y + k as u16, line, inner.width);
    }
}

/// The overlay's lines laid out: keys in a column `key_width` wide, descriptions wrapped at
/// word boundaries to `text_width` so nothing is cut off in a narrow terminal.
fn wrapped(theme: &Theme, key_width: usize, text_width: usize) -> Vec<Line<'static>> {
    let mut out = Vec::new();
    for (keys, description, heading) in lines() {
        if heading {
            out.push(Line::from(Span::styled(keys, theme.heading())));
            continue;
        }
        let mut keys = if keys.chars().count() > key_width {
            out.push(Line::from(Span::styled(
                format!("  {keys}"),
                theme.partner(),
            )));
            " ".repeat(key_width + 4)
        } else {
            format!("  {keys:<key_width$}  ")
        };
        for part in super::wrap_words(&description, text_width) {
            out.push(Line::from(vec![
                Span::styled(std::mem::take(&mut keys), theme.partner()),
                Span::raw(part),
            ]));
            keys = " ".repeat(key_width + 4);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::wrap_words;

    #[test]
    fn words_wrap_within_the_width_and_keep_every_character() {
        let text = "load the selected AU or expression (muscles: type a value)";
        for width in [1, 5, 12, 20, 80] {
            let lines = wrap_words(text, width);
            assert!(
                lines.iter().all(|l| l.chars().count() <= width),
                "{width}: {lines:?}"
            );
            let joined: String = lines.concat().split_whitespace().collect();
            let expected: String = text.split_whitespace().collect();
            assert_eq!(joined, expected, "width {width}");
        }
        assert_eq!(wrap_words("a bc de", 4), ["a bc", "de"]);
        assert_eq!(wrap_words("", 10), [""]);
    }
}
