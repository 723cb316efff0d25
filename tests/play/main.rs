//! `grimace play`: OpenFace files, timelines, live streams and the terminal view.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/play.rs"]
mod play_common;

mod default_face;
mod live;
mod livelink;
mod openface;
mod rules;
mod timeline;
mod view;
