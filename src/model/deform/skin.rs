//! Keeping the skin on the face: the rules applied after the muscles (they go beyond the
//! paper; `docs/model.md` describes them), chosen by [`SkinRules`].
//!
//! - **Slide** (`slide.rs`): the part of a displacement that ends below the rest surface
//!   is mostly removed, so the skin slides along the face instead of into it.
//! - **Area bound** (`guard.rs`): triangles that would shrink below a fraction of their
//!   rest area get their displacements scaled back.
//! - **Spread** (`spread.rs`): each muscle's pull carried into the skin around it.
//!
//! This module holds the rules' values and what they share: the mesh's vertex neighbours
//! and outward rest normals.

use glam::{DVec3, Vec3};

use crate::model::mesh::Mesh;

/// How displaced skin is kept on the face, beyond the paper's equations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkinRules {
    /// Fraction of a vertex's sink below the rest surface that is removed: 0 keeps the
    /// paper's displacement, 1 keeps the vertex on the fitted rest surface.
    pub slide: f32,
    /// Smallest fraction of its rest area (projected on its rest normal) a triangle keeps;
    /// 0 bounds nothing.
    pub min_area: f32,
    /// Radius of the patch of rest surface fitted around each vertex, as a fraction of the
    /// diagonal of the mesh's bounding box.
    pub patch: f32,
    /// Length over which each muscle's pull is spread into the skin around it, as a
    /// fraction of the diagonal of the box around the rig's muscles (`spread.rs`); 0 keeps
    /// each muscle's own field.
    pub spread: f32,
    /// Largest stretch of a skin edge a single linear or sheet muscle (or a mirror pair)
    /// makes at activation 2.0, where the edge's ends move alike in direction (`stretch.rs`):
    /// each field's size changes along an edge by at most `(stretch - 1) / 2` per unit of
    /// length moving straight away from the neighbour, `sqrt(stretch^2 - 1) / 2` across the
    /// edge. 0 leaves the fields as the muscles make them.
    pub stretch: f32,
}

impl SkinRules {
    /// The paper's deformation: no slide, no area bound, no stretch limit.
    pub const PAPER: SkinRules = SkinRules {
        slide: 0.0,
        min_area: 0.0,
        patch: 0.05,
        spread: 0.0,
        stretch: 0.0,
    };

    /// What the editor, `grimace play`, `grimace render`, `export` and `check` bind with:
    /// 85 % of the sink removed, every triangle keeps at least 20 % of its rest area,
    /// patches of 5 % of the face's diagonal (about 14 mm on the default face), and no
    /// linear or sheet muscle stretching an edge beyond twice its length at 2.0.
    pub const DEFAULT: SkinRules = SkinRules {
        slide: 0.85,
        min_area: 0.2,
        patch: 0.05,
        spread: 0.0,
        stretch: 2.0,
    };

    /// [`SkinRules::DEFAULT`] with each linear and sheet muscle's pull spread into the skin around
    /// it over 2 % of the diagonal of the box around the rig's muscles (about 4 mm on the
    /// built-in face; `docs/model.md`, "The skin spread"). Fewer tears; not yet the default
    /// because it moves some AUs of the built-in table (AU17 pushes the lower lip through
    /// the upper).
    pub const TISSUE: SkinRules = SkinRules {
        spread: 0.02,
        ..SkinRules::DEFAULT
    };

    /// True when every rule is off.
    pub fn is_paper(&self) -> bool {
        self.slide == 0.0 && self.min_area == 0.0 && self.spread == 0.0 && self.stretch == 0.0
    }

    /// Checks the values: slide and min_area in 0..1 (min_area below 1), patch above 0,
    /// stretch 0 or above 1.
    pub fn check(&self) -> Result<(), String> {
        if !(self.slide.is_finite() && (0.0..=1.0).contains(&self.slide)) {
            return Err(format!("skin slide {} is outside 0.0 to 1.0", self.slide));
        }
        if !(self.min_area.is_finite() && (0.0..1.0).contains(&self.min_area)) {
            return Err(format!(
                "skin min_area {} is outside 0.0 to below 1.0",
                self.min_area
            ));
        }
        if !(self.spread.is_finite() && (0.0..=0.5).contains(&self.spread)) {
            return Err(format!("skin spread {} is outside 0.0 to 0.5", self.spread));
        }
        if !(self.stretch == 0.0 || (self.stretch.is_finite() && self.stretch > 1.0)) {
            return Err(format!(
                "skin stretch {} must be 0.0 (no limit) or above 1.0",
                self.stretch
            ));
        }
        if !(self.patch.is_finite() && self.patch > 0.0 && self.patch <= 1.0) {
            return Err(format!(
                "skin patch {} must be above 0.0 and at most 1.0",
                self.patch
            ));
        }
        Ok(())
    }
}

impl Default for SkinRules {
    fn default() -> SkinRules {
        SkinRules::DEFAULT
    }
}

/// Vertex neighbours of a mesh (CSR).
pub(super) struct Adjacency {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Adjacency {
    pub(super) fn of(mesh: &Mesh) -> Adjacency {
        let n = mesh.positions.len();
        let edges = mesh.edges();
        let mut count = vec![0u32; n + 1];
        for [a, b] in &edges {
            count[*a as usize + 1] += 1;
            count[*b as usize + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut list = vec![0u32; count[n] as usize];
        for [a, b] in &edges {
            list[fill[*a as usize] as usize] = *b;
            fill[*a as usize] += 1;
            list[fill[*b as usize] as usize] = *a;
            fill[*b as usize] += 1;
        }
        Adjacency { start: count, list }
    }

    pub(super) fn of_vertex(&self, v: usize) -> &[u32] {
        &self.list[self.start[v] as usize..self.start[v + 1] as usize]
    }
}

/// The outward rest normals: area-weighted vertex normals, turned round when the mesh's
/// triangles face into the head (their normals point toward the centroid on the whole).
pub(super) fn outward_normals(mesh: &Mesh) -> Vec<Vec3> {
    let rest = &mesh.positions;
    let mut normals = mesh.vertex_normals(rest);
    let centroid = rest.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / rest.len().max(1) as f64;
    let mut outward = 0.0f64;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| rest[i as usize].as_dvec3());
        outward += (b - a).cross(c - a).dot((a + b + c) / 3.0 - centroid);
    }
    if outward < 0.0 {
        normals.iter_mut().for_each(|n| *n = -*n);
    }
    normals
}
