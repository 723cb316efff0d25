//! The core library: the model, FACS tables, file formats, the default face and its
//! presets.
//!
//! One test binary with a module per former test file (fewer binaries to link).

#[path = "../common/mod.rs"]
mod common;

mod au_shapes;
mod brow_hair;
mod classic_face;
mod convention;
mod corners;
mod eyeballs;
mod face_gallery;
mod face_mesh;
mod face_rig;
mod facs_combo;
mod facs_table;
mod frames;
mod full_contraction;
mod fuzz_regressions;
mod golden_linear;
mod io_rig_table;
mod io_waters;
mod jaw_mouth;
mod lids;
mod lip_linings;
mod openface_proptest;
mod presets_builtin;
mod presets_table;
mod properties;
mod regions;
mod skin;
mod spread;
mod stretch;
mod tears;
