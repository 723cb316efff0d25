//! Files: RON rigs and AU tables, Wavefront OBJ meshes, the classic Waters data, atomic saves.
//!
//! Every load error names the file and, where the format gives them, line and column
//! ([`LoadError`]). No input makes a loader panic; every file is size-checked before it is
//! read. Saves go through [`atomic::write_atomic`], which never leaves a partial file.

pub mod acts;
pub mod arkit;
pub mod atomic;
pub mod bind_cache;
pub mod builtin;
pub mod error;
pub mod faces;
pub mod gltf;
pub mod inputs;
pub mod landmark_text;
pub mod landmarks;
pub mod lines;
pub mod livelink;
pub mod load;
pub mod lock;
pub mod morph;
pub mod obj;
pub mod openface;
pub mod pick_recovery;
pub mod presets;
pub mod printable;
pub mod recovery;
pub mod reference;
pub mod rig_file;
pub mod shape_map;
pub mod table_file;
pub mod timeline;
pub mod waters;

pub(crate) mod ron_text;

pub use error::{line_column, LoadError, SaveError, MAX_FILE_BYTES};
pub use load::{load_rig, parse_rig, LoadedRig};
pub use rig_file::{rig_to_ron, save_rig};
pub use table_file::{load_table, parse_table, save_table, table_to_ron};
