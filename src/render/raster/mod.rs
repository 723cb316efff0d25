//! The rasterizer: back-face culling, a depth buffer at dot resolution, depth-tested lines,
//! feature-line extraction, shading and overlays.
//!
//! A frame runs in passes, one module each, all working on the [`Renderer`]'s buffers:
//!
//! * `project`: project the pose, decide which triangles face the viewer, detect the
//!   mesh's winding;
//! * `features`: gather the style's lines (silhouettes, borders, creases, contours) with
//!   their colour and depth bias;
//! * `depth`: fill the depth buffer under the gathered lines only;
//! * `lines`: walk and draw lines, each with a pen (colour, layer, depth bias, and whether
//!   it covers lit dots): the gathered mesh lines depth-tested, then the rest-pose ghost
//!   and the overlays;
//! * `fill`: vertex normals, Lambert shading and the dithered fill of the shaded style.
//!
//! Each pass runs once per frame and is kept out of line (`#[inline(never)]`) so that a
//! profile shows where the frame's time goes.

mod brow;
mod depth;
mod features;
mod fill;
mod grid;
mod iris;
mod lines;
mod pieces;
mod project;

pub use depth::depth_triangle;

use glam::{Vec2, Vec3};

use super::camera::{Camera, Projection};
use super::canvas::{DotCanvas, Layer, Rgb};
use super::scene::{Orientation, Scene, Style};
pub(crate) use crate::model::mesh::bounds_of as finite_bounds_of;
use crate::model::Mesh;
use depth::DotMask;
use features::build_edges;
use fill::LIGHT;
use lines::LineDot;
use project::{detect_orientation, project_all, Normals};

/// What a camera fit depends on besides the rest pose: the camera's yaw, pitch, zoom and
/// pan and the dot aspect (as bits), and the canvas size.
type FitKey = ([u32; 15], usize, usize);

/// No second triangle on this edge (a mesh border).
const NONE: u32 = u32::MAX;

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

/// How [`Renderer::lit_triangles`] draws a triangle.
#[derive(Debug, Clone, Copy)]
enum Piece {
    /// Flat, as lit.
    Whole,
    /// The iris triangle of this index, cut into the eyeball, the iris and the pupil.
    Iris(usize),
    /// The brow triangle of this index, cut along its band's edge.
    Brow(usize),
}

