//! The depth pass: the depth buffer at dot resolution, filled only under the gathered lines.

use glam::{Vec2, Vec3};

use super::grid::{ceil_nonneg, floor_end};
use super::lines::{walk_line, LineDot};
use super::Renderer;
use crate::render::canvas::DotCanvas;

impl Renderer {
    /// Marks the screen rectangle of the front-facing triangles dirty (the rasterizer
    /// writes the buffers directly).
    #[inline(never)]
    pub(super) fn mark_faces_dirty(&self, canvas: &mut DotCanvas) {
        // Every projected vertex, not only those of front faces: a cheap superset.
        let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
        for p in &self.projected {
            let p = p.truncate();
            if p.is_finite() {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        if lo.x <= hi.x && lo.y <= hi.y {
            let lo = lo.max(Vec2::ZERO);
            canvas.mark_dirty(
                lo.x as usize,
                lo.y as usize,
                hi.x.max(0.0) as usize + 1,
                hi.y.max(0.0) as usize + 1,
            );
        }
    }

    /// Rasterizes into the depth buffer the front-facing triangles that lie under some
    /// gathered line: the depth buffer is only read where a line is drawn, and a triangle
    /// whose dots no line visits cannot hide any line.
    #[inline(never)]
    pub(super) fn fill_depth(&mut self, canvas: &mut DotCanvas) {
        self.mark_faces_dirty(canvas);
        let (w, h) = (canvas.width(), canvas.height());
        self.line_dots.reset(w, h);
        let (depth, _, _, _) = canvas.buffers_mut();
        if w.max(h) >= 1 << 24 {
            // Beyond what the integer boxes below handle: every front face, everywhere.
            for (t, tri) in self.triangles.iter().enumerate() {
                if self.facing[t] {
                    depth_triangle(tri.map(|i| self.projected[i as usize]), w, h, depth);
                }
            }
            return;
        }
        // The steps are kept, so drawing does not walk the lines again.
        for s in &self.segments {
            walk_line(s.a, s.b, w, h, |x, y, p| {
                self.line_dots.set(x, y);
                // A canvas side fits in u32 here (checked above).
                let (x, y) = (x as u32, y as u32);
                self.walked.push(LineDot { x, y, p });
            });
            self.walk_ends.push(self.walked.len() as u32);
        }
        // With feature lines most triangles are rejected, so the test must be cheaper than
        // the float box: each vertex's part of the box once, then integer min/max per
        // triangle.
        self.dot_spans.clear();
        self.dot_spans
            .extend(self.projected.iter().map(move |&p| dot_span(p, w, h)));
        for (t, tri) in self.triangles.iter().enumerate() {
            if !self.facing[t] {
                continue;
            }
            let [x0, x1, y0, y1] = triangle_box(tri.map(|i| self.dot_spans[i as usize]));
            if x0 < x1 && y0 < y1 && self.line_dots.any(x0, x1, y0, y1) {
                let p = tri.map(|i| self.projected[i as usize]);
                depth_triangle_in(p, [x0, x1, y0, y1], w, Some(&self.line_dots), depth);
            }
        }
    }
}

/// The depth slope of a projected triangle: dots of depth per dot across the screen.
#[inline(always)]
pub(super) fn depth_slope([a, b, c]: [Vec3; 3]) -> f32 {
    let (ab, ac) = (b - a, c - a);
    let area = ab.x * ac.y - ab.y * ac.x;
    let gx = (ab.z * ac.y - ac.z * ab.y) / area;
    let gy = (ab.x * ac.z - ac.x * ab.z) / area;
    let g = (gx * gx + gy * gy).sqrt();
    if g.is_finite() {
        g
    } else {
        f32::MAX
    }
}

/// The barycentric weights of corners a and b of `[a, b, c]` (signed doubled area `area`)
/// as linear functions of the dot position, `l = kx * x + ky * y + k0`, as `(kx, ky, k0)`;
/// the weight of c is `1 - la - lb`.
#[inline(always)]
pub(super) fn corner_weights([a, b, c]: [Vec3; 3], area: f32) -> [(f32, f32, f32); 2] {
    let inv = 1.0 / area;
    let weight = |p: Vec3, q: Vec3| {
        let kx = -(q.y - p.y) * inv;
        let ky = (q.x - p.x) * inv;
        (kx, ky, -(kx * p.x + ky * p.y))
    };
    [weight(b, c), weight(c, a)]
}
/// One bit per dot of the canvas: the dots some depth-tested line will be drawn on.
#[derive(Debug, Clone, Default)]
pub(super) struct DotMask {
    width: usize,
    height: usize,
    /// 64-bit words per row.
    stride: usize,
    words: Vec<u64>,
}

impl DotMask {
    /// Clears every dot of a `w` x `h` dot canvas.
    pub(super) fn reset(&mut self, w: usize, h: usize) {
        (self.width, self.height) = (w, h);
        self.stride = w.div_ceil(64);
        self.words.clear();
        self.words.resize(self.stride * h, 0);
    }

    /// Sets the dot (x, y) (inside the canvas).
    #[inline]
    pub(super) fn set(&mut self, x: usize, y: usize) {
        self.words[y * self.stride + x / 64] |= 1 << (x % 64);
    }

    /// Sets the dots the line a-b will visit on a `w` x `h` canvas.
    #[cfg(test)]
    pub(super) fn mark_line(&mut self, a: Vec3, b: Vec3, w: usize, h: usize) {
        walk_line(a, b, w, h, |x, y, _| self.set(x, y));
    }

    /// One past the last set dot of row `y` within [x0, x1), if any is set (a non-empty
    /// range inside the canvas).
    #[inline]
    pub(super) fn last_set(&self, y: usize, x0: usize, x1: usize) -> Option<usize> {
        let row = &self.words[y * self.stride..];
        let (k0, k1) = (x0 / 64, (x1 - 1) / 64);
        (k0..=k1).rev().find_map(|k| {
            let mut bits = row[k];
            if k == k1 {
                bits &= u64::MAX >> (63 - (x1 - 1) % 64);
            }
            if k == k0 {
                bits &= u64::MAX << (x0 % 64);
            }
            (bits != 0).then(|| k * 64 + 64 - bits.leading_zeros() as usize)
        })
    }

    /// Whether any dot of [x0, x1) x [y0, y1) is set (non-empty ranges inside the canvas).
    #[inline]
    pub(super) fn any(&self, x0: usize, x1: usize, y0: usize, y1: usize) -> bool {
        let (k0, k1) = (x0 / 64, (x1 - 1) / 64);
        // Bits x0 % 64 and up of the first word, bits up to (x1 - 1) % 64 of the last.
        let first = u64::MAX << (x0 % 64);
        let last = u64::MAX >> (63 - (x1 - 1) % 64);
        (y0..y1).any(|y| {
            let row = &self.words[y * self.stride..];
            if k0 == k1 {
                row[k0] & first & last != 0
            } else {
                row[k0] & first != 0
                    || row[k0 + 1..k1].iter().any(|&w| w != 0)
                    || row[k1] & last != 0
            }
        })
    }
}

/// The box of dots a projected vertex contributes to a triangle's bounding box of dot
/// centres: `[x0, x1, y0, y1]`, the first column and row whose centre is at or past it and
/// one past the last at or before it, clamped to the canvas.
///
/// A triangle's box is the minimum of its corners' starts and the maximum of their ends,
/// exactly what [`depth_triangle`] computes from the corners' minimum and maximum
/// (subtracting 0.5, rounding and clamping all keep the order), so it can be found with
/// integer min/max from values computed once per vertex. For canvases below 2^24 dots on
/// a side.
#[inline]
pub(super) fn dot_span(p: Vec3, w: usize, h: usize) -> [u32; 4] {
    let (x0, x1) = span(p.x - 0.5, w);
    let (y0, y1) = span(p.y - 0.5, h);
    [x0, x1, y0, y1]
}

/// `(ceil_nonneg(v).min(limit), floor_end(v, limit))` from one conversion and no branch,
/// for a `limit` below 2^24 (exact as f32).
#[inline]
pub(super) fn span(v: f32, limit: usize) -> (u32, u32) {
    // Clamped to [-2, limit] (max() turns NaN into -2): both ends come out the same there,
    // and NaN ends at (0, 0) as in the helpers. Truncation is floor from 0 up; below, the
    // start clamps to 0 and the end to 0 whatever the rounding.
    let limit = limit.min(1 << 24) as i32;
    let c = v.max(-2.0).min(limit as f32);
    let t = c as i32;
    let back = t as f32;
    let start = (t + (back < c) as i32).max(0);
    let end = (t - (back > c) as i32 + 1).clamp(0, limit);
    (start as u32, end as u32)
}

/// A triangle's box of dot centres `[x0, x1, y0, y1]` (exclusive ends) from its corners'
/// [`dot_span`]s.
#[inline]
pub(super) fn triangle_box(s: [[u32; 4]; 3]) -> [usize; 4] {
    [
        s[0][0].min(s[1][0]).min(s[2][0]) as usize,
        s[0][1].max(s[1][1]).max(s[2][1]) as usize,
        s[0][2].min(s[1][2]).min(s[2][2]) as usize,
        s[0][3].max(s[1][3]).max(s[2][3]) as usize,
    ]
}

/// Rasterizes a screen triangle (dots, x right, y down, z larger nearer) into the depth
/// buffer `depth` (`w` x `h`, row-major), keeping the nearer depth at every dot whose centre
/// lies inside it. The one depth rasterizer: the renderer's depth pass and the landmark
/// picker's visibility use it.
///
/// The same dots and depths as [`raster_triangle`] with a max-depth callback (the same
/// arithmetic in the same order), but without branches per dot: at terminal resolution a
/// triangle covers a handful of dots, and whether the next one is inside is a coin toss the
/// branch predictor loses.
// Always inlined: passed by value through the stack, its corners cost a stalled reload.
#[inline(always)]
pub fn depth_triangle(p: [Vec3; 3], w: usize, h: usize, depth: &mut [f32]) {
    let [a, b, c] = p;
    let x0 = ceil_nonneg(a.x.min(b.x).min(c.x) - 0.5);
    let x1 = floor_end(a.x.max(b.x).max(c.x) - 0.5, w);
    let y0 = ceil_nonneg(a.y.min(b.y).min(c.y) - 0.5);
    let y1 = floor_end(a.y.max(b.y).max(c.y) - 0.5, h);
    depth_triangle_in(p, [x0, x1, y0, y1], w, None, depth);
}

/// [`depth_triangle`] with the triangle's box of dot centres `[x0, x1, y0, y1]` already
/// known (from [`triangle_box`]). With `wanted`, only the dots it sets are sure to be
/// written: rows without one are skipped and each row stops after its last one (the dots
/// before it are stepped through as usual, so the wanted dots get the same bits).
#[inline(always)]
pub(super) fn depth_triangle_in(
    p: [Vec3; 3],
    dots: [usize; 4],
    w: usize,
    wanted: Option<&DotMask>,
    depth: &mut [f32],
) {
    let [a, b, c] = p;
    let [x0, x1, y0, y1] = dots;
    let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if !area.is_finite() || area.abs() < 1e-9 || x0 >= x1 || y0 >= y1 {
        return;
    }
    let [(ax, ay, a0), (bx, by, b0)] = corner_weights(p, area);
    let (va, vb, vc) = (a.z, b.z, c.z);
    let zx = ax * (va - vc) + bx * (vb - vc);
    let zy = ay * (va - vc) + by * (vb - vc);
    let z0 = a0 * (va - vc) + b0 * (vb - vc) + vc;
    const EPS: f32 = -1e-5;
    let px = x0 as f32 + 0.5;
    for y in y0..y1 {
        let end = match wanted {
            Some(mask) => match mask.last_set(y, x0, x1) {
                Some(end) => end,
                None => continue,
            },
            None => x1,
        };
        let py = y as f32 + 0.5;
        let mut la = ax * px + ay * py + a0;
        let mut lb = bx * px + by * py + b0;
        let mut z = zx * px + zy * py + z0;
        let Some(row) = depth.get_mut(y * w + x0..y * w + end) else {
            return;
        };
        for d in row {
            let inside = (la >= EPS) & (lb >= EPS) & (1.0 - la - lb >= EPS);
            let nearer = inside & (z > *d);
            *d = if nearer { z } else { *d };
            la += ax;
            lb += bx;
            z += zx;
        }
    }
}
