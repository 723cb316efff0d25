//! The status line: file, unsaved mark, mode, view settings and the most useful keys.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};

use super::theme::Theme;
use crate::tui::app::{App, Mode};
use crate::tui::keymap;

/// Draws the status line.
pub fn draw(app: &App, theme: &Theme, area: Rect, buf: &mut Buffer) {
    buf.set_style(area, theme.status());
    let dirty = match (app.dirty(), app.new_file()) {
        (true, _) => " [+]",
        (false, true) => " [new]",
        (false, false) => "",
    };
    let left = match app.mode {
        Mode::Normal if app.rig_edit.on => " RIG ".to_string(),
        _ => format!(" {} ", app.mode.name()),
    };
    // A big head's rig is bound on a thread: the rest pose is shown until it lands.
    let binding = if app.doc.face.is_binding() {
        "| binding... "
    } else {
        ""
    };
    let file = format!(" {}{dirty} {binding}", app.file_label());
    let view = format!(
        "| {} {} {} ",
        app.view.style.name(),
        crate::tui::app::cells_name(app.view.drawn_cells()),
        colors_label(app.view.colors)
    );
    let used = left.chars().count() + file.chars().count() + view.chars().count();
    let room = (area.width as usize).saturating_sub(used);
    let mut hints = String::new();
    let typing = matches!(app.mode, Mode::Input(_));
    if let (true, Some(message)) = (typing, &app.message) {
        // While typing, the bottom line holds the input: messages (completions) go here.
        hints = message.text.chars().take(room.saturating_sub(1)).collect();
        hints.push(' ');
    }
    for (key, hint) in keymap::hints_for(app)
        .into_iter()
        .filter(|_| !typing || app.message.is_none())
    {
        let piece = format!("{key} {hint}  ");
        if hints.chars().count() + piece.chars().count() > room {
            break;
        }
        hints.push_str(&piece);
    }
    let hints = format!("{hints:>room$}");
    let line = Line::from(vec![
        Span::styled(left, theme.mode()),
        Span::styled(file, theme.status()),
        Span::styled(view, theme.status()),
        Span::styled(hints, theme.status()),
    ]);
    buf.set_line(area.x, area.y, &line, area.width);
}

/// The colour mode as the status line shows it.
fn colors_label(colors: crate::render::ColorMode) -> String {
    match colors {
        crate::render::ColorMode::None => "no colour".into(),
        crate::render::ColorMode::TrueColor => "truecolor".into(),
        other => format!("{} colours", other.name()),
    }
}

#[cfg(test)]
mod tests {
    use ratatui::buffer::Buffer;
    use ratatui::layout::Rect;

    use super::*;
    use crate::io::builtin;

    fn status_text(app: &App) -> String {
        let area = Rect::new(0, 0, 160, 1);
        let mut buf = Buffer::empty(area);
        draw(app, &Theme::new(app.view.colors), area, &mut buf);
        buf.content().iter().map(|cell| cell.symbol()).collect()
    }

    #[test]
    fn the_status_line_says_binding_until_the_bound_rig_is_taken() {
        let face =
            crate::tui::fixture::started(builtin::default_rig(), crate::tui::fixture::big_face())
                .unwrap();
        let mut app = App::new(face, builtin::default_table(), None);
        assert!(
            status_text(&app).contains("| binding... "),
            "{}",
            status_text(&app)
        );
        app.doc.face.wait_for_bind().unwrap();
        assert!(
            !status_text(&app).contains("binding"),
            "{}",
            status_text(&app)
        );
    }
}
