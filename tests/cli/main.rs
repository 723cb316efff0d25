//! The commands end to end through the built binary: files, the bad-input corpus, `render`,
//! `gen-face`, completions.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;

mod bad_inputs;
mod check_cli;
mod completions;
mod face_cli;
mod files;
mod gltf_blending;
mod gltf_export;
mod one_deformation;
mod readme_example;
mod render_cli;
