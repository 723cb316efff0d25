//! The rasterizer: back-face culling, a depth buffer at dot resolution, depth-tested lines,
//! feature-line extraction, shading and overlays.

use glam::{Vec2, Vec3};

use super::camera::{Camera, Projection};
use super::canvas::{DotCanvas, Layer, Rgb};
use super::scene::{displacement_ramp, Orientation, Overlay, Scene, Shape, Style};
use crate::model::Mesh;

/// No second triangle on this edge (a mesh border).
const NONE: u32 = u32::MAX;
/// Light direction in view space: from the upper front, a little from the viewer's left.
const LIGHT: Vec3 = Vec3::new(-0.30, 0.55, 0.78);
/// Shading floor, so surfaces turned away from the light still show a few dots.
const AMBIENT: f32 = 0.08;
/// Depth bias (in dot heights) that lets a line lying on a surface pass the depth test.
const BASE_BIAS: f32 = 1.0;
/// Extra bias per unit of the adjacent faces' depth slope (dots of depth per dot).
const SLOPE_BIAS: f32 = 0.8;
/// Cap on the slope part of the bias, so steep faces do not let hidden lines through.
const MAX_SLOPE_BIAS: f32 = 6.0;

/// A 4x4 ordered-dither (Bayer) matrix, thresholds 0..16.
const BAYER: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// One undirected mesh edge and the (up to two) triangles sharing it.
#[derive(Debug, Clone, Copy)]
struct Edge {
    a: u32,
    b: u32,
    t0: u32,
    t1: u32,
}

/// A depth-tested line of this frame, in canvas dot coordinates with depth.
#[derive(Debug, Clone, Copy)]
struct Segment {
    a: Vec3,
    b: Vec3,
    /// How far behind the surface the line may lie and still show.
    bias: f32,
    color: Rgb,
}

/// A visible piece of a line, in canvas dot coordinates (for vector output).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Run {
    /// Start point, in dots (x right, y down).
    pub from: Vec2,
    /// End point, in dots.
    pub to: Vec2,
    /// Colour.
    pub color: Rgb,
    /// What the line belongs to.
    pub layer: Layer,
}

/// A visible, lit triangle in canvas dot coordinates (for vector output of shaded views).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LitTriangle {
    /// Corners in dots (x right, y down).
    pub corners: [Vec2; 3],
    /// Mean depth (larger is nearer), for painter's ordering.
    pub depth: f32,
    /// Lambert intensity, 0.0 to 1.0.
    pub shade: f32,
}

/// Renders scenes of one mesh, keeping its edge topology and scratch buffers between frames.
///
/// Build one per mesh and call [`Renderer::render`] every frame; nothing is allocated once
/// the buffers have grown to the mesh's size. A scene whose mesh has different triangles
/// makes the renderer rebuild its topology first.
#[derive(Debug, Clone, Default)]
pub struct Renderer {
    triangles: Vec<[u32; 3]>,
    edges: Vec<Edge>,
    /// +1 when right-hand normals point outward, -1 when inward (auto-detected at build).
    auto_sign: f32,
    projected: Vec<Vec3>,
    facing: Vec<bool>,
    normals: Vec<Vec3>,
    vertex_shade: Vec<f32>,
    vertex_heat: Vec<f32>,
    rest_projected: Vec<Vec3>,
    rest_facing: Vec<bool>,
    light_mesh: Vec3,
    viewer_mesh: Vec3,
    vertex_facing: Vec<f32>,
    face_normals: Vec<Vec3>,
    face_normals_ready: bool,
    runs: Option<Vec<Run>>,
    /// This frame's depth-tested lines, in drawing order, kept until the depth buffer holds
    /// every surface they pass over.
    segments: Vec<Segment>,
    /// Depth slope per triangle for this frame, NaN until first needed.
    slopes: Vec<f32>,
    /// The dots some depth-tested line of this frame will be drawn on.
    line_dots: DotMask,
    /// The dot steps of the gathered lines, walked while marking `line_dots`, and where
    /// each line's steps end (empty when the lines were not walked ahead).
    walked: Vec<LineDot>,
    walk_ends: Vec<u32>,
    /// Per vertex, [`dot_span`] of its projection (this frame).
    dot_spans: Vec<[u32; 4]>,
}

impl Renderer {
    /// A renderer for `mesh`: builds its edge list and detects its winding.
    pub fn new(mesh: &Mesh) -> Renderer {
        let mut renderer = Renderer::default();
        renderer.rebuild(mesh);
        renderer
    }

    fn rebuild(&mut self, mesh: &Mesh) {
        self.triangles.clear();
        self.triangles.extend_from_slice(&mesh.triangles);
        self.edges = build_edges(&mesh.triangles, mesh.positions.len());
        self.auto_sign = detect_orientation(mesh);
    }

    /// The winding the renderer detected for its mesh: `Outward` or `Inward`.
    pub fn detected_orientation(&self) -> Orientation {
        if self.auto_sign < 0.0 {
            Orientation::Inward
        } else {
            Orientation::Outward
        }
    }

    /// Draws `scene` seen by `camera` in `style` into `canvas` (cleared first), fitting the
    /// rest pose, as this camera sees it, to the canvas.
    pub fn render(&mut self, scene: &Scene, camera: &Camera, style: Style, canvas: &mut DotCanvas) {
        self.runs = None;
        self.draw(scene, camera, style, canvas);
    }

    /// Like [`Renderer::render`], and also returns every visible piece of every line drawn
    /// (mesh lines, ghost, overlays) in dot coordinates, for vector output.
    pub fn render_runs(
        &mut self,
        scene: &Scene,
        camera: &Camera,
        style: Style,
        canvas: &mut DotCanvas,
    ) -> Vec<Run> {
        self.runs = Some(Vec::new());
        self.draw(scene, camera, style, canvas);
        self.runs.take().unwrap_or_default()
    }

