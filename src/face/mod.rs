//! The built-in default face: a procedural neutral adult face mesh and its rigs.
//!
//! [`generate`] builds the mesh from published facial proportions ([`anthropometry`]) and
//! smooth anatomical features ([`surface`]); [`obj`] writes it deterministically.

pub mod anthropometry;
pub mod generator;
pub mod groups;
pub mod obj;
pub mod surface;
pub mod topology;

pub use generator::generate;
