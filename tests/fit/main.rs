//! Fitting rigs to other faces by landmarks and AU entries to shapes, in the library and
//! through `grimace fit-rig` / `fit-au`.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;

mod au;
mod classic;
mod cli;
mod lids;
mod lipcut;
mod mouth;
mod parts;
mod real;
mod rig;
mod rings;
mod scheme;

use glam::Vec3;
use grimace::io::builtin;
use grimace::model::BoundRig;

/// Positions of `bound` at an AU of the built-in table, at full intensity.
fn positions_at_au(bound: &BoundRig, key: &str) -> Vec<Vec3> {
    let table = builtin::default_table();
    let act = table
        .entry_activations(&key.parse().unwrap(), bound.rig())
        .unwrap();
    let mut out = Vec::new();
    bound.deform(&act, &mut out).unwrap();
    out
}
