//! The built-in default face: a procedural neutral adult face mesh and its rigs.
//!
//! [`generate`] builds the mesh from published facial proportions ([`anthropometry`]) and
//! smooth anatomical features ([`surface`]); [`rigs`] places the paper's and the default rig on
//! it and [`au_table`] holds the default AU table ([`crate::io::presets`] writes them all as files).

pub mod anthropometry;
pub mod au_table;
mod brow;
mod brow_lowering;
pub mod classic;
pub mod generator;
pub mod groups;
mod jaw_skin;
mod lids;
pub mod mouth;
pub mod rigs;
pub mod surface;
pub mod topology;

use glam::Vec3;

use crate::model::Mesh;

/// Builds the default face mesh with its named vertex groups (see [`groups`]).
pub fn generate() -> Mesh {
    let (mut mesh, slits) = generator::build();
    mesh.groups = groups::find_groups(&mesh, &slits);
    mesh
}

/// Rounds to 3 decimals so rig files stay readable (0.001 units is 0.01 mm).
pub(crate) fn round3(v: f32) -> f32 {
    (v * 1000.0).round() / 1000.0
}

/// Each coordinate rounded with [`round3`].
pub(crate) fn rounded(p: Vec3) -> Vec3 {
    Vec3::new(round3(p.x), round3(p.y), round3(p.z))
}
