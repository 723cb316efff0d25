//! Checks of a rig's contents (names, mirror partners, every muscle's parameters, masks, the
//! jaw) and of a rig against its mesh, each failure a [`RigIssue`] naming the muscle and field.

use std::fmt;

use crate::model::field::validate_muscle;
use crate::model::{Jaw, Mask, Mesh, Muscle, Rig, RIG_VERSION};

/// A problem with a rig's contents, naming the muscle (and field) where it lies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RigIssue {
    /// The muscle concerned, if the problem is in one muscle.
    pub muscle: Option<String>,
    /// The field concerned (`zone`, `mirror`, `weights`...), if known.
    pub field: Option<&'static str>,
    /// What is wrong and what was expected.
    pub message: String,
}

impl fmt::Display for RigIssue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.muscle {
            Some(name) => write!(f, "muscle `{name}`: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for RigIssue {}

fn issue(muscle: Option<&str>, field: &'static str, message: String) -> RigIssue {
    RigIssue {
        muscle: muscle.map(str::to_string),
        field: Some(field),
        message,
    }
}

/// The most muscles a rig may have. Binding keeps a field per muscle that may span the whole
/// mesh, so memory grows as muscles times vertices: 200 000 muscles (a 30 MB file) would
/// take tens of gigabytes. The classic face has 18 linear muscles, the enhanced one 23.
pub const MAX_MUSCLES: usize = 256;

/// Checks a rig's contents: version, unique well-formed names, mirror partners that exist and
/// point back, and finite, in-range parameters for every muscle and the jaw.
pub fn check_rig(rig: &Rig) -> Result<(), RigIssue> {
    if rig.version != RIG_VERSION {
        return Err(issue(
            None,
            "version",
            format!(
                "rig version {} is not supported; this grimace reads version {RIG_VERSION}",
                rig.version
            ),
        ));
    }
    if rig.mesh.as_os_str().is_empty() {
        return Err(issue(
            None,
            "mesh",
            "the mesh path is empty; expected a file path or builtin:NAME".to_string(),
        ));
    }
    if rig.muscles.len() > MAX_MUSCLES {
        return Err(issue(
            None,
            "muscles",
            format!(
                "the rig has {} muscles, more than the limit of {MAX_MUSCLES}",
                rig.muscles.len()
            ),
        ));
    }
    for (i, muscle) in rig.muscles.iter().enumerate() {
        check_name(&muscle.name)?;
        if rig.muscles[..i].iter().any(|m| m.name == muscle.name) {
            return Err(issue(
                Some(&muscle.name),
                "name",
                "the name is used by an earlier muscle; names must be unique".to_string(),
            ));
        }
    }
    // Partners that do not exist first: a one-sided pair is only worth reporting once both
    // names are real.
    for muscle in &rig.muscles {
        check_partner_exists(rig, muscle)?;
    }
    for muscle in &rig.muscles {
        check_mirror(rig, muscle)?;
        check_kind(muscle)?;
    }
    if let Some(jaw) = &rig.jaw {
        check_jaw(jaw)?;
    }
    for mask in &rig.masks {
        check_mask(rig, mask)?;
    }
    Ok(())
}

fn check_mask(rig: &Rig, mask: &Mask) -> Result<(), RigIssue> {
    if !(mask.gain.is_finite() && mask.gain > 0.0 && mask.gain <= 1e6) {
        return Err(issue(
            None,
            "gain",
            format!(
                "a mask's gain is {}; expected a finite number above 0 and at most 1e6",
                mask.gain
            ),
        ));
    }
    if let Some(name) = mask.muscles.iter().find(|n| rig.muscle_index(n).is_none()) {
        return Err(issue(
            None,
            "masks",
            format!("a mask names the muscle `{name}`, which is not a muscle of this rig"),
        ));
    }
    for (i, &(vertex, weight)) in mask.weights.iter().enumerate() {
        if !(weight.is_finite() && (0.0..=1.0).contains(&weight)) {
            return Err(issue(
                None,
                "masks",
                format!("mask weight of vertex {vertex} is {weight}; expected 0.0 to 1.0"),
            ));
        }
        if i > 0 && mask.weights[i - 1].0 >= vertex {
            return Err(issue(
                None,
                "masks",
                format!(
                    "mask weights must be sorted by vertex with no repeats; vertex {vertex} comes after {}",
                    mask.weights[i - 1].0
                ),
            ));
        }
    }
    Ok(())
}

/// Names are used as keys in AU tables and on the command line (`--set NAME=VALUE`).
fn check_name(name: &str) -> Result<(), RigIssue> {
    let bad = |why: &str| {
        Err(RigIssue {
            muscle: None,
            field: Some("name"),
            message: format!("muscle name {name:?} {why}"),
        })
    };
    if name.is_empty() {
        return bad("is empty");
    }
    if name.trim() != name {
        return bad("starts or ends with a space");
    }
    if name.contains('=') || name.contains('+') || name.chars().any(char::is_control) {
        return bad("contains `=`, `+` or a control character");
    }
    Ok(())
}

fn check_partner_exists(rig: &Rig, muscle: &Muscle) -> Result<(), RigIssue> {
    match &muscle.mirror {
        Some(partner) if rig.muscle_index(partner).is_none() => Err(issue(
            Some(&muscle.name),
            "mirror",
            format!("the mirror partner `{partner}` is not a muscle of this rig"),
        )),
        _ => Ok(()),
    }
}

fn check_mirror(rig: &Rig, muscle: &Muscle) -> Result<(), RigIssue> {
    let Some(partner) = &muscle.mirror else {
        return Ok(());
    };
    let name = Some(muscle.name.as_str());
    if *partner == muscle.name {
        return Err(issue(
            name,
            "mirror",
            "a muscle cannot mirror itself".into(),
        ));
    }
    let Some(other) = rig.muscles.iter().find(|m| &m.name == partner) else {
        return Err(issue(
            name,
            "mirror",
            format!("the mirror partner `{partner}` is not a muscle of this rig"),
        ));
    };
    if other.mirror.as_deref() != Some(muscle.name.as_str()) {
        return Err(issue(
            name,
            "mirror",
            format!(
                "the mirror partner `{partner}` does not name `{}` as its mirror",
                muscle.name
            ),
        ));
    }
    Ok(())
}

/// Muscle parameters are checked by the model itself, so a rig file accepts exactly the
/// muscles the deformation can bind.
fn check_kind(muscle: &Muscle) -> Result<(), RigIssue> {
    validate_muscle(muscle).map_err(|e| RigIssue {
        muscle: Some(e.muscle),
        field: Some(e.parameter),
        message: format!("{} {}", e.parameter, e.message),
    })
}

fn check_jaw(jaw: &Jaw) -> Result<(), RigIssue> {
    if !jaw.pivot.is_finite() {
        return Err(issue(
            None,
            "pivot",
            format!("the jaw pivot {} is not finite", jaw.pivot),
        ));
    }
    if !(jaw.axis.is_finite() && jaw.axis.length() > 0.0) {
        return Err(issue(
            None,
            "axis",
            format!(
                "the jaw axis {} is not a finite, non-zero direction",
                jaw.axis
            ),
        ));
    }
    if !jaw.degrees_per_unit.is_finite() {
        return Err(issue(
            None,
            "degrees_per_unit",
            format!(
                "the jaw's degrees_per_unit is {}; expected a finite number",
                jaw.degrees_per_unit
            ),
        ));
    }
    for (i, &(vertex, weight)) in jaw.weights.iter().enumerate() {
        if !(weight.is_finite() && (0.0..=1.0).contains(&weight)) {
            return Err(issue(
                None,
                "weights",
                format!("jaw weight of vertex {vertex} is {weight}; expected 0.0 to 1.0"),
            ));
        }
        if i > 0 && jaw.weights[i - 1].0 >= vertex {
            return Err(issue(
                None,
                "weights",
                format!(
                    "jaw weights must be sorted by vertex with no repeats; vertex {vertex} comes after {}",
                    jaw.weights[i - 1].0
                ),
            ));
        }
    }
    Ok(())
}

/// Checks a rig against the mesh it is placed on: every jaw weight names a vertex of the mesh.
pub fn check_rig_mesh(rig: &Rig, mesh: &Mesh) -> Result<(), RigIssue> {
    let count = mesh.vertex_count();
    if let Some(jaw) = &rig.jaw {
        if let Some(&(vertex, _)) = jaw.weights.iter().find(|(v, _)| *v as usize >= count) {
            return Err(issue(
                None,
                "weights",
                format!("jaw weight for vertex {vertex}, but the mesh has only {count} vertices"),
            ));
        }
    }
    for mask in &rig.masks {
        if let Some(&(vertex, _)) = mask.weights.iter().find(|(v, _)| *v as usize >= count) {
            return Err(issue(
                None,
                "masks",
                format!("mask weight for vertex {vertex}, but the mesh has only {count} vertices"),
            ));
        }
    }
    Ok(())
}
