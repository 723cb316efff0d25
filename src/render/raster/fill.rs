//! Shading: vertex normals, Lambert light, and the dithered fill of the shaded style.

use glam::Vec3;

use super::depth::{corner_weights, dot_span, triangle_box};
use super::features::HEAT_FLOOR;
use super::grid::{ceil_nonneg, floor_end};
use super::project::Normals;
use super::Renderer;
use crate::model::Mesh;
use crate::render::canvas::{DotCanvas, Layer, Rgb};
use crate::render::scene::{displacement_ramp, Scene};

/// Light direction in view space: from the upper front, a little from the viewer's left.
pub(super) const LIGHT: Vec3 = Vec3::new(-0.30, 0.55, 0.78);
/// Shading floor, so surfaces turned away from the light still show a few dots.
pub(super) const AMBIENT: f32 = 0.08;
/// A 4x4 ordered-dither (Bayer) matrix, thresholds 0..16.
const BAYER: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

impl Renderer {
    /// Rasterizes front-facing triangles with depth and Gouraud-interpolated Lambert shading
    /// (and, with displacement colours, the interpolated displacement), dithered when the
    /// canvas asks for it.
    ///
    /// Two steps: every triangle writes depth and its interpolated values into per-dot
    /// buffers without a branch per dot (at terminal resolution a triangle covers a handful
    /// of dots, and whether the next one is inside is a coin toss the branch predictor
    /// loses); then each dot the surface covers is lit once, from the nearest triangle's
    /// values. The same dots, depths and colours as lighting each dot as it is drawn.
    #[inline(never)]
    pub(super) fn fill_shaded(&mut self, scene: &Scene, canvas: &mut DotCanvas) {
        self.mark_faces_dirty(canvas);
        let (w, h, dither) = (canvas.width(), canvas.height(), canvas.dither);
        let dirty = canvas.dirty_rect();
        let n = w * h;
        if self.dot_shade.len() < n {
            self.dot_shade.resize(n, 0.0);
        }
        let heat = !self.vertex_heat.is_empty();
        if heat && self.dot_heat.len() < n {
            self.dot_heat.resize(n, 0.0);
        }
        let small = w.max(h) < 1 << 24;
        self.dot_spans.clear();
        if small {
            self.dot_spans
                .extend(self.projected.iter().map(move |&p| dot_span(p, w, h)));
        }
        let (depth, on, color, layer) = canvas.buffers_mut();
        for (t, tri) in self.triangles.iter().enumerate() {
            if !self.facing[t] {
                continue;
            }
            let p = tri.map(|i| self.projected[i as usize]);
            let dots = if small {
                triangle_box(tri.map(|i| self.dot_spans[i as usize]))
            } else {
                float_box(p, w, h)
            };
            let s = tri.map(|i| self.vertex_shade[i as usize]);
            if heat {
                let k = tri.map(|i| self.vertex_heat[i as usize]);
                let out = [&mut self.dot_shade[..], &mut self.dot_heat[..]];
                shade_triangle_in::<2>(p, [s, k], dots, w, depth, out);
            } else {
                let out = [&mut self.dot_shade[..]];
                shade_triangle_in::<1>(p, [s], dots, w, depth, out);
            }
        }
        self.tone_brows(w, h, depth);
        self.tone_irises(w, h, depth);
        let look = Look {
            base: scene.palette.mesh,
            dither,
            heat: heat.then_some(&self.dot_heat[..]),
        };
        look.light_dots(dirty, w, depth, &self.dot_shade, (on, color, layer));
    }

    /// Per-vertex Lambert intensity from oriented, area-weighted vertex normals.
    #[inline(never)]
    pub(super) fn compute_shading(&mut self, scene: &Scene) {
        self.compute_normals(scene);
        let n = self.projected.len();
        // The light is fixed to the viewer; it was turned into mesh coordinates once in
        // `prepare`, instead of turning every normal into view space.
        self.vertex_shade.clear();
        self.vertex_shade.resize(n, 0.0);
        for (shade, normal) in self.vertex_shade.iter_mut().zip(&self.normals) {
            *shade = normal.dot(self.light_mesh);
        }
        for shade in &mut self.vertex_shade {
            *shade = AMBIENT + (1.0 - AMBIENT) * shade.max(0.0);
        }
        for (shade, tone) in self.vertex_shade.iter_mut().zip(&self.vertex_tone) {
            *shade *= tone;
        }
    }

