//! Reliability (`docs/reliability.md`): bad and hostile files through every command,
//! limits, failed saves, the editor against other editors, hostile live input.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;

mod bind;
mod commands;
mod editor;
mod files;
mod layers;
mod limits;
mod outputs;
mod play;
mod saves;
mod silent;
