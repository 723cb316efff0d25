//! From AU intensities to muscle activations, through an AU table.
//!
//! Each AU's recorded activations (its [`crate::facs::AuEntry`]) are scaled by the AU's
//! factor, the scaled AUs add up, and the sum is clamped to the activation ranges -- the way
//! the FACS letters A-E scale an AU (E = 5/5 = 1.0). A tracker's intensity `r` on OpenFace's
//! 0-5 scale is the factor `r/5`; on an already normalised 0-1 stream it is `r` itself.
//!
//! The mapper resolves muscle names once, so a frame costs one multiply-add per recorded
//! muscle of each active AU.

use std::collections::{BTreeMap, BTreeSet};

use crate::facs::{AuKey, AuTable};
use crate::model::{Activations, Rig, Side, JAW_RANGE, MUSCLE_RANGE};

/// The scale of incoming intensities.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IntensityScale {
    /// OpenFace's 0-5 (factor = r / 5).
    #[default]
    ZeroToFive,
    /// Already normalised to 0-1 (factor = r).
    ZeroToOne,
}

impl IntensityScale {
    /// The largest intensity on this scale.
    pub fn max(self) -> f32 {
        match self {
            IntensityScale::ZeroToFive => crate::io::openface::OPENFACE_MAX_INTENSITY,
            IntensityScale::ZeroToOne => 1.0,
        }
    }

    /// Clamps an intensity to the scale; the flag says whether it was outside.
    pub fn clamp(self, value: f32) -> (f32, bool) {
        let clamped = value.clamp(0.0, self.max());
        (clamped, clamped != value)
    }

    /// The factor (0-1) that scales a recorded AU.
    pub fn factor(self, value: f32) -> f32 {
        self.clamp(value).0 / self.max()
    }
}

/// One AU of a frame: its number, its intensity as given (clamped to the scale) and its
/// factor 0-1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AuIntensity {
    /// The AU (bilateral for tracker input).
    pub key: AuKey,
    /// The intensity on the input's scale, after clamping.
    pub value: f32,
    /// The factor that scales the recorded AU (0-1).
    pub factor: f32,
}

/// One AU's recorded activations, resolved to rig indices.
#[derive(Debug, Clone, Default, PartialEq)]
struct Contribution {
    muscles: Vec<(usize, f32)>,
    jaw: f32,
}

/// Turns AU intensities into activations for one rig and table.
#[derive(Debug, Clone)]
pub struct AuMapper {
    muscle_count: usize,
    contributions: BTreeMap<AuKey, Vec<Contribution>>,
    /// One-sided AUs the table only records bilaterally, made from that recording.
    derived: BTreeMap<AuKey, Vec<Contribution>>,
    unknown_muscles: BTreeSet<String>,
}

impl AuMapper {
    /// Resolves every recorded AU of `table` against `rig`. Muscle names the rig lacks are
    /// collected (see [`AuMapper::unknown_muscles`]) and contribute nothing.
    pub fn new(table: &AuTable, rig: &Rig) -> AuMapper {
        let mut unknown_muscles = BTreeSet::new();
        let mut contributions: BTreeMap<AuKey, Vec<Contribution>> = BTreeMap::new();
        for (key, entry) in &table.aus {
            let mut muscles = Vec::new();
            for (name, &value) in &entry.muscles {
                match rig.muscle_index(name) {
                    Some(index) if value.is_finite() => muscles.push((index, value)),
                    Some(_) => {}
                    None => {
                        unknown_muscles.insert(name.clone());
                    }
                }
            }
            let jaw = if entry.jaw.is_finite() {
                entry.jaw
            } else {
                0.0
            };
            contributions
                .entry(*key)
                .or_default()
                .push(Contribution { muscles, jaw });
        }
        let derived = one_sided_from_bilateral(&contributions, rig);
        AuMapper {
            muscle_count: rig.muscles.len(),
            contributions,
            derived,
            unknown_muscles,
        }
    }

    /// Muscle names the table uses but the rig lacks.
    pub fn unknown_muscles(&self) -> &BTreeSet<String> {
        &self.unknown_muscles
    }

