//! From dots to terminal cells: braille, ASCII and half-block, with colours reduced to what
//! the terminal can show.

use std::fmt::Write as _;
use std::str::FromStr;

use super::canvas::{DotCanvas, Layer, Rgb};

/// How dots become characters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum CellMode {
    /// Unicode braille, 2x4 dots per cell.
    #[default]
    Braille,
    /// Plain ASCII for fonts without braille: each cell's 2x4 dot pattern becomes the
    /// character that looks most like it (`|`, `/`, `\`, `-`, `_`, `.`, ...).
    Ascii,
    /// Upper and lower half blocks with foreground and background colours, 1x2 dots per
    /// cell (for colour terminals).
    HalfBlock,
}

impl CellMode {
    /// Dots per cell, as (columns, rows).
    pub fn dots_per_cell(self) -> (usize, usize) {
        match self {
            CellMode::Braille | CellMode::Ascii => (2, 4),
            CellMode::HalfBlock => (1, 2),
        }
    }

    /// The width of one dot over its height, for terminal cells `cell_aspect` times as wide
    /// as they are tall (about 0.5 on most terminals).
    pub fn dot_aspect(self, cell_aspect: f32) -> f32 {
        let (dx, dy) = self.dots_per_cell();
        cell_aspect * dy as f32 / dx as f32
    }

    /// A canvas sized for `cols` x `rows` cells of this mode on a terminal with the usual
    /// 1:2 cells (dithering shading except in half-block mode, which shows grey levels).
    pub fn canvas(self, cols: usize, rows: usize) -> DotCanvas {
        let mut canvas = DotCanvas::new(0, 0);
        self.prepare(&mut canvas, cols, rows);
        canvas
    }

    /// Resizes `canvas` for `cols` x `rows` cells of this mode (reusing its buffers) and sets
    /// its dot aspect and dithering.
    pub fn prepare(self, canvas: &mut DotCanvas, cols: usize, rows: usize) {
        let (dx, dy) = self.dots_per_cell();
        canvas.resize(cols.saturating_mul(dx), rows.saturating_mul(dy));
        canvas.dot_aspect = self.dot_aspect(0.5);
        canvas.dither = self != CellMode::HalfBlock;
    }
}

impl FromStr for CellMode {
    type Err = String;

    fn from_str(s: &str) -> Result<CellMode, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "braille" => Ok(CellMode::Braille),
            "ascii" => Ok(CellMode::Ascii),
            "halfblock" | "half-block" | "block" => Ok(CellMode::HalfBlock),
            other => Err(format!(
                "unknown cell mode `{other}` (expected braille, ascii or half-block)"
            )),
        }
    }
}

/// How many colours the output may use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ColorMode {
    /// No colour at all (`NO_COLOR`, pipes).
    None,
    /// The 16 ANSI colours; every colour is snapped to the nearest of [`ANSI16`].
    Ansi16,
    /// The xterm 256-colour palette: greys are drawn from its 24-step grey ramp with ordered
    /// dithering between neighbouring steps, other colours snapped to its 6x6x6 cube.
    Ansi256,
    /// 24-bit colour.
    #[default]
    TrueColor,
}

impl ColorMode {
    /// What a terminal can show, as most terminal programs read it: none under `NO_COLOR` or
    /// `TERM=dumb`; 24-bit under `COLORTERM=truecolor` (or `24bit`), a `TERM` ending in
    /// `-direct`, or a terminal known to have it (kitty, WezTerm, iTerm2, Alacritty, foot,
    /// Ghostty, VS Code); 256 colours for a `TERM` naming `256color`; else 16. `COLORTERM` is
    /// often dropped over SSH, hence the other signs.
    pub fn detect(no_color: bool, term: &str, colorterm: &str, term_program: &str) -> ColorMode {
        const TRUECOLOR_TERMS: &[&str] = &["kitty", "wezterm", "alacritty", "foot", "ghostty"];
        const TRUECOLOR_PROGRAMS: &[&str] = &["iTerm.app", "WezTerm", "vscode", "ghostty"];
        if no_color || term == "dumb" {
            return ColorMode::None;
        }
        if matches!(colorterm, "truecolor" | "24bit")
            || term.ends_with("-direct")
            || TRUECOLOR_TERMS.iter().any(|t| term.contains(t))
            || TRUECOLOR_PROGRAMS.contains(&term_program)
        {
            ColorMode::TrueColor
        } else if term.contains("256color") {
            ColorMode::Ansi256
        } else {
            ColorMode::Ansi16
        }
    }

