//! The built-in default face: a procedural neutral adult face mesh and its rigs.
//!
//! [`generate`] builds the mesh from published facial proportions ([`anthropometry`]) and
//! smooth anatomical features ([`surface`]); [`rigs`] places the paper's and the default rig on
//! it and [`au_table`] holds the default AU table ([`crate::io::presets`] writes them all as files).

pub mod anthropometry;
pub mod au_table;
pub mod classic;
pub mod generator;
pub mod groups;
mod jaw_skin;
mod lids;
pub mod mouth;
pub mod rigs;
pub mod surface;
pub mod topology;

pub use generator::generate;