    /// Whether the table has a recording for this AU: the key itself, for a bilateral key
    /// both or either side (`12` is played as `L12` + `R12` when only the sides are
    /// recorded), for a one-sided key the bilateral recording (`L45` is the `45`
    /// recording's left muscles and half its midline muscles and jaw, so `L45` + `R45` is
    /// `45`).
    pub fn knows(&self, key: AuKey) -> bool {
        !self.entries_for(key).is_empty()
    }

    fn entries_for(&self, key: AuKey) -> Vec<&Contribution> {
        if let Some(found) = self.contributions.get(&key) {
            return found.iter().collect();
        }
        if key.side.is_none() {
            return [Side::Left, Side::Right]
                .into_iter()
                .filter_map(|side| {
                    self.contributions.get(&AuKey {
                        number: key.number,
                        side: Some(side),
                    })
                })
                .flatten()
                .collect();
        }
        self.derived
            .get(&key)
            .map(|found| found.iter().collect())
            .unwrap_or_default()
    }

    /// The activations for a set of AUs with factors: the scaled recordings added, clamped to
    /// the ranges. AUs the table lacks contribute nothing.
    pub fn map(&self, aus: impl IntoIterator<Item = (AuKey, f32)>, out: &mut Activations) {
        out.muscles.clear();
        out.muscles.resize(self.muscle_count, 0.0);
        out.jaw = 0.0;
        for (key, factor) in aus {
            if factor == 0.0 || !factor.is_finite() {
                continue;
            }
            for contribution in self.entries_for(key) {
                for &(index, value) in &contribution.muscles {
                    out.muscles[index] += factor * value;
                }
                out.jaw += factor * contribution.jaw;
            }
        }
        clamp_activations(out);
    }
}

/// The one-sided AUs a table records only bilaterally (`L45`, `R45` from `45`): the
/// recording's muscles on that side, and half of its midline muscles and jaw, so the two
/// sides add up to the bilateral AU.
fn one_sided_from_bilateral(
    contributions: &BTreeMap<AuKey, Vec<Contribution>>,
    rig: &Rig,
) -> BTreeMap<AuKey, Vec<Contribution>> {
    let mut derived = BTreeMap::new();
    for (key, list) in contributions.iter().filter(|(k, _)| k.side.is_none()) {
        for side in [Side::Left, Side::Right] {
            let sided = AuKey {
                number: key.number,
                side: Some(side),
            };
            if contributions.contains_key(&sided) {
                continue;
            }
            let half = list
                .iter()
                .map(|c| Contribution {
                    muscles: c
                        .muscles
                        .iter()
                        .filter_map(|&(i, v)| match rig.muscles[i].side {
                            Side::Centre => Some((i, v * 0.5)),
                            s if s == side => Some((i, v)),
                            _ => None,
                        })
                        .collect(),
                    jaw: c.jaw * 0.5,
                })
                .collect();
            derived.insert(sided, half);
        }
    }
    derived
}

