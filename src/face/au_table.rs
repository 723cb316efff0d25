//! The default AU table: FACS Action Units as muscle activations of the default rig, and the
//! EMFACS emotion prototypes as AU combinations.
//!
//! Each AU is recorded at its strongest natural intensity (FACS E); combinations scale it
//! with intensity letters (A 0.15 ... E 1.0, FACS's unequal bands: `facs::combo`). The activations were tuned by looking at the
//! rendered face (`docs/gallery.md`); `docs/au.md` says which AUs are approximate and why.

use std::collections::BTreeMap;

use crate::facs::{catalogue, AuEntry, AuKey, AuTable, TABLE_VERSION};
use crate::model::Side;

/// The rig the default table is for.
pub const RIG_PATH: &str = "builtin:default";

/// Which muscles of a pair an AU uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Sides {
    /// Both sides (a bilateral AU, or a midline muscle).
    Both,
    /// The subject's left only.
    Left,
    /// The subject's right only.
    Right,
}

/// One AU: its number, the FACS name if the catalogue lacks it, `(muscle base name,
/// activation)` pairs (the base name without `L_`/`R_`; midline muscles by full name), jaw,
/// and whether FACS scores it unilaterally as well.
struct AuSpec {
    number: u8,
    muscles: &'static [(&'static str, f32)],
    jaw: f32,
    unilateral: bool,
}

const fn au(number: u8, muscles: &'static [(&'static str, f32)], jaw: f32) -> AuSpec {
    AuSpec {
        number,
        muscles,
        jaw,
        unilateral: false,
    }
}

const fn sided(number: u8, muscles: &'static [(&'static str, f32)], jaw: f32) -> AuSpec {
    AuSpec {
        number,
        muscles,
        jaw,
        unilateral: true,
    }
}

/// The AUs of the default table, strongest natural intensity. The values of the muscles
/// `rigs` gives a range (a gain under 1, so 2.0 tears nothing) are in that range: 1.625 of
/// `Labii_Nasi` at its gain of 0.4 is the field 0.65 of the bare muscle.
const AUS: &[AuSpec] = &[
    // the medial frontalis lifts the head of the brow as a band, 8.6 mm
    sided(1, &[("Frontalis_Medial", 1.5)], 0.0),
    sided(
        2,
        &[
            ("Frontalis_Outer", 1.4),
            ("Frontalis_Major", 0.5),
            ("Frontalis_Sheet", 0.6),
        ],
        0.0,
    ),
    // the whole brow comes down over the lid (the orbital fibres' sheet, 7 mm), its head
    // drawn in a little (the corrugator, which at 1.3 turned the brow's head over with it;
    // the depressor supercilii at 1.0 squeezed the skin beside the nose root to 9 %)
    sided(
        4,
        &[
            ("Orbicularis_Oculi_Superior", 1.75),
            ("Lateral_Corrugator", 0.6),
            ("Depressor_Supercilii", 0.5),
            ("Procerus", 1.0),
        ],
        0.0,
    ),
    // 1.6 at the levator palpebrae's range of 0.625: its bare field at 1.0
    au(5, &[("Levator_Palpebrae", 1.6)], 0.0),
    sided(
        6,
        &[
            ("Orbicularis_Oculi_Orbital", 2.0),
            ("Orbicularis_Oculi_Lower", 0.5),
        ],
        0.0,
    ),
    // mainly the lower lid, the upper lid a little
    sided(
        7,
        &[
            ("Orbicularis_Oculi_Lower", 1.4),
            ("Orbicularis_Oculi", 0.25),
        ],
        0.0,
    ),
    au(
        9,
        &[
            ("Inner_Labii_Nasi", 1.1),
            ("Labii_Nasi", 0.875),
            ("Procerus", 1.0),
        ],
        0.0,
    ),
    sided(10, &[("Labii_Nasi", 1.625)], 0.0),
    sided(11, &[("Zygomatic_Minor", 1.4)], 0.0),
    sided(12, &[("Zygomatic_Major", 1.5)], 0.0),
    sided(14, &[("Buccinator", 1.5)], 0.0),
    // the corners down 9 mm at E (a frown a face tracker reads, 0.3 and more)
    sided(15, &[("Angular_Depressor", 2.0)], 0.0),
    au(16, &[("Depressor_Labii_Inferioris", 0.8)], 0.0),
    au(17, &[("Mentalis", 1.1)], 0.0),
    au(18, &[("Orbicularis_Oris", 2.0)], 0.0),
    sided(20, &[("Risorius", 2.0)], 0.0),
    au(
        23,
        &[
            ("Orbicularis_Oris", 0.5),
            ("Orbicularis_Oris_Marginal", 1.2),
        ],
        0.0,
    ),
    // pressed, not pushed: the marginal sphincter presses the red together on the mouth
    // line, the mentalis pushes the lower lip up from the chin
    au(
        24,
        &[
            ("Orbicularis_Oris_Marginal", 0.4),
            ("Mentalis", 0.8),
            ("Orbicularis_Oris", 0.2),
        ],
        0.0,
    ),
    au(25, &[("Depressor_Labii_Inferioris", 0.6)], 0.8),
    // the lips stay round the opening: the sphincter draws the corners in, so the corners
    // do not stay wide and high above the dropped lower lip (which reads as a smile)
    au(26, &[("Orbicularis_Oris", 1.0)], 2.2),
    au(27, &[("Orbicularis_Oris", 0.6)], 4.0),
    au(43, &[("Orbicularis_Oculi", 2.0)], 0.0),
    au(45, &[("Orbicularis_Oculi", 2.0)], 0.0),
    sided(
        46,
        &[
            ("Orbicularis_Oculi", 2.0),
            ("Orbicularis_Oculi_Orbital", 0.625),
        ],
        0.0,
    ),
];

