//! Files: RON rigs and AU tables, Wavefront OBJ meshes, the classic Waters data, atomic saves.
//!
//! Every load error names the file and, where the format gives them, line and column.

pub mod openface;
pub mod timeline;
