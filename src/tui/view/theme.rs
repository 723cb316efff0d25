//! Colours and emphasis, degraded to 16 colours or none (NO_COLOR).

use ratatui::style::{Color, Modifier, Style};

use crate::tui::app::{ColorMode, Severity};

/// The styles of the screen for one colour capability.
#[derive(Debug, Clone, Copy)]
pub struct Theme {
    /// What the terminal can show.
    pub colors: ColorMode,
}

impl Theme {
    /// The theme for a colour capability.
    pub fn new(colors: ColorMode) -> Theme {
        Theme { colors }
    }

    fn fg(&self, color: Color) -> Style {
        match self.colors {
            ColorMode::None => Style::default(),
            _ => Style::default().fg(color),
        }
    }

    /// Plain text.
    pub fn text(&self) -> Style {
        Style::default()
    }

    /// Less important text.
    pub fn dim(&self) -> Style {
        match self.colors {
            ColorMode::None => Style::default(),
            _ => Style::default().fg(Color::DarkGray),
        }
    }

    /// Group headings.
    pub fn heading(&self) -> Style {
        self.fg(Color::Yellow).add_modifier(Modifier::BOLD)
    }

    /// The selected row.
    pub fn selected(&self, focused: bool) -> Style {
        match (self.colors, focused) {
            (ColorMode::None, true) => Style::default().add_modifier(Modifier::REVERSED),
            (ColorMode::None, false) => Style::default().add_modifier(Modifier::UNDERLINED),
            (_, true) => Style::default().fg(Color::Black).bg(Color::Cyan),
            (_, false) => Style::default().fg(Color::Black).bg(Color::Gray),
        }
    }

    /// The filled part of a gauge.
    pub fn gauge(&self) -> Style {
        self.fg(Color::Green)
    }

    /// The mirror-partner mark.
    pub fn partner(&self) -> Style {
        self.fg(Color::Magenta).add_modifier(Modifier::BOLD)
    }

    /// Panel borders; the focused panel's stands out.
    pub fn border(&self, focused: bool) -> Style {
        if focused {
            self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
        } else {
            self.dim()
        }
    }

    /// The face.
    pub fn face(&self) -> Style {
        self.fg(Color::White)
    }

    /// A status message.
    pub fn message(&self, severity: Severity) -> Style {
        match severity {
            Severity::Info => self.text(),
            Severity::Warning => self.fg(Color::Yellow).add_modifier(Modifier::BOLD),
            Severity::Error => self.fg(Color::Red).add_modifier(Modifier::BOLD),
        }
    }

    /// The status line background.
    pub fn status(&self) -> Style {
        match self.colors {
            ColorMode::None => Style::default().add_modifier(Modifier::REVERSED),
            _ => Style::default().fg(Color::Black).bg(Color::Gray),
        }
    }

    /// The unsaved mark and mode name.
    pub fn mode(&self) -> Style {
        match self.colors {
            ColorMode::None => Style::default().add_modifier(Modifier::BOLD | Modifier::REVERSED),
            _ => Style::default()
                .fg(Color::Black)
                .bg(Color::Cyan)
                .add_modifier(Modifier::BOLD),
        }
    }

    /// A colour for the viewport, degraded to what the terminal shows.
    pub fn rgb(&self, r: u8, g: u8, b: u8) -> Option<Color> {
        super::cells::to_color(crate::render::Rgb(r, g, b), self.colors)
    }
}