/// The EMFACS emotion prototypes (see `docs/au.md` for sources and intensity choices).
pub const EXPRESSIONS: &[(&str, &str)] = &[
    ("happiness", "6C+12D"),
    // the brows' heads drawn together (4A: a stronger 4 brings the whole brow down and takes
    // back the inner brow raise), the corners down (15D)
    ("sadness", "1E+4A+15D"),
    ("surprise", "1D+2D+5B+26C"),
    ("fear", "1C+2C+4C+5D+7C+20C+26B"),
    ("anger", "4D+5C+7C+23D"),
    ("disgust", "9D+15C+16B"),
    ("contempt", "R12C+R14B"),
];

/// Builds the default AU table.
pub fn default_table() -> AuTable {
    let mut aus = BTreeMap::new();
    for spec in AUS {
        let name = catalogue::name_of(spec.number)
            .unwrap_or("Unnamed")
            .to_string();
        if spec.number == 46 {
            // a wink is one eye by definition: 46 alone is the subject's right eye
            aus.insert(AuKey::new(46), entry(&name, spec, Sides::Right));
        } else {
            aus.insert(AuKey::new(spec.number), entry(&name, spec, Sides::Both));
        }
        if spec.unilateral {
            for (side, sides) in [(Side::Left, Sides::Left), (Side::Right, Sides::Right)] {
                let key = AuKey {
                    number: spec.number,
                    side: Some(side),
                };
                aus.insert(key, entry(&name, spec, sides));
            }
        }
    }
    let expressions = EXPRESSIONS
        .iter()
        .map(|(name, combo)| (name.to_string(), combo.to_string()))
        .collect();
    AuTable {
        version: TABLE_VERSION,
        rig: RIG_PATH.into(),
        aus,
        expressions,
    }
}

fn entry(name: &str, spec: &AuSpec, sides: Sides) -> AuEntry {
    let mut muscles = BTreeMap::new();
    for &(base, value) in spec.muscles {
        if is_midline(base) {
            // one side of a midline muscle: half of it
            let share = if sides == Sides::Both { 1.0 } else { 0.5 };
            muscles.insert(base.to_string(), value * share);
            continue;
        }
        if sides != Sides::Right {
            muscles.insert(format!("L_{base}"), value);
        }
        if sides != Sides::Left {
            muscles.insert(format!("R_{base}"), value);
        }
    }
    AuEntry {
        name: name.to_string(),
        muscles,
        jaw: spec.jaw,
    }
}

/// Midline muscles have no side prefix.
fn is_midline(name: &str) -> bool {
    matches!(
        name,
        "Orbicularis_Oris" | "Orbicularis_Oris_Marginal" | "Procerus"
    )
}
