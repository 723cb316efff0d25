//! AU table files (`*.au.ron`): recorded AUs and named expressions for one rig, in RON.
//!
//! Read with unknown fields and repeated keys refused, then checked (version first, then
//! size, FACS codes, activation ranges and expressions; against a rig, the muscle names).
//! Written by hand in a fixed layout that reads back bit for bit. See `docs/formats.md`.

use std::path::{Path, PathBuf};

use super::error::{read_text, LoadError, SaveError, MAX_FILE_BYTES};
use super::rig_file::{load_rig_ref, LoadedRig, BUILTIN_PREFIX};
use super::{atomic, builtin, ron_text};
use crate::facs::table::TableError;
use crate::facs::{AuKey, AuTable, TABLE_VERSION};
use crate::model::Rig;

/// Where a table's rig comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RigRef {
    /// An embedded rig, by the name after `builtin:`.
    Builtin(String),
    /// A file, already resolved against the table file's folder.
    File(PathBuf),
}

impl RigRef {
    /// The reference as [`super::rig_file::load_rig_ref`] takes it: `builtin:NAME` or the file.
    pub fn to_path(&self) -> PathBuf {
        match self {
            RigRef::Builtin(name) => PathBuf::from(format!("{BUILTIN_PREFIX}{name}")),
            RigRef::File(path) => path.clone(),
        }
    }
}

/// Resolves a table's `rig` field: `builtin:NAME`, or a path relative to the table file's
/// real folder (see [`super::reference`]; absolute paths are kept).
pub fn rig_ref(table_path: &Path, rig: &Path) -> RigRef {
    if let Some(name) = rig.to_str().and_then(|s| s.strip_prefix(BUILTIN_PREFIX)) {
        return RigRef::Builtin(name.to_string());
    }
    RigRef::File(super::reference::resolve(table_path, rig))
}

/// Loads and checks a table file on its own (its rig is not loaded; see [`load_table_for`]).
pub fn load_table(path: &Path) -> Result<AuTable, LoadError> {
    let text = read_text(path, MAX_FILE_BYTES)?;
    parse_table(&text, path)
}

/// Loads a table file and checks it against a rig: every muscle it names must exist.
pub fn load_table_for(path: &Path, rig: &Rig) -> Result<AuTable, LoadError> {
    let text = read_text(path, MAX_FILE_BYTES)?;
    let table = parse_table(&text, path)?;
    check_table_rig(&table, rig, &text, path)?;
    Ok(table)
}

/// Loads a table by reference (`builtin:NAME` for a table embedded in grimace, or a table
/// file) and the rig it names (built in, or a file relative to the table), with that rig's
/// mesh or `mesh_override`, and checks them against each other. Errors about the rig
/// reference point at the table's `rig` field.
pub fn load_table_and_rig(
    path: &Path,
    mesh_override: Option<&Path>,
) -> Result<(AuTable, LoadedRig), LoadError> {
    let (table, text) = match builtin::builtin_name(path) {
        Some(name) => {
            let table = builtin::table(name).ok_or_else(|| {
                LoadError::new(
                    path,
                    format!("there is no built-in table named `{name}`; the built-in table is builtin:default"),
                )
            })?;
            let text = table_to_ron(&table);
            (table, text)
        }
        None => {
            let text = read_text(path, MAX_FILE_BYTES)?;
            (parse_table(&text, path)?, text)
        }
    };
    let at_rig = |message: String| match ron_text::find_field(&text, 0, "rig") {
        Some(offset) => LoadError::at_offset(path, &text, offset, message),
        None => LoadError::new(path, message),
    };
    let rig_path = match rig_ref(path, &table.rig) {
        RigRef::File(file) => {
            if let Some(reason) = super::error::not_a_file(&file) {
                return Err(at_rig(format!(
                    "the rig file `{}` {reason} (paths are relative to the table file)",
                    file.display()
                )));
            }
            file
        }
        RigRef::Builtin(_) => table.rig.clone(),
    };
    let rig = load_rig_ref(&rig_path, mesh_override)
        .map_err(|e| at_rig(format!("the rig it names does not load: {e}")))?;
    check_table_rig(&table, &rig.rig, &text, path)?;
    Ok((table, rig))
}

/// Loads a table by reference (`builtin:NAME` or a file) and checks it against a rig.
pub fn load_table_ref_for(path: &Path, rig: &Rig) -> Result<AuTable, LoadError> {
    match builtin::builtin_name(path) {
        Some(name) => {
            let table = builtin::table(name).ok_or_else(|| {
                LoadError::new(path, format!("there is no built-in table named `{name}`"))
            })?;
            check_table_rig(&table, rig, &table_to_ron(&table), path)?;
            Ok(table)
        }
        None => load_table_for(path, rig),
    }
}