    /// The front-facing triangles of `scene` as lit 2D triangles in dot coordinates, sorted
    /// back to front (for painter's-algorithm vector output). Uses the same projection as
    /// [`Renderer::render`] on a canvas of this size.
    pub fn lit_triangles(
        &mut self,
        scene: &Scene,
        camera: &Camera,
        width: usize,
        height: usize,
        dot_aspect: f32,
    ) -> Vec<LitTriangle> {
        if self
            .prepare(scene, camera, width, height, dot_aspect)
            .is_none()
        {
            return Vec::new();
        }
        self.compute_shading(scene);
        let mut out = Vec::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            if !self.facing[t] {
                continue;
            }
            let p = tri.map(|i| self.projected[i as usize]);
            let shade = tri
                .iter()
                .map(|&i| self.vertex_shade[i as usize])
                .sum::<f32>()
                / 3.0;
            out.push(LitTriangle {
                corners: p.map(|v| v.truncate()),
                depth: (p[0].z + p[1].z + p[2].z) / 3.0,
                shade,
            });
        }
        out.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        out
    }

    /// Projects the scene and decides facing; `None` when there is nothing to draw.
    #[inline(never)]
    fn prepare(
        &mut self,
        scene: &Scene,
        camera: &Camera,
        width: usize,
        height: usize,
        dot_aspect: f32,
    ) -> Option<Projection> {
        if scene.mesh.triangles != self.triangles {
            self.rebuild(scene.mesh);
        }
        if width == 0 || height == 0 {
            return None;
        }
        let proj = camera.fit_points(scene.rest_positions(), width, height, dot_aspect);
        let sign = self.sign(scene.orientation);
        self.light_mesh = proj.view.transpose() * LIGHT.normalize();
        self.viewer_mesh = proj.view.transpose() * Vec3::Z;
        project_all(
            &proj,
            scene.positions,
            scene.mesh.positions.len(),
            &mut self.projected,
        );
        classify(&self.triangles, &self.projected, sign, &mut self.facing);
        // Face normals follow the pose and the facing of this frame.
        self.face_normals_ready = false;
        Some(proj)
    }

    fn sign(&self, orientation: Orientation) -> f32 {
        match orientation {
            Orientation::Auto => self.auto_sign,
            Orientation::Outward => 1.0,
            Orientation::Inward => -1.0,
        }
    }

    fn draw(&mut self, scene: &Scene, camera: &Camera, style: Style, canvas: &mut DotCanvas) {
        canvas.clear();
        let (w, h, aspect) = (canvas.width(), canvas.height(), canvas.dot_aspect);
        let Some(proj) = self.prepare(scene, camera, w, h, aspect) else {
            return;
        };
        if style == Style::Shaded {
            self.compute_shading(scene);
            self.fill_shaded(scene, canvas);
        } else {
            // The lines are gathered first, so the depth buffer only needs the surfaces
            // under them; then they are drawn, depth-tested, in the same order.
            self.segments.clear();
            self.walked.clear();
            self.walk_ends.clear();
            self.slopes.clear();
            self.slopes.resize(self.triangles.len(), f32::NAN);
            self.compute_heat(scene);
            self.collect_edges(scene, style);
            if style == Style::Lines && scene.contours > 0 {
                self.collect_contours(scene);
            }
            if style == Style::Lines && !scene.facing_contours.is_empty() {
                self.collect_facing_contours(scene);
            }
            self.fill_depth(canvas);
            self.draw_segments(canvas);
        }
        if scene.ghost {
            self.draw_ghost(scene, &proj, canvas);
        }
        self.draw_overlays(scene.overlays, &proj, canvas);
    }

    /// Marks the screen rectangle of the front-facing triangles dirty (the rasterizer
    /// writes the buffers directly).
    // The passes of a frame are kept out of line (here and below) so that a profile shows
    // where the frame's time goes; each runs once per frame.
    #[inline(never)]
    fn mark_faces_dirty(&self, canvas: &mut DotCanvas) {
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
    fn fill_depth(&mut self, canvas: &mut DotCanvas) {
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

    /// Draws the gathered lines with the depth test, in the order they were gathered.
    #[inline(never)]
    fn draw_segments(&mut self, canvas: &mut DotCanvas) {
        let mut runs = self.runs.take();
        if self.walk_ends.len() == self.segments.len() {
            // Walked once already, while marking the depth buffer's dots.
            let mut from = 0;
            for (s, &end) in self.segments.iter().zip(&self.walk_ends) {
                let dots = &self.walked[from..end as usize];
                draw_walked(canvas, runs.as_mut(), dots, s.bias, s.color);
                from = end as usize;
            }
            self.runs = runs;
            return;
        }
        for s in &self.segments {
            draw_line(
                canvas,
                runs.as_mut(),
                s.a,
                s.b,
                Some(s.bias),
                s.color,
                Layer::Mesh,
                false,
            );
        }
        self.runs = runs;
    }

    /// Rasterizes front-facing triangles with depth and Gouraud-interpolated Lambert shading,
    /// dithered when the canvas asks for it.
    #[inline(never)]
    fn fill_shaded(&self, scene: &Scene, canvas: &mut DotCanvas) {
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
    fn compute_shading(&mut self, scene: &Scene) {
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
    }

    /// Right-hand face normals, length twice the area, of the front-facing triangles (zero
    /// for the others), unless this frame already has them.
    #[inline(never)]
    fn compute_face_normals(&mut self, scene: &Scene) {
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
    fn compute_normals(&mut self, scene: &Scene) {
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

impl Renderer {
    /// The projected position of vertex `i`, NaN when missing.
    #[inline]
    fn vert(&self, i: u32) -> Vec3 {
        self.projected.get(i as usize).copied().unwrap_or(Vec3::NAN)
    }

    /// How far each vertex moved from rest, as a fraction of the full-colour displacement.
    #[inline(never)]
    fn compute_heat(&mut self, scene: &Scene) {
        self.vertex_heat.clear();
        if !scene.displacement {
            return;
        }
        let rest = scene.rest_positions();
        let (lo, hi) = finite_bounds(rest);
        let full = (scene.displacement_full * (hi - lo).length()).max(f32::EPSILON);
        self.vertex_heat.extend(
            scene
                .positions
                .iter()
                .zip(rest)
                .map(|(p, r)| (*p - *r).length() / full),
        );
    }

    fn edge_color(&self, scene: &Scene, e: &Edge) -> Rgb {
        let heat = |i: u32| self.vertex_heat.get(i as usize).copied().unwrap_or(0.0);
        let h = heat(e.a).max(heat(e.b));
        if self.vertex_heat.is_empty() || h.is_nan() || h < 0.02 {
            scene.palette.mesh
        } else {
            displacement_ramp(h)
        }
    }

    /// The depth bias for a line lying on the given triangles (the steeper, the larger).
    fn bias(&mut self, tris: [u32; 2]) -> f32 {
        let mut slope = 0.0f32;
        for t in tris {
            if t != NONE && self.facing.get(t as usize) == Some(&true) {
                slope = slope.max(self.slope(t as usize));
            }
        }
        BASE_BIAS + (SLOPE_BIAS * slope).min(MAX_SLOPE_BIAS)
    }

    /// The depth slope of front-facing triangle `t`, computed once per frame.
    #[inline]
    fn slope(&mut self, t: usize) -> f32 {
        let cached = self.slopes[t];
        // A slope is never NaN (`depth_slope` turns NaN into f32::MAX): NaN means not yet.
        if !cached.is_nan() {
            return cached;
        }
        let slope = depth_slope(self.triangles[t].map(|i| self.vert(i)));
        self.slopes[t] = slope;
        slope
    }

    /// Whether an edge belongs to the style's line set.
    fn wanted(&self, style: Style, e: &Edge, cos_crease: f32) -> bool {
        let f0 = self.facing[e.t0 as usize];
        let f1 = e.t1 != NONE && self.facing[e.t1 as usize];
        match style {
            Style::Wireframe => f0 || f1,
            Style::Shaded => false,
            Style::Lines => {
                if e.t1 == NONE {
                    return true;
                }
                if f0 != f1 {
                    return true;
                }
                f0 && f1 && {
                    let n0 = self.face_normals[e.t0 as usize];
                    let n1 = self.face_normals[e.t1 as usize];
                    n0.dot(n1) < cos_crease * (n0.length_squared() * n1.length_squared()).sqrt()
                }
            }
        }
    }

    /// Gathers the style's edges.
    #[inline(never)]
    fn collect_edges(&mut self, scene: &Scene, style: Style) {
        if style == Style::Lines {
            self.compute_face_normals(scene);
        }
        let cos_crease = scene.crease_degrees.to_radians().cos();
        for k in 0..self.edges.len() {
            let e = self.edges[k];
            if !self.wanted(style, &e, cos_crease) {
                continue;
            }
            let (a, b) = (self.vert(e.a), self.vert(e.b));
            let bias = self.bias([e.t0, e.t1]);
            let color = self.edge_color(scene, &e);
            self.segments.push(Segment { a, b, bias, color });
        }
    }

    /// Gathers lines where the surface turns away from the viewer by a given amount: iso-lines of
    /// (vertex normal . direction to the viewer), drawn across front-facing triangles. They
    /// outline the sides of the nose, the eye sockets and the lips, which are smooth (no
    /// crease) and not on the silhouette.
    #[inline(never)]
    fn collect_facing_contours(&mut self, scene: &Scene) {
        self.compute_normals(scene);
        self.vertex_facing.clear();
        let viewer = self.viewer_mesh;
        self.vertex_facing
            .extend(self.normals.iter().map(|n| n.dot(viewer)));
        let sign = self.sign(scene.orientation);
        let cos_crease = scene.crease_degrees.to_radians().cos();
        let color = scene.palette.contour;
        for t in 0..self.triangles.len() {
            if !self.facing[t] {
                continue;
            }
            let tri = self.triangles[t];
            let f = tri.map(|i| self.vertex_facing[i as usize]);
            // Most faces cross no level: test that first, smoothness only when one does.
            let mut smooth = None;
            for &level in scene.facing_contours {
                if !crosses(f, level) {
                    continue;
                }
                let Some((a, b)) = iso_crossing(tri.map(|i| self.vert(i)), f, level) else {
                    continue;
                };
                // Next to a crease the smoothed vertex normals say nothing about this face
                // (a box's corner normals would draw a line across a flat side): skip it.
                if !*smooth.get_or_insert_with(|| {
                    let face = self.face_normals[t].normalize_or_zero() * sign;
                    tri.iter()
                        .all(|&i| self.normals[i as usize].dot(face) >= cos_crease)
                }) {
                    break;
                }
                let bias = self.bias([t as u32, NONE]);
                self.segments.push(Segment { a, b, bias, color });
            }
        }
    }

    /// Gathers iso-depth contours across the front-facing triangles.
    #[inline(never)]
    fn collect_contours(&mut self, scene: &Scene) {
        let (zmin, zmax) = self
            .projected
            .iter()
            .filter(|p| p.is_finite())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.z), hi.max(p.z))
            });
        if zmin >= zmax {
            return;
        }
        let step = (zmax - zmin) / (scene.contours + 1) as f32;
        let color = scene.palette.contour;
        for t in 0..self.triangles.len() {
            if !self.facing[t] {
                continue;
            }
            let p = self.triangles[t].map(|i| self.vert(i));
            let lo = p[0].z.min(p[1].z).min(p[2].z);
            let hi = p[0].z.max(p[1].z).max(p[2].z);
            let first = (((lo - zmin) / step).floor() as i64 + 1).max(1);
            let last = (((hi - zmin) / step).ceil() as i64 - 1).min(scene.contours as i64);
            for k in first..=last {
                let level = zmin + step * k as f32;
                if let Some((a, b)) = level_crossing(p, level) {
                    let bias = self.bias([t as u32, NONE]);
                    self.segments.push(Segment { a, b, bias, color });
                }
            }
        }
    }

    /// The rest pose's borders and silhouette, faint, only where the canvas is still dark.
    #[inline(never)]
    fn draw_ghost(&mut self, scene: &Scene, proj: &Projection, canvas: &mut DotCanvas) {
        let n = scene.mesh.positions.len();
        project_all(proj, scene.rest_positions(), n, &mut self.rest_projected);
        let sign = self.sign(scene.orientation);
        classify(
            &self.triangles,
            &self.rest_projected,
            sign,
            &mut self.rest_facing,
        );
        let mut runs = self.runs.take();
        for e in &self.edges {
            let f0 = self.rest_facing[e.t0 as usize];
            let f1 = e.t1 != NONE && self.rest_facing[e.t1 as usize];
            let border = e.t1 == NONE && f0;
            if border || (e.t1 != NONE && f0 != f1) {
                let get = |i: u32| {
                    self.rest_projected
                        .get(i as usize)
                        .copied()
                        .unwrap_or(Vec3::NAN)
                };
                draw_line(
                    canvas,
                    runs.as_mut(),
                    get(e.a),
                    get(e.b),
                    None,
                    scene.palette.ghost,
                    Layer::Ghost,
                    true,
                );
            }
        }
        self.runs = runs;
    }

    #[inline(never)]
    fn draw_overlays(&mut self, overlays: &[Overlay], proj: &Projection, canvas: &mut DotCanvas) {
        let mut runs = self.runs.take();
        for overlay in overlays {
            let layer = if overlay.selected {
                Layer::Selected
            } else {
                Layer::Overlay
            };
            let mut line = |a: Vec3, b: Vec3| {
                draw_line(
                    canvas,
                    runs.as_mut(),
                    a,
                    b,
                    None,
                    overlay.color,
                    layer,
                    false,
                );
            };
            match overlay.shape {
                Shape::Segment { from, to } => {
                    line(proj.project(from), proj.project(to));
                    cross(proj.project(from), 1.5, &mut line);
                }
                Shape::Ellipse {
                    centre,
                    semi_x,
                    semi_y,
                } => {
                    const STEPS: usize = 48;
                    let at = |k: usize| {
                        let a = k as f32 / STEPS as f32 * std::f32::consts::TAU;
                        proj.project(centre + Vec3::new(semi_x * a.cos(), semi_y * a.sin(), 0.0))
                    };
                    for k in 0..STEPS {
                        line(at(k), at(k + 1));
                    }
                }
                Shape::Quad { corners } => {
                    for k in 0..4 {
                        line(proj.project(corners[k]), proj.project(corners[(k + 1) % 4]));
                    }
                }
                Shape::Point { at } => cross(proj.project(at), 2.0, &mut line),
            }
        }
        self.runs = runs;
    }
}

/// `c` scaled by `t` in 0..=1 (no rounding call: this runs per dot).
#[inline]
fn scale(c: Rgb, t: f32) -> Rgb {
    let t = t.clamp(0.0, 1.0);
    let f = |v: u8| (v as f32 * t + 0.5) as u8;
    Rgb(f(c.0), f(c.1), f(c.2))
}

/// Draws a small + centred on `p` (in dots).
fn cross(p: Vec3, r: f32, line: &mut impl FnMut(Vec3, Vec3)) {
    line(p - Vec3::new(r, 0.0, 0.0), p + Vec3::new(r, 0.0, 0.0));
    line(p - Vec3::new(0.0, r, 0.0), p + Vec3::new(0.0, r, 0.0));
}

/// Where the plane `z = level` cuts a triangle, as a segment (depth included).
fn level_crossing(p: [Vec3; 3], level: f32) -> Option<(Vec3, Vec3)> {
    iso_crossing(p, [p[0].z, p[1].z, p[2].z], level)
}

/// Whether [`iso_crossing`] finds a segment: the corners are not all on one side of
/// `level` (NaN counts as not below, as there). Cheap and branch-free, for the many faces
/// no line crosses.
#[inline]
fn crosses(f: [f32; 3], level: f32) -> bool {
    let below = (f[0] < level) as u8 + (f[1] < level) as u8 + (f[2] < level) as u8;
    below % 3 != 0
}

/// Where a per-corner scalar `f` crosses `level` inside a triangle, as a segment between
/// points interpolated on its edges.
fn iso_crossing(p: [Vec3; 3], f: [f32; 3], level: f32) -> Option<(Vec3, Vec3)> {
    let mut hits = [Vec3::ZERO; 2];
    let mut n = 0;
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        if (f[i] < level) != (f[j] < level) && n < 2 {
            let t = (level - f[i]) / (f[j] - f[i]);
            hits[n] = p[i] + (p[j] - p[i]) * t;
            n += 1;
        }
    }
    (n == 2).then_some((hits[0], hits[1]))
}

