//! grimace: a terminal editor for muscle-based facial models.
//!
//! The model is Waters' muscle-based face (SIGGRAPH 1987) with the enhancements of Kumar &
//! Sharma (VISIGRAPP 2019): linear, sheet and sphincter muscles and a weighted jaw. This crate
//! is the core library (no terminal dependency) and, behind the default feature `tui`, the
//! front ends `cli` and `tui`. Built with `--no-default-features` it is the core alone:
//! model, FACS, formats, fitting, playback sources and renderer, without ratatui,
//! crossterm or clap.
//!
//! Layers, arrows pointing down only:
//!
//! ```text
//!  cli (the commands)          tui (ratatui + crossterm editor)    [feature `tui`]
//!              \                  /
//!   play   (frame sources, tracker intensities, playback clock)
//!   render (camera, raster to a dot canvas, text, svg, png)
//!   fit    (rigs carried to other faces by landmarks, AU entries fitted to shapes, quality)
//!   face   (the generator of the built-in default face and its rigs)
//!   io     (RON rig and table files, OBJ, classic Waters import, OpenFace CSV, atomic save)
//!   facs   (AU keys and catalogue, AU tables, combination strings, the AU mapper)
//!   model  (mesh, muscles, jaw, rig, fields, deform, the one deformation)
//! ```

#![warn(missing_docs)]

pub mod batch;
#[cfg(feature = "tui")]
pub mod cli;
pub mod export;
pub mod face;
pub mod facs;
pub mod fit;
pub mod io;
pub mod model;
pub mod play;
pub mod render;
#[cfg(feature = "tui")]
pub mod tui;
