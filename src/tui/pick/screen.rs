//! The mesh as the picker's viewport shows it: where each vertex lands in dots (the same
//! projection the renderer uses for a canvas of this size), which vertices can be seen, and
//! the nearest visible vertex to a point of the screen.
//!
//! A vertex is visible when one of its triangles faces the viewer and no surface lies in
//! front of it: the front faces are rasterized into a depth buffer at dot resolution (by the renderer's
//! own depth rasterizer, [`crate::render::raster::depth_triangle`]), and a
//! vertex passes when it is no farther than that buffer's nearest surface at its dot, less a
//! tolerance that grows with the slope of its own triangles there (a dot's centre is not the
//! vertex).

use glam::{Vec2, Vec3};

use crate::model::Mesh;
use crate::render::raster::depth_triangle;
use crate::render::{Camera, CellMode, Projection};

/// The largest depth tolerance, in dot heights.
const MAX_TOLERANCE: f32 = 6.0;

/// One view of a mesh on a canvas of dots.
#[derive(Debug, Clone)]
pub struct Screen {
    /// The projection (the renderer's, for the same canvas).
    pub projection: Projection,
    /// Canvas size in dots.
    pub width: usize,
    /// Canvas height in dots.
    pub height: usize,
    /// Dots per cell (columns, rows).
    pub cell: (usize, usize),
    /// A dot's width over its height.
    pub aspect: f32,
    /// Each vertex in dots (x right, y down) with its depth (larger is nearer).
    pub projected: Vec<Vec3>,
    /// Whether each vertex can be seen (and so picked).
    pub visible: Vec<bool>,
}

impl Screen {
    /// The mesh seen by `camera` on `cols` x `rows` cells of `mode`, the view fitted to the
    /// points `frame` (the head of a body, or the whole mesh). `sign` is the mesh's
    /// winding (+1 when right-hand normals point out of the head, as
    /// [`crate::render::Renderer::detected_orientation`] finds).
    pub fn new(
        mesh: &Mesh,
        frame: &[Vec3],
        sign: f32,
        camera: &Camera,
        (cols, rows): (usize, usize),
        mode: CellMode,
    ) -> Screen {
        let cell = mode.dots_per_cell();
        let (width, height) = (cols * cell.0, rows * cell.1);
        let aspect = mode.dot_aspect(0.5);
        let projection = camera.fit_points(frame, width, height, aspect);
        let projected: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|&p| projection.project(p))
            .collect();
        let visible = visibility(mesh, &projected, sign, width, height);
        Screen {
            projection,
            width,
            height,
            cell,
            aspect,
            projected,
            visible,
        }
    }

    /// Whether a point (in dots) lies on the canvas.
    pub fn contains(&self, at: Vec2) -> bool {
        at.x >= 0.0 && at.y >= 0.0 && at.x < self.width as f32 && at.y < self.height as f32
    }

    /// The visible vertex nearest `at` (in dots), measured on the screen (a dot is `aspect`
    /// as wide as it is tall); ties go to the nearer vertex, then the lower number.
    pub fn nearest_visible(&self, at: Vec2) -> Option<u32> {
        let mut best: Option<(f32, f32, u32)> = None;
        for (i, p) in self.projected.iter().enumerate() {
            if !self.visible[i] {
                continue;
            }
            let d = Vec2::new((p.x - at.x) * self.aspect, p.y - at.y).length_squared();
            let better = match best {
                None => true,
                Some((bd, bz, _)) => d < bd || (d == bd && p.z > bz),
            };
            if better {
                best = Some((d, p.z, i as u32));
            }
        }
        best.map(|(_, _, i)| i)
    }

    /// Where vertex `v` lands, in dots (`None` for a vertex the mesh lacks).
    pub fn dot_of(&self, v: u32) -> Option<Vec2> {
        self.projected
            .get(v as usize)
            .map(|p| p.truncate())
            .filter(|p| p.is_finite())
    }

    /// The cell (column, row) of a point in dots, when it lies on the canvas.
    pub fn cell_of(&self, at: Vec2) -> Option<(u16, u16)> {
        self.contains(at).then(|| {
            (
                (at.x as usize / self.cell.0) as u16,
                (at.y as usize / self.cell.1) as u16,
            )
        })
    }

    /// The centre of a cell, in dots.
    pub fn cell_centre(&self, col: u16, row: u16) -> Vec2 {
        Vec2::new(
            (f32::from(col) + 0.5) * self.cell.0 as f32,
            (f32::from(row) + 0.5) * self.cell.1 as f32,
        )
    }
}

