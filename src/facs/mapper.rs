//! From AUs to muscle activations: the one mapper every front end uses.
//!
//! Each AU's recorded activations (its [`AuEntry`](crate::facs::AuEntry)) are scaled by the
//! AU's factor, the scaled AUs add up, and the sum is clamped to the activation ranges
//! ([`clamp_to_ranges`]) -- the way the FACS letters A-E scale an AU (E = 5/5 = 1.0).
//!
//! An AU key resolves to recordings by one rule ([`resolve`]): the key itself when recorded;
//! a bilateral key the table records only by side is both recorded sides (`12` is `L12` +
//! `R12`); a one-sided key the table records only bilaterally is derived from that recording
//! ([`resolve`] lives with the AU keys)
//! (`L45` is the `45` recording's left muscles and half its midline muscles and jaw, so
//! `L45` and `R45` add up to `45`). The editor's `:combo`, `render`, `export` (OBJ and glTF) and `play` all
//! go through [`AuMapper`], so every key one accepts, the others accept.
//!
//! The mapper resolves muscle names once, so a frame costs one multiply-add per recorded
//! muscle of each active AU.

use std::collections::{BTreeMap, BTreeSet};

use super::au::{resolve, AuKey, Resolved};
use super::combo::Combo;
use super::table::{AuTable, TableError};
use crate::model::{Activations, Rig, Side, JAW_RANGE, MUSCLE_RANGE};

/// Clamps muscles to 0-2 and the jaw to 0-4.
pub fn clamp_to_ranges(act: &mut Activations) {
    for value in &mut act.muscles {
        *value = value.clamp(*MUSCLE_RANGE.start(), *MUSCLE_RANGE.end());
    }
    act.jaw = act.jaw.clamp(*JAW_RANGE.start(), *JAW_RANGE.end());
}

/// One AU's recorded activations, resolved to rig indices.
#[derive(Debug, Clone, Default, PartialEq)]
struct Contribution {
    muscles: Vec<(usize, f32)>,
    jaw: f32,
}

/// Turns AUs with factors into activations for one rig and table.
#[derive(Debug, Clone)]
pub struct AuMapper {
    muscle_count: usize,
    recorded: BTreeMap<AuKey, Contribution>,
    /// One-sided AUs the table only records bilaterally, made from that recording.
    derived: BTreeMap<AuKey, Contribution>,
    unknown_muscles: BTreeSet<String>,
}

impl AuMapper {
    /// Resolves every recorded AU of `table` against `rig`. Muscle names the rig lacks are
    /// collected (see [`AuMapper::unknown_muscles`]) and contribute nothing.
    pub fn new(table: &AuTable, rig: &Rig) -> AuMapper {
        let mut unknown_muscles = BTreeSet::new();
        let mut recorded = BTreeMap::new();
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
            recorded.insert(*key, Contribution { muscles, jaw });
        }
        let derived = one_sided_from_bilateral(&recorded, rig);
        AuMapper {
            muscle_count: rig.muscles.len(),
            recorded,
            derived,
            unknown_muscles,
        }
    }

    /// Muscle names the table uses but the rig lacks.
    pub fn unknown_muscles(&self) -> &BTreeSet<String> {
        &self.unknown_muscles
    }

    /// The notice every command gives when the table names muscles the rig lacks.
    pub fn unknown_notice(&self) -> Option<String> {
        (!self.unknown_muscles.is_empty()).then(|| {
            let names: Vec<&str> = self.unknown_muscles.iter().map(String::as_str).collect();
            format!(
                "the AU table names muscles the rig lacks (ignored): {}",
                names.join(", ")
            )
        })
    }

    /// Whether the table gives this AU (see [`resolve`]).
    pub fn knows(&self, key: AuKey) -> bool {
        resolve(&self.recorded, key) != Resolved::Missing
    }

    fn contributions(&self, key: AuKey) -> Vec<&Contribution> {
        match resolve(&self.recorded, key) {
            Resolved::Recorded => self.recorded.get(&key).into_iter().collect(),
            Resolved::Sides(sides) => sides.iter().filter_map(|k| self.recorded.get(k)).collect(),
            Resolved::FromBilateral(_) => self.derived.get(&key).into_iter().collect(),
            Resolved::Missing => Vec::new(),
        }
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
            for contribution in self.contributions(key) {
                for &(index, value) in &contribution.muscles {
                    out.muscles[index] += factor * value;
                }
                out.jaw += factor * contribution.jaw;
            }
        }
        clamp_to_ranges(out);
    }
}