    /// Right-hand face normals, length twice the area, of the front-facing triangles (zero
    /// for the others), unless this frame already has them.
    #[inline(never)]
    pub(super) fn compute_face_normals(&mut self, scene: &Scene) {
        if self.normals_ready >= Normals::Faces {
            return;
        }
        self.face_normals.clear();
        self.face_normals.extend(
            self.triangles
                .iter()
                .zip(&self.facing)
                .map(|(tri, &facing)| {
                    if facing {
                        let [a, b, c] = tri.map(|i| scene.positions[i as usize]);
                        (b - a).cross(c - a)
                    } else {
                        Vec3::ZERO
                    }
                }),
        );
        self.normals_ready = Normals::Faces;
    }

    /// Oriented, area-weighted unit vertex normals from the front-facing triangles (zero
    /// where none touches).
    #[inline(never)]
    pub(super) fn compute_normals(&mut self, scene: &Scene) {
        if self.normals_ready == Normals::Vertices {
            return;
        }
        self.compute_face_normals(scene);
        let n = self.projected.len();
        self.normals.clear();
        self.normals.resize(n, Vec3::ZERO);
        let sign = self.sign(scene.orientation);
        for ((tri, normal), &facing) in self
            .triangles
            .iter()
            .zip(&self.face_normals)
            .zip(&self.facing)
        {
            // Faces turned away have a zero normal: adding it changes nothing.
            if facing {
                let normal = *normal * sign;
                for &i in tri {
                    self.normals[i as usize] += normal;
                }
            }
        }
        normalize_or_zero_all(&mut self.normals);
        self.normals_ready = Normals::Vertices;
    }
}

/// The lit colour of a dot of the shaded surface: whether it is on, and its colour
/// (`base` scaled by the light, which dithering keeps from going dark).
#[cfg(test)]
pub(super) fn reference_light(
    base: Rgb,
    dither: bool,
    x: usize,
    y: usize,
    shade: f32,
    heat: Option<f32>,
) -> (bool, Rgb) {
    let lit = !dither || shade * 16.0 > BAYER[y & 3][x & 3] as f32 + 0.5;
    let base = heat.map_or(base, |h| heat_color(base, h));
    (
        lit,
        scale(base, if dither { 0.35 + 0.65 * shade } else { shade }),
    )
}

/// Whether the SSE2 kernels run (x86-64, unless the `scalar-raster` feature asks for the
/// portable code everywhere, as CI does to test the path other machines run).
const SIMD: bool = cfg!(all(target_arch = "x86_64", not(feature = "scalar-raster")));

/// How the shaded surface's dots are lit and coloured.
struct Look<'a> {
    /// The surface's colour at full light.
    base: Rgb,
    /// Whether the shading is dithered into on and off dots.
    dither: bool,
    /// Per dot, the displacement as a fraction of the full colour (displacement colours on).
    heat: Option<&'a [f32]>,
}

impl Look<'_> {
    /// Lights every dot of the rectangle `(x0, y0, x1, y1)` (exclusive ends) that the
    /// surface covers (finite depth), from its interpolated shade (and heat).
    #[inline(never)]
    fn light_dots(
        &self,
        (x0, y0, x1, y1): (usize, usize, usize, usize),
        w: usize,
        depth: &[f32],
        shade: &[f32],
        (on, color, layer): (&mut [bool], &mut [Rgb], &mut [Layer]),
    ) {
        #[cfg(target_arch = "x86_64")]
        if SIMD && self.heat.is_none() {
            let end = y1.saturating_sub(1) * w + x1;
            if y0 < y1
                && x0 < x1
                && [depth.len(), shade.len(), on.len()]
                    .iter()
                    .all(|&n| n >= end)
                && color.len() >= end
                && layer.len() >= end
            {
                sse::light_rows(
                    (x0, y0, x1, y1),
                    w,
                    self.base,
                    self.dither,
                    depth,
                    shade,
                    (on, color, layer),
                );
            }
            return;
        }
        self.light_rows((x0, y0, x1, y1), w, depth, shade, (on, color, layer));
    }

    /// The portable [`Look::light_dots`]: the same dots and colours as the SSE2 steps
    /// (tested).
    fn light_rows(
        &self,
        (x0, y0, x1, y1): (usize, usize, usize, usize),
        w: usize,
        depth: &[f32],
        shade: &[f32],
        (on, color, layer): (&mut [bool], &mut [Rgb], &mut [Layer]),
    ) {
        for y in y0..y1 {
            let thresholds = BAYER[y & 3].map(|b| b as f32 + 0.5);
            let (from, to) = (y * w + x0, y * w + x1);
            // Without branches on the dither, which is a coin toss per dot: the colour is
            // computed for every covered dot (only read where the dot is on).
            for (x, i) in (x0..x1).zip(from..to) {
                if depth[i] == f32::NEG_INFINITY {
                    continue;
                }
                let s = shade[i];
                let lit = !self.dither || s * 16.0 > thresholds[x & 3];
                on[i] = lit;
                layer[i] = if lit { Layer::Mesh } else { Layer::Empty };
                let base = match self.heat {
                    Some(heat) => heat_color(self.base, heat[i]),
                    None => self.base,
                };
                color[i] = scale(base, if self.dither { 0.35 + 0.65 * s } else { s });
            }
        }
    }
}