    /// The name shown on the status line and accepted by `--colors`.
    pub fn name(self) -> &'static str {
        match self {
            ColorMode::None => "none",
            ColorMode::Ansi16 => "16",
            ColorMode::Ansi256 => "256",
            ColorMode::TrueColor => "truecolor",
        }
    }
}

impl FromStr for ColorMode {
    type Err = String;

    fn from_str(s: &str) -> Result<ColorMode, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "none" | "no" | "never" => Ok(ColorMode::None),
            "16" => Ok(ColorMode::Ansi16),
            "256" => Ok(ColorMode::Ansi256),
            "truecolor" | "24bit" => Ok(ColorMode::TrueColor),
            other => Err(format!(
                "unknown colour mode `{other}` (expected truecolor, 256, 16 or none)"
            )),
        }
    }
}

/// One terminal cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Cell {
    /// The character.
    pub ch: char,
    /// Foreground colour, `None` for the terminal's default.
    pub fg: Option<Rgb>,
    /// Background colour, `None` for the terminal's default.
    pub bg: Option<Rgb>,
}

impl Cell {
    /// A blank cell in default colours.
    pub const BLANK: Cell = Cell {
        ch: ' ',
        fg: None,
        bg: None,
    };
}

impl Default for Cell {
    fn default() -> Cell {
        Cell::BLANK
    }
}

/// A reusable grid of cells, row-major.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CellGrid {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` cells, row by row.
    pub cells: Vec<Cell>,
}

impl CellGrid {
    /// A blank grid.
    pub fn new(width: usize, height: usize) -> CellGrid {
        let mut grid = CellGrid::default();
        grid.resize(width, height);
        grid
    }

    /// Resizes and blanks the grid, reusing its allocation.
    pub fn resize(&mut self, width: usize, height: usize) {
        self.width = width;
        self.height = height;
        self.cells.clear();
        self.cells.resize(width.saturating_mul(height), Cell::BLANK);
    }

    /// The cell at (col, row), if inside.
    pub fn get(&self, col: usize, row: usize) -> Option<&Cell> {
        (col < self.width && row < self.height).then(|| &self.cells[row * self.width + col])
    }

    /// One row of cells.
    pub fn row(&self, row: usize) -> &[Cell] {
        if row >= self.height {
            return &[];
        }
        &self.cells[row * self.width..(row + 1) * self.width]
    }

    /// Fills the grid from `canvas` (resizing the grid to fit it) in `mode`, with colours
    /// reduced to `colors`.
    pub fn fill(&mut self, canvas: &DotCanvas, mode: CellMode, colors: ColorMode) {
        let (dx, dy) = mode.dots_per_cell();
        let cols = canvas.width() / dx;
        let rows = canvas.height() / dy;
        if self.width != cols || self.height != rows {
            self.resize(cols, rows);
        }
        // Cells wholly outside the drawn rectangle are blank.
        let (x0, y0, x1, y1) = canvas.dirty_rect();
        let (c0, c1) = (x0 / dx, x1.div_ceil(dx).min(cols));
        let (r0, r1) = (y0 / dy, y1.div_ceil(dy).min(rows));
        self.cells.fill(Cell::BLANK);
        if mode != CellMode::HalfBlock {
            self.fill_2x4(canvas, mode, colors, (c0, c1), (r0, r1));
            return;
        }
        let (on, color, _) = canvas.buffers();
        let cw = canvas.width();
        for row in r0..r1 {
            for col in c0..c1 {
                let top = row * 2 * cw + col;
                let bottom = top + cw;
                let t = on[top].then(|| dither_256(color[top], col, row * 2, colors));
                let b = on[bottom].then(|| dither_256(color[bottom], col, row * 2 + 1, colors));
                self.cells[row * cols + col] = half_block(t, b, colors);
            }
        }
    }

