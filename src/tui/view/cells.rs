//! The face as the renderer drew it: a [`CellGrid`] copied into the ratatui buffer. The
//! editor's viewport and the player draw the face through this one widget.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::widgets::Widget;

use crate::render::{nearest_ansi16, nearest_ansi256, CellGrid, ColorMode, Rgb};

/// Draws a cell grid from the top left of its area (what does not fit is cut off).
#[derive(Debug, Clone, Copy)]
pub struct CellGridView<'a> {
    /// The cells.
    pub grid: &'a CellGrid,
    /// What the terminal can show.
    pub colors: ColorMode,
    /// The style of cells without a colour of their own.
    pub plain: Style,
}

/// A renderer colour as a terminal colour: named ANSI colours on 16-colour terminals (so the
/// terminal's own palette applies), none without colour.
pub fn to_color(rgb: Rgb, colors: ColorMode) -> Option<Color> {
    const NAMED: [Color; 16] = [
        Color::Black,
        Color::Red,
        Color::Green,
        Color::Yellow,
        Color::Blue,
        Color::Magenta,
        Color::Cyan,
        Color::Gray,
        Color::DarkGray,
        Color::LightRed,
        Color::LightGreen,
        Color::LightYellow,
        Color::LightBlue,
        Color::LightMagenta,
        Color::LightCyan,
        Color::White,
    ];
    match colors {
        ColorMode::None => None,
        ColorMode::Ansi16 => Some(NAMED[usize::from(nearest_ansi16(rgb)) & 15]),
        ColorMode::Ansi256 => Some(Color::Indexed(nearest_ansi256(rgb))),
        ColorMode::TrueColor => Some(Color::Rgb(rgb.0, rgb.1, rgb.2)),
    }
}

impl Widget for CellGridView<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let grid = self.grid;
        for row in 0..grid.height.min(usize::from(area.height)) {
            for (col, cell) in grid
                .row(row)
                .iter()
                .enumerate()
                .take(usize::from(area.width))
            {
                // Blank cells are left as they are: an idle frame sends nothing for them.
                if cell.ch == ' ' && cell.bg.is_none() {
                    continue;
                }
                let Some(target) = buf.cell_mut((area.x + col as u16, area.y + row as u16)) else {
                    continue;
                };
                target.set_char(cell.ch);
                match cell.fg.and_then(|c| to_color(c, self.colors)) {
                    Some(fg) => {
                        target.set_fg(fg);
                    }
                    None => {
                        target.set_style(self.plain);
                    }
                }
                if let Some(bg) = cell.bg.and_then(|c| to_color(c, self.colors)) {
                    target.set_bg(bg);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Cell;

    #[test]
    fn cells_are_copied_with_colours_the_terminal_can_show() {
        let grid = CellGrid {
            width: 3,
            height: 1,
            cells: vec![
                Cell {
                    ch: 'a',
                    fg: Some(Rgb(250, 10, 10)),
                    bg: None,
                },
                Cell::BLANK,
                Cell {
                    ch: 'c',
                    fg: None,
                    bg: None,
                },
            ],
        };
        let area = Rect::new(1, 1, 2, 1);
        let draw = |colors| {
            let mut buf = Buffer::empty(Rect::new(0, 0, 4, 3));
            CellGridView {
                grid: &grid,
                colors,
                plain: Style::default().fg(Color::White),
            }
            .render(area, &mut buf);
            buf
        };
        let buf = draw(ColorMode::Ansi16);
        assert_eq!(buf[(1, 1)].symbol(), "a");
        assert_eq!(buf[(1, 1)].fg, Color::LightRed);
        assert_eq!(buf[(2, 1)].symbol(), " ", "blank cells stay blank");
        assert_eq!(
            buf[(3, 1)].symbol(),
            " ",
            "the third column is outside the area"
        );
        assert_eq!(
            draw(ColorMode::TrueColor)[(1, 1)].fg,
            Color::Rgb(250, 10, 10)
        );
        assert_eq!(draw(ColorMode::None)[(1, 1)].fg, Color::White);
    }
}
