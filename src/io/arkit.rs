//! ARKit's 52 face blendshape names and the AU each one shows.
//!
//! The names are those of Apple's `ARFaceAnchor.BlendShapeLocation` (`eyeBlink_L`, ...,
//! `tongueOut`). Live Link Face writes the same shapes as `EyeBlinkLeft`, ...; both
//! spellings are read ([`canonical`]). `_L` and `_R` are the subject's sides, like grimace's
//! `L` and `R` AU keys.
//!
//! The AU of each name comes from the one shipped shape map, `presets/arkit.map.ron`
//! (`builtin:arkit`, read by [`crate::io::shape_map`], the same file `grimace fit-au --map`
//! uses). A name the map leaves out (`"-"`) has no AU: grimace plays and exports nothing
//! for it.

use std::collections::BTreeMap;
use std::path::Path;

use super::error::LoadError;
use super::shape_map;
use crate::facs::AuKey;

/// ARKit's 52 blendshape names, in alphabetical order (the order `--targets arkit` writes).
pub const ARKIT_NAMES: [&str; 52] = [
    "browDown_L",
    "browDown_R",
    "browInnerUp",
    "browOuterUp_L",
    "browOuterUp_R",
    "cheekPuff",
    "cheekSquint_L",
    "cheekSquint_R",
    "eyeBlink_L",
    "eyeBlink_R",
    "eyeLookDown_L",
    "eyeLookDown_R",
    "eyeLookIn_L",
    "eyeLookIn_R",
    "eyeLookOut_L",
    "eyeLookOut_R",
    "eyeLookUp_L",
    "eyeLookUp_R",
    "eyeSquint_L",
    "eyeSquint_R",
    "eyeWide_L",
    "eyeWide_R",
    "jawForward",
    "jawLeft",
    "jawOpen",
    "jawRight",
    "mouthClose",
    "mouthDimple_L",
    "mouthDimple_R",
    "mouthFrown_L",
    "mouthFrown_R",
    "mouthFunnel",
    "mouthLeft",
    "mouthLowerDown_L",
    "mouthLowerDown_R",
    "mouthPress_L",
    "mouthPress_R",
    "mouthPucker",
    "mouthRight",
    "mouthRollLower",
    "mouthRollUpper",
    "mouthShrugLower",
    "mouthShrugUpper",
    "mouthSmile_L",
    "mouthSmile_R",
    "mouthStretch_L",
    "mouthStretch_R",
    "mouthUpperUp_L",
    "mouthUpperUp_R",
    "noseSneer_L",
    "noseSneer_R",
    "tongueOut",
];

/// The ARKit name for a spelling of it: `eyeBlink_L`, `EyeBlinkLeft` or `eyeblinkleft` all
/// give `eyeBlink_L`. `None` for anything else (Live Link Face's head and eye rotation
/// columns, for instance).
pub fn canonical(name: &str) -> Option<&'static str> {
    let folded = fold(name);
    ARKIT_NAMES.iter().copied().find(|n| fold(n) == folded)
}

/// Lower case without underscores, with a final `left`/`right` shortened to `l`/`r`.
fn fold(name: &str) -> String {
    let lower: String = name
        .chars()
        .filter(|c| *c != '_')
        .map(|c| c.to_ascii_lowercase())
        .collect();
    if let Some(stem) = lower.strip_suffix("left") {
        format!("{stem}l")
    } else if let Some(stem) = lower.strip_suffix("right") {
        format!("{stem}r")
    } else {
        lower
    }
}

/// The built-in ARKit map's name.
pub const BUILTIN_ARKIT: &str = "builtin:arkit";

/// Each of the 52 names with its AU, or `None` where the map leaves it out.
#[derive(Debug, Clone, PartialEq)]
pub struct ArkitMap {
    keys: BTreeMap<&'static str, Option<AuKey>>,
}

impl ArkitMap {
    /// The shipped map (`presets/arkit.map.ron`).
    pub fn builtin() -> ArkitMap {
        ArkitMap::load(Path::new(BUILTIN_ARKIT)).expect("the built-in ARKit map is tested")
    }

    /// Reads a shape map for the ARKit names: a file or `builtin:arkit`. Every name must be
    /// one of the 52 (in either spelling); names it does not give have no AU.
    pub fn load(path: &Path) -> Result<ArkitMap, LoadError> {
        let map = shape_map::load_map(path)?;
        let mut keys: BTreeMap<&'static str, Option<AuKey>> =
            ARKIT_NAMES.iter().map(|n| (*n, None)).collect();
        for (name, key) in map {
            let arkit = canonical(&name).ok_or_else(|| {
                LoadError::new(
                    path,
                    format!("`{name}` is not one of ARKit's 52 blendshapes"),
                )
            })?;
            keys.insert(arkit, Some(key));
        }
        Ok(ArkitMap { keys })
    }

    /// The AU an ARKit name shows (`None` for no AU, or a name that is not ARKit's).
    pub fn au(&self, name: &str) -> Option<AuKey> {
        canonical(name).and_then(|n| self.keys.get(n).copied().flatten())
    }

    /// The 52 names in [`ARKIT_NAMES`] order, each with its AU or `None`.
    pub fn entries(&self) -> impl Iterator<Item = (&'static str, Option<AuKey>)> + '_ {
        ARKIT_NAMES.iter().map(|n| (*n, self.keys[n]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_spellings_fold_to_one_name_and_no_two_names_collide() {
        assert_eq!(canonical("EyeBlinkLeft"), Some("eyeBlink_L"));
        assert_eq!(canonical("mouthSmile_R"), Some("mouthSmile_R"));
        assert_eq!(canonical("MouthLeft"), Some("mouthLeft"));
        assert_eq!(canonical("JawOpen"), Some("jawOpen"));
        assert_eq!(canonical("HeadYaw"), None);
        assert_eq!(canonical("LeftEyePitch"), None);
        let mut folded: Vec<String> = ARKIT_NAMES.iter().map(|n| fold(n)).collect();
        folded.sort();
        folded.dedup();
        assert_eq!(folded.len(), 52);
    }

    #[test]
    fn the_shipped_map_covers_the_52_names() {
        let map = ArkitMap::builtin();
        assert_eq!(map.entries().count(), 52);
        assert_eq!(map.au("mouthSmile_L"), Some("L12".parse().unwrap()));
        assert_eq!(map.au("MouthSmileRight"), Some("R12".parse().unwrap()));
        assert_eq!(map.au("jawOpen"), Some(AuKey::new(26)));
        assert_eq!(map.au("eyeBlink_L"), Some("L45".parse().unwrap()));
        assert_eq!(map.au("browInnerUp"), Some(AuKey::new(1)));
        assert_eq!(map.au("mouthLeft"), None);
        // Every name of the file is one of the 52 (load refuses others).
        let text = crate::io::builtin::ARKIT_MAP;
        for name in ARKIT_NAMES {
            assert!(text.contains(&format!("\"{name}\"")), "{name} missing");
        }
    }

    #[test]
    fn a_name_that_is_not_arkit_is_refused_with_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.map.ron");
        std::fs::write(&path, "{ \"smileLeft\": \"L12\" }").unwrap();
        let e = ArkitMap::load(&path).unwrap_err().to_string();
        assert!(e.contains("x.map.ron") && e.contains("smileLeft"), "{e}");
    }
}