    /// Fills the cells `cols` x `rows` (ranges) of an already blanked grid with braille or
    /// ASCII characters of 2x4 dots. A frame of feature lines leaves most cells dark, so
    /// four dark cells (eight dots on each of four rows) are skipped at once, and a dark
    /// cell is left blank (a pattern of no dots is a blank cell in both modes).
    fn fill_2x4(
        &mut self,
        canvas: &DotCanvas,
        mode: CellMode,
        colors: ColorMode,
        (c0, c1): (usize, usize),
        (r0, r1): (usize, usize),
    ) {
        let (on, color, layer) = canvas.buffers();
        let cw = canvas.width();
        let cols = self.width;
        // A cell has one colour, so the rest-pose ghost's own dots in a cell with live dots
        // would take the live colour and read as moved skin. They are left out of the
        // pattern and the cell gets the ghost's dim colour as its background instead: the
        // live lines stay exact, and only cells where the rest pose differs are marked.
        // None where the terminal would only show black.
        let ghost_bg = canvas
            .ghost_color()
            .and_then(|c| reduce(c.mix(Rgb(0, 0, 0), GHOST_UNDER_DIM), colors))
            .filter(|&c| c != Rgb(0, 0, 0));
        for row in r0..r1 {
            let mut col = c0;
            while col < c1 {
                if col + 4 <= c1 && dark_2x4_run(on, cw, col * 2, row * 4) {
                    col += 4;
                    continue;
                }
                let (mut bits, fg, top) = gather_2x4(on, color, layer, cw, col * 2, row * 4);
                let mut bg = None;
                if top > Layer::Ghost {
                    let ghost = ghost_2x4(on, layer, cw, col * 2, row * 4);
                    if ghost != 0 {
                        bits &= !ghost;
                        bg = ghost_bg;
                    }
                }
                if bits != 0 {
                    let ch = if mode == CellMode::Braille {
                        braille_char(bits)
                    } else {
                        ascii_char(bits)
                    };
                    self.cells[row * cols + col] = Cell {
                        ch,
                        fg: reduce(dither_256(fg, col, row, colors), colors),
                        bg,
                    };
                }
                col += 1;
            }
        }
    }
}

/// Whether the 8 x 4 dots from (x, y) (four cells of 2x4) are all dark.
#[inline]
fn dark_2x4_run(on: &[bool], width: usize, x: usize, y: usize) -> bool {
    (y..y + 4).all(|row| {
        let dots: &[bool; 8] = on[row * width + x..][..8].try_into().expect("eight dots");
        // Read as one word: a bool is one byte, 0 or 1.
        u64::from_ne_bytes(dots.map(u8::from)) == 0
    })
}

/// How much darker than the ghost's colour the background under live dots is.
pub const GHOST_UNDER_DIM: f32 = 0.35;

/// The braille bits of the 2x4 dots from (x, y) lit by the ghost alone.
#[inline]
fn ghost_2x4(on: &[bool], layer: &[Layer], width: usize, x: usize, y: usize) -> u8 {
    let mut bits = 0;
    for dy in 0..4 {
        for dx in 0..2 {
            let i = (y + dy) * width + x + dx;
            if on[i] && layer[i] == Layer::Ghost {
                bits |= braille_bit(dx, dy);
            }
        }
    }
    bits
}

/// The 2x4 dot pattern of a cell in braille bit order, and the colour and layer of its
/// highest-layer lit dot.
#[inline]
fn gather_2x4(
    on: &[bool],
    color: &[Rgb],
    layer: &[Layer],
    width: usize,
    x: usize,
    y: usize,
) -> (u8, Rgb, Layer) {
    const BITS: [[u8; 2]; 4] = [[0x01, 0x08], [0x02, 0x10], [0x04, 0x20], [0x40, 0x80]];
    let mut bits = 0u8;
    for (dy, row_bits) in BITS.iter().enumerate() {
        let row = &on[(y + dy) * width + x..][..2];
        bits |= (row[0] as u8 * row_bits[0]) | (row[1] as u8 * row_bits[1]);
    }
    if bits == 0 {
        return (0, Rgb::default(), Layer::Empty);
    }
    let mut best = (Layer::Empty, Rgb::default());
    for dy in 0..4 {
        let row = (y + dy) * width + x;
        for i in row..row + 2 {
            if on[i] && (layer[i] > best.0 || best.0 == Layer::Empty) {
                best = (layer[i], color[i]);
            }
        }
    }
    (bits, best.1, best.0)
}