/// Checks a parsed table against a rig, locating the error in the table's text.
pub fn check_table_rig(
    table: &AuTable,
    rig: &Rig,
    text: &str,
    path: &Path,
) -> Result<(), LoadError> {
    table.check_rig(rig).map_err(|e| locate(path, text, &e))
}

/// Parses and checks the text of a table file. `path` is used in error messages only.
pub fn parse_table(text: &str, path: &Path) -> Result<AuTable, LoadError> {
    ron_text::check_version(path, text, TABLE_VERSION, "table")?;
    let table: AuTable = ron_text::parse(path, text, "an AU table")?;
    table.check().map_err(|e| locate(path, text, &e))?;
    Ok(table)
}

/// Writes a table file atomically (see [`atomic::write_atomic`]), after checking the table.
pub fn save_table(path: &Path, table: &AuTable) -> Result<(), SaveError> {
    table
        .check()
        .map_err(|e| SaveError::new(path, e.to_string()))?;
    if table.rig.to_str().is_none() {
        return Err(SaveError::new(path, "the rig path is not valid UTF-8"));
    }
    atomic::write_atomic(path, table_to_ron(table).as_bytes()).map_err(|e| SaveError::io(path, &e))
}

/// Turns a table check error into a load error at the AU's (or expression's) place.
fn locate(path: &Path, text: &str, error: &TableError) -> LoadError {
    let in_aus = |key: &AuKey| {
        let from = ron_text::find_field(text, 0, "aus")?;
        ron_text::find_string(text, from, &key.to_string())
    };
    let in_expressions = |name: &str| {
        let from = ron_text::find_field(text, 0, "expressions")?;
        ron_text::find_string(text, from, name)
    };
    let offset = match error {
        TableError::WrongVersion(_) => ron_text::find_field(text, 0, "version"),
        TableError::NotFacs(key) | TableError::EmptyMuscleName { au: key } => in_aus(key),
        TableError::TooManyAus(_) => ron_text::find_field(text, 0, "aus"),
        TableError::UnknownMuscle { au, muscle } => {
            in_aus(au).and_then(|at| ron_text::find_string(text, at, muscle))
        }
        TableError::Activation { au, muscle, .. } => in_aus(au).and_then(|at| {
            if muscle == "jaw" {
                ron_text::find_field(text, at, "jaw")
            } else {
                ron_text::find_string(text, at, muscle)
            }
        }),
        TableError::BadCombo { expression, .. }
        | TableError::ExpressionMissingAus { expression, .. }
        | TableError::BadExpressionName(expression) => in_expressions(expression),
        _ => None,
    };
    let message = error.to_string();
    match offset {
        Some(offset) => LoadError::at_offset(path, text, offset, message),
        None => LoadError::new(path, message),
    }
}

/// Writes a table as pretty RON in the stable layout of `docs/formats.md` (AUs in key order,
/// muscles and expressions by name). Every number reads back as exactly the same `f32`.
pub fn table_to_ron(table: &AuTable) -> String {
    use ron_text::{float, string};
    let AuTable {
        version,
        rig,
        aus,
        expressions,
    } = table;
    let mut out = String::new();
    out.push_str("// grimace AU table: muscle activations per FACS AU; see docs/formats.md\n(\n");
    out.push_str(&format!("    version: {version},\n"));
    out.push_str(&format!("    rig: {},\n", string(&rig.to_string_lossy())));
    out.push_str("    aus: {\n");
    for (key, entry) in aus {
        let crate::facs::AuEntry { name, muscles, jaw } = entry;
        out.push_str(&format!("        {}: (\n", string(&key.to_string())));
        out.push_str(&format!("            name: {},\n", string(name)));
        if muscles.is_empty() {
            out.push_str("            muscles: {},\n");
        } else {
            out.push_str("            muscles: {\n");
        }
        for (muscle, value) in muscles {
            out.push_str(&format!(
                "                {}: {},\n",
                string(muscle),
                float(*value)
            ));
        }
        if !muscles.is_empty() {
            out.push_str("            },\n");
        }
        out.push_str(&format!("            jaw: {},\n", float(*jaw)));
        out.push_str("        ),\n");
    }
    out.push_str("    },\n");
    out.push_str("    expressions: {\n");
    for (name, combo) in expressions {
        out.push_str(&format!("        {}: {},\n", string(name), string(combo)));
    }
    out.push_str("    },\n)\n");
    out
}
