//! The editor: startup, whole-screen snapshots, bytes sent, and the real binary in a
//! pseudo-terminal.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;

mod bytes;
mod colors;
mod e2e;
mod editing;
mod picker;
mod rig_mode;
mod screens;
mod startup;