/// The tone of a vertex group's material by its name: irises are mid grey, pupils and the
/// inside of the mouth and of a cut-open eye nearly black (an eye with an iris painted on it
/// is lit instead, `iris`), brow hair dark, the tongue and gums a little darker than skin and
/// teeth, everything else as lit.
const TONES: [(&str, f32); 7] = [
    ("pupil", 0.12),
    ("mouth_interior", 0.06),
    ("eye_interior", 0.08),
    ("iris", 0.45),
    (BROW_HAIR, BROW_TONE),
    ("tongue", 0.6),
    ("gum", 0.7),
];

/// The name part of brow hair's groups, and its tone.
const BROW_HAIR: &str = "brow_hair";
/// How dark brow hair is drawn.
pub(super) const BROW_TONE: f32 = 0.3;

/// Per-vertex tones from the mesh's named groups ([`TONES`]; the first name that matches
/// wins), or nothing when no group names a dark material. With `brows_per_dot` brow hair
/// is left out: its tone is decided per dot (`brow`).
pub(super) fn vertex_tones(mesh: &Mesh, brows_per_dot: bool, out: &mut Vec<f32>) {
    out.clear();
    for (word, tone) in TONES.iter().rev() {
        if brows_per_dot && *word == BROW_HAIR {
            continue;
        }
        for (name, members) in &mesh.groups {
            if !name.to_ascii_lowercase().contains(word) {
                continue;
            }
            if out.is_empty() {
                out.resize(mesh.positions.len(), 1.0);
            }
            for &v in members {
                if let Some(t) = out.get_mut(v as usize) {
                    *t = *tone;
                }
            }
        }
    }
}

/// The surface colour for a displacement `heat` (a fraction of the full colour): the
/// displacement ramp, or `base` where the skin barely moved (as the feature lines do).
#[inline]
fn heat_color(base: Rgb, heat: f32) -> Rgb {
    if heat.is_nan() || heat < HEAT_FLOOR {
        base
    } else {
        displacement_ramp(heat)
    }
}