/// Which vertices can be seen: on a front face and not behind another surface.
fn visibility(
    mesh: &Mesh,
    projected: &[Vec3],
    sign: f32,
    width: usize,
    height: usize,
) -> Vec<bool> {
    let n = projected.len();
    let mut depth = vec![f32::NEG_INFINITY; width * height];
    // Per vertex: whether a front face uses it, and the steepest such face's depth slope.
    let mut slope = vec![f32::NAN; n];
    // Helper geometry is not drawn, so it hides nothing and shows nothing to pick.
    let drawn = crate::fit::parts::drawn_triangles(mesh);
    for tri in drawn.as_deref().unwrap_or(&mesh.triangles) {
        let Some(p) = corners(projected, *tri) else {
            continue;
        };
        let (ab, ac) = (p[1] - p[0], p[2] - p[0]);
        let area = ab.x * ac.y - ab.y * ac.x;
        // Screen y runs down: counter-clockwise as seen has a negative area here.
        if sign * area >= 0.0 || area.is_nan() {
            continue;
        }
        // The depth plane z = a x + b y + c.
        let a = (ab.z * ac.y - ac.z * ab.y) / area;
        let b = (ac.z * ab.x - ab.z * ac.x) / area;
        let steep = (a * a + b * b).sqrt();
        for &v in tri {
            let s = &mut slope[v as usize];
            *s = if s.is_nan() { steep } else { s.max(steep) };
        }
        depth_triangle(p, width, height, &mut depth);
    }
    (0..n)
        .map(|i| {
            let p = projected[i];
            if slope[i].is_nan() || !(p.x >= 0.0 && p.y >= 0.0) {
                return false;
            }
            let (x, y) = (p.x as usize, p.y as usize);
            if x >= width || y >= height {
                return false;
            }
            let tolerance = (0.5 + 1.5 * slope[i]).min(MAX_TOLERANCE);
            p.z >= depth[y * width + x] - tolerance
        })
        .collect()
}

fn corners(projected: &[Vec3], tri: [u32; 3]) -> Option<[Vec3; 3]> {
    let p = tri.map(|i| projected.get(i as usize).copied().unwrap_or(Vec3::NAN));
    p.iter().all(|v| v.is_finite()).then_some(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two squares facing the viewer (+z), one in front of the other, half overlapping.
    fn two_squares() -> Mesh {
        let square = |x: f32, z: f32| {
            [
                Vec3::new(x, 0.0, z),
                Vec3::new(x + 2.0, 0.0, z),
                Vec3::new(x + 2.0, 2.0, z),
                Vec3::new(x, 2.0, z),
            ]
        };
        let mut positions = square(0.0, 0.0).to_vec();
        positions.extend(square(1.0, 1.0));
        // A point in the middle of the back square, under the front one.
        positions.push(Vec3::new(1.5, 1.0, 0.0));
        let triangles = vec![
            [0, 1, 8],
            [1, 2, 8],
            [2, 3, 8],
            [3, 0, 8],
            [4, 5, 6],
            [4, 6, 7],
        ];
        Mesh::new(positions, triangles).unwrap()
    }

    /// The whole mesh seen by `camera` on 40 x 20 braille cells.
    fn whole(mesh: &Mesh, camera: &Camera) -> Screen {
        Screen::new(
            mesh,
            &mesh.positions,
            1.0,
            camera,
            (40, 20),
            CellMode::Braille,
        )
    }

    #[test]
    fn hidden_and_back_facing_vertices_are_not_visible() {
        let mesh = two_squares();
        let screen = whole(&mesh, &Camera::front());
        assert!(
            screen.visible[0] && screen.visible[3],
            "back square's free corners"
        );
        assert!(!screen.visible[8], "under the front square");
        assert!(screen.visible[4] && screen.visible[6], "front square");
        // From behind, every face turns away.
        let back = Camera {
            yaw: std::f32::consts::PI,
            ..Camera::front()
        };
        let screen = whole(&mesh, &back);
        assert!(screen.visible.iter().all(|v| !v));
        assert_eq!(screen.nearest_visible(Vec2::new(10.0, 10.0)), None);
    }

    #[test]
    fn the_nearest_visible_vertex_is_found_on_the_screen() {
        let mesh = two_squares();
        let screen = whole(&mesh, &Camera::front());
        // Straight onto the hidden vertex: the nearest visible one is taken instead.
        let hidden = screen.dot_of(8).unwrap();
        let got = screen.nearest_visible(hidden).unwrap();
        assert_ne!(got, 8);
        assert!(screen.visible[got as usize]);
        let corner = screen.dot_of(0).unwrap();
        assert_eq!(
            screen.nearest_visible(corner + Vec2::new(1.0, -1.0)),
            Some(0)
        );
        let (col, row) = screen.cell_of(corner - Vec2::new(0.01, 0.01)).unwrap();
        assert!(screen.cell_centre(col, row).distance(corner) < 3.0);
    }
}