/// The braille bit of the dot at column `dx` (0-1), row `dy` (0-3) of a cell (Unicode's
/// dot numbering: dots 1-3 and 7 down the left column, 4-6 and 8 down the right).
pub const fn braille_bit(dx: usize, dy: usize) -> u8 {
    match (dx, dy) {
        (0, 0) => 0x01,
        (0, 1) => 0x02,
        (0, 2) => 0x04,
        (1, 0) => 0x08,
        (1, 1) => 0x10,
        (1, 2) => 0x20,
        (0, 3) => 0x40,
        (1, 3) => 0x80,
        _ => 0,
    }
}

/// The braille character for a pattern of dot bits (`U+2800 + bits`; blank is a space so
/// text output trims cleanly).
pub fn braille_char(bits: u8) -> char {
    if bits == 0 {
        ' '
    } else {
        char::from_u32(0x2800 + bits as u32).unwrap_or(' ')
    }
}

/// Candidate ASCII characters with the 2x4 dot patterns (as rows of two dots, top first)
/// they resemble. Ties go to the earlier entry.
const ASCII_SHAPES: &[(char, [&str; 4])] = &[
    ('|', ["#.", "#.", "#.", "#."]),
    ('|', [".#", ".#", ".#", ".#"]),
    ('-', ["..", "##", "..", ".."]),
    ('-', ["..", "..", "##", ".."]),
    ('_', ["..", "..", "..", "##"]),
    ('\'', ["##", "..", "..", ".."]),
    ('/', [".#", ".#", "#.", "#."]),
    ('/', ["..", ".#", "#.", ".."]),
    ('\\', ["#.", "#.", ".#", ".#"]),
    ('\\', ["..", "#.", ".#", ".."]),
    ('.', ["..", "..", "..", "#."]),
    ('.', ["..", "..", "..", ".#"]),
    ('\'', ["#.", "..", "..", ".."]),
    ('\'', [".#", "..", "..", ".."]),
    ('-', ["..", "#.", "..", ".."]),
    ('-', ["..", ".#", "..", ".."]),
    ('-', ["..", "..", "#.", ".."]),
    ('-', ["..", "..", ".#", ".."]),
    (':', ["#.", "..", "#.", ".."]),
    (':', [".#", "..", ".#", ".."]),
    ('=', ["##", "..", "##", ".."]),
    ('=', ["..", "##", "..", "##"]),
    ('L', ["#.", "#.", "#.", "##"]),
    ('J', [".#", ".#", ".#", "##"]),
    ('7', ["##", ".#", ".#", ".#"]),
    ('r', ["##", "#.", "#.", "#."]),
    ('(', [".#", "#.", "#.", ".#"]),
    (')', ["#.", ".#", ".#", "#."]),
    ('v', ["#.", "#.", ".#", ".."]),
    ('^', [".#", "#.", "..", ".."]),
    ('+', ["#.", "##", "#.", ".."]),
    ('o', ["..", "##", "##", ".."]),
    ('#', ["##", "##", "##", "##"]),
];

const fn shape_bits(rows: [&str; 4]) -> u8 {
    let mut bits = 0u8;
    let mut dy = 0;
    while dy < 4 {
        let row = rows[dy].as_bytes();
        let mut dx = 0;
        while dx < 2 {
            if row[dx] == b'#' {
                bits |= braille_bit(dx, dy);
            }
            dx += 1;
        }
        dy += 1;
    }
    bits
}

