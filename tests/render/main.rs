//! The renderer: camera, rasterizer, cells, SVG and PNG, on synthetic meshes, the default
//! face and the classic face.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;

mod brows;
mod cells;
mod classic;
mod colors;
mod default_face;
mod defaults;
mod eyes;
mod files;
mod framing;
mod geometry;
mod ghost;
mod helpers;
mod lod;
