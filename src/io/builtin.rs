//! The default face, its rigs and its AU table, embedded in the binary so grimace runs from
//! any folder.
//!
//! Files name them as `builtin:NAME`: the mesh `builtin:face`, the rigs `builtin:default`
//! and `builtin:paper`, the table `builtin:default`. The embedded texts are the committed
//! files `assets/face.obj` and `presets/*.ron`, parsed with the same loaders as files on
//! disk; a test proves each of them loads.

use std::path::Path;
use std::sync::OnceLock;

use super::rig_file::{parse_rig_with, BUILTIN_PREFIX};
use super::table_file::parse_table;
use super::{obj, LoadError};
use crate::face::groups::find_groups_in;
use crate::facs::AuTable;
use crate::model::{Mesh, Rig};

/// The default face mesh (`assets/face.obj`).
pub const FACE_OBJ: &str = include_str!("../../assets/face.obj");
/// The paper's rig on the default face (`presets/paper.rig.ron`).
pub const PAPER_RIG: &str = include_str!("../../presets/paper.rig.ron");
/// The default rig (`presets/default.rig.ron`).
pub const DEFAULT_RIG: &str = include_str!("../../presets/default.rig.ron");
/// The default AU table (`presets/default.au.ron`).
pub const DEFAULT_TABLE: &str = include_str!("../../presets/default.au.ron");
/// The map from ARKit's 52 blendshape names to AU keys (`presets/arkit.map.ron`).
pub const ARKIT_MAP: &str = include_str!("../../presets/arkit.map.ron");
/// The 68 landmarks of the default face (`presets/default.landmarks.ron`).
pub const DEFAULT_LANDMARKS: &str = include_str!("../../presets/default.landmarks.ron");

/// The default face with its named vertex groups (landmarks, lids, lips, brows).
///
/// # Panics
/// Never in a correctly built binary: the embedded file is checked by the tests.
pub fn default_mesh() -> Mesh {
    face_mesh().clone()
}

/// The default face, parsed once.
fn face_mesh() -> &'static Mesh {
    static MESH: OnceLock<Mesh> = OnceLock::new();
    MESH.get_or_init(|| load_mesh().unwrap_or_else(|e| panic!("embedded face: {e}")))
}

/// Millimetres per mesh unit when `mesh` is the built-in face at rest (its scale is known:
/// [`crate::face::anthropometry::MM_PER_UNIT`]), else `None`: other meshes' units are their
/// own, and commands estimate them from the landmarks (`grimace check`) or take `--unit-mm`.
/// Compared by rest positions, so a copy of the face loaded from a file counts too.
pub fn mm_per_unit(mesh: &Mesh) -> Option<f32> {
    let face = face_mesh();
    (face.positions.len() == mesh.positions.len() && face.positions == mesh.positions)
        .then_some(crate::face::anthropometry::MM_PER_UNIT as f32)
}

/// The default rig: the paper's muscles plus those needed for the AUs face trackers report.
///
/// # Panics
/// Never in a correctly built binary: the embedded file is checked by the tests.
pub fn default_rig() -> Rig {
    load_rig(DEFAULT_RIG, "default.rig.ron").unwrap_or_else(|e| panic!("embedded rig: {e}"))
}

/// The paper's rig: 18 linear muscles, 2 frontalis sheets, 3 sphincters and the jaw.
///
/// # Panics
/// Never in a correctly built binary: the embedded file is checked by the tests.
pub fn paper_rig() -> Rig {
    load_rig(PAPER_RIG, "paper.rig.ron").unwrap_or_else(|e| panic!("embedded rig: {e}"))
}

/// Keeps the eyeballs of the built-in face still under `rig`, whatever muscles it has: rigs
/// written before the face had eyeballs carry no mask for them, and a rig file may add
/// muscles the saved mask does not name. Meshes other than `builtin:face` are left alone.
pub fn hold_eyes_still(mesh_name: &str, mesh: &Mesh, rig: &mut Rig) {
    if mesh_name == "face" {
        crate::face::groups::hold_still(mesh, rig);
    }
}

/// The default AU table, for the default rig.
///
/// # Panics
/// Never in a correctly built binary: the embedded file is checked by the tests.
pub fn default_table() -> AuTable {
    load_table(DEFAULT_TABLE, "default.au.ron").unwrap_or_else(|e| panic!("embedded table: {e}"))
}

/// The landmarks of the built-in mesh called `name` (`face`, `default`, `paper`): the
/// templates' landmarks for fitting.
///
/// # Panics
/// Never in a correctly built binary: the embedded file is checked by the tests.
pub fn landmarks(name: &str) -> Option<crate::landmarks::Landmarks> {
    matches!(name, "face" | "default" | "paper").then(|| {
        super::landmarks::parse_landmarks(DEFAULT_LANDMARKS, &embedded("default.landmarks.ron"))
            .unwrap_or_else(|e| panic!("embedded landmarks: {e}"))
    })
}

/// The name after `builtin:` in a path, if it is a built-in reference.
pub fn builtin_name(path: &Path) -> Option<&str> {
    path.to_str()?.strip_prefix(BUILTIN_PREFIX)
}

/// The built-in mesh called `name`: `face` (also `default` and `paper`, the meshes of the
/// built-in rigs). Fits [`super::rig_file::BuiltinMeshes`].
pub fn mesh(name: &str) -> Option<Mesh> {
    matches!(name, "face" | "default" | "paper").then(default_mesh)
}

/// The built-in rig called `name`: `default` or `paper`.
pub fn rig(name: &str) -> Option<Rig> {
    match name {
        "default" => Some(default_rig()),
        "paper" => Some(paper_rig()),
        _ => None,
    }
}

/// The built-in AU table called `name`: `default`.
pub fn table(name: &str) -> Option<AuTable> {
    (name == "default").then(default_table)
}

/// Parses the embedded face and finds its named vertex groups again.
pub fn load_mesh() -> Result<Mesh, LoadError> {
    let mut mesh = obj::parse_obj(FACE_OBJ, &embedded("face.obj"))?;
    mesh.groups = find_groups_in(&mesh);
    Ok(mesh)
}

/// Parses an embedded rig.
pub fn load_rig(text: &str, name: &str) -> Result<Rig, LoadError> {
    parse_rig_with(text, &embedded(name), mesh).map(|(rig, _)| rig)
}

/// Parses an embedded AU table.
pub fn load_table(text: &str, name: &str) -> Result<AuTable, LoadError> {
    parse_table(text, &embedded(name))
}

/// The path embedded files are reported under in errors.
fn embedded(name: &str) -> std::path::PathBuf {
    Path::new(BUILTIN_PREFIX).join(name)
}