const fn build_ascii_table() -> [u8; 256] {
    let mut table = [b' '; 256];
    let mut pattern = 1;
    while pattern < 256 {
        let mut best = b'#';
        let mut best_cost = u32::MAX;
        let mut k = 0;
        while k < ASCII_SHAPES.len() {
            let (ch, rows) = ASCII_SHAPES[k];
            let bits = shape_bits(rows);
            // Missing a dot the character has costs a little less than showing a dot that
            // is not there, so sparse patterns pick light characters.
            let extra = (bits & !(pattern as u8)).count_ones() * 2;
            let missing = ((pattern as u8) & !bits).count_ones() * 3;
            let cost = extra + missing;
            if cost < best_cost {
                best_cost = cost;
                best = ch as u8;
            }
            k += 1;
        }
        table[pattern] = best;
        pattern += 1;
    }
    table
}

static ASCII_TABLE: [u8; 256] = build_ascii_table();

/// The ASCII character that best resembles a 2x4 dot pattern given in braille bits.
pub fn ascii_char(bits: u8) -> char {
    ASCII_TABLE[bits as usize] as char
}

fn half_block(top: Option<Rgb>, bottom: Option<Rgb>, colors: ColorMode) -> Cell {
    match (top, bottom) {
        (None, None) => Cell::BLANK,
        (Some(t), None) => Cell {
            ch: '▀',
            fg: reduce(t, colors),
            bg: None,
        },
        (None, Some(b)) => Cell {
            ch: '▄',
            fg: reduce(b, colors),
            bg: None,
        },
        (Some(t), Some(b)) => {
            let (t, b) = (reduce(t, colors), reduce(b, colors));
            if t == b {
                Cell {
                    ch: '█',
                    fg: t,
                    bg: None,
                }
            } else {
                Cell {
                    ch: '▀',
                    fg: t,
                    bg: b,
                }
            }
        }
    }
}

/// The 16 ANSI colours (xterm's defaults), indexed 0-15: black, red, green, yellow, blue,
/// magenta, cyan, white, then their bright forms.
pub const ANSI16: [Rgb; 16] = [
    Rgb(0, 0, 0),
    Rgb(205, 0, 0),
    Rgb(0, 205, 0),
    Rgb(205, 205, 0),
    Rgb(0, 0, 238),
    Rgb(205, 0, 205),
    Rgb(0, 205, 205),
    Rgb(229, 229, 229),
    Rgb(127, 127, 127),
    Rgb(255, 0, 0),
    Rgb(0, 255, 0),
    Rgb(255, 255, 0),
    Rgb(92, 92, 255),
    Rgb(255, 0, 255),
    Rgb(0, 255, 255),
    Rgb(255, 255, 255),
];

/// A 4x4 ordered-dither (Bayer) matrix, thresholds 0..16.
const BAYER: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// The grey levels of the 256-colour palette, dark to light: black (16), the 24-step ramp
/// (232-255: 8, 18, ... 238) and white (231).
fn grey_levels() -> [u8; 26] {
    let mut levels = [0u8; 26];
    for (k, level) in levels.iter_mut().enumerate().skip(1).take(24) {
        *level = 8 + 10 * (k as u8 - 1);
    }
    levels[25] = 255;
    levels
}

/// In 256-colour mode, a grey at dot (x, y) as one of the two palette greys around it,
/// chosen by ordered dithering so areas average to the true level; other colours and modes
/// pass through (reduced later).
pub fn dither_256(c: Rgb, x: usize, y: usize, colors: ColorMode) -> Rgb {
    if colors != ColorMode::Ansi256 || !(c.0 == c.1 && c.1 == c.2) {
        return c;
    }
    let levels = grey_levels();
    let v = c.0;
    let i = levels.iter().rposition(|&l| l <= v).unwrap_or(0).min(24);
    let (lo, hi) = (levels[i], levels[i + 1]);
    let frac = f32::from(v - lo) / f32::from(hi - lo);
    let level = if frac * 16.0 > f32::from(BAYER[y & 3][x & 3]) + 0.5 {
        hi
    } else {
        lo
    };
    Rgb(level, level, level)
}

/// The colour of index `i` (16-255) of the xterm 256-colour palette.
pub fn ansi256_rgb(i: u8) -> Rgb {
    const STEPS: [u8; 6] = [0, 95, 135, 175, 215, 255];
    match i {
        0..=15 => ANSI16[i as usize],
        16..=231 => {
            let k = i - 16;
            Rgb(
                STEPS[(k / 36) as usize],
                STEPS[(k / 6 % 6) as usize],
                STEPS[(k % 6) as usize],
            )
        }
        _ => {
            let l = 8 + 10 * (i - 232);
            Rgb(l, l, l)
        }
    }
}