/// Renders scenes of one mesh, keeping its edge topology and scratch buffers between frames.
///
/// Build one per mesh and call [`Renderer::render`] every frame; nothing is allocated once
/// the buffers have grown to the mesh's size. A scene whose mesh has different triangles
/// makes the renderer rebuild its topology first.
#[derive(Debug, Clone, Default)]
pub struct Renderer {
    triangles: Vec<[u32; 3]>,
    /// The mesh's own triangles when `triangles` leaves helper geometry out (empty when it
    /// draws them all), to tell a new mesh from the same one.
    source: Vec<[u32; 3]>,
    edges: Vec<Edge>,
    /// +1 when right-hand normals point outward, -1 when inward (auto-detected at build).
    auto_sign: f32,
    projected: Vec<Vec3>,
    facing: Vec<bool>,
    normals: Vec<Vec3>,
    vertex_shade: Vec<f32>,
    /// Per vertex, how dark its material is in the shaded style (empty: all 1.0).
    vertex_tone: Vec<f32>,
    /// The triangles a brow band's edge crosses, in triangle order (empty when the brows,
    /// if any, are toned per vertex).
    brows: Vec<brow::BrowTriangle>,
    /// Per vertex, whether it lies on an eye drawn without an iris (empty: none).
    blank_eyes: Vec<bool>,
    /// The triangles of blank eyes that reach an iris's disc (see `iris`).
    irises: Vec<iris::IrisTriangle>,
    /// The irises `irises` was found for (`None`: not yet, since the last rebuild).
    painted_irises: Option<Vec<crate::render::framing::Iris>>,
    vertex_heat: Vec<f32>,
    rest_projected: Vec<Vec3>,
    rest_facing: Vec<bool>,
    light_mesh: Vec3,
    viewer_mesh: Vec3,
    vertex_facing: Vec<f32>,
    face_normals: Vec<Vec3>,
    /// Which normals this frame has computed so far (`face_normals`, `normals`).
    normals_ready: Normals,
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
    /// Per dot, the shade (and displacement) of the nearest triangle the shaded style drew
    /// there; read only where the depth buffer is finite.
    dot_shade: Vec<f32>,
    dot_heat: Vec<f32>,
    /// The last camera fit: the camera and dot aspect (their bits), the canvas size, and
    /// the projection it gave; and the rest pose it fitted (copied).
    fit: Option<(FitKey, Projection)>,
    fit_rest: Vec<Vec3>,
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
        self.source.clear();
        // Helper geometry (proxies, joint markers) is never drawn: one rule, in fit::parts.
        match crate::fit::parts::drawn_triangles(mesh) {
            Some(drawn) => {
                self.triangles = drawn;
                self.source.extend_from_slice(&mesh.triangles);
            }
            None => self.triangles.extend_from_slice(&mesh.triangles),
        }
        self.edges = build_edges(&self.triangles, mesh.positions.len());
        self.auto_sign = detect_orientation(mesh);
        self.blank_eyes = iris::blank_eyes(mesh);
        self.irises.clear();
        self.painted_irises = None;
        self.compute_tones(mesh);
    }

    /// Per-vertex tones of the materials, the brows' bands, and the eyes: a blank eye that
    /// has an iris painted on it is a lit sclera.
    fn compute_tones(&mut self, mesh: &Mesh) {
        let brows = brow::brow_triangles(mesh, &self.triangles, self.auto_sign);
        fill::vertex_tones(mesh, brows.is_some(), &mut self.vertex_tone);
        self.brows = brows.unwrap_or_default();
        let n = mesh.positions.len();
        brow::tone_corners(&self.brows, &self.triangles, n, &mut self.vertex_tone);
        // Only the triangles a band's edge crosses need their dots toned one by one.
        self.brows.retain(|b| b.corners_in_band() != [true; 3]);
        if !self.irises.is_empty() && !self.vertex_tone.is_empty() {
            for (tone, _) in self
                .vertex_tone
                .iter_mut()
                .zip(&self.blank_eyes)
                .filter(|(_, &eye)| eye)
            {
                *tone = 1.0;
            }
        }
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
            .prepare(
                scene,
                camera,
                (width, height, dot_aspect),
                Normals::Vertices,
            )
            .is_none()
        {
            return Vec::new();
        }
        self.paint_irises(scene.mesh, scene.irises);
        self.compute_shading(scene);
        // Which iris or brow triangle each triangle is, if any (toned per dot when rastered,
        // cut into pieces here).
        let mut piece_of = vec![Piece::Whole; self.triangles.len()];
        for (k, b) in self.brows.iter().enumerate() {
            piece_of[b.triangle as usize] = Piece::Brow(k);
        }
        for (k, i) in self.irises.iter().enumerate() {
            piece_of[i.triangle as usize] = Piece::Iris(k);
        }
        let mut out = Vec::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            if !self.facing[t] {
                continue;
            }
            let p = tri.map(|i| self.projected[i as usize]);
            let corners = p.map(|v| v.truncate());
            let depth = (p[0].z + p[1].z + p[2].z) / 3.0;
            match piece_of[t] {
                Piece::Iris(k) => {
                    out.extend(self.iris_pieces(k, corners, depth));
                    continue;
                }
                Piece::Brow(k) => {
                    out.extend(self.brow_pieces(k, corners, depth));
                    continue;
                }
                Piece::Whole => {}
            }
            let shade = tri
                .iter()
                .map(|&i| self.vertex_shade[i as usize])
                .sum::<f32>()
                / 3.0;
            out.push(LitTriangle {
                corners,
                depth,
                shade,
            });
        }
        // Stable: the pieces cut from a triangle stay over it.
        out.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        out
    }

    /// Projects the scene, decides facing and computes the normals `want` asks for;
    /// `None` when there is nothing to draw on a canvas of `(width, height, dot_aspect)`.
    #[inline(never)]
    fn prepare(
        &mut self,
        scene: &Scene,
        camera: &Camera,
        (width, height, dot_aspect): (usize, usize, f32),
        want: Normals,
    ) -> Option<Projection> {
        let drawn_from = if self.source.is_empty() {
            &self.triangles
        } else {
            &self.source
        };
        if scene.mesh.triangles != *drawn_from {
            self.rebuild(scene.mesh);
        }
        if width == 0 || height == 0 {
            return None;
        }
        let proj = self.fit(camera, scene.framed_points(), width, height, dot_aspect);
        let sign = self.sign(scene.orientation);
        self.light_mesh = proj.view.transpose() * LIGHT.normalize();
        self.viewer_mesh = proj.view.transpose() * Vec3::Z;
        project_all(
            &proj,
            scene.positions,
            scene.mesh.positions.len(),
            &mut self.projected,
        );
        // Face and vertex normals follow the pose and the facing of this frame.
        self.classify_with_normals(scene.positions, sign, want);
        Some(proj)
    }

    /// `camera.fit_points(rest, ...)`, reused from the last frame when the camera, the
    /// canvas and the rest pose (bit for bit) are the same: the editor redraws the same
    /// view of the same rest pose for every edit.
    fn fit(
        &mut self,
        camera: &Camera,
        rest: &[Vec3],
        width: usize,
        height: usize,
        dot_aspect: f32,
    ) -> Projection {
        // Every field, so that a new one cannot be forgotten here.
        let Camera {
            yaw,
            pitch,
            zoom,
            pan,
            basis,
        } = *camera;
        let b = basis.to_cols_array();
        let key: FitKey = (
            [
                yaw, pitch, zoom, pan.x, pan.y, dot_aspect, b[0], b[1], b[2], b[3], b[4], b[5],
                b[6], b[7], b[8],
            ]
            .map(f32::to_bits),
            width,
            height,
        );
        let bits = |v: &Vec3| v.to_array().map(f32::to_bits);
        if let Some((last, proj)) = self.fit {
            if last == key
                && rest.len() == self.fit_rest.len()
                && rest
                    .iter()
                    .zip(&self.fit_rest)
                    .all(|(p, q)| bits(p) == bits(q))
            {
                return proj;
            }
        }
        let proj = camera.fit_points(rest, width, height, dot_aspect);
        self.fit = Some((key, proj));
        self.fit_rest.clear();
        self.fit_rest.extend_from_slice(rest);
        proj
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
        let want = match style {
            Style::Shaded => Normals::Vertices,
            Style::Lines if !scene.facing_contours.is_empty() => Normals::Vertices,
            Style::Lines => Normals::Faces,
            Style::Wireframe => Normals::None,
        };
        let Some(proj) = self.prepare(scene, camera, (w, h, aspect), want) else {
            return;
        };
        if style == Style::Shaded {
            self.paint_irises(scene.mesh, scene.irises);
            self.compute_shading(scene);
            self.compute_heat(scene);
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

    /// The projected position of vertex `i`, NaN when missing.
    #[inline]
    fn vert(&self, i: u32) -> Vec3 {
        self.projected.get(i as usize).copied().unwrap_or(Vec3::NAN)
    }
}

/// Draws `scene` into `canvas` with a renderer built for this call (convenient for one-off
/// images; an editor should keep a [`Renderer`]).
pub fn render(scene: &Scene, camera: &Camera, style: Style, canvas: &mut DotCanvas) {
    Renderer::new(scene.mesh).render(scene, camera, style, canvas);
}

#[cfg(test)]
mod tests;
