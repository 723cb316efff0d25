//! Combination strings: generated combos print and parse back; no string makes the parser
//! panic; evaluation of random combos on a random table stays in range.

use std::path::PathBuf;

use glam::Vec3;
use grimace::facs::combo::{parse_combo, Combo, Intensity, Term};
use grimace::facs::{AuEntry, AuKey, AuTable};
use grimace::model::{Linear, Muscle, MuscleKind, Rig, Side, JAW_RANGE, MUSCLE_RANGE};
use proptest::prelude::*;

fn key() -> impl Strategy<Value = AuKey> {
    (1u8..=99, prop::option::of(prop::bool::ANY)).prop_map(|(number, side)| AuKey {
        number,
        side: side.map(|left| if left { Side::Left } else { Side::Right }),
    })
}

fn intensity() -> impl Strategy<Value = Intensity> {
    prop_oneof![
        Just(Intensity::Full),
        prop::sample::select(vec!['A', 'B', 'C', 'D', 'E']).prop_map(Intensity::Letter),
        (0u32..100_000).prop_map(|n| Intensity::Scale(n as f32 / 1000.0)),
    ]
}

fn combo() -> impl Strategy<Value = Combo> {
    prop::collection::vec((key(), intensity()), 1..8).prop_map(|terms| Combo {
        terms: terms
            .into_iter()
            .map(|(key, intensity)| Term { key, intensity })
            .collect(),
    })
}

fn rig(n: usize) -> Rig {
    Rig {
        masks: Vec::new(),
        version: grimace::model::RIG_VERSION,
        mesh: PathBuf::from("m.obj"),
        landmarks: None,
        combine: Default::default(),
        muscles: (0..n)
            .map(|i| Muscle {
                name: format!("m{i}"),
                side: Side::Centre,
                mirror: None,
                kind: MuscleKind::Linear(Linear {
                    attachment: Vec3::ZERO,
                    insertion: Vec3::X,
                    zone: 40.0,
                    falloff_start: 0.1,
                    falloff_end: 2.0,
                }),
            })
            .collect(),
        jaw: None,
    }
}

proptest! {
    #[test]
    fn generated_combos_round_trip(c in combo()) {
        let text = c.to_string();
        prop_assert_eq!(parse_combo(&text).unwrap(), c.clone());
        // Spaces around terms and `+` change nothing.
        let spaced = format!("  {}\t", text.replace('+', " + "));
        prop_assert_eq!(parse_combo(&spaced).unwrap(), c);
    }

    #[test]
    fn any_string_parses_or_errors_within_it(s in "[LRlr0-9A-Fa-f@.+ \t,xé-]{0,24}") {
        match parse_combo(&s) {
            Ok(c) => prop_assert!(!c.terms.is_empty()),
            Err(e) => prop_assert!(e.column >= 1 && e.column <= s.chars().count() + 1, "{e}"),
        }
    }

    #[test]
    fn evaluation_stays_in_range_and_reports_every_missing_au(
        c in combo(),
        entries in prop::collection::btree_map(key(), (prop::collection::vec(0.0f32..=2.0, 4), 0.0f32..=4.0), 0..30),
    ) {
        let r = rig(4);
        let mut table = AuTable::new("r.rig.ron");
        for (k, (values, jaw)) in entries {
            let muscles = values.iter().enumerate().map(|(i, v)| (format!("m{i}"), *v)).collect();
            table.aus.insert(k, AuEntry { name: String::new(), muscles, jaw });
        }
        // A key is given when recorded, or derived: one side from the bilateral recording,
        // the bilateral AU from its recorded sides.
        let given = |k: &AuKey| {
            let bilateral = AuKey::new(k.number);
            let sides = ["L", "R"].map(|s| format!("{s}{}", k.number).parse::<AuKey>().unwrap());
            table.aus.contains_key(k)
                || (k.side.is_some() && table.aus.contains_key(&bilateral))
                || (k.side.is_none() && sides.iter().any(|s| table.aus.contains_key(s)))
        };
        let missing: Vec<AuKey> = c.terms.iter().map(|t| t.key).filter(|k| !given(k)).collect();
        match table.evaluate(&c, &r) {
            Ok(act) => {
                prop_assert!(missing.is_empty());
                prop_assert!(act.muscles.iter().all(|v| MUSCLE_RANGE.contains(v)));
                prop_assert!(JAW_RANGE.contains(&act.jaw));
                act.validate(&r).unwrap();
            }
            Err(grimace::facs::table::TableError::MissingAus(keys)) => {
                for k in &missing {
                    prop_assert!(keys.contains(k));
                }
                prop_assert!(keys.iter().all(|k| missing.contains(k)));
            }
            Err(other) => prop_assert!(false, "{other}"),
        }
    }
}
