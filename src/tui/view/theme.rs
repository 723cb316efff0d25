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
        match self.colors {
            ColorMode::None => None,
            ColorMode::TrueColor => Some(Color::Rgb(r, g, b)),
            ColorMode::Ansi16 => Some(nearest_ansi(r, g, b)),
        }
    }
}

/// The nearest of the 16 ANSI colours (by the usual xterm palette).
pub fn nearest_ansi(r: u8, g: u8, b: u8) -> Color {
    const PALETTE: [(Color, [i32; 3]); 16] = [
        (Color::Black, [0, 0, 0]),
        (Color::Red, [205, 0, 0]),
        (Color::Green, [0, 205, 0]),
        (Color::Yellow, [205, 205, 0]),
        (Color::Blue, [0, 0, 238]),
        (Color::Magenta, [205, 0, 205]),
        (Color::Cyan, [0, 205, 205]),
        (Color::Gray, [229, 229, 229]),
        (Color::DarkGray, [127, 127, 127]),
        (Color::LightRed, [255, 0, 0]),
        (Color::LightGreen, [0, 255, 0]),
        (Color::LightYellow, [255, 255, 0]),
        (Color::LightBlue, [92, 92, 255]),
        (Color::LightMagenta, [255, 0, 255]),
        (Color::LightCyan, [0, 255, 255]),
        (Color::White, [255, 255, 255]),
    ];
    let (r, g, b) = (i32::from(r), i32::from(g), i32::from(b));
    PALETTE
        .iter()
        .min_by_key(|(_, [pr, pg, pb])| (r - pr).pow(2) + (g - pg).pow(2) + (b - pb).pow(2))
        .map_or(Color::White, |(c, _)| *c)
}
