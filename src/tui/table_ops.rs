//! The AU table operations the editor uses, in one place so the editor calls the core library
//! through a single door.

use crate::facs::{AuEntry, AuKey, AuTable, MAX_AUS};
use crate::model::{Activations, Rig};

/// Stores the current state as AU `key` named `name` (replacing any entry of that key).
pub fn record(
    table: &mut AuTable,
    key: AuKey,
    name: &str,
    rig: &Rig,
    activations: &Activations,
) -> Result<(), String> {
    if !table.aus.contains_key(&key) && table.aus.len() >= MAX_AUS {
        return Err(format!(
            "the table already holds {MAX_AUS} AUs, the most it may hold; delete one first"
        ));
    }
    let muscles = rig
        .muscles
        .iter()
        .zip(&activations.muscles)
        .filter(|(_, &a)| a != 0.0)
        .map(|(m, &a)| (m.name.clone(), a))
        .collect();
    table.aus.insert(
        key,
        AuEntry {
            name: name.to_string(),
            muscles,
            jaw: activations.jaw,
        },
    );
    Ok(())
}

/// The activations AU `key` stands for on `rig`.
pub fn activations_of(table: &AuTable, key: AuKey, rig: &Rig) -> Result<Activations, String> {
    let entry = table
        .aus
        .get(&key)
        .ok_or_else(|| format!("the table has no AU {key}"))?;
    let mut activations = Activations::zero(rig);
    for (name, &value) in &entry.muscles {
        let index = rig
            .muscle_index(name)
            .ok_or_else(|| format!("AU {key} names the muscle `{name}`, which the rig lacks"))?;
        activations.muscles[index] = value;
    }
    activations.jaw = entry.jaw;
    activations
        .validate(rig)
        .map_err(|e| format!("AU {key}: {e}"))?;
    Ok(activations)
}

/// The activations of a combination string such as `1+2+5B+26`.
pub fn evaluate(table: &AuTable, combo: &str, rig: &Rig) -> Result<Activations, String> {
    let _ = (table, rig);
    Err(format!(
        "cannot evaluate `{combo}`: combinations are not available in this build"
    ))
}

/// Checks a combination string without evaluating it.
pub fn check_combo(table: &AuTable, combo: &str, rig: &Rig) -> Result<(), String> {
    evaluate(table, combo, rig).map(|_| ())
}

/// The FACS name of an AU number, if the catalogue knows it.
pub fn facs_name(number: u8) -> Option<&'static str> {
    let _ = number;
    None
}

/// The table as the text of a table file.
pub fn to_ron(table: &AuTable) -> String {
    let config = ron::ser::PrettyConfig::new();
    ron::ser::to_string_pretty(table, config).unwrap_or_else(|e| format!("// {e}"))
}

/// Adds `intensity` times `add` to `base`, keeping every value in its range.
pub fn add_scaled(base: &Activations, add: &Activations, intensity: f32) -> Activations {
    let (m0, m1) = (
        *crate::model::MUSCLE_RANGE.start(),
        *crate::model::MUSCLE_RANGE.end(),
    );
    let (j0, j1) = (
        *crate::model::JAW_RANGE.start(),
        *crate::model::JAW_RANGE.end(),
    );
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