/// `c` scaled by `t` in 0..=1 (no rounding call: this runs per dot).
#[inline]
fn scale(c: Rgb, t: f32) -> Rgb {
    let t = t.clamp(0.0, 1.0);
    let f = |v: u8| (v as f32 * t + 0.5) as u8;
    Rgb(f(c.0), f(c.1), f(c.2))
}
/// `Vec3::normalize_or_zero` on every vector, four at a time so that the square roots and
/// divisions run side by side (the same operations in the same order, so the same bits).
pub(super) fn normalize_or_zero_all(v: &mut [Vec3]) {
    let mut chunks = v.chunks_exact_mut(4);
    for c in &mut chunks {
        let mut rcp = [0.0f32; 4];
        for (r, n) in rcp.iter_mut().zip(c.iter()) {
            *r = 1.0 / n.dot(*n).sqrt();
        }
        for (n, r) in c.iter_mut().zip(rcp) {
            *n = if r.is_finite() && r > 0.0 {
                *n * r
            } else {
                Vec3::ZERO
            };
        }
    }
    for n in chunks.into_remainder() {
        *n = n.normalize_or_zero();
    }
}
/// Rasterizes a screen triangle: calls `f(index, x, y, depth, attribute)` for every dot
/// whose centre lies inside it (either winding), with depth and attribute interpolated.
///
/// At terminal resolution most triangles cover a handful of dots, so the cost is in the
/// setup: one division, then the edge functions step across the bounding box.
/// The plain reference the fast fills are tested against.
#[cfg(test)]
#[inline]
pub(super) fn raster_triangle(
    p: [Vec3; 3],
    attr: [f32; 3],
    w: usize,
    h: usize,
    mut f: impl FnMut(usize, usize, usize, f32, f32),
) {
    let [a, b, c] = p;
    let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if !area.is_finite() || area.abs() < 1e-9 {
        return;
    }
    // Dots whose centres (x + 0.5, y + 0.5) lie within the bounding box.
    let x0 = ceil_nonneg(a.x.min(b.x).min(c.x) - 0.5);
    let x1 = floor_end(a.x.max(b.x).max(c.x) - 0.5, w);
    let y0 = ceil_nonneg(a.y.min(b.y).min(c.y) - 0.5);
    let y1 = floor_end(a.y.max(b.y).max(c.y) - 0.5, h);
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    let [(ax, ay, a0), (bx, by, b0)] = corner_weights(p, area);
    // Depth and attribute as linear functions of (x, y).
    let plane = |va: f32, vb: f32, vc: f32| {
        (
            ax * (va - vc) + bx * (vb - vc),
            ay * (va - vc) + by * (vb - vc),
            a0 * (va - vc) + b0 * (vb - vc) + vc,
        )
    };
    let (zx, zy, z0) = plane(a.z, b.z, c.z);
    let (sx, sy, s0) = plane(attr[0], attr[1], attr[2]);
    const EPS: f32 = -1e-5;
    let px = x0 as f32 + 0.5;
    for y in y0..y1 {
        let py = y as f32 + 0.5;
        let mut la = ax * px + ay * py + a0;
        let mut lb = bx * px + by * py + b0;
        let mut z = zx * px + zy * py + z0;
        let mut s = sx * px + sy * py + s0;
        let row = y * w;
        for x in x0..x1 {
            if la >= EPS && lb >= EPS && 1.0 - la - lb >= EPS {
                f(row + x, x, y, z, s);
            }
            la += ax;
            lb += bx;
            z += zx;
            s += sx;
        }
    }
}

/// A triangle's box of dot centres `[x0, x1, y0, y1]` from its corners, for any canvas (see
/// [`triangle_box`] for the fast way below 2^24 dots a side).
pub(super) fn float_box([a, b, c]: [Vec3; 3], w: usize, h: usize) -> [usize; 4] {
    [
        ceil_nonneg(a.x.min(b.x).min(c.x) - 0.5),
        floor_end(a.x.max(b.x).max(c.x) - 0.5, w),
        ceil_nonneg(a.y.min(b.y).min(c.y) - 0.5),
        floor_end(a.y.max(b.y).max(c.y) - 0.5, h),
    ]
}

/// Rasterizes a screen triangle over its box of dot centres `dots` into the depth buffer,
/// and where it is nearer, writes its `N` interpolated attributes into `out`.
///
/// Every value at a dot centre `(x, y)` is its plane evaluated there, `(kx * x + ky * y) +
/// k0` (as [`plane_at`] does), not a running sum along the row: so four dots are tested
/// and written side by side, without a branch per dot, and with no error piling up along
/// a row. A dot is inside when its three barycentric weights are at least `-1e-5`, so an
/// edge shared by two triangles leaves no gap.
#[inline(always)]
pub(super) fn shade_triangle_in<const N: usize>(
    p: [Vec3; 3],
    attr: [[f32; 3]; N],
    dots: [usize; 4],
    w: usize,
    depth: &mut [f32],
    out: [&mut [f32]; N],
) {
    let [a, b, c] = p;
    let [x0, x1, y0, y1] = dots;
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if !area.is_finite() || area.abs() < 1e-9 {
        return;
    }
    let [wa, wb] = corner_weights(p, area);
    let z = plane(wa, wb, [a.z, b.z, c.z]);
    let planes = attr.map(|v| plane(wa, wb, v));
    let padded = (x1 - x0).next_multiple_of(4);
    // Every row's steps fit in the buffers when the last row's do.
    let last_end = (y1 - 1) * w + x0 + padded;
    #[cfg(target_arch = "x86_64")]
    if SIMD && last_end <= depth.len() && out.iter().all(|o| o.len() >= last_end) {
        sse::shade_rows([x0, x1, y0, y1], w, [wa, wb, z], planes, depth, out);
        return;
    }
    let _ = last_end;
    shade_rows([x0, x1, y0, y1], w, [wa, wb, z], planes, depth, out);
}

