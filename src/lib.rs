//! grimace: a terminal editor for muscle-based facial models.
//!
//! The model is Waters' muscle-based face (SIGGRAPH 1987) with the enhancements of Kumar &
//! Sharma (VISIGRAPP 2019): linear, sheet and sphincter muscles and a weighted jaw. This crate
//! is the core library (no terminal dependency) and, behind the default feature `tui`, the
//! front ends `cli` and `tui`. Built with `--no-default-features` it is the core alone:
//! model, FACS, formats, fitting, playback sources and renderer, without ratatui,
//! crossterm or clap.
//!
//! Layers (docs/architecture.md): a module uses only the rows below its own.
//!
//! ```text
//!  cli/        the commands, one module each; `edit` starts the editor   [feature `tui`]
//!  tui/        the editor, the player's view, the landmark picker       [feature `tui`]
//!  batch/      batch plans, items and their stable IDs, shards, resumable runs, labels
//!  render/ play/ capture/   drawing (camera, framing, raster; text, SVG, PNG); frame sources
//!              and the playback clock; muscles solved from tracked 3D landmarks
//!  io/         files: RON rigs and tables, OBJ, glTF and its morph targets, landmark files,
//!              classic Waters import, OpenFace CSV, atomic save, recovery, lock, the
//!              built-in face embedded (`io::builtin`) and written (`io::presets`)
//!  face/       the generator of the default face, its rigs, its named vertex groups
//!  fit/        rigs carried to other faces by landmarks; AU entries fitted to shapes; quality
//!  facs/       AU keys, FACS catalogue, AU tables, combination strings, the AU mapper
//!  landmarks/  the 68-point iBUG scheme, its checks, the face's frame, the mm estimate
//!  model/      mesh, muscles, jaw, rig, fields, deform, the one deformation
//! ```

#![warn(missing_docs)]

pub mod batch;
pub mod capture;
#[cfg(feature = "tui")]
pub mod cli;
pub mod face;
pub mod facs;
pub mod fit;
pub mod io;
pub mod landmarks;
pub mod model;
pub mod play;
pub mod render;
#[cfg(feature = "tui")]
pub mod tui;
