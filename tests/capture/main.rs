//! `grimace capture`: muscles solved back from synthetic OpenFace recordings made by the rig
//! itself, the pose removed, bad frames skipped, and the real samples measured.

#[path = "../common/mod.rs"]
mod common;

mod aus;
mod faces;
mod neutral;
mod samples;
mod synthetic;