/// The sorted unique edges of `triangles` with the triangles on each side.
fn build_edges(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<Edge> {
    let mut half: Vec<(u32, u32, u32)> = Vec::with_capacity(triangles.len() * 3);
    for (t, tri) in triangles.iter().enumerate() {
        if tri.iter().any(|&i| i as usize >= vertex_count) {
            continue;
        }
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let (a, b) = (tri[i].min(tri[j]), tri[i].max(tri[j]));
            if a != b {
                half.push((a, b, t as u32));
            }
        }
    }
    half.sort_unstable();
    let mut edges: Vec<Edge> = Vec::with_capacity(half.len() / 2 + 1);
    for (a, b, t) in half {
        match edges.last_mut() {
            Some(e) if e.a == a && e.b == b => {
                // A third triangle on one edge (non-manifold) is ignored.
                if e.t1 == NONE {
                    e.t1 = t;
                }
            }
            _ => edges.push(Edge {
                a,
                b,
                t0: t,
                t1: NONE,
            }),
        }
    }
    edges
}

/// +1 when most of the surface's right-hand normals point away from its (area-weighted)
/// centroid, -1 when they point toward it. When that cannot decide (a flat or nearly flat
/// sheet), it falls back to the z convention: faces look toward +z.
fn detect_orientation(mesh: &Mesh) -> f32 {
    let tris: Vec<([Vec3; 3], Vec3)> = mesh
        .triangles
        .iter()
        .filter_map(|t| tri_positions(&mesh.positions, *t))
        .map(|[a, b, c]| ([a, b, c], (b - a).cross(c - a)))
        .filter(|(p, n)| n.is_finite() && p.iter().all(|v| v.is_finite()))
        .collect();
    let area: f32 = tris.iter().map(|(_, n)| n.length()).sum();
    if tris.is_empty() || area <= 0.0 {
        return 1.0;
    }
    let centroid = tris
        .iter()
        .map(|(p, n)| (p[0] + p[1] + p[2]) / 3.0 * n.length())
        .sum::<Vec3>()
        / area;
    let (mut outward, mut spread, mut toward_z) = (0.0f64, 0.0f64, 0.0f64);
    for ([a, b, c], n) in &tris {
        let offset = (*a + *b + *c) / 3.0 - centroid;
        outward += n.dot(offset) as f64;
        spread += (n.length() * offset.length()) as f64;
        toward_z += n.z as f64;
    }
    let decisive = if outward.abs() > 1e-3 * spread {
        outward
    } else {
        toward_z
    };
    if decisive < 0.0 {
        -1.0
    } else {
        1.0
    }
}

