//! grimace: a terminal editor for muscle-based facial models.
//!
//! The model is Waters' muscle-based face (SIGGRAPH 1987) with the enhancements of Kumar &
//! Sharma (VISIGRAPP 2019): linear, sheet and sphincter muscles and a weighted jaw. This crate
//! is the core library (no terminal dependency outside [`tui`]) and the front ends.
//!
//! Layers, arrows pointing down only:
//!
//! ```text
//!  cli (headless commands)     tui (ratatui + crossterm editor)
//!              \                  /
//!   render (camera, raster to a dot canvas, text, svg, png)
//!   face   (the generator of the built-in default face and its rigs)
//!   io     (RON rig and table files, OBJ, classic Waters import, atomic save)
//!   facs   (AU keys and catalogue, AU tables, combination strings)
//!   model  (mesh, muscles, jaw, rig, fields, deform)
//! ```

#![warn(missing_docs)]

pub mod cli;
pub mod face;
pub mod facs;
pub mod fit;
pub mod io;
pub mod model;
pub mod play;
pub mod render;
pub mod tui;
