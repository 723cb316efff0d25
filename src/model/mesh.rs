//! Triangle meshes: rest positions, triangles, derived edges and normals, named vertex groups.

use std::collections::BTreeMap;

use glam::Vec3;
use thiserror::Error;

/// Why a set of positions and triangles is not a usable mesh.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    /// The mesh has no triangles at all.
    #[error("the mesh has no faces")]
    NoFaces,
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "triangle {triangle} refers to vertex {index}, but the mesh has only {count} vertices"
    )]
    IndexOutOfRange {
        /// Triangle number (0-based).
        triangle: usize,
        /// The offending vertex index (0-based).
        index: u32,
        /// Number of vertices in the mesh.
        count: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate ({position:?})")]
    NonFinite {
        /// Vertex number (0-based).
        vertex: usize,
        /// The offending position.
        position: [f32; 3],
    },
    /// A named vertex group refers to a vertex that does not exist.
    #[error(
        "vertex group `{group}` refers to vertex {index}, but the mesh has only {count} vertices"
    )]
    GroupOutOfRange {
        /// The group's name.
        group: String,
        /// The offending vertex index.
        index: u32,
        /// Number of vertices in the mesh.
        count: usize,
    },
    /// The mesh is larger than grimace accepts.
    #[error("the mesh has {count} {what}, more than the limit of {limit}")]
    TooLarge {
        /// "vertices" or "triangles".
        what: &'static str,
        /// How many the input has.
        count: usize,
        /// The limit.
        limit: usize,
    },
}

/// The most vertices a mesh may have (a dense face scan is far below this).
pub const MAX_VERTICES: usize = 4_000_000;
/// The most triangles a mesh may have.
pub const MAX_TRIANGLES: usize = 8_000_000;

/// A triangle mesh at rest.
///
/// Positions use the face convention of the whole project, glTF's: right-handed, x across the
/// face (the subject's left at positive x), y up, z out of the face toward the viewer.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Rest positions, one per vertex.
    pub positions: Vec<Vec3>,
    /// Triangles as vertex indices. Winding is kept as read.
    pub triangles: Vec<[u32; 3]>,
    /// Named vertex groups (for example `jaw`, `upper_lip`), each a sorted list of vertex indices.
    pub groups: BTreeMap<String, Vec<u32>>,
}

impl Mesh {
    /// Builds a mesh and checks that it is usable: at least one triangle, every index in
    /// range, every coordinate finite, sizes within limits.
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Mesh, MeshError> {
        let mesh = Mesh {
            positions,
            triangles,
            groups: BTreeMap::new(),
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// Checks the invariants [`Mesh::new`] establishes (useful after editing fields directly).
    pub fn validate(&self) -> Result<(), MeshError> {
        let count = self.positions.len();
        if count > MAX_VERTICES {
            return Err(MeshError::TooLarge {
                what: "vertices",
                count,
                limit: MAX_VERTICES,
            });
        }
        if self.triangles.len() > MAX_TRIANGLES {
            return Err(MeshError::TooLarge {
                what: "triangles",
                count: self.triangles.len(),
                limit: MAX_TRIANGLES,
            });
        }
        if self.triangles.is_empty() {
            return Err(MeshError::NoFaces);
        }
        for (vertex, p) in self.positions.iter().enumerate() {
            if !p.is_finite() {
                return Err(MeshError::NonFinite {
                    vertex,
                    position: p.to_array(),
                });
            }
        }
        for (triangle, tri) in self.triangles.iter().enumerate() {
            for &index in tri {
                if index as usize >= count {
                    return Err(MeshError::IndexOutOfRange {
                        triangle,
                        index,
                        count,
                    });
                }
            }
        }
        for (group, members) in &self.groups {
            for &index in members {
                if index as usize >= count {
                    return Err(MeshError::GroupOutOfRange {
                        group: group.clone(),
                        index,
                        count,
                    });
                }
            }
        }
        Ok(())
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// For each undirected edge `[low, high]`, how many triangles use it in each direction:
    /// `(low -> high, high -> low)`.
    pub fn edge_uses(&self) -> std::collections::BTreeMap<[u32; 2], (u32, u32)> {
        Mesh::edge_uses_of(&self.triangles)
    }

    /// [`Mesh::edge_uses`] of some triangles (a part of a mesh).
    pub fn edge_uses_of<'a>(
        triangles: impl IntoIterator<Item = &'a [u32; 3]>,
    ) -> std::collections::BTreeMap<[u32; 2], (u32, u32)> {
        let mut uses = std::collections::BTreeMap::<[u32; 2], (u32, u32)>::new();
        for t in triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let entry = uses.entry([a.min(b), a.max(b)]).or_default();
                if a < b {
                    entry.0 += 1;
                } else {
                    entry.1 += 1;
                }
            }
        }
        uses
    }

