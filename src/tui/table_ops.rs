//! The AU table operations the editor uses, in one place: thin calls into the core library
//! ([`crate::facs`], [`crate::io`]) that turn its errors into status-line messages.

use crate::facs::combo::parse_combo;
use crate::facs::{catalogue, AuKey, AuTable};
use crate::model::{Activations, Rig, JAW_RANGE, MUSCLE_RANGE};

/// Stores the current state as AU `key` named `name` (replacing any entry of that key).
pub fn record(
    table: &mut AuTable,
    key: AuKey,
    name: &str,
    rig: &Rig,
    activations: &Activations,
) -> Result<(), String> {
    table
        .record(key, name, rig, activations)
        .map_err(|e| e.to_string())
}

/// The activations AU `key` stands for on `rig`.
pub fn activations_of(table: &AuTable, key: AuKey, rig: &Rig) -> Result<Activations, String> {
    table
        .entry_activations(&key, rig)
        .map_err(|e| e.to_string())
}

/// The activations of a combination string such as `1+2+5B+26`.
pub fn evaluate(table: &AuTable, combo: &str, rig: &Rig) -> Result<Activations, String> {
    let parsed = parse_combo(combo).map_err(|e| format!("`{combo}`: {e}"))?;
    table.evaluate(&parsed, rig).map_err(|e| e.to_string())
}

/// Adds or replaces a named expression (the combination must parse and name AUs of the table).
pub fn set_expression(table: &mut AuTable, name: &str, combo: &str) -> Result<(), String> {
    table.set_expression(name, combo).map_err(|e| e.to_string())
}

/// Removes an AU (refused while an expression uses it).
pub fn remove(table: &mut AuTable, key: AuKey) -> Result<(), String> {
    table.remove(&key).map(|_| ()).map_err(|e| e.to_string())
}

/// The FACS name of an AU number, if the catalogue knows it.
pub fn facs_name(number: u8) -> Option<&'static str> {
    catalogue::name_of(number)
}

/// The table as the text of a table file.
pub fn to_ron(table: &AuTable) -> String {
    crate::io::table_to_ron(table)
}

/// Adds `intensity` times `add` to `base`, keeping every value in its range.
pub fn add_scaled(base: &Activations, add: &Activations, intensity: f32) -> Activations {
    let (m0, m1) = (*MUSCLE_RANGE.start(), *MUSCLE_RANGE.end());
    let (j0, j1) = (*JAW_RANGE.start(), *JAW_RANGE.end());
    Activations {
        muscles: base
            .muscles
            .iter()
            .zip(&add.muscles)
            .map(|(&a, &b)| (a + intensity * b).clamp(m0, m1))
            .collect(),
        jaw: (base.jaw + intensity * add.jaw).clamp(j0, j1),
    }
}

/// Reads a table to import from: `builtin:NAME`, or a table file (checked on its own; AUs
/// that do not fit the rig are left out by the import).
pub fn read(path: &std::path::Path) -> Result<AuTable, String> {
    match crate::io::builtin::builtin_name(path) {
        Some(name) => crate::io::builtin::table(name).ok_or_else(|| {
            format!(
                "there is no built-in table named `{name}`; the built-in table is builtin:default"
            )
        }),
        None => crate::io::load_table(path).map_err(|e| e.to_string()),
    }
}