/// The index (16-255) of the 256-colour palette entry nearest to `c` (the 6x6x6 cube and the
/// grey ramp; the first 16 are left out, as terminals redefine them).
pub fn nearest_ansi256(c: Rgb) -> u8 {
    let dist = |p: Rgb| {
        let d = |a: u8, b: u8| (a as i32 - b as i32).pow(2);
        2 * d(c.0, p.0) + 4 * d(c.1, p.1) + 3 * d(c.2, p.2)
    };
    (16..=255u8)
        .min_by_key(|&i| dist(ansi256_rgb(i)))
        .unwrap_or(231)
}

/// The index (0-15) of the ANSI colour nearest to `c` (squared distance, weighted toward
/// green as the eye is).
pub fn nearest_ansi16(c: Rgb) -> u8 {
    let dist = |p: Rgb| {
        let d = |a: u8, b: u8| (a as i32 - b as i32).pow(2);
        2 * d(c.0, p.0) + 4 * d(c.1, p.1) + 3 * d(c.2, p.2)
    };
    (0..16u8)
        .min_by_key(|&i| dist(ANSI16[i as usize]))
        .unwrap_or(7)
}

/// A colour as the output may show it: unchanged, snapped to [`ANSI16`], or none.
pub fn reduce(c: Rgb, colors: ColorMode) -> Option<Rgb> {
    match colors {
        ColorMode::None => None,
        ColorMode::Ansi16 => Some(ANSI16[nearest_ansi16(c) as usize]),
        ColorMode::Ansi256 => Some(ansi256_rgb(nearest_ansi256(c))),
        ColorMode::TrueColor => Some(c),
    }
}