/// The portable [`shade_triangle_in`] over the rows of its box: the same dots and bits as
/// the SSE2 steps (tested), four lanes at a time where the buffers hold the padding, one dot
/// at a time at the canvas's end.
fn shade_rows<const N: usize>(
    [x0, x1, y0, y1]: [usize; 4],
    w: usize,
    [wa, wb, z]: [(f32, f32, f32); 3],
    planes: [(f32, f32, f32); N],
    depth: &mut [f32],
    out: [&mut [f32]; N],
) {
    /// Dots per step.
    const LANES: usize = 4;
    const STEP: [f32; LANES] = [0.5, 1.5, 2.5, 3.5];
    let width = x1 - x0;
    let padded = width.next_multiple_of(LANES);
    for y in y0..y1 {
        let py = y as f32 + 0.5;
        let from = y * w + x0;
        // The steps may run past the row's end, into dots they leave as they are (each
        // lane past the end is masked off), but not past the buffers' end.
        let end = from + padded;
        if end > depth.len() || out.iter().any(|o| o.len() < end) {
            // The last dots of the canvas: one at a time.
            if from + width > depth.len() || out.iter().any(|o| o.len() < from + width) {
                return;
            }
            for (x, i) in (x0..x1).zip(from..) {
                let px = x as f32 + 0.5;
                let (la, lb) = (plane_at(wa, px, py), plane_at(wb, px, py));
                let zi = plane_at(z, px, py);
                let nearer = inside(la, lb) & (zi > depth[i]);
                depth[i] = if nearer { zi } else { depth[i] };
                for j in 0..N {
                    let v = plane_at(planes[j], px, py);
                    out[j][i] = if nearer { v } else { out[j][i] };
                }
            }
            continue;
        }
        // The parts of each plane that do not change along the row.
        let row = |(kx, ky, k0): (f32, f32, f32)| (kx, ky * py, k0);
        let (ra, rb, rz) = (row(wa), row(wb), row(z));
        let rv = planes.map(row);
        let mut i = from;
        let mut x = x0;
        while i < end {
            let xs = STEP.map(|s| x as f32 + s);
            let at = |(kx, ky, k0): (f32, f32, f32)| xs.map(|px| kx * px + ky + k0);
            let (la, lb, lz) = (at(ra), at(rb), at(rz));
            let d: &mut [f32; LANES] = (&mut depth[i..i + LANES]).try_into().expect("four");
            let mut nearer = [false; LANES];
            for l in 0..LANES {
                let valid = x + l < x1;
                nearer[l] = valid & inside(la[l], lb[l]) & (lz[l] > d[l]);
                d[l] = if nearer[l] { lz[l] } else { d[l] };
            }
            for j in 0..N {
                let v = at(rv[j]);
                let o: &mut [f32; LANES] = (&mut out[j][i..i + LANES]).try_into().expect("four");
                for l in 0..LANES {
                    o[l] = if nearer[l] { v[l] } else { o[l] };
                }
            }
            i += LANES;
            x += LANES;
        }
    }
}

/// Whether a dot with barycentric weights `la`, `lb` (and `1 - la - lb`) lies inside its
/// triangle, within a small tolerance.
#[inline(always)]
pub(super) fn inside(la: f32, lb: f32) -> bool {
    const EPS: f32 = -1e-5;
    (la >= EPS) & (lb >= EPS) & (1.0 - la - lb >= EPS)
}

/// The plane through the values `v` at a triangle's corners, as `(kx, ky, k0)`, from the
/// linear functions `wa`, `wb` giving the weights of its first two corners.
#[inline(always)]
pub(super) fn plane(wa: (f32, f32, f32), wb: (f32, f32, f32), v: [f32; 3]) -> (f32, f32, f32) {
    let (ax, ay, a0) = wa;
    let (bx, by, b0) = wb;
    let [va, vb, vc] = v;
    (
        ax * (va - vc) + bx * (vb - vc),
        ay * (va - vc) + by * (vb - vc),
        a0 * (va - vc) + b0 * (vb - vc) + vc,
    )
}

/// A plane `(kx, ky, k0)` evaluated at `(x, y)`: `(kx * x + ky * y) + k0`.
#[inline(always)]
pub(super) fn plane_at((kx, ky, k0): (f32, f32, f32), x: f32, y: f32) -> f32 {
    kx * x + ky * y + k0
}

