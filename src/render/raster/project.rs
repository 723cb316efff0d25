//! Projection: the pose in dot coordinates, which triangles face the viewer, and the
//! mesh's winding.

use glam::Vec3;

use super::fill::normalize_or_zero_all;
use super::Renderer;
use crate::model::Mesh;
use crate::render::camera::Projection;

/// +1 when most of the surface's right-hand normals point away from its (area-weighted)
/// centroid, -1 when they point toward it. When that cannot decide (a flat or nearly flat
/// sheet), it falls back to the z convention: faces look toward +z.
pub(super) fn detect_orientation(mesh: &Mesh) -> f32 {
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

pub(super) fn tri_positions(positions: &[Vec3], tri: [u32; 3]) -> Option<[Vec3; 3]> {
    let a = *positions.get(tri[0] as usize)?;
    let b = *positions.get(tri[1] as usize)?;
    let c = *positions.get(tri[2] as usize)?;
    Some([a, b, c])
}

/// Projects `count` vertices (missing ones become NaN, so they are skipped).
#[inline(never)]
pub(super) fn project_all(
    proj: &Projection,
    positions: &[Vec3],
    count: usize,
    out: &mut Vec<Vec3>,
) {
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
pub(super) fn classify(
    triangles: &[[u32; 3]],
    projected: &[Vec3],
    sign: f32,
    facing: &mut Vec<bool>,
) {
    facing.clear();
    facing.extend(
        triangles
            .iter()
            .map(|tri| faces_viewer(projected, *tri, sign)),
    );
}

/// Whether one triangle faces the viewer (see [`classify`]).
#[inline(always)]
fn faces_viewer(projected: &[Vec3], tri: [u32; 3], sign: f32) -> bool {
    let Some([a, b, c]) = tri_positions(projected, tri) else {
        return false;
    };
    let (ab, ac) = (b - a, c - a);
    let area = ab.x * ac.y - ab.y * ac.x;
    // Screen y runs down, so a triangle counter-clockwise as the viewer sees it has a
    // negative area here. NaN anywhere makes the comparison false.
    sign * area < 0.0 && (a.z + b.z + c.z).is_finite()
}

/// What a frame needs besides facing, computed in the same pass over the triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Default)]
pub(super) enum Normals {
    /// Nothing (wireframe).
    #[default]
    None,
    /// The front faces' normals (the crease test of `lines`).
    Faces,
    /// Those and the oriented unit vertex normals (shading, facing contours).
    Vertices,
}

impl Renderer {
    /// Decides facing (as [`classify`]) and computes what `want` asks of the normals in
    /// one pass over the triangles: each triangle's indices and corners are read once
    /// instead of once per pass. The same values, bit for bit, as classifying first and
    /// then calling `compute_face_normals` and `compute_normals` (the same arithmetic, the
    /// vertex sums added in the same triangle order).
    #[inline(never)]
    pub(super) fn classify_with_normals(&mut self, positions: &[Vec3], sign: f32, want: Normals) {
        self.normals_ready = want;
        if want == Normals::None {
            classify(&self.triangles, &self.projected, sign, &mut self.facing);
            return;
        }
        let vertices = want == Normals::Vertices;
        self.facing.clear();
        self.face_normals.clear();
        if vertices {
            self.normals.clear();
            self.normals.resize(self.projected.len(), Vec3::ZERO);
        }
        for &tri in &self.triangles {
            let facing = faces_viewer(&self.projected, tri, sign);
            self.facing.push(facing);
            if !facing {
                self.face_normals.push(Vec3::ZERO);
                continue;
            }
            // A facing triangle's corners were projected from the pose, so they are there.
            let [a, b, c] = tri.map(|i| positions[i as usize]);
            let normal = (b - a).cross(c - a);
            self.face_normals.push(normal);
            if vertices {
                let oriented = normal * sign;
                for i in tri {
                    self.normals[i as usize] += oriented;
                }
            }
        }
        if vertices {
            normalize_or_zero_all(&mut self.normals);
        }
    }
}
