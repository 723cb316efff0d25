//! The files of the default face: the mesh as OBJ, the two rigs and the AU table as RON.

use crate::face::{au_table, rigs};
use crate::io::obj::write_obj;
use crate::io::{rig_to_ron, table_to_ron};
use crate::model::Mesh;

/// File name of the paper's rig.
pub const PAPER_RIG_FILE: &str = "paper.rig.ron";
/// File name of the default rig.
pub const DEFAULT_RIG_FILE: &str = "default.rig.ron";
/// File name of the default AU table.
pub const DEFAULT_TABLE_FILE: &str = "default.au.ron";

/// The OBJ text of a generated face (vertex groups are not written; they are found again
/// from the geometry, see [`super::groups::find_groups_in`]).
pub fn mesh_file(mesh: &Mesh) -> String {
    write_obj(mesh, &mesh.positions)
}

/// The preset files for a generated default face, as `(file name, RON text)`.
pub fn preset_files(mesh: &Mesh) -> Result<Vec<(&'static str, String)>, rigs::PlacementError> {
    let paper = rigs::paper_rig(mesh)?;
    let default = rigs::default_rig(mesh)?;
    Ok(vec![
        (PAPER_RIG_FILE, rig_to_ron(&paper)),
        (DEFAULT_RIG_FILE, rig_to_ron(&default)),
        (DEFAULT_TABLE_FILE, table_to_ron(&au_table::default_table())),
    ])
}