    /// The boundary edges (used by exactly one triangle), directed as that triangle uses them.
    pub fn boundary_edges(&self) -> Vec<(u32, u32)> {
        Mesh::boundary_edges_of(&self.triangles)
    }

    /// [`Mesh::boundary_edges`] of some triangles (a part of a mesh): the edges of its border.
    pub fn boundary_edges_of<'a>(
        triangles: impl IntoIterator<Item = &'a [u32; 3]>,
    ) -> Vec<(u32, u32)> {
        Mesh::edge_uses_of(triangles)
            .into_iter()
            .filter_map(|([a, b], (ab, ba))| match (ab, ba) {
                (1, 0) => Some((a, b)),
                (0, 1) => Some((b, a)),
                _ => None,
            })
            .collect()
    }

    /// The unique undirected edges, each as `[low, high]`, sorted.
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut edges: Vec<[u32; 2]> = self
            .triangles
            .iter()
            .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
            .map(|[a, b]| if a < b { [a, b] } else { [b, a] })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        edges
    }

    /// Face normals of the triangles for the given positions (right-hand rule on the winding,
    /// unit length, zero for degenerate triangles).
    pub fn face_normals(&self, positions: &[Vec3]) -> Vec<Vec3> {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                (b - a).cross(c - a).normalize_or_zero()
            })
            .collect()
    }

    /// Area-weighted vertex normals for the given positions (unit length, zero where no
    /// triangle contributes).
    pub fn vertex_normals(&self, positions: &[Vec3]) -> Vec<Vec3> {
        let mut normals = vec![Vec3::ZERO; positions.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in t {
                normals[i as usize] += n;
            }
        }
        for n in &mut normals {
            *n = n.normalize_or_zero();
        }
        normals
    }

    /// The vertices in no triangle that lie exactly where a vertex of a triangle lies, each
    /// with that vertex (the lowest-numbered): `[follower, lead]`, by follower.
    ///
    /// A mesh split at its texture seams (as many exporters write one) keeps each split
    /// vertex once per side; `grimace fit-rig` joins the sides for the skin and leaves the
    /// copies in no face, and a deformation moves each copy with its lead, so the user's
    /// numbering still holds every vertex.
    pub fn followers(&self) -> Vec<[u32; 2]> {
        let mut in_face = vec![false; self.positions.len()];
        for &v in self.triangles.iter().flatten() {
            in_face[v as usize] = true;
        }
        if in_face.iter().all(|&f| f) {
            return Vec::new();
        }
        // the loose vertices by place (usually few), then the first vertex of a face at each
        let mut loose: std::collections::HashMap<[u32; 3], Option<u32>> = (0..self.positions.len())
            .filter(|&v| !in_face[v])
            .map(|v| (position_key(self.positions[v]), None))
            .collect();
        for (v, p) in self.positions.iter().enumerate() {
            if in_face[v] {
                if let Some(lead @ None) = loose.get_mut(&position_key(*p)) {
                    *lead = Some(v as u32);
                }
            }
        }
        (0..self.positions.len())
            .filter(|&v| !in_face[v])
            .filter_map(|v| {
                let lead = loose[&position_key(self.positions[v])]?;
                Some([v as u32, lead])
            })
            .collect()
    }

    /// The axis-aligned bounding box of the rest positions, as `(min, max)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        bounds_of(&self.positions)
    }
}

/// The vertex `v` takes its position from: its lead in `followers` ([`Mesh::followers`],
/// sorted by follower) when it is a copy, else itself.
pub fn lead_of(followers: &[[u32; 2]], v: u32) -> u32 {
    match followers.binary_search_by_key(&v, |f| f[0]) {
        Ok(i) => followers[i][1],
        Err(_) => v,
    }
}

/// A position as a key for exact coincidence (`-0.0` and `0.0` alike).
pub fn position_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// The axis-aligned bounding box of the finite points of a set, as `(min, max)`; zero when
/// there are none. The one bounding box: a deformed pose drawn mid-edit may hold a NaN, which
/// must not spoil the box of the rest.
pub fn bounds_of(points: &[Vec3]) -> (Vec3, Vec3) {
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

/// A distance along a mesh, ordered totally, for the queues of walks along its edges
/// (never NaN there: rest positions are finite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Distance(pub f64);

impl Eq for Distance {}

impl PartialOrd for Distance {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Distance {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}
