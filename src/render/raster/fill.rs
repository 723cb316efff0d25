//! Shading: vertex normals, Lambert light, and the dithered fill of the shaded style.

use glam::Vec3;

use super::depth::{ceil_nonneg, corner_weights, floor_end};
use super::Renderer;
use crate::model::Mesh;
use crate::render::canvas::{DotCanvas, Layer, Rgb};
use crate::render::scene::Scene;

/// Light direction in view space: from the upper front, a little from the viewer's left.
pub(super) const LIGHT: Vec3 = Vec3::new(-0.30, 0.55, 0.78);
/// Shading floor, so surfaces turned away from the light still show a few dots.
const AMBIENT: f32 = 0.08;
/// A 4x4 ordered-dither (Bayer) matrix, thresholds 0..16.
const BAYER: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

impl Renderer {
    /// Rasterizes front-facing triangles with depth and Gouraud-interpolated Lambert shading,
    /// dithered when the canvas asks for it.
    #[inline(never)]
    pub(super) fn fill_shaded(&self, scene: &Scene, canvas: &mut DotCanvas) {
        self.mark_faces_dirty(canvas);
        let (w, h, dither) = (canvas.width(), canvas.height(), canvas.dither);
        let base = scene.palette.mesh;
        let (depth, on, color, layer) = canvas.buffers_mut();
        for (t, tri) in self.triangles.iter().enumerate() {
            if !self.facing[t] {
                continue;
            }
            let p = tri.map(|i| self.projected[i as usize]);
            let s = tri.map(|i| self.vertex_shade[i as usize]);
            raster_triangle(p, s, w, h, |i, x, y, z, shade| {
                if z > depth[i] {
                    depth[i] = z;
                    let lit = !dither || shade * 16.0 > BAYER[y & 3][x & 3] as f32 + 0.5;
                    on[i] = lit;
                    color[i] = scale(base, if dither { 0.35 + 0.65 * shade } else { shade });
                    layer[i] = if lit { Layer::Mesh } else { Layer::Empty };
                }
            });
        }
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
        if self.face_normals_ready {
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
        self.face_normals_ready = true;
    }

    /// Oriented, area-weighted unit vertex normals from the front-facing triangles (zero
    /// where none touches).
    #[inline(never)]
    pub(super) fn compute_normals(&mut self, scene: &Scene) {
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
    }
}

/// The tone of a vertex group's material by its name: irises are mid grey, pupils nearly
/// black, everything else as lit.
const TONES: [(&str, f32); 2] = [("pupil", 0.12), ("iris", 0.45)];

/// Per-vertex tones from the mesh's named groups ([`TONES`]; the first name that matches
/// wins), or nothing when no group names a dark material.
pub(super) fn vertex_tones(mesh: &Mesh, out: &mut Vec<f32>) {
    out.clear();
    for (word, tone) in TONES.iter().rev() {
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
