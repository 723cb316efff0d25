//! The dot canvas: on/off dots with a colour, a drawing layer and a depth buffer.

/// A 24-bit colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// A grey of the given level (0.0 black to 1.0 white, clamped).
    pub fn grey(level: f32) -> Rgb {
        let v = (level.clamp(0.0, 1.0) * 255.0).round() as u8;
        Rgb(v, v, v)
    }

    /// Linear blend toward `other` by `t` (0.0 gives `self`, 1.0 gives `other`).
    pub fn mix(self, other: Rgb, t: f32) -> Rgb {
        let t = if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let f = |a: u8, b: u8| (a as f32 + (b as f32 - a as f32) * t).round() as u8;
        Rgb(f(self.0, other.0), f(self.1, other.1), f(self.2, other.2))
    }

    /// Relative brightness, 0.0 to 1.0 (Rec. 601 weights).
    pub fn luma(self) -> f32 {
        (0.299 * self.0 as f32 + 0.587 * self.1 as f32 + 0.114 * self.2 as f32) / 255.0
    }
}

/// What a dot belongs to; when several dots share a terminal cell, the cell takes the
/// colour of the highest layer among its lit dots.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub enum Layer {
    /// Nothing drawn.
    #[default]
    Empty,
    /// The rest pose drawn faintly behind the mesh.
    Ghost,
    /// The mesh surface or its lines.
    Mesh,
    /// An overlay (muscles, pivot).
    Overlay,
    /// The selected overlay.
    Selected,
}

/// How the renderer draws the dots of a line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pen {
    /// The dots' colour.
    pub color: Rgb,
    /// What the line belongs to.
    pub layer: Layer,
    /// With a bias, each dot is depth-tested: drawn only where no surface in the depth
    /// buffer is more than `bias` nearer. Without, every dot is drawn.
    pub bias: Option<f32>,
    /// Whether the line recolours lit dots of its own or a lower layer; without, it only
    /// lights dots that are still dark (the faint rest-pose ghost).
    pub overwrite: bool,
}

impl Pen {
    /// A mesh line, depth-tested with `bias`.
    pub fn mesh(color: Rgb, bias: f32) -> Pen {
        Pen {
            color,
            layer: Layer::Mesh,
            bias: Some(bias),
            overwrite: true,
        }
    }

    /// A line drawn over everything on `layer` (overlays), not depth-tested.
    pub fn on_top(color: Rgb, layer: Layer) -> Pen {
        Pen {
            color,
            layer,
            bias: None,
            overwrite: true,
        }
    }

    /// A faint line on `layer` (the ghost) that only lights dark dots, not depth-tested.
    pub fn faint(color: Rgb, layer: Layer) -> Pen {
        Pen {
            color,
            layer,
            bias: None,
            overwrite: false,
        }
    }
}

/// A grid of dots, each on or off with a colour and a layer, plus a depth buffer at dot
/// resolution (larger depth is nearer the viewer).
///
/// [`DotCanvas::clear`] and [`DotCanvas::resize`] reuse the buffers, so an editor can redraw
/// every frame without allocating.
#[derive(Debug, Clone, Default)]
pub struct DotCanvas {
    width: usize,
    height: usize,
    /// Width of one dot over its height: 1.0 for braille and half-block cells on a terminal
    /// whose cells are twice as tall as wide.
    pub dot_aspect: f32,
    /// Whether shaded surfaces are dithered into on/off dots (braille, ASCII) or every
    /// surface dot is lit with its grey level (half-block colour, PNG).
    pub dither: bool,
    on: Vec<bool>,
    color: Vec<Rgb>,
    layer: Vec<Layer>,
    depth: Vec<f32>,
    /// The faint line's colour, once one was drawn since the last clear.
    ghost_color: Option<Rgb>,
    /// The rectangle (x0, y0, x1, y1), exclusive ends, outside which nothing has been drawn
    /// since the last clear; clearing only touches it.
    dirty: (usize, usize, usize, usize),
}

const CLEAN: (usize, usize, usize, usize) = (usize::MAX, usize::MAX, 0, 0);

impl DotCanvas {
    /// A blank canvas of `width` x `height` square dots that dithers shading.
    pub fn new(width: usize, height: usize) -> DotCanvas {
        let mut canvas = DotCanvas {
            dot_aspect: 1.0,
            dither: true,
            ..DotCanvas::default()
        };
        canvas.resize(width, height);
        canvas
    }

    /// Width in dots.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in dots.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Changes the size and clears, reusing the allocation when it is large enough.
    pub fn resize(&mut self, width: usize, height: usize) {
        self.width = width;
        self.height = height;
        let n = width.saturating_mul(height);
        self.on.resize(n, false);
        self.color.resize(n, Rgb::default());
        self.layer.resize(n, Layer::Empty);
        self.depth.resize(n, f32::NEG_INFINITY);
        self.on.fill(false);
        self.ghost_color = None;
        self.depth.fill(f32::NEG_INFINITY);
        self.dirty = CLEAN;
    }

    /// Turns every dot off and resets the depth buffer to "infinitely far".
    pub fn clear(&mut self) {
        // Colour and layer are only read where a dot is on, so they need no reset; and only
        // the rectangle drawn into since the last clear needs clearing.
        let (x0, y0, x1, y1) = self.dirty;
        if x0 < x1 && y0 < y1 {
            for y in y0..y1 {
                let row = y * self.width;
                self.on[row + x0..row + x1].fill(false);
                self.depth[row + x0..row + x1].fill(f32::NEG_INFINITY);
            }
        }
        self.ghost_color = None;
        self.dirty = CLEAN;
    }

