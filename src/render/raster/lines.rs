//! Walking and drawing lines: the gathered mesh lines (depth-tested), the rest-pose ghost
//! and the overlays, each drawn with a [`Pen`].

use glam::Vec3;

use super::grid::ceil_nonneg;
use super::project::{classify, project_all};
use super::{Renderer, Run, NONE};
use crate::render::camera::Projection;
use crate::render::canvas::{DotCanvas, Layer, Pen};
use crate::render::scene::{Overlay, Scene, Shape};

impl Renderer {
    /// Draws the gathered lines with the depth test, in the order they were gathered.
    #[inline(never)]
    pub(super) fn draw_segments(&mut self, canvas: &mut DotCanvas) {
        let mut runs = self.runs.take();
        if self.walk_ends.len() == self.segments.len() {
            // Walked once already, while marking the depth buffer's dots.
            let mut from = 0;
            for (s, &end) in self.segments.iter().zip(&self.walk_ends) {
                let dots = &self.walked[from..end as usize];
                draw_walked(canvas, runs.as_mut(), dots, Pen::mesh(s.color, s.bias));
                from = end as usize;
            }
            self.runs = runs;
            return;
        }
        for s in &self.segments {
            draw_line(canvas, runs.as_mut(), s.a, s.b, Pen::mesh(s.color, s.bias));
        }
        self.runs = runs;
    }

    /// The rest pose's borders and silhouette, faint, only where the canvas is still dark.
    #[inline(never)]
    pub(super) fn draw_ghost(&mut self, scene: &Scene, proj: &Projection, canvas: &mut DotCanvas) {
        let n = scene.mesh.positions.len();
        project_all(proj, scene.rest_positions(), n, &mut self.rest_projected);
        let sign = self.sign(scene.orientation);
        classify(
            &self.triangles,
            &self.rest_projected,
            sign,
            &mut self.rest_facing,
        );
        let pen = Pen::faint(scene.palette.ghost, Layer::Ghost);
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
                draw_line(canvas, runs.as_mut(), get(e.a), get(e.b), pen);
            }
        }
        self.runs = runs;
    }

    /// The overlays (muscles, pivot), on top of everything.
    #[inline(never)]
    pub(super) fn draw_overlays(
        &mut self,
        overlays: &[Overlay],
        proj: &Projection,
        canvas: &mut DotCanvas,
    ) {
        let mut runs = self.runs.take();
        for overlay in overlays {
            let layer = if overlay.selected {
                Layer::Selected
            } else {
                Layer::Overlay
            };
            let pen = Pen::on_top(overlay.color, layer);
            let mut line = |a: Vec3, b: Vec3| draw_line(canvas, runs.as_mut(), a, b, pen);
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
                        proj.project(centre + semi_x * a.cos() + semi_y * a.sin())
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

/// Draws a small + centred on `p` (in dots).
fn cross(p: Vec3, r: f32, line: &mut impl FnMut(Vec3, Vec3)) {
    line(p - Vec3::new(r, 0.0, 0.0), p + Vec3::new(r, 0.0, 0.0));
    line(p - Vec3::new(0.0, r, 0.0), p + Vec3::new(0.0, r, 0.0));
}

/// Clips the segment a-b (x, y in dots, z depth) to the rectangle [0, w] x [0, h].
pub(super) fn clip(a: Vec3, b: Vec3, w: f32, h: f32) -> Option<(Vec3, Vec3)> {
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
pub(super) fn walk_line(
    a: Vec3,
    b: Vec3,
    w: usize,
    h: usize,
    mut f: impl FnMut(usize, usize, Vec3),
) {
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

/// Draws a line in dot coordinates with `pen`. Visible pieces are appended to `runs` when
/// given.
pub(super) fn draw_line(
    canvas: &mut DotCanvas,
    runs: Option<&mut Vec<Run>>,
    a: Vec3,
    b: Vec3,
    pen: Pen,
) {
    let (w, h) = (canvas.width(), canvas.height());
    let mut pieces = Pieces::new(runs, a, pen);
    walk_line(a, b, w, h, |x, y, p| {
        pieces.step(canvas.line_dot(x, y, p.z, pen), p);
    });
    pieces.finish();
}

/// [`draw_line`] over dot steps walked earlier (see [`Renderer::fill_depth`]).
pub(super) fn draw_walked(
    canvas: &mut DotCanvas,
    runs: Option<&mut Vec<Run>>,
    dots: &[LineDot],
    pen: Pen,
) {
    let Some(first) = dots.first() else {
        return;
    };
    let mut pieces = Pieces::new(runs, first.p, pen);
    for d in dots {
        let visible = canvas.line_dot(d.x as usize, d.y as usize, d.p.z, pen);
        pieces.step(visible, d.p);
    }
    pieces.finish();
}

/// One dot step of a line: the dot, and the point on the line there (depth included).
#[derive(Debug, Clone, Copy)]
pub(super) struct LineDot {
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) p: Vec3,
}

/// Follows which steps of a line were visible, to report its visible pieces as runs.
struct Pieces<'a> {
    out: Option<&'a mut Vec<Run>>,
    start: Option<Vec3>,
    /// The previous step; only read while a piece is open, which needs an earlier step.
    last: Vec3,
    pen: Pen,
}

impl<'a> Pieces<'a> {
    fn new(out: Option<&'a mut Vec<Run>>, first: Vec3, pen: Pen) -> Self {
        Pieces {
            out,
            start: None,
            last: first,
            pen,
        }
    }

    #[inline]
    fn step(&mut self, visible: bool, p: Vec3) {
        if visible {
            self.start.get_or_insert(p);
        } else if let Some(start) = self.start.take() {
            push_run(self.out.as_deref_mut(), start, self.last, self.pen);
        }
        self.last = p;
    }

    fn finish(self) {
        if let Some(start) = self.start {
            push_run(self.out, start, self.last, self.pen);
        }
    }
}

fn push_run(runs: Option<&mut Vec<Run>>, from: Vec3, to: Vec3, pen: Pen) {
    if let Some(runs) = runs {
        runs.push(Run {
            from: from.truncate(),
            to: to.truncate(),
            color: pen.color,
            layer: pen.layer,
        });
    }
}