/// Clamps muscles to 0-2 and the jaw to 0-4.
pub fn clamp_activations(act: &mut Activations) {
    for value in &mut act.muscles {
        *value = value.clamp(*MUSCLE_RANGE.start(), *MUSCLE_RANGE.end());
    }
    act.jaw = act.jaw.clamp(*JAW_RANGE.start(), *JAW_RANGE.end());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::facs::AuEntry;
    use crate::model::{Linear, Muscle, MuscleKind};
    use glam::Vec3;
    use std::path::PathBuf;

    fn muscle(name: &str) -> Muscle {
        Muscle {
            name: name.into(),
            side: Side::Centre,
            mirror: None,
            kind: MuscleKind::Linear(Linear {
                attachment: Vec3::ZERO,
                insertion: Vec3::X,
                zone: 30.0,
                falloff_start: 0.0,
                falloff_end: 1.0,
            }),
        }
    }

    fn rig_and_table() -> (Rig, AuTable) {
        let rig = Rig {
            masks: Vec::new(),
            version: 1,
            mesh: PathBuf::from("builtin:test"),
            combine: Default::default(),
            muscles: vec![muscle("a"), muscle("b")],
            jaw: None,
        };
        let mut aus = BTreeMap::new();
        let entry = |pairs: &[(&str, f32)], jaw| AuEntry {
            name: String::new(),
            muscles: pairs.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
            jaw,
        };
        aus.insert(AuKey::new(6), entry(&[("a", 1.0)], 0.0));
        aus.insert(AuKey::new(12), entry(&[("a", 1.5), ("b", 0.5)], 0.0));
        aus.insert(AuKey::new(26), entry(&[("ghost", 1.0)], 2.0));
        aus.insert("L14".parse().unwrap(), entry(&[("a", 0.4)], 0.0));
        aus.insert("R14".parse().unwrap(), entry(&[("b", 0.4)], 0.0));
        let table = AuTable {
            version: 1,
            rig: PathBuf::from("builtin:test"),
            aus,
            expressions: BTreeMap::new(),
        };
        (rig, table)
    }

    #[test]
    fn intensity_scales_the_recording_and_sums_clamp() {
        let (rig, table) = rig_and_table();
        let mapper = AuMapper::new(&table, &rig);
        let mut out = Activations::default();
        mapper.map([(AuKey::new(12), 0.5)], &mut out);
        assert_eq!(out.muscles, vec![0.75, 0.25]);
        mapper.map([(AuKey::new(12), 1.0), (AuKey::new(6), 1.0)], &mut out);
        assert_eq!(out.muscles, vec![2.0, 0.5], "1.5 + 1.0 clamps to 2.0");
        mapper.map([(AuKey::new(26), 1.0)], &mut out);
        assert_eq!((out.muscles.clone(), out.jaw), (vec![0.0, 0.0], 2.0));
        assert!(mapper.unknown_muscles().contains("ghost"));
    }

    #[test]
    fn bilateral_input_plays_both_recorded_sides() {
        let (rig, table) = rig_and_table();
        let mapper = AuMapper::new(&table, &rig);
        assert!(mapper.knows(AuKey::new(14)));
        assert!(!mapper.knows(AuKey::new(1)));
        let mut out = Activations::default();
        mapper.map([(AuKey::new(14), 0.5)], &mut out);
        assert_eq!(out.muscles, vec![0.2, 0.2]);
    }

    #[test]
    fn one_sided_input_plays_its_side_of_a_bilateral_recording() {
        let (mut rig, table) = rig_and_table();
        rig.muscles[0].side = Side::Left;
        let mapper = AuMapper::new(&table, &rig);
        assert!(mapper.knows("L12".parse().unwrap()));
        assert!(!mapper.knows("L1".parse().unwrap()));
        let mut left = Activations::default();
        mapper.map([("L12".parse().unwrap(), 1.0)], &mut left);
        // a is on the left (all of it), b on the midline (half of it).
        assert_eq!(left.muscles, vec![1.5, 0.25]);
        let mut right = Activations::default();
        mapper.map([("R12".parse().unwrap(), 1.0)], &mut right);
        assert_eq!(right.muscles, vec![0.0, 0.25]);
        let mut both = Activations::default();
        mapper.map([(AuKey::new(12), 1.0)], &mut both);
        assert_eq!(both.muscles, vec![1.5, 0.5], "the sides add up to the AU");
        // Recorded sides are used as they are.
        mapper.map([("L14".parse().unwrap(), 1.0)], &mut left);
        assert_eq!(left.muscles, vec![0.4, 0.0]);
    }

    #[test]
    fn scales_clamp_and_divide() {
        assert_eq!(IntensityScale::ZeroToFive.factor(2.5), 0.5);
        assert_eq!(IntensityScale::ZeroToFive.clamp(7.0), (5.0, true));
        assert_eq!(IntensityScale::ZeroToOne.factor(0.3), 0.3);
        assert_eq!(IntensityScale::ZeroToOne.clamp(-0.1), (0.0, true));
    }
}