/// The one-sided AUs a table records only bilaterally (`L45`, `R45` from `45`): the
/// recording's muscles on that side, and half of its midline muscles and jaw, so the two
/// sides add up to the bilateral AU.
fn one_sided_from_bilateral(
    recorded: &BTreeMap<AuKey, Contribution>,
    rig: &Rig,
) -> BTreeMap<AuKey, Contribution> {
    let mut derived = BTreeMap::new();
    for (key, whole) in recorded.iter().filter(|(k, _)| k.side.is_none()) {
        for side in [Side::Left, Side::Right] {
            let sided = AuKey {
                number: key.number,
                side: Some(side),
            };
            if recorded.contains_key(&sided) {
                continue;
            }
            let half = Contribution {
                muscles: whole
                    .muscles
                    .iter()
                    .filter_map(|&(i, v)| match rig.muscles[i].side {
                        Side::Centre => Some((i, v * 0.5)),
                        s if s == side => Some((i, v)),
                        _ => None,
                    })
                    .collect(),
                jaw: whole.jaw * 0.5,
            };
            derived.insert(sided, half);
        }
    }
    derived
}

/// Evaluating a table's AUs and expressions on a rig, through the mapper.
impl AuTable {
    /// The activations of one AU on a rig, at full intensity (see [`AuTable::evaluate`]).
    pub fn entry_activations(&self, key: &AuKey, rig: &Rig) -> Result<Activations, TableError> {
        if !self.gives(*key) {
            return Err(TableError::NoSuchAu(*key));
        }
        self.map_checked([(*key, 1.0)], rig)
    }

    /// Evaluates a combination on a rig through [`AuMapper`]: each term's AU scaled by its
    /// intensity; overlapping AUs add, then every value is clamped to its range (muscles
    /// 0-2, jaw 0-4). AUs the table cannot give are all reported together
    /// ([`TableError::MissingAus`]).
    pub fn evaluate(&self, combo: &Combo, rig: &Rig) -> Result<Activations, TableError> {
        let missing = self.missing(combo);
        if !missing.is_empty() {
            return Err(TableError::MissingAus(missing));
        }
        self.map_checked(
            combo
                .terms
                .iter()
                .map(|term| (term.key, term.intensity.factor())),
            rig,
        )
    }

    /// Maps AUs the table gives, refusing a recording that names a muscle the rig lacks.
    fn map_checked(
        &self,
        aus: impl IntoIterator<Item = (AuKey, f32)> + Clone,
        rig: &Rig,
    ) -> Result<Activations, TableError> {
        for (key, _) in aus.clone() {
            for source in self.sources_of(key) {
                let entry = &self.aus[&source];
                if let Some(muscle) = entry.muscles.keys().find(|m| rig.muscle_index(m).is_none()) {
                    return Err(TableError::UnknownMuscle {
                        au: source,
                        muscle: muscle.clone(),
                    });
                }
            }
        }
        let mut out = Activations::zero(rig);
        AuMapper::new(self, rig).map(aus, &mut out);
        Ok(out)
    }

    /// Evaluates a named expression on a rig (see [`AuTable::evaluate`]).
    pub fn expression_activations(&self, name: &str, rig: &Rig) -> Result<Activations, TableError> {
        let combo = self
            .expressions
            .get(name)
            .ok_or_else(|| TableError::NoSuchExpression(name.to_string()))?;
        let parsed = self.check_expression(name, combo)?;
        self.evaluate(&parsed, rig)
    }
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
            landmarks: None,
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
    fn the_table_resolves_keys_by_the_same_rule() {
        let (_, table) = rig_and_table();
        let key = |t: &str| t.parse::<AuKey>().unwrap();
        assert_eq!(resolve(&table.aus, key("12")), Resolved::Recorded);
        assert_eq!(
            resolve(&table.aus, key("L12")),
            Resolved::FromBilateral(key("12"))
        );
        assert_eq!(
            resolve(&table.aus, key("14")),
            Resolved::Sides(vec![key("L14"), key("R14")])
        );
        assert_eq!(resolve(&table.aus, key("L1")), Resolved::Missing);
    }

    #[test]
    fn clamping_keeps_muscles_and_jaw_in_range() {
        let mut act = Activations {
            muscles: vec![-1.0, 0.5, 9.0],
            jaw: 7.0,
        };
        clamp_to_ranges(&mut act);
        assert_eq!((act.muscles, act.jaw), (vec![0.0, 0.5, 2.0], 4.0));
    }
}