/// The grid's characters as text, one line per row, trailing spaces trimmed, colours
/// dropped.
pub fn to_text(grid: &CellGrid) -> String {
    let mut out = String::with_capacity(grid.cells.len() * 3 + grid.height);
    for row in 0..grid.height {
        let line: String = grid.row(row).iter().map(|c| c.ch).collect();
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

/// The grid as text with ANSI colour escapes (24-bit, or the 16-colour codes for colours
/// in [`ANSI16`]), resetting at the end of each line.
pub fn to_ansi(grid: &CellGrid, colors: ColorMode) -> String {
    if colors == ColorMode::None {
        return to_text(grid);
    }
    let mut out = String::new();
    for row in 0..grid.height {
        let cells = grid.row(row);
        let used = cells
            .iter()
            .rposition(|c| *c != Cell::BLANK)
            .map_or(0, |i| i + 1);
        let mut current: (Option<Rgb>, Option<Rgb>) = (None, None);
        for cell in &cells[..used] {
            if (cell.fg, cell.bg) != current {
                out.push_str("\x1b[0m");
                if let Some(fg) = cell.fg {
                    push_sgr(&mut out, fg, colors, false);
                }
                if let Some(bg) = cell.bg {
                    push_sgr(&mut out, bg, colors, true);
                }
                current = (cell.fg, cell.bg);
            }
            out.push(cell.ch);
        }
        if current != (None, None) {
            out.push_str("\x1b[0m");
        }
        out.push('\n');
    }
    out
}

fn push_sgr(out: &mut String, c: Rgb, colors: ColorMode, background: bool) {
    match colors {
        ColorMode::None => {}
        ColorMode::Ansi16 => {
            let i = nearest_ansi16(c);
            let base = match (background, i < 8) {
                (false, true) => 30,
                (false, false) => 90 - 8,
                (true, true) => 40,
                (true, false) => 100 - 8,
            };
            let _ = write!(out, "\x1b[{}m", base + i as u32);
        }
        ColorMode::Ansi256 => {
            let code = if background { 48 } else { 38 };
            let _ = write!(out, "\x1b[{code};5;{}m", nearest_ansi256(c));
        }
        ColorMode::TrueColor => {
            let code = if background { 48 } else { 38 };
            let _ = write!(out, "\x1b[{code};2;{};{};{}m", c.0, c.1, c.2);
        }
    }
}

#[cfg(test)]
mod color_mode_tests {
    use super::*;

    #[test]
    fn detection_reads_colorterm_direct_terms_known_terminals_and_256color() {
        let d = ColorMode::detect;
        assert_eq!(d(true, "xterm-256color", "truecolor", ""), ColorMode::None);
        assert_eq!(d(false, "dumb", "truecolor", ""), ColorMode::None);
        assert_eq!(d(false, "xterm", "truecolor", ""), ColorMode::TrueColor);
        assert_eq!(d(false, "xterm", "24bit", ""), ColorMode::TrueColor);
        assert_eq!(d(false, "xterm-direct", "", ""), ColorMode::TrueColor);
        assert_eq!(d(false, "xterm-kitty", "", ""), ColorMode::TrueColor);
        assert_eq!(d(false, "alacritty", "", ""), ColorMode::TrueColor);
        assert_eq!(
            d(false, "xterm-256color", "", "iTerm.app"),
            ColorMode::TrueColor
        );
        assert_eq!(d(false, "xterm-256color", "", ""), ColorMode::Ansi256);
        assert_eq!(d(false, "screen-256color", "", ""), ColorMode::Ansi256);
        assert_eq!(d(false, "xterm", "", ""), ColorMode::Ansi16);
        assert_eq!(d(false, "", "", ""), ColorMode::Ansi16);
    }

    #[test]
    fn names_parse_back() {
        for mode in [
            ColorMode::None,
            ColorMode::Ansi16,
            ColorMode::Ansi256,
            ColorMode::TrueColor,
        ] {
            assert_eq!(mode.name().parse::<ColorMode>(), Ok(mode));
        }
        assert!("257".parse::<ColorMode>().unwrap_err().contains("`257`"));
    }

    #[test]
    fn the_palette_round_trips_and_greys_land_on_the_ramp() {
        for i in 16..=255u8 {
            assert_eq!(nearest_ansi256(ansi256_rgb(i)), i, "index {i}");
        }
        assert_eq!(nearest_ansi256(Rgb(128, 128, 128)), 244);
        assert_eq!(ansi256_rgb(244), Rgb(128, 128, 128));
        assert_eq!(ansi256_rgb(196), Rgb(255, 0, 0));
    }

    #[test]
    fn dithered_greys_average_to_the_true_level_on_every_4x4_tile() {
        for v in 0..=255u8 {
            let grey = Rgb(v, v, v);
            let mut sum = 0.0;
            let mut levels = std::collections::BTreeSet::new();
            for y in 0..4 {
                for x in 0..4 {
                    let d = dither_256(grey, x, y, ColorMode::Ansi256);
                    assert_eq!(
                        reduce(d, ColorMode::Ansi256),
                        Some(d),
                        "{d:?} is a palette grey"
                    );
                    sum += f32::from(d.0);
                    levels.insert(d.0);
                }
            }
            assert!(levels.len() <= 2, "{v}: {levels:?}");
            // Steps are at most 17 apart; sixteen thresholds leave at most a sixteenth off.
            assert!(
                (sum / 16.0 - f32::from(v)).abs() <= 17.0 / 16.0 + 0.5,
                "{v}: {}",
                sum / 16.0
            );
        }
        // Colours and other modes pass through.
        assert_eq!(
            dither_256(Rgb(200, 40, 40), 1, 1, ColorMode::Ansi256),
            Rgb(200, 40, 40)
        );
        assert_eq!(
            dither_256(Rgb(77, 77, 77), 1, 1, ColorMode::TrueColor),
            Rgb(77, 77, 77)
        );
    }

    #[test]
    fn sgr_codes_in_256_colours() {
        let mut out = String::new();
        push_sgr(&mut out, Rgb(128, 128, 128), ColorMode::Ansi256, false);
        push_sgr(&mut out, Rgb(255, 0, 0), ColorMode::Ansi256, true);
        assert_eq!(out, "\x1b[38;5;244m\x1b[48;5;196m");
    }
}