/// The four-dots-at-a-time steps of [`shade_triangle_in`] in SSE2 (always present on
/// x86-64): the same arithmetic in the same order, so the same bits, with the choice of
/// each dot's value made by masks, never by a branch or a per-dot store.
#[cfg(target_arch = "x86_64")]
mod sse {
    use std::arch::x86_64::*;

    use super::BAYER;
    use crate::render::canvas::{Layer, Rgb};

    /// A plane `(kx, ky, k0)`.
    type Plane = (f32, f32, f32);

    /// Lights the dots of the rectangle `(x0, y0, x1, y1)` without displacement colours,
    /// four at a time and without a branch per dot: a dot is on where the surface covers
    /// it (finite depth) and, dithered, its shade beats the threshold; its colour is
    /// `base` scaled as `scale` does (written for every dot: colour and layer are read
    /// only where a dot is on).
    ///
    /// The caller checks that the rectangle lies inside every buffer.
    pub(super) fn light_rows(
        (x0, y0, x1, y1): (usize, usize, usize, usize),
        w: usize,
        base: Rgb,
        dither: bool,
        depth: &[f32],
        shade: &[f32],
        (on, color, layer): (&mut [bool], &mut [Rgb], &mut [Layer]),
    ) {
        let end = (y1 - 1) * w + x1;
        assert!(depth.len() >= end && shade.len() >= end && on.len() >= end);
        assert!(color.len() >= end && layer.len() >= end);
        // SAFETY: SSE and SSE2 are part of x86-64; the loads read `depth` and `shade` at
        // `i..i + 4` with `i + 4 <= y * w + x1 <= end`.
        unsafe {
            let (zero, one) = (_mm_setzero_ps(), _mm_set1_ps(1.0));
            let empty = _mm_set1_ps(f32::NEG_INFINITY);
            let channels = [base.0, base.1, base.2].map(|c| _mm_set1_ps(c as f32));
            let half = _mm_set1_ps(0.5);
            let sixteen = _mm_set1_ps(16.0);
            let (dim, bright) = (_mm_set1_ps(0.35), _mm_set1_ps(0.65));
            for y in y0..y1 {
                let row = BAYER[y & 3].map(|b| b as f32 + 0.5);
                let t = |l: usize| row[(x0 + l) & 3];
                let thresholds = _mm_setr_ps(t(0), t(1), t(2), t(3));
                let from = y * w + x0;
                let to = y * w + x1;
                let mut i = from;
                while i + 4 <= to {
                    let s = _mm_loadu_ps(shade.as_ptr().add(i));
                    let covered = _mm_cmpneq_ps(_mm_loadu_ps(depth.as_ptr().add(i)), empty);
                    let lit = if dither {
                        _mm_and_ps(covered, _mm_cmpgt_ps(_mm_mul_ps(s, sixteen), thresholds))
                    } else {
                        covered
                    };
                    let k = if dither {
                        _mm_add_ps(dim, _mm_mul_ps(bright, s))
                    } else {
                        s
                    };
                    // `k.clamp(0.0, 1.0)`, with NaN as 0.0 (the same channel values).
                    let k = _mm_max_ps(_mm_min_ps(one, k), zero);
                    let [r, g, b] =
                        channels.map(|c| _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(c, k), half)));
                    let [r, g, b]: [[i32; 4]; 3] = [r, g, b].map(|v| std::mem::transmute(v));
                    let mask = _mm_movemask_ps(lit);
                    for l in 0..4 {
                        let is_on = mask >> l & 1 != 0;
                        on[i + l] = is_on;
                        layer[i + l] = if is_on { Layer::Mesh } else { Layer::Empty };
                        color[i + l] = Rgb(r[l] as u8, g[l] as u8, b[l] as u8);
                    }
                    i += 4;
                }
                for x in (i - from + x0)..x1 {
                    let i = y * w + x;
                    let s = shade[i];
                    let lit = depth[i] != f32::NEG_INFINITY && (!dither || s * 16.0 > row[x & 3]);
                    on[i] = lit;
                    layer[i] = if lit { Layer::Mesh } else { Layer::Empty };
                    color[i] = super::scale(base, if dither { 0.35 + 0.65 * s } else { s });
                }
            }
        }
    }

    /// Steps over the rows `y0..y1` of the box `[x0, x1, y0, y1]` four dots at a time,
    /// writing depth and the `N` attributes where a dot is inside and nearer.
    ///
    /// The caller checks that every step, including the padding past `x1` of the last
    /// row, lies inside `depth` and every `out` buffer.
    #[inline(always)]
    pub(super) fn shade_rows<const N: usize>(
        [x0, x1, y0, y1]: [usize; 4],
        w: usize,
        [wa, wb, z]: [Plane; 3],
        planes: [Plane; N],
        depth: &mut [f32],
        out: [&mut [f32]; N],
    ) {
        let padded = (x1 - x0).next_multiple_of(4);
        assert!((y1 - 1) * w + x0 + padded <= depth.len());
        for o in &out {
            assert!((y1 - 1) * w + x0 + padded <= o.len());
        }
        // SAFETY: SSE and SSE2 are part of x86-64; every load and store stays inside the
        // buffers (the asserts above).
        unsafe {
            let out_ptr = out.map(|o| o.as_mut_ptr());
            let depth_ptr = depth.as_mut_ptr();
            let step = _mm_setr_ps(0.5, 1.5, 2.5, 3.5);
            let eps = _mm_set1_ps(-1e-5);
            let one = _mm_set1_ps(1.0);
            // Dot centres past the box's last column are masked off (exact: below 2^24).
            let x_end = _mm_set1_ps(x1 as f32);
            let splat = |(kx, _, k0): Plane| (_mm_set1_ps(kx), _mm_set1_ps(k0));
            let (ka, kb, kz) = (splat(wa), splat(wb), splat(z));
            let kv = planes.map(splat);
            for y in y0..y1 {
                let py = y as f32 + 0.5;
                // `(kx * x + ky * y) + k0`, with `ky * y` computed once per row.
                let row = |p: Plane| _mm_set1_ps(p.1 * py);
                let (ya, yb, yz) = (row(wa), row(wb), row(z));
                let yv = planes.map(row);
                let at = |(kx, k0): (__m128, __m128), ky: __m128, xs: __m128| {
                    _mm_add_ps(_mm_add_ps(_mm_mul_ps(kx, xs), ky), k0)
                };
                let from = y * w + x0;
                let mut x = x0;
                let mut i = from;
                while i < from + padded {
                    let xs = _mm_add_ps(_mm_set1_ps(x as f32), step);
                    let la = at(ka, ya, xs);
                    let lb = at(kb, yb, xs);
                    let lz = at(kz, yz, xs);
                    let lc = _mm_sub_ps(_mm_sub_ps(one, la), lb);
                    let inside = _mm_and_ps(
                        _mm_and_ps(_mm_cmpge_ps(la, eps), _mm_cmpge_ps(lb, eps)),
                        _mm_and_ps(_mm_cmpge_ps(lc, eps), _mm_cmplt_ps(xs, x_end)),
                    );
                    // `i + 4 <= from + padded <= (y1 - 1) * w + x0 + padded`, which the
                    // asserts above keep inside `depth` and every `out` buffer.
                    let d = _mm_loadu_ps(depth_ptr.add(i));
                    let nearer = _mm_and_ps(inside, _mm_cmpgt_ps(lz, d));
                    let keep = |new: __m128, old: __m128| {
                        _mm_or_ps(_mm_and_ps(nearer, new), _mm_andnot_ps(nearer, old))
                    };
                    _mm_storeu_ps(depth_ptr.add(i), keep(lz, d));
                    for j in 0..N {
                        let o = out_ptr[j].add(i);
                        _mm_storeu_ps(o, keep(at(kv[j], yv[j], xs), _mm_loadu_ps(o)));
                    }
                    i += 4;
                    x += 4;
                }
            }
        }
    }
}