fn tri_positions(positions: &[Vec3], tri: [u32; 3]) -> Option<[Vec3; 3]> {
    let a = *positions.get(tri[0] as usize)?;
    let b = *positions.get(tri[1] as usize)?;
    let c = *positions.get(tri[2] as usize)?;
    Some([a, b, c])
}

/// Bounds of the finite points; zero when there are none.
pub(crate) fn finite_bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    let (lo, hi) = points.iter().filter(|p| p.is_finite()).fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if lo.is_finite() {
        (lo, hi)
    } else {
        (Vec3::ZERO, Vec3::ZERO)
    }
}

/// `Vec3::normalize_or_zero` on every vector, four at a time so that the square roots and
/// divisions run side by side (the same operations in the same order, so the same bits).
fn normalize_or_zero_all(v: &mut [Vec3]) {
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

/// Projects `count` vertices (missing ones become NaN, so they are skipped).
#[inline(never)]
fn project_all(proj: &Projection, positions: &[Vec3], count: usize, out: &mut Vec<Vec3>) {
    out.clear();
    if let Some(all) = positions.get(..count) {
        out.extend(all.iter().map(|&p| proj.project(p)));
        return;
    }
    out.extend((0..count).map(|i| positions.get(i).map_or(Vec3::NAN, |&p| proj.project(p))));
}

/// Decides which triangles face the viewer: signed screen area times the winding sign
/// (triangles with a missing or non-finite corner face nowhere).
#[inline(never)]
fn classify(triangles: &[[u32; 3]], projected: &[Vec3], sign: f32, facing: &mut Vec<bool>) {
    facing.clear();
    facing.extend(triangles.iter().map(|tri| {
        let Some([a, b, c]) = tri_positions(projected, *tri) else {
            return false;
        };
        let (ab, ac) = (b - a, c - a);
        let area = ab.x * ac.y - ab.y * ac.x;
        // Screen y runs down, so a triangle counter-clockwise as the viewer sees it has a
        // negative area here. NaN anywhere makes the comparison false.
        sign * area < 0.0 && (a.z + b.z + c.z).is_finite()
    }));
}

/// The depth slope of a projected triangle: dots of depth per dot across the screen.
#[inline(always)]
fn depth_slope([a, b, c]: [Vec3; 3]) -> f32 {
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
fn corner_weights([a, b, c]: [Vec3; 3], area: f32) -> [(f32, f32, f32); 2] {
    let inv = 1.0 / area;
    let weight = |p: Vec3, q: Vec3| {
        let kx = -(q.y - p.y) * inv;
        let ky = (q.x - p.x) * inv;
        (kx, ky, -(kx * p.x + ky * p.y))
    };
    [weight(b, c), weight(c, a)]
}

/// Rasterizes a screen triangle: calls `f(index, x, y, depth, attribute)` for every dot
/// whose centre lies inside it (either winding), with depth and attribute interpolated.
///
/// At terminal resolution most triangles cover a handful of dots, so the cost is in the
/// setup: one division, then the edge functions step across the bounding box.
#[inline]
fn raster_triangle(
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

/// One bit per dot of the canvas: the dots some depth-tested line will be drawn on.
#[derive(Debug, Clone, Default)]
struct DotMask {
    width: usize,
    height: usize,
    /// 64-bit words per row.
    stride: usize,
    words: Vec<u64>,
}

impl DotMask {
    /// Clears every dot of a `w` x `h` dot canvas.
    fn reset(&mut self, w: usize, h: usize) {
        (self.width, self.height) = (w, h);
        self.stride = w.div_ceil(64);
        self.words.clear();
        self.words.resize(self.stride * h, 0);
    }

    /// Sets the dot (x, y) (inside the canvas).
    #[inline]
    fn set(&mut self, x: usize, y: usize) {
        self.words[y * self.stride + x / 64] |= 1 << (x % 64);
    }

    /// Sets the dots the line a-b will visit on a `w` x `h` canvas.
    #[cfg(test)]
    fn mark_line(&mut self, a: Vec3, b: Vec3, w: usize, h: usize) {
        walk_line(a, b, w, h, |x, y, _| self.set(x, y));
    }

    /// One past the last set dot of row `y` within [x0, x1), if any is set (a non-empty
    /// range inside the canvas).
    #[inline]
    fn last_set(&self, y: usize, x0: usize, x1: usize) -> Option<usize> {
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
    fn any(&self, x0: usize, x1: usize, y0: usize, y1: usize) -> bool {
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
fn dot_span(p: Vec3, w: usize, h: usize) -> [u32; 4] {
    let (x0, x1) = span(p.x - 0.5, w);
    let (y0, y1) = span(p.y - 0.5, h);
    [x0, x1, y0, y1]
}

/// `(ceil_nonneg(v).min(limit), floor_end(v, limit))` from one conversion and no branch,
/// for a `limit` below 2^24 (exact as f32).
#[inline]
fn span(v: f32, limit: usize) -> (u32, u32) {
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
fn triangle_box(s: [[u32; 4]; 3]) -> [usize; 4] {
    [
        s[0][0].min(s[1][0]).min(s[2][0]) as usize,
        s[0][1].max(s[1][1]).max(s[2][1]) as usize,
        s[0][2].min(s[1][2]).min(s[2][2]) as usize,
        s[0][3].max(s[1][3]).max(s[2][3]) as usize,
    ]
}

/// Rasterizes a screen triangle into the depth buffer `depth` (`w` x `h`, row-major),
/// keeping the nearer depth at every dot whose centre lies inside it.
///
/// The same dots and depths as [`raster_triangle`] with a max-depth callback (the same
/// arithmetic in the same order), but without branches per dot: at terminal resolution a
/// triangle covers a handful of dots, and whether the next one is inside is a coin toss the
/// branch predictor loses.
// Always inlined: passed by value through the stack, its corners cost a stalled reload.
#[inline(always)]
fn depth_triangle(p: [Vec3; 3], w: usize, h: usize, depth: &mut [f32]) {
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
fn depth_triangle_in(
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

/// `ceil(v)` for the dot grid, clamped at 0 (no libm call: this runs per row).
#[inline]
fn ceil_nonneg(v: f32) -> usize {
    if v.is_nan() || v <= 0.0 {
        return 0;
    }
    // The cast saturates for huge values and infinity: do not step past it.
    let t = v as usize;
    if (t as f32) < v {
        t.saturating_add(1)
    } else {
        t
    }
}

/// `floor(v) + 1` clamped to `0..=limit`: the end of a range of dots (no libm call).
#[inline]
fn floor_end(v: f32, limit: usize) -> usize {
    if v.is_nan() {
        return 0;
    }
    // Saturating: the cast saturates at infinities, and one more step must not overflow.
    let t = v as i64;
    let floor = if (t as f32) > v {
        t.saturating_sub(1)
    } else {
        t
    };
    floor
        .saturating_add(1)
        .clamp(0, limit.min(i64::MAX as usize) as i64) as usize
}

/// Clips the segment a-b (x, y in dots, z depth) to the rectangle [0, w] x [0, h].
fn clip(a: Vec3, b: Vec3, w: f32, h: f32) -> Option<(Vec3, Vec3)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (p, q) in [(-d.x, a.x), (d.x, w - a.x), (-d.y, a.y), (d.y, h - a.y)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then(|| (a + d * t0, a + d * t1))
}

/// Calls `f(x, y, point)` for every dot step of the line a-b (x, y in dots, z depth),
/// clipped to a `w` x `h` canvas; nothing for a non-finite line.
///
/// The one stepping rule shared by drawing a line and by marking where lines will be drawn,
/// so both visit exactly the same dots.
#[inline]
fn walk_line(a: Vec3, b: Vec3, w: usize, h: usize, mut f: impl FnMut(usize, usize, Vec3)) {
    if !a.is_finite() || !b.is_finite() || w == 0 || h == 0 {
        return;
    }
    let (wf, hf) = (w as f32, h as f32);
    let inside = |p: Vec3| p.x >= 0.0 && p.x <= wf && p.y >= 0.0 && p.y <= hf;
    // Clipping a line that lies inside the canvas gives (a, a + (b - a)): skip its
    // divisions (most lines are a mesh edge a few dots long, well inside).
    let (a, b) = if inside(a) && inside(b) {
        (a, a + (b - a))
    } else {
        let Some(clipped) = clip(a, b, wf, hf) else {
            return;
        };
        clipped
    };
    let d = b - a;
    let steps = ceil_nonneg(d.x.abs().max(d.y.abs())).max(1);
    let inc = d / steps as f32;
    let mut p = a;
    for _ in 0..=steps {
        // Clipped coordinates are non-negative, so truncation is floor.
        let x = (p.x as usize).min(w - 1);
        let y = (p.y as usize).min(h - 1);
        f(x, y, p);
        p += inc;
    }
}

/// Draws a line in dot coordinates. With `bias`, each dot is depth-tested against the depth
/// buffer (visible when the line is no more than `bias` behind the surface there); without,
/// it is always drawn. `if_dark` only lights dots that are still dark. Visible pieces are
/// appended to `runs` when given.
#[allow(clippy::too_many_arguments)]
fn draw_line(
    canvas: &mut DotCanvas,
    runs: Option<&mut Vec<Run>>,
    a: Vec3,
    b: Vec3,
    bias: Option<f32>,
    color: Rgb,
    layer: Layer,
    if_dark: bool,
) {
    let (w, h) = (canvas.width(), canvas.height());
    let mut pieces = Pieces::new(runs, a, color, layer);
    walk_line(a, b, w, h, |x, y, p| {
        pieces.step(canvas.line_dot(x, y, p.z, bias, color, layer, if_dark), p);
    });
    pieces.finish();
}

/// [`draw_line`] over dot steps walked earlier (see [`Renderer::fill_depth`]), depth-tested
/// with `bias`, on the mesh layer.
fn draw_walked(
    canvas: &mut DotCanvas,
    runs: Option<&mut Vec<Run>>,
    dots: &[LineDot],
    bias: f32,
    color: Rgb,
) {
    let Some(first) = dots.first() else {
        return;
    };
    let mut pieces = Pieces::new(runs, first.p, color, Layer::Mesh);
    for d in dots {
        let visible = canvas.line_dot(
            d.x as usize,
            d.y as usize,
            d.p.z,
            Some(bias),
            color,
            Layer::Mesh,
            false,
        );
        pieces.step(visible, d.p);
    }
    pieces.finish();
}

/// One dot step of a line: the dot, and the point on the line there (depth included).
#[derive(Debug, Clone, Copy)]
struct LineDot {
    x: u32,
    y: u32,
    p: Vec3,
}

/// Follows which steps of a line were visible, to report its visible pieces as runs.
struct Pieces<'a> {
    out: Option<&'a mut Vec<Run>>,
    start: Option<Vec3>,
    /// The previous step; only read while a piece is open, which needs an earlier step.
    last: Vec3,
    color: Rgb,
    layer: Layer,
}

impl<'a> Pieces<'a> {
    fn new(out: Option<&'a mut Vec<Run>>, first: Vec3, color: Rgb, layer: Layer) -> Self {
        Pieces {
            out,
            start: None,
            last: first,
            color,
            layer,
        }
    }

    #[inline]
    fn step(&mut self, visible: bool, p: Vec3) {
        if visible {
            self.start.get_or_insert(p);
        } else if let Some(start) = self.start.take() {
            push_run(
                self.out.as_deref_mut(),
                start,
                self.last,
                self.color,
                self.layer,
            );
        }
        self.last = p;
    }

    fn finish(self) {
        if let Some(start) = self.start {
            push_run(self.out, start, self.last, self.color, self.layer);
        }
    }
}

fn push_run(runs: Option<&mut Vec<Run>>, from: Vec3, to: Vec3, color: Rgb, layer: Layer) {
    if let Some(runs) = runs {
        runs.push(Run {
            from: from.truncate(),
            to: to.truncate(),
            color,
            layer,
        });
    }
}

/// Draws `scene` into `canvas` with a renderer built for this call (convenient for one-off
/// images; an editor should keep a [`Renderer`]).
pub fn render(scene: &Scene, camera: &Camera, style: Style, canvas: &mut DotCanvas) {
    Renderer::new(scene.mesh).render(scene, camera, style, canvas);
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const W: usize = 40;
    const H: usize = 32;

    /// A corner a little beyond the canvas on every side, with depth.
    fn corner() -> impl Strategy<Value = Vec3> {
        (-6.0f32..46.0, -6.0f32..38.0, -50.0f32..50.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    /// Corners snapped to quarter dots, so that edges through dot centres and shared
    /// corners (the cases rounding decides) come up often.
    fn snapped_corner() -> impl Strategy<Value = Vec3> {
        (-24i32..184, -24i32..152, -50.0f32..50.0)
            .prop_map(|(x, y, z)| Vec3::new(x as f32 * 0.25, y as f32 * 0.25, z))
    }

    /// A corner far off the canvas, up to overflowing every integer conversion.
    fn far_corner() -> impl Strategy<Value = Vec3> {
        let far = prop_oneof![-1e12f32..1e12, Just(f32::INFINITY), Just(f32::NEG_INFINITY)];
        (far, -6.0f32..38.0, -50.0f32..50.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    fn any_corner() -> impl Strategy<Value = Vec3> {
        prop_oneof![4 => corner(), 4 => snapped_corner(), 1 => far_corner()]
    }

    /// A depth buffer with some dots already drawn.
    fn depth_buffer() -> impl Strategy<Value = Vec<f32>> {
        proptest::collection::vec(prop_oneof![Just(f32::NEG_INFINITY), -60.0f32..60.0], W * H)
    }

    /// The general rasterizer keeping the nearer depth, as the depth pass did before it had
    /// its own loop.
    fn reference_depth(p: [Vec3; 3], depth: &mut [f32]) {
        raster_triangle(p, [0.0; 3], W, H, |i, _, _, z, _| {
            if z > depth[i] {
                depth[i] = z;
            }
        });
    }

    /// The line stepping as it was before the inside-the-canvas shortcut: always clipped.
    fn reference_walk(a: Vec3, b: Vec3, w: usize, h: usize) -> Vec<(usize, usize, Vec3)> {
        let mut out = Vec::new();
        if !a.is_finite() || !b.is_finite() || w == 0 || h == 0 {
            return out;
        }
        let Some((a, b)) = clip(a, b, w as f32, h as f32) else {
            return out;
        };
        let d = b - a;
        let steps = ceil_nonneg(d.x.abs().max(d.y.abs())).max(1);
        let inc = d / steps as f32;
        let mut p = a;
        for _ in 0..=steps {
            out.push(((p.x as usize).min(w - 1), (p.y as usize).min(h - 1), p));
            p += inc;
        }
        out
    }

    fn bits(v: &[f32]) -> Vec<u32> {
        v.iter().map(|z| z.to_bits()).collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// The depth pass's own loop lights the same dots with the same depths, bit for
        /// bit, as the general rasterizer.
        #[test]
        fn depth_triangle_matches_the_general_rasterizer(
            a in any_corner(), b in any_corner(), c in any_corner(), start in depth_buffer(),
        ) {
            let mut expected = start.clone();
            reference_depth([a, b, c], &mut expected);
            let mut got = start;
            depth_triangle([a, b, c], W, H, &mut got);
            prop_assert_eq!(bits(&got), bits(&expected));
        }

        /// The branch-free span ends agree with the rasterizer's rounding helpers on any
        /// value, NaN and infinities included.
        #[test]
        fn span_ends_match_the_rounding_helpers(
            v in prop_oneof![
                4 => -50.0f32..500.0,
                2 => (-200i32..2000).prop_map(|k| k as f32 * 0.25),
                1 => proptest::num::f32::ANY,
            ],
            limit in 0usize..400,
        ) {
            let (start, end) = span(v, limit);
            prop_assert_eq!(start as usize, ceil_nonneg(v).min(limit));
            prop_assert_eq!(end as usize, floor_end(v, limit));
        }

        /// The box from the corners' spans is the box the rasterizer computes.
        #[test]
        fn the_box_from_vertex_spans_is_the_rasterizer_box(
            a in any_corner(), b in any_corner(), c in any_corner(),
        ) {
            let got = triangle_box([a, b, c].map(|p| dot_span(p, W, H)));
            let x0 = ceil_nonneg(a.x.min(b.x).min(c.x) - 0.5);
            let x1 = floor_end(a.x.max(b.x).max(c.x) - 0.5, W);
            let y0 = ceil_nonneg(a.y.min(b.y).min(c.y) - 0.5);
            let y1 = floor_end(a.y.max(b.y).max(c.y) - 0.5, H);
            // Starts are clamped to the canvas; a start past it is an empty range either way.
            prop_assert_eq!(got, [x0.min(W), x1, y0.min(H), y1]);
            let mut expected = vec![f32::NEG_INFINITY; W * H];
            depth_triangle([a, b, c], W, H, &mut expected);
            let mut via_spans = vec![f32::NEG_INFINITY; W * H];
            depth_triangle_in([a, b, c], got, W, None, &mut via_spans);
            prop_assert_eq!(bits(&via_spans), bits(&expected));
        }

        /// Hidden-line removal does not change: on every dot a line visits, the depth
        /// buffer filled only under the lines equals the one filled everywhere.
        #[test]
        fn the_depth_under_every_line_dot_is_the_full_depth(
            tris in proptest::collection::vec((any_corner(), any_corner(), any_corner()), 1..40),
            lines in proptest::collection::vec((any_corner(), any_corner()), 1..6),
        ) {
            let mut mask = DotMask::default();
            mask.reset(W, H);
            for &(a, b) in &lines {
                mask.mark_line(a, b, W, H);
            }
            let mut full = vec![f32::NEG_INFINITY; W * H];
            let mut culled = vec![f32::NEG_INFINITY; W * H];
            for &(a, b, c) in &tris {
                depth_triangle([a, b, c], W, H, &mut full);
                let [x0, x1, y0, y1] = triangle_box([a, b, c].map(|p| dot_span(p, W, H)));
                if x0 < x1 && y0 < y1 && mask.any(x0, x1, y0, y1) {
                    depth_triangle_in([a, b, c], [x0, x1, y0, y1], W, Some(&mask), &mut culled);
                }
            }
            for &(a, b) in &lines {
                let mut visited = 0;
                walk_line(a, b, W, H, |x, y, _| {
                    visited += 1;
                    assert_eq!(culled[y * W + x].to_bits(), full[y * W + x].to_bits());
                });
                prop_assert_eq!(visited, reference_walk(a, b, W, H).len());
            }
        }

        /// The mask's box test agrees with looking at every dot of the box.
        #[test]
        fn the_mask_box_test_matches_a_dot_by_dot_scan(
            dots in proptest::collection::vec((0usize..150, 0usize..9), 0..6),
            x0 in 0usize..150, dx in 1usize..80, y0 in 0usize..9, dy in 1usize..4,
        ) {
            let (w, h) = (150, 9);
            let mut mask = DotMask::default();
            mask.reset(w, h);
            for &(x, y) in &dots {
                let p = Vec3::new(x as f32 + 0.5, y as f32 + 0.5, 0.0);
                mask.mark_line(p, p, w, h);
            }
            let (x1, y1) = ((x0 + dx).min(w), (y0 + dy).min(h));
            let brute = dots.iter().any(|&(x, y)| (x0..x1).contains(&x) && (y0..y1).contains(&y));
            prop_assert_eq!(mask.any(x0, x1, y0, y1), brute);
            for y in y0..y1 {
                let last = dots
                    .iter()
                    .filter(|&&(x, dy)| dy == y && (x0..x1).contains(&x))
                    .map(|&(x, _)| x + 1)
                    .max();
                prop_assert_eq!(mask.last_set(y, x0, x1), last);
            }
        }

        /// Skipping the clip for lines inside the canvas visits the same dots at the same
        /// points as clipping.
        #[test]
        fn walking_a_line_matches_the_clipped_walk(a in any_corner(), b in any_corner()) {
            let mut got = Vec::new();
            walk_line(a, b, W, H, |x, y, p| got.push((x, y, p)));
            let expected = reference_walk(a, b, W, H);
            prop_assert_eq!(got.len(), expected.len());
            for (g, e) in got.iter().zip(&expected) {
                prop_assert_eq!((g.0, g.1), (e.0, e.1));
                prop_assert_eq!(g.2.to_array().map(f32::to_bits), e.2.to_array().map(f32::to_bits));
            }
        }

        /// Normalizing four at a time gives the same bits as one at a time.
        #[test]
        fn normalizing_in_fours_matches_glam(
            v in proptest::collection::vec(
                proptest::array::uniform3(prop_oneof![
                    4 => -10.0f32..10.0,
                    1 => Just(0.0f32),
                    1 => proptest::num::f32::ANY,
                    1 => -1e-20f32..1e-20,
                ]),
                0..11,
            ),
        ) {
            let v: Vec<Vec3> = v.into_iter().map(Vec3::from_array).collect();
            let mut got = v.clone();
            normalize_or_zero_all(&mut got);
            for (g, n) in got.iter().zip(&v) {
                let e = n.normalize_or_zero();
                prop_assert_eq!(g.to_array().map(f32::to_bits), e.to_array().map(f32::to_bits));
            }
        }

        /// Drawing steps walked ahead lights the same dots, in the same colours, and
        /// reports the same visible pieces as drawing the line itself.
        #[test]
        fn drawing_walked_steps_matches_drawing_the_line(
            tris in proptest::collection::vec((any_corner(), any_corner(), any_corner()), 0..12),
            lines in proptest::collection::vec((any_corner(), any_corner(), 0.0f32..4.0), 1..6),
        ) {
            let mut direct = DotCanvas::new(W, H);
            {
                let (depth, _, _, _) = direct.buffers_mut();
                for &(a, b, c) in &tris {
                    depth_triangle([a, b, c], W, H, depth);
                }
            }
            let mut walked = direct.clone();
            let color = Rgb(1, 2, 3);
            let (mut direct_runs, mut walked_runs) = (Vec::new(), Vec::new());
            for &(a, b, bias) in &lines {
                draw_line(&mut direct, Some(&mut direct_runs), a, b, Some(bias), color, Layer::Mesh, false);
                let mut dots = Vec::new();
                walk_line(a, b, W, H, |x, y, p| dots.push(LineDot { x: x as u32, y: y as u32, p }));
                draw_walked(&mut walked, Some(&mut walked_runs), &dots, bias, color);
            }
            prop_assert_eq!(direct_runs, walked_runs);
            for y in 0..H {
                for x in 0..W {
                    prop_assert_eq!(direct.color(x, y), walked.color(x, y));
                    prop_assert_eq!(direct.layer(x, y), walked.layer(x, y));
                }
            }
        }

        /// The cheap crossing test says yes exactly when the crossing finds a segment.
        #[test]
        fn crosses_agrees_with_iso_crossing(
            f in proptest::array::uniform3(prop_oneof![Just(f32::NAN), Just(0.5f32), -1.0f32..2.0]),
            level in prop_oneof![Just(0.5f32), -1.0f32..2.0],
        ) {
            let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
            prop_assert_eq!(crosses(f, level), iso_crossing(p, f, level).is_some());
        }
    }
}
