//! The deformation grimace uses, named once.
//!
//! Every front end (the editor, `play`, `render`, `export` to OBJ and glTF, `fit-au`, `check`)
//! binds through [`Deformation::bind`], so a face exported, fitted or checked is the face the
//! user saw. [`Deformation::Skin`] is the default: the paper's muscles and jaw followed by the
//! skin rules ([`SkinRules::DEFAULT`]), a nonlinear function of the activations.
//! [`Deformation::Paper`] is the paper's bare model ([`SkinRules::PAPER`], linear in the muscle
//! activations), kept by name for the golden comparison with the classic data.

use std::fmt;
use std::str::FromStr;

use super::deform::{BindError, BoundRig, SkinRules};
use super::mesh::Mesh;
use super::rig::Rig;

/// Which deformation a rig is bound with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Deformation {
    /// What grimace shows, exports and fits: the muscles, the jaw and the skin rules.
    #[default]
    Skin,
    /// The paper's bare model: muscles and jaw only, linear in the muscle activations.
    Paper,
}

impl Deformation {
    /// Both deformations, the default first.
    pub const ALL: [Deformation; 2] = [Deformation::Skin, Deformation::Paper];

    /// The skin rules this deformation binds with.
    pub fn skin(self) -> SkinRules {
        match self {
            Deformation::Skin => SkinRules::DEFAULT,
            Deformation::Paper => SkinRules::PAPER,
        }
    }

    /// The name used on the command line (`--model skin`, `--model paper`).
    pub fn name(self) -> &'static str {
        match self {
            Deformation::Skin => "skin",
            Deformation::Paper => "paper",
        }
    }

    /// Checks the rig against the mesh and binds it with this deformation.
    pub fn bind(self, rig: &Rig, mesh: &Mesh) -> Result<BoundRig, BindError> {
        BoundRig::bind_with(rig, mesh, self.skin())
    }
}

impl fmt::Display for Deformation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Deformation {
    type Err = String;

    fn from_str(text: &str) -> Result<Deformation, String> {
        Deformation::ALL
            .into_iter()
            .find(|d| d.name() == text.trim().to_ascii_lowercase())
            .ok_or_else(|| format!("`{text}` is not a deformation model; use skin or paper"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_the_default_is_the_skin() {
        for d in Deformation::ALL {
            assert_eq!(d.name().parse::<Deformation>(), Ok(d));
        }
        assert_eq!(Deformation::default(), Deformation::Skin);
        assert_eq!(Deformation::Skin.skin(), SkinRules::DEFAULT);
        assert!(Deformation::Paper.skin().is_paper());
        assert!("linear".parse::<Deformation>().is_err());
    }
}