/// The SSE2 kernels promise the portable code's bits: both run on the same random triangles
/// and buffers and must leave the same depth, attributes, dots and colours.
#[cfg(all(test, target_arch = "x86_64"))]
mod simd_matches_portable {
    use super::*;
    use proptest::prelude::*;

    fn corner() -> impl Strategy<Value = Vec3> {
        (-8.0f32..72.0, -8.0f32..40.0, -5.0f32..5.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    fn bits(v: &[f32]) -> Vec<u32> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]

        #[test]
        fn shading_steps_give_the_same_bits(
            p in [corner(), corner(), corner()],
            attr in proptest::array::uniform2(proptest::array::uniform3(0.0f32..1.0)),
            seed in any::<u32>(),
        ) {
            let (w, h) = (64usize, 32usize);
            let [a, b, c] = p;
            let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
            prop_assume!(area.is_finite() && area.abs() >= 1e-9);
            let dots = float_box(p, w, h);
            let [x0, x1, y0, y1] = dots;
            prop_assume!(x0 < x1 && y0 < y1);
            let [wa, wb] = corner_weights(p, area);
            let z = plane(wa, wb, [a.z, b.z, c.z]);
            let planes = attr.map(|v| plane(wa, wb, v));
            // Room for the last row's padding, and some dots already drawn nearer.
            let len = w * h + 4;
            let start: Vec<f32> = (0..len)
                .map(|i| if (i as u32 ^ seed) % 5 == 0 { 1.0 } else { f32::NEG_INFINITY })
                .collect();
            let (mut d1, mut d2) = (start.clone(), start.clone());
            let (mut s1, mut s2, mut k1, mut k2) =
                (vec![0.25; len], vec![0.25; len], vec![0.5; len], vec![0.5; len]);
            sse::shade_rows(dots, w, [wa, wb, z], planes, &mut d1, [&mut s1, &mut k1]);
            shade_rows(dots, w, [wa, wb, z], planes, &mut d2, [&mut s2, &mut k2]);
            prop_assert_eq!(bits(&d1), bits(&d2));
            prop_assert_eq!(bits(&s1), bits(&s2));
            prop_assert_eq!(bits(&k1), bits(&k2));
        }

        #[test]
        fn lighting_steps_give_the_same_dots_and_colours(
            rect in (0usize..60, 0usize..30, 1usize..64, 1usize..32),
            dither in any::<bool>(),
            base in (any::<u8>(), any::<u8>(), any::<u8>()),
            seed in any::<u32>(),
        ) {
            let (w, h) = (64usize, 32usize);
            let (x0, y0) = (rect.0, rect.1);
            let (x1, y1) = ((x0 + rect.2).min(w), (y0 + rect.3).min(h));
            prop_assume!(x0 < x1 && y0 < y1);
            let len = w * h;
            let mut r = seed;
            let mut next = || {
                r = r.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (r >> 8) as f32 / (1 << 24) as f32
            };
            let depth: Vec<f32> =
                (0..len).map(|_| if next() < 0.2 { f32::NEG_INFINITY } else { next() }).collect();
            // Shades past 0..1 and NaN clamp alike in both.
            let shade: Vec<f32> = (0..len)
                .map(|i| if i % 97 == 0 { f32::NAN } else { next() * 1.4 - 0.2 })
                .collect();
            let look = Look { base: Rgb(base.0, base.1, base.2), dither, heat: None };
            let (mut on1, mut c1, mut l1) = (vec![false; len], vec![Rgb(0, 0, 0); len], vec![Layer::Empty; len]);
            let (mut on2, mut c2, mut l2) = (on1.clone(), c1.clone(), l1.clone());
            sse::light_rows((x0, y0, x1, y1), w, look.base, dither, &depth, &shade, (&mut on1, &mut c1, &mut l1));
            look.light_rows((x0, y0, x1, y1), w, &depth, &shade, (&mut on2, &mut c2, &mut l2));
            // Colour and layer are read only where a dot is on, as the kernels say.
            for i in 0..len {
                prop_assert_eq!(on1[i], on2[i], "dot {}", i);
                if on1[i] {
                    prop_assert_eq!(c1[i], c2[i], "dot {}", i);
                    prop_assert_eq!(l1[i], l2[i], "dot {}", i);
                }
            }
        }
    }
}

#[cfg(test)]
mod tone_tests {
    use super::vertex_tones;

    /// The built-in face's eyebrows are drawn dark; the skin around them stays as lit.
    #[test]
    fn the_builtin_face_draws_its_brows_dark() {
        let mesh = crate::io::builtin::default_mesh();
        let mut tones = Vec::new();
        vertex_tones(&mesh, false, &mut tones);
        for side in ["left", "right"] {
            let brow = &mesh.groups[&format!("{side}_brow_hair")];
            assert!(brow.iter().all(|&v| tones[v as usize] < 0.5), "{side} brow");
            let forehead = mesh.groups[&format!("{side}_forehead")][0];
            assert_eq!(tones[forehead as usize], 1.0, "{side} forehead");
        }
    }
}
