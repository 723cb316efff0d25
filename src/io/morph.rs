//! Morph targets: which states of a rig become the targets of an exported mesh.
//!
//! A morph target is the face at one state's full activation, taken from grimace's own
//! deformation; an engine that blends targets adds their displacements linearly, which is
//! exact for one target at weight 1 and approximate elsewhere (docs/gltf.md says where and by
//! how much).

use glam::Vec3;
use thiserror::Error;

use crate::facs::table::TableError;
use crate::facs::AuMapper;
use crate::facs::{AuKey, AuTable};
use crate::io::arkit::ArkitMap;
use crate::io::gltf::MorphTarget;
use crate::model::{ActivationError, Activations, BoundRig, Rig};

/// Which states become morph targets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetSet {
    /// One per recorded AU of the table, named `AU12`, `AU_L12`, `AU_R12`.
    Aus,
    /// One per named expression of the table, named by the expression.
    Expressions,
    /// One per muscle at activation 1, named by the muscle, and `jaw` at 1 when the rig has
    /// a jaw.
    Muscles,
    /// ARKit's 52 blendshapes, each the AU the ARKit map gives it, played through the table
    /// as `grimace play` plays it; a name without an AU, or whose AU the table lacks, is a
    /// target that moves nothing.
    Arkit,
}

/// A target set that cannot be built.
#[derive(Debug, Error)]
pub enum TargetError {
    /// The table cannot give a state (an expression naming a missing AU, ...).
    #[error(transparent)]
    Table(#[from] TableError),
    /// A state out of range for the rig.
    #[error(transparent)]
    Activation(#[from] ActivationError),
}

/// The glTF target name of an AU key: `AU12`, `AU_L12`, `AU_R12`.
pub fn au_target_name(key: &AuKey) -> String {
    match key.side {
        Some(_) => format!("AU_{key}"),
        None => format!("AU{key}"),
    }
}

/// The named states of a target set, in the order they are written.
#[derive(Debug, Clone, Default)]
pub struct TargetStates {
    /// Each target's name and activations.
    pub states: Vec<(String, Activations)>,
    /// ARKit names that move nothing on this table, each with the reason.
    pub silent: Vec<String>,
}

/// The states of a target set on a rig and table.
pub fn target_states(
    set: TargetSet,
    rig: &Rig,
    table: &AuTable,
    arkit: &ArkitMap,
) -> Result<TargetStates, TargetError> {
    let mut states = Vec::new();
    let mut silent = Vec::new();
    match set {
        TargetSet::Aus => {
            for key in table.aus.keys() {
                states.push((au_target_name(key), table.entry_activations(key, rig)?));
            }
        }
        TargetSet::Expressions => {
            for name in table.expressions.keys() {
                states.push((name.clone(), table.expression_activations(name, rig)?));
            }
        }
        TargetSet::Muscles => {
            for (i, muscle) in rig.muscles.iter().enumerate() {
                let mut act = Activations::zero(rig);
                act.muscles[i] = 1.0;
                states.push((muscle.name.clone(), act));
            }
            if rig.jaw.is_some() {
                let mut act = Activations::zero(rig);
                act.jaw = 1.0;
                states.push(("jaw".to_string(), act));
            }
        }
        TargetSet::Arkit => {
            let mapper = AuMapper::new(table, rig);
            for (name, key) in arkit.entries() {
                let mut act = Activations::zero(rig);
                match key {
                    Some(key) if mapper.knows(key) => mapper.map([(key, 1.0)], &mut act),
                    Some(key) => silent.push(format!("{name} (AU {key} not in the table)")),
                    None => silent.push(format!("{name} (no AU)")),
                }
                states.push((name.to_string(), act));
            }
        }
    }
    Ok(TargetStates { states, silent })
}

/// Deforms the mesh into each state: the morph targets to write.
pub fn morph_targets(
    bound: &BoundRig,
    states: &[(String, Activations)],
) -> Result<Vec<MorphTarget>, TargetError> {
    let mut targets = Vec::with_capacity(states.len());
    for (name, act) in states {
        let mut positions: Vec<Vec3> = Vec::new();
        bound.deform(act, &mut positions)?;
        targets.push(MorphTarget {
            name: name.clone(),
            positions,
        });
    }
    Ok(targets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn au_names_say_the_side_with_an_underscore() {
        assert_eq!(au_target_name(&AuKey::new(12)), "AU12");
        assert_eq!(au_target_name(&"L12".parse().unwrap()), "AU_L12");
        assert_eq!(au_target_name(&"R4".parse().unwrap()), "AU_R4");
    }
}
