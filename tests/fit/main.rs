//! Fitting rigs to other faces by landmarks and AU entries to shapes, in the library and
//! through `grimace fit-rig` / `fit-au`.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;

mod au;
mod classic;
mod cli;
mod lipcut;
mod parts;
mod real;
mod rig;
mod rings;
mod scheme;
