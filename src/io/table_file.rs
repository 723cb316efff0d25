//! AU table files (`*.au.ron`): recorded AUs and named expressions for one rig, in RON.
//!
//! Read with unknown fields and repeated keys refused, then checked (version first, then
//! size, FACS codes, activation ranges and expressions; against a rig, the muscle names).
//! Written by hand in a fixed layout that reads back bit for bit. See `docs/formats.md`.

use std::path::Path;

use super::error::{read_text, LoadError, SaveError, MAX_FILE_BYTES};
use super::{atomic, ron_text};
use crate::facs::table::TableError;
use crate::facs::{AuKey, AuTable, TABLE_VERSION};
use crate::model::Rig;

/// Loads and checks a table file on its own (its rig is not loaded; see [`load_table_for`] and
/// [`super::load::load_table_and_rig`]).
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