    /// The rectangle `(x0, y0, x1, y1)` (exclusive ends) that holds everything drawn since
    /// the last clear; every dot outside it is off. Empty (x0 >= x1) when nothing was drawn.
    pub fn dirty_rect(&self) -> (usize, usize, usize, usize) {
        self.dirty
    }

    /// Widens the dirty rectangle to include the dots [x0, x1) x [y0, y1) (clamped to the
    /// canvas).
    #[inline]
    pub(crate) fn mark_dirty(&mut self, x0: usize, y0: usize, x1: usize, y1: usize) {
        let (x1, y1) = (x1.min(self.width), y1.min(self.height));
        if x0 >= x1 || y0 >= y1 {
            return;
        }
        let d = &mut self.dirty;
        *d = (d.0.min(x0), d.1.min(y0), d.2.max(x1), d.3.max(y1));
    }

    /// One dot of a line at depth `z`, drawn with `pen`. Returns whether the line is visible
    /// there. The caller keeps (x, y) inside the canvas.
    #[inline(always)]
    pub(crate) fn line_dot(&mut self, x: usize, y: usize, z: f32, pen: Pen) -> bool {
        let i = y * self.width + x;
        if let Some(bias) = pen.bias {
            if z + bias < self.depth[i] {
                return false;
            }
        }
        let on = self.on[i];
        let d = &mut self.dirty;
        *d = (d.0.min(x), d.1.min(y), d.2.max(x + 1), d.3.max(y + 1));
        if !pen.overwrite && self.depth[i] != f32::NEG_INFINITY {
            // A faint line (the ghost) stays behind any surface drawn: it shows where the
            // face was, not through the face that is.
            return false;
        }
        if !pen.overwrite {
            // The cells give the faint line's colour to the background of cells it shares
            // with live dots.
            self.ghost_color = Some(pen.color);
        }
        if !on || (pen.overwrite && self.layer[i] <= pen.layer) {
            self.color[i] = pen.color;
            self.layer[i] = pen.layer;
        }
        self.on[i] = true;
        true
    }

    #[inline]
    fn index(&self, x: usize, y: usize) -> Option<usize> {
        (x < self.width && y < self.height).then(|| y * self.width + x)
    }

    /// Whether the dot at (x, y) is lit (false outside the canvas).
    pub fn is_on(&self, x: usize, y: usize) -> bool {
        self.index(x, y).is_some_and(|i| self.on[i])
    }

    /// The colour of the dot at (x, y), if it is lit.
    pub fn color(&self, x: usize, y: usize) -> Option<Rgb> {
        self.index(x, y)
            .filter(|&i| self.on[i])
            .map(|i| self.color[i])
    }

    /// The layer of the dot at (x, y) (`Empty` when off or outside).
    pub fn layer(&self, x: usize, y: usize) -> Layer {
        self.index(x, y)
            .filter(|&i| self.on[i])
            .map_or(Layer::Empty, |i| self.layer[i])
    }

    /// The depth buffer at (x, y): the nearest surface drawn there, or negative infinity.
    ///
    /// With the line styles the renderer may rasterize the surface only where it can hide
    /// a line (the dots some depth-tested line visits, and some around them), so away from
    /// the lines the buffer may stay at negative infinity; the shaded style fills it
    /// everywhere.
    pub fn depth(&self, x: usize, y: usize) -> f32 {
        self.index(x, y)
            .map_or(f32::NEG_INFINITY, |i| self.depth[i])
    }

    /// The colour of the faint lines drawn since the last clear, if any.
    pub fn ghost_color(&self) -> Option<Rgb> {
        self.ghost_color
    }

    /// Number of lit dots.
    pub fn count_on(&self) -> usize {
        self.on.iter().filter(|&&b| b).count()
    }

    /// Lights the dot at (x, y) with `color` on `layer`. A dot already lit on a higher layer
    /// keeps its colour. Out-of-range coordinates are ignored.
    #[inline]
    pub fn plot(&mut self, x: i32, y: i32, color: Rgb, layer: Layer) {
        if x < 0 || y < 0 {
            return;
        }
        if let Some(i) = self.index(x as usize, y as usize) {
            self.mark_dirty(x as usize, y as usize, x as usize + 1, y as usize + 1);
            if !self.on[i] || self.layer[i] <= layer {
                self.color[i] = color;
                self.layer[i] = layer;
            }
            self.on[i] = true;
        }
    }

    /// Lights the dot only if it is still dark (used for faint layers drawn last).
    #[inline]
    pub fn plot_if_dark(&mut self, x: i32, y: i32, color: Rgb, layer: Layer) {
        if x < 0 || y < 0 {
            return;
        }
        if let Some(i) = self.index(x as usize, y as usize) {
            self.mark_dirty(x as usize, y as usize, x as usize + 1, y as usize + 1);
            if !self.on[i] {
                self.on[i] = true;
                self.color[i] = color;
                self.layer[i] = layer;
            }
        }
    }

    /// Turns the dot at (x, y) off.
    pub fn unplot(&mut self, x: usize, y: usize) {
        if let Some(i) = self.index(x, y) {
            self.on[i] = false;
            self.layer[i] = Layer::Empty;
        }
    }

    /// Raw access for the rasterizer: depth, on, colour and layer slices, row-major.
    pub(crate) fn buffers_mut(&mut self) -> (&mut [f32], &mut [bool], &mut [Rgb], &mut [Layer]) {
        (
            &mut self.depth,
            &mut self.on,
            &mut self.color,
            &mut self.layer,
        )
    }

    /// Raw read access: on, colour and layer slices, row-major.
    pub(crate) fn buffers(&self) -> (&[bool], &[Rgb], &[Layer]) {
        (&self.on, &self.color, &self.layer)
    }
}
