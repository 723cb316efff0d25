//! AU tables: evaluating combinations, recording, renaming and removing AUs, expressions.

use std::path::PathBuf;

use glam::Vec3;
use grimace::facs::combo::parse_combo;
use grimace::facs::table::TableError;
use grimace::facs::{AuEntry, AuKey, AuTable, MAX_AUS};
use grimace::model::{Activations, Linear, Muscle, MuscleKind, Rig, Side, RIG_VERSION};

fn rig(names: &[&str]) -> Rig {
    Rig {
        masks: Vec::new(),
        version: RIG_VERSION,
        mesh: PathBuf::from("m.obj"),
        landmarks: None,
        combine: Default::default(),
        muscles: names
            .iter()
            .map(|n| Muscle {
                name: n.to_string(),
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

fn key(s: &str) -> AuKey {
    s.parse().unwrap()
}

fn entry(muscles: &[(&str, f32)], jaw: f32) -> AuEntry {
    AuEntry {
        name: String::new(),
        muscles: muscles.iter().map(|(m, v)| (m.to_string(), *v)).collect(),
        jaw,
    }
}

fn table() -> AuTable {
    let mut t = AuTable::new("r.rig.ron");
    t.aus.insert(key("6"), entry(&[("orb", 1.0)], 0.0));
    t.aus
        .insert(key("12"), entry(&[("zl", 1.5), ("zr", 1.5)], 0.0));
    t.aus.insert(key("R12"), entry(&[("zr", 0.8)], 0.0));
    t.aus.insert(key("26"), entry(&[], 3.0));
    t
}

fn r() -> Rig {
    rig(&["zl", "zr", "orb", "other"])
}

#[test]
fn evaluate_scales_adds_and_clamps() {
    let t = table();
    let a = t.evaluate(&parse_combo("6+12C").unwrap(), &r()).unwrap();
    assert_eq!(a.muscles, vec![1.5 * 0.5, 1.5 * 0.5, 1.0, 0.0]);
    assert_eq!(a.jaw, 0.0);

    // 12 at full plus R12 at 1.0: zr = 1.5 + 0.8 = 2.3, clamped to 2.
    let a = t.evaluate(&parse_combo("12+R12").unwrap(), &r()).unwrap();
    assert_eq!(a.muscles, vec![1.5, 2.0, 0.0, 0.0]);

    // Jaw 3.0 * 2 = 6, clamped to 4; B = 0.3 -> 0.9.
    assert_eq!(
        t.evaluate(&parse_combo("26@2").unwrap(), &r()).unwrap().jaw,
        4.0
    );
    assert_eq!(
        t.evaluate(&parse_combo("26B").unwrap(), &r()).unwrap().jaw,
        3.0 * 0.3
    );

    // Scale 0 leaves the rest state.
    assert!(t
        .evaluate(&parse_combo("12@0").unwrap(), &r())
        .unwrap()
        .is_rest());
}

#[test]
fn missing_aus_are_all_reported() {
    let err = table()
        .evaluate(&parse_combo("1+12+L12+L1+1+5B").unwrap(), &r())
        .unwrap_err();
    assert_eq!(
        err,
        TableError::MissingAus(vec![key("1"), key("L1"), key("5")])
    );
    assert_eq!(err.to_string(), "the table has no AU 1, L1, 5");
}

#[test]
fn unknown_muscles_are_errors_not_dropped() {
    let err = table()
        .evaluate(&parse_combo("12").unwrap(), &rig(&["zl"]))
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "AU 12 names muscle `zr`, which the rig does not have"
    );
}

#[test]
fn entry_activations_are_the_recorded_values() {
    let a = table().entry_activations(&key("R12"), &r()).unwrap();
    assert_eq!(a.muscles, vec![0.0, 0.8, 0.0, 0.0]);
    assert_eq!(
        table().entry_activations(&key("4"), &r()).unwrap_err(),
        TableError::NoSuchAu(key("4"))
    );
}

#[test]
fn record_stores_non_zero_muscles_by_name() {
    let mut t = AuTable::new("r.rig.ron");
    let act = Activations {
        muscles: vec![0.0, 1.25, 0.0, 0.5],
        jaw: 1.5,
    };
    t.record(key("L12"), "", &r(), &act).unwrap();
    let e = &t.aus[&key("L12")];
    assert_eq!(e.name, "Lip Corner Puller");
    assert_eq!(
        e.muscles.iter().collect::<Vec<_>>(),
        [(&"other".to_string(), &0.5), (&"zr".to_string(), &1.25)]
    );
    assert_eq!(e.jaw, 1.5);
    // Reading it back gives the same activations.
    assert_eq!(t.entry_activations(&key("L12"), &r()).unwrap(), act);

    // Out of range activations and non-FACS codes are refused.
    let bad = Activations {
        muscles: vec![0.0, 2.5, 0.0, 0.0],
        jaw: 0.0,
    };
    assert!(t.record(key("12"), "x", &r(), &bad).is_err());
    assert_eq!(
        t.record(key("3"), "x", &r(), &act).unwrap_err(),
        TableError::NotFacs(key("3"))
    );
}

#[test]
fn the_table_holds_at_most_64_aus() {
    let mut t = AuTable::new("r.rig.ron");
    let act = Activations::zero(&r());
    let codes: Vec<u8> = grimace::facs::catalogue::CATALOGUE
        .iter()
        .map(|a| a.number)
        .collect();
    let mut keys = vec![];
    for n in &codes {
        keys.push(AuKey::new(*n));
        keys.push(key(&format!("L{n}")));
    }
    for k in &keys[..MAX_AUS] {
        t.record(*k, "", &r(), &act).unwrap();
    }
    assert_eq!(
        t.record(keys[MAX_AUS], "", &r(), &act),
        Err(TableError::Full)
    );
    // Replacing an existing AU in a full table is fine.
    t.record(keys[0], "again", &r(), &act).unwrap();
    assert_eq!(t.aus.len(), MAX_AUS);
    t.check().unwrap();
    t.aus.insert(keys[MAX_AUS], AuEntry::default());
    assert_eq!(t.check(), Err(TableError::TooManyAus(65)));
}

#[test]
fn rename_rewrites_expressions_and_remove_protects_them() {
    let mut t = table();
    t.set_expression("happy", "6 + 12B").unwrap();
    t.set_expression("lopsided", "R12+26A").unwrap();
    assert_eq!(
        t.set_expression("bad", "6+4"),
        Err(TableError::ExpressionMissingAus {
            expression: "bad".into(),
            missing: vec![key("4")]
        })
    );
    assert!(matches!(
        t.set_expression("bad", "6+"),
        Err(TableError::BadCombo { .. })
    ));

    t.rename(&key("12"), key("L12")).unwrap();
    assert_eq!(t.expressions["happy"], "6+L12B");
    assert_eq!(t.expressions["lopsided"], "R12+26A");
    assert!(t.aus.contains_key(&key("L12")) && !t.aus.contains_key(&key("12")));
    assert_eq!(
        t.rename(&key("L12"), key("R12")),
        Err(TableError::Exists(key("R12")))
    );
    assert_eq!(
        t.rename(&key("L12"), key("40")),
        Err(TableError::NotFacs(key("40")))
    );

    let err = t.remove(&key("26")).unwrap_err();
    assert_eq!(
        err.to_string(),
        "AU 26 is used by expression `lopsided`; change or remove those first"
    );
    t.remove_expression("lopsided").unwrap();
    assert_eq!(t.remove(&key("26")).unwrap().jaw, 3.0);
    t.check().unwrap();

    let a = t.expression_activations("happy", &r()).unwrap();
    assert_eq!(a.muscles, vec![1.5 * 0.3, 1.5 * 0.3, 1.0, 0.0]);
    assert_eq!(
        t.expression_activations("sad", &r()),
        Err(TableError::NoSuchExpression("sad".into()))
    );
}
