//! Muscle placement on the default face: the paper's rig and the default (extended) rig.
//!
//! Every muscle is placed from the face's own geometry: points on the skin found by
//! projecting a front-view position (millimetres, from the face's proportions) onto the
//! mesh, or named landmarks, pushed under the skin by an anatomical depth. Falloff distances
//! are fractions of each muscle's own length, so the rig follows the mesh if its proportions
//! change. Muscles are placed on the subject's left (x > 0, glTF's convention) and mirrored
//! exactly to the right.

use glam::Vec3;
use thiserror::Error;

use super::anthropometry::*;
pub use super::jaw_skin::{jaw_weights, JAW_CORNER_WEIGHT};
use super::jaw_skin::{relax_jaw_weights, MouthSlit, JAW_CORNER_REACH_MM};
use super::lids::{closing_gain, LidProfile, Margin};
use super::{brow_lowering, surface};
use super::{round3, rounded};
use crate::model::{
    Convergence, Frame, Jaw, Linear, Mask, Mesh, Muscle, MuscleKind, Rig, Sheet, Side, Sphincter,
    RIG_VERSION,
};

/// The mesh path the built-in rigs name: the embedded default face.
pub const FACE_PATH: &str = "builtin:face";

/// Jaw rotation in degrees per unit of jaw activation: 4.0 turns the jaw 25 degrees, which
/// with the condyle's slide opens the mouth about 45 mm at the lips (an adult's widest
/// opening is 40 to 55 mm between the incisors); 2.0 drops the lower incisors about 18 mm.
pub const JAW_DEGREES_PER_UNIT: f32 = 6.25;

/// The condyle: height above the nasion (mm) and distance in front of the tragion (mm), just
/// in front of the tragus at the height of the ala-tragus line.
pub const CONDYLE_MM: (f64, f64) = (-38.0, 8.0);

/// How far the condyle slides forward and down the articular eminence per degree of jaw
/// turn (mm): about 19 mm over the widest opening of 25 degrees (adults: 15 to 20 mm).
pub const CONDYLE_SLIDE_MM_PER_DEGREE: f64 = 0.75;

/// The slope of the condyle's path below the horizontal (degrees): the articular eminence
/// is steeper, but the condyle rides onto its crest and the path flattens as it goes.
pub const EMINENCE_SLOPE_DEGREES: f64 = 30.0;

/// The jaw's slide per degree of turn (mm, as (down, forward)): the condyle glides forward
/// and down the articular eminence while the jaw turns about it, so the chin moves mostly
/// down; about the condyle alone it would move back almost as much as down.
pub fn jaw_slide_mm() -> (f64, f64) {
    let slope = EMINENCE_SLOPE_DEGREES.to_radians();
    (
        CONDYLE_SLIDE_MM_PER_DEGREE * slope.sin(),
        CONDYLE_SLIDE_MM_PER_DEGREE * slope.cos(),
    )
}

/// Why a rig cannot be placed on a mesh.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PlacementError {
    /// A landmark group the placement needs is missing or not a single vertex.
    #[error("the mesh has no single-vertex landmark group `{0}` (is it the default face?)")]
    MissingLandmark(String),
    /// No skin lies under a front-view position.
    #[error("no skin under ({x:.1} mm, {y:.1} mm) to place `{muscle}` on")]
    NoSkin {
        /// The muscle being placed.
        muscle: String,
        /// Front-view x (mm, the subject's left positive).
        x: f64,
        /// Front-view height above the nasion (mm).
        y: f64,
    },
}

/// Where one end of a muscle goes.
#[derive(Debug, Clone, Copy)]
enum Anchor {
    /// The skin under a front-view point (x mm, height above nasion mm), pushed this many mm
    /// under the skin.
    Skin(f64, f64, f64),
    /// A landmark, offset in the front view (mm) and pushed under the skin (mm).
    Mark(&'static str, f64, f64, f64),
}

/// A linear muscle of the subject's left side (x > 0), before placement.
struct LinearSpec {
    name: &'static str,
    attachment: Anchor,
    insertion: Anchor,
    zone: f32,
    /// Falloff start and end as fractions of the attachment-insertion length.
    falloff: (f32, f32),
}

/// The paper's 9 linear muscle pairs (names after the classic Waters set).
const PAPER_LINEAR: [LinearSpec; 9] = [
    // from the zygomatic bone to the modiolus above and outside the mouth corner
    LinearSpec {
        name: "Zygomatic_Major",
        attachment: Anchor::Skin(52.0, -26.0, 4.0),
        insertion: Anchor::Mark("left_mouth_corner", 1.5, 1.0, 1.0),
        zone: 40.0,
        falloff: (0.45, 1.3),
    },
    // depressor anguli oris: from the mandible's lower border up to the mouth corner
    LinearSpec {
        name: "Angular_Depressor",
        attachment: Anchor::Skin(33.0, -100.0, 3.0),
        insertion: Anchor::Mark("left_mouth_corner", 0.5, -1.0, 1.0),
        zone: 35.0,
        falloff: (0.4, 1.3),
    },
    // frontalis fibres from the galea at the hairline down into the brow skin
    LinearSpec {
        name: "Frontalis_Inner",
        attachment: Anchor::Skin(13.0, 60.0, 3.0),
        insertion: Anchor::Skin(16.0, 13.0, 1.0),
        zone: 30.0,
        falloff: (0.7, 1.2),
    },
    LinearSpec {
        name: "Frontalis_Major",
        attachment: Anchor::Skin(30.0, 60.0, 3.0),
        insertion: Anchor::Skin(30.0, 16.0, 1.0),
        zone: 30.0,
        falloff: (0.7, 1.2),
    },
    LinearSpec {
        name: "Frontalis_Outer",
        attachment: Anchor::Skin(43.0, 54.0, 3.0),
        insertion: Anchor::Skin(45.0, 11.0, 1.0),
        zone: 30.0,
        falloff: (0.7, 1.2),
    },
    // levator labii superioris: infraorbital margin to the upper lip beside the philtrum
    LinearSpec {
        name: "Labii_Nasi",
        attachment: Anchor::Skin(25.0, -21.0, 3.0),
        insertion: Anchor::Skin(11.0, -61.0, 1.0),
        zone: 40.0,
        falloff: (0.5, 1.2),
    },
    // levator labii superioris alaeque nasi: beside the nasal bridge to the ala and lip
    LinearSpec {
        name: "Inner_Labii_Nasi",
        attachment: Anchor::Skin(11.0, -5.0, 3.0),
        insertion: Anchor::Skin(15.0, -52.0, 1.0),
        zone: 35.0,
        falloff: (0.5, 1.15),
    },
    // corrugator supercilii: medial brow ridge to the skin of the middle brow
    LinearSpec {
        name: "Lateral_Corrugator",
        attachment: Anchor::Skin(5.0, 5.0, 4.0),
        insertion: Anchor::Skin(30.0, 15.0, 1.0),
        zone: 40.0,
        falloff: (0.6, 1.2),
    },
    // medial frontalis fibres pulling the head of the brow up and out
    LinearSpec {
        name: "Secondary_Frontalis",
        attachment: Anchor::Skin(22.0, 58.0, 3.0),
        insertion: Anchor::Skin(9.0, 12.0, 1.0),
        zone: 30.0,
        falloff: (0.7, 1.2),
    },
];

/// The default rig's levator labii superioris, in place of the paper's: its pull reaches the
/// middle of the upper lip (masked to the upper lip, see `LIP_MASKED`), which rises a little
/// more than the sides, the upper lip's straight lift of AU10.
const LABII_NASI: LinearSpec = LinearSpec {
    name: "Labii_Nasi",
    attachment: Anchor::Skin(25.0, -21.0, 3.0),
    insertion: Anchor::Skin(9.0, -63.0, 1.0),
    zone: 40.0,
    falloff: (0.7, 1.6),
};

/// The muscles the default rig adds for the AUs face trackers report.
const EXTRA_LINEAR: [LinearSpec; 8] = [
    // levator palpebrae superioris: from the orbit roof, retracts the upper lid up and back
    LinearSpec {
        name: "Levator_Palpebrae",
        attachment: Anchor::Mark("left_upper_lid_centre", 0.0, 20.0, 15.0),
        insertion: Anchor::Mark("left_upper_lid_centre", 0.0, 0.0, 0.0),
        zone: 45.0,
        falloff: (0.3, 1.28),
    },
    // orbicularis oculi, pars orbitalis: lifts the cheek toward the orbit (AU6)
    LinearSpec {
        name: "Orbicularis_Oculi_Orbital",
        attachment: Anchor::Mark("left_lower_lid_centre", 4.0, -3.0, 2.0),
        insertion: Anchor::Skin(40.0, -34.0, 1.0),
        zone: 45.0,
        falloff: (0.6, 1.4),
    },
    // buccinator: draws the mouth corner straight back (AU14)
    LinearSpec {
        name: "Buccinator",
        attachment: Anchor::Skin(44.0, -73.0, 18.0),
        insertion: Anchor::Mark("left_mouth_corner", 0.0, 0.0, 1.0),
        zone: 35.0,
        falloff: (0.6, 1.2),
    },
    // risorius: draws the mouth corner sideways (AU20)
    LinearSpec {
        name: "Risorius",
        attachment: Anchor::Skin(54.0, -72.0, 2.0),
        insertion: Anchor::Mark("left_mouth_corner", 0.0, 0.0, 1.0),
        zone: 40.0,
        falloff: (0.6, 1.2),
    },
    // mentalis: from the incisive fossa into the chin boss; it bunches the chin skin up and
    // pushes the lower lip up and out (AU17). The model's linear muscle pulls skin toward
    // its attachment, so the attachment stands for where the push goes: above and in front
    // of the lower lip (masked to the lower lip and chin, see `LIP_MASKED`)
    LinearSpec {
        name: "Mentalis",
        attachment: Anchor::Mark("lower_lip_centre", 4.0, 8.0, -14.0),
        insertion: Anchor::Skin(4.0, -108.0, 1.0),
        zone: 45.0,
        falloff: (0.5, 1.15),
    },
    // depressor labii inferioris: mandible to the lower lip, pulls it down and out (AU16);
    // its pull reaches the middle of the lower lip (masked to the lower lip)
    LinearSpec {
        name: "Depressor_Labii_Inferioris",
        attachment: Anchor::Skin(18.0, -108.0, 3.0),
        insertion: Anchor::Skin(7.0, -79.0, 1.0),
        zone: 40.0,
        falloff: (0.55, 1.45),
    },
    // depressor supercilii: medial orbit to the head of the brow, pulls it down (AU4)
    LinearSpec {
        name: "Depressor_Supercilii",
        attachment: Anchor::Skin(9.0, -6.0, 3.0),
        insertion: Anchor::Skin(15.0, 12.0, 1.0),
        zone: 40.0,
        falloff: (0.5, 1.25),
    },
    // zygomatic minor: from the zygoma to the upper lip outside the philtrum (AU11)
    LinearSpec {
        name: "Zygomatic_Minor",
        attachment: Anchor::Skin(40.0, -24.0, 4.0),
        insertion: Anchor::Skin(17.0, -62.0, 1.0),
        zone: 35.0,
        falloff: (0.5, 1.15),
    },
];

/// Places the paper's rig on the default face: 18 linear muscles, 2 frontalis sheets, the
/// mouth and eye sphincters, and the jaw.
pub fn paper_rig(mesh: &Mesh) -> Result<Rig, PlacementError> {
    let place = Placer { mesh };
    let mut muscles = Vec::new();
    for spec in &PAPER_LINEAR {
        muscles.extend(place.linear_pair(spec)?);
    }
    muscles.extend(place.frontalis_sheets()?);
    muscles.push(place.orbicularis_oris()?);
    muscles.extend(place.orbicularis_oculi()?);
    let mut rig = Rig {
        masks: Vec::new(),
        version: RIG_VERSION,
        mesh: FACE_PATH.into(),
        landmarks: None,
        combine: Default::default(),
        muscles,
        jaw: Some(place.jaw()?),
    };
    super::groups::hold_still(mesh, &mut rig);
    Ok(rig)
}

/// Places the default rig: the paper's rig plus the muscles it lacks for the AUs face
/// trackers report (levator palpebrae, pars orbitalis, buccinator, risorius, mentalis,
/// depressor labii inferioris, depressor supercilii, zygomatic minor, procerus, the marginal
/// part of the mouth sphincter, the orbital orbicularis's upper fibres).
pub fn default_rig(mesh: &Mesh) -> Result<Rig, PlacementError> {
    let mut rig = paper_rig(mesh)?;
    let place = Placer { mesh };
    for spec in &EXTRA_LINEAR {
        rig.muscles.extend(place.linear_pair(spec)?);
    }
    rig.muscles.push(place.procerus()?);
    rig.muscles.push(place.orbicularis_oris_marginal()?);
    let medial = place.frontalis_medial_sheets()?;
    for (muscle, side) in medial.iter().zip([1.0, -1.0]) {
        let lowest = y_units(-5.0) as f32; // below the sheet's reach under the brows
        rig.masks
            .push(super::brow::medial_mask(mesh, &muscle.name, side, lowest));
    }
    rig.muscles.extend(medial);
    // the orbital orbicularis's upper fibres lowering the whole brow (AU4)
    let (x, y, depth) = brow_lowering::DEPTH_AT;
    let z = place.skin(brow_lowering::NAME, x, y)?.z - units(depth) as f32;
    let lowering = frontalis_pair(brow_lowering::NAME, brow_lowering::sheet(z));
    for (muscle, side) in lowering.iter().zip([1.0, -1.0]) {
        let mask = brow_lowering::mask(mesh, &muscle.name, side);
        rig.masks
            .push(mask.ok_or_else(|| PlacementError::MissingLandmark("left_upper_lid".into()))?);
    }
    rig.muscles.extend(lowering);
    let [left, right] = place.linear_pair(&LABII_NASI)?;
    for muscle in &mut rig.muscles {
        if muscle.name == left.name {
            *muscle = left.clone();
        } else if muscle.name == right.name {
            *muscle = right.clone();
        }
    }
    place.eyelids(&mut rig)?;
    // a stronger bulge than the paper's (Z 6, not 10): the lips push forward 3.8 mm at 2.0,
    // AU18's pucker
    for muscle in &mut rig.muscles {
        if let (true, MuscleKind::Sphincter(s)) =
            (muscle.name == "Orbicularis_Oris", &mut muscle.kind)
        {
            s.bulge = 6.0;
        }
    }
    for (name, upper, own_half) in LIP_MASKED {
        for side in ["L", "R"] {
            let mask = place.lip_mask(&rig, &format!("{side}_{name}"), upper, own_half)?;
            rig.masks.push(mask);
        }
    }
    for (name, gain) in MUSCLE_RANGES {
        rig.masks.push(Mask {
            muscles: vec![format!("L_{name}"), format!("R_{name}")],
            gain,
            weights: Vec::new(),
        });
    }
    super::groups::hold_still(mesh, &mut rig);
    Ok(rig)
}

/// The range of the default rig's muscles whose bare field at full contraction (2.0) drives
/// the skin far past what the tissue over them allows: a gain on the whole field, so 2.0 is
/// the muscle's largest excursion and the AU table's values are divided by the same gain
/// (the AUs keep their shapes). Without it, at 2.0: the levator labii superioris lifted the
/// upper lip 20 mm, into the nose (58 triangles turned, edges stretched 4.9x); the frontalis
/// sheet's edge turned 21 triangles and stretched 4.9x; the mentalis pushed the lower lip up
/// over itself (19 turned); the medial frontalis stretched the brow 3.8x, the pars orbitalis
/// 2.7x and the risorius 2.6x; the orbital orbicularis's upper fibres (a sheet lowering the
/// brow its whole activation in mesh units) bring the brow 11.5 mm down at 1.0. The gains leave each muscle's 2.0 within what it does
/// without a tear (no triangle turned, no edge over 2.5x) with a margin: the levator lifts
/// the upper lip about 8 mm, the most it rises over the teeth. The levator palpebrae's 2.0
/// drew the upper lid back under the brow's fold until its small triangles turned over (one
/// at 1.6, six at 2.0); its range keeps 2.0 at 1.25 of the lid's AU5 E.
const MUSCLE_RANGES: [(&str, f32); 8] = [
    ("Labii_Nasi", 0.4),
    ("Frontalis_Sheet", 0.25),
    ("Frontalis_Medial", 0.5),
    ("Mentalis", 0.5),
    ("Orbicularis_Oculi_Orbital", 0.8),
    ("Risorius", 0.8),
    ("Levator_Palpebrae", 0.625),
    (brow_lowering::NAME, 0.4),
];

/// Lip muscles of the default rig kept to one lip: `true` for the upper lip, `false` for
/// the lower lip and chin. Their pull reaches the middle of the lip; the mask keeps it off
/// the other lip, which the mouth separates from it. The last flag fades the pull out across
/// the midline, so each side's muscle moves its own half (the middle gets half of each): for
/// the levator, whose AU10 FACS scores on one side too. The mentalis and the depressor act
/// as one midline pair (AU16 and AU17 are scored bilaterally) and keep their full pull.
const LIP_MASKED: [(&str, bool, bool); 3] = [
    ("Labii_Nasi", true, true),
    ("Depressor_Labii_Inferioris", false, false),
    ("Mentalis", false, false),
];

/// Below (or above) the mouth line outside the mouth corners, the skin is one piece: a lip
/// mask fades over this distance (mm) from the mouth line there.
const LIP_MASK_FADE_MM: f64 = 8.0;

/// Radius (mm) round a mouth corner over which a lip mask turns to a half: the corner is
/// part of both lips.
const LIP_MASK_CORNER_MM: f64 = 4.0;

/// The lip mask's weight at `outward` beyond the mouth corner (negative: between the corners)
/// and `beyond` the mouth line on the other lip's side (negative: on the muscle's own lip).
/// On its own side 1; on the other side it turns with the angle about the corner, from 1
/// along the mouth line's continuation outside the corner to 0 against the slit (the other
/// lip, which the opening separates), and fades out `fade` beyond the line. The slit is the
/// only place where it jumps; within `corner` of the corner it tends to a half, the
/// corner's own weight. (Before, the weight beyond the line rose from 0 only outward of the
/// corner, a step along the line beside it: the levator at AU10 stretched the edge below
/// the corner 2.98x, 7.1x at 2.0.)
fn lip_side_weight(outward: f64, beyond: f64, fade: f64, corner: f64) -> f64 {
    let turned = if beyond <= 0.0 {
        1.0
    } else {
        let angle = beyond.atan2(outward);
        let near_line = 1.0 - surface::smoothstep(0.0, fade, beyond);
        (1.0 - surface::smoothstep(0.0, std::f64::consts::PI, angle)) * near_line
    };
    let r = outward.hypot(beyond);
    0.5 + (turned - 0.5) * surface::smoothstep(0.0, corner, r)
}

/// How far beyond a muscle's falloff end (as a multiple of it) its lip mask lists vertices.
/// The mask is carried to fitted heads, whose zones can reach further on their face than on
/// this one: a vertex the mask does not list carries 1, and on a scanned head the levator
/// labii moved the skin 14 mm below the lower lip (AU10 turned triangles there).
const LIP_MASK_REACH: f32 = 1.5;

/// A lip mask fades from 0 to 1 between this distance (mm) on the other side of the midline
/// and the same distance on the muscle's own side.
const LIP_MASK_MIDLINE_MM: f64 = 4.0;

/// Share of a blink's travel the upper lid carries in the default rig: in a blink the upper
/// lid sweeps down over the eye and the lower lid barely rises.
pub const UPPER_LID_SHARE: f32 = 0.85;

struct Placer<'a> {
    mesh: &'a Mesh,
}

impl Placer<'_> {
    fn landmark(&self, name: &str) -> Result<Vec3, PlacementError> {
        match self.mesh.groups.get(name).map(Vec::as_slice) {
            Some([v]) => Ok(self.mesh.positions[*v as usize]),
            _ => Err(PlacementError::MissingLandmark(name.to_string())),
        }
    }

    /// The skin point under a front-view position (mm), or an error naming the muscle.
    fn skin(&self, muscle: &str, x: f64, y: f64) -> Result<Vec3, PlacementError> {
        let target = (units(x) as f32, y_units(y) as f32);
        skin_under(self.mesh, target.0, target.1).ok_or_else(|| PlacementError::NoSkin {
            muscle: muscle.to_string(),
            x,
            y,
        })
    }

    fn anchor(&self, muscle: &str, anchor: Anchor) -> Result<Vec3, PlacementError> {
        let (point, depth) = match anchor {
            Anchor::Skin(x, y, depth) => (self.skin(muscle, x, y)?, depth),
            Anchor::Mark(name, dx, dy, depth) => {
                let p = self.landmark(name)? + Vec3::new(units(dx) as f32, units(dy) as f32, 0.0);
                (p, depth)
            }
        };
        Ok(rounded(point - Vec3::new(0.0, 0.0, units(depth) as f32)))
    }

    /// A left-side linear muscle and its right mirror, left first.
    fn linear_pair(&self, spec: &LinearSpec) -> Result<[Muscle; 2], PlacementError> {
        let attachment = self.anchor(spec.name, spec.attachment)?;
        let insertion = self.anchor(spec.name, spec.insertion)?;
        let length = attachment.distance(insertion);
        let left = Linear {
            attachment,
            insertion,
            zone: spec.zone,
            falloff_start: round3(spec.falloff.0 * length),
            falloff_end: round3(spec.falloff.1 * length),
        };
        let right = Linear {
            attachment: mirror(left.attachment),
            insertion: mirror(left.insertion),
            ..left.clone()
        };
        Ok(pair(
            spec.name,
            MuscleKind::Linear(left),
            MuscleKind::Linear(right),
        ))
    }

    /// The frontalis as two sheets, each from the hairline down to its brow.
    fn frontalis_sheets(&self) -> Result<[Muscle; 2], PlacementError> {
        let name = "Frontalis";
        let a1 = self.anchor(name, Anchor::Skin(4.0, 56.0, 3.0))?;
        let a2 = self.anchor(name, Anchor::Skin(50.0, 46.0, 3.0))?;
        let l1 = self.anchor(name, Anchor::Skin(6.0, 8.0, 0.0))?;
        let l2 = self.anchor(name, Anchor::Skin(50.0, 6.0, 0.0))?;
        let axis = (0.5 * (a1 + a2)).distance(0.5 * (l1 + l2));
        Ok(frontalis_pair(
            "Frontalis_Sheet",
            Sheet {
                attachment: [a1, a2],
                insertion: [l1, l2],
                // the insertion runs just under the brows; the pull fades out 8 mm below it,
                // above the upper lids
                length: round3(axis + units(8.0) as f32),
                width: round3(units(52.0) as f32),
            },
        ))
    }

    /// The frontalis' medial fibres (default rig): the sheet moved across the midline, its
    /// medial share set by `brow::medial_mask`, so AU1 lifts the head of the brow as a band.
    fn frontalis_medial_sheets(&self) -> Result<[Muscle; 2], PlacementError> {
        let name = "Frontalis_Medial";
        let a1 = self.anchor(name, Anchor::Skin(-10.0, 56.0, 3.0))?;
        let a2 = self.anchor(name, Anchor::Skin(36.0, 50.0, 3.0))?;
        let l1 = self.anchor(name, Anchor::Skin(-10.0, 8.0, 0.0))?;
        let l2 = self.anchor(name, Anchor::Skin(36.0, 7.0, 0.0))?;
        let axis = (0.5 * (a1 + a2)).distance(0.5 * (l1 + l2));
        let sheet = Sheet {
            attachment: [a1, a2],
            insertion: [l1, l2],
            length: round3(axis + units(8.0) as f32),
            width: round3(units(52.0) as f32),
        };
        Ok(frontalis_pair(name, sheet))
    }

    /// The mouth sphincter, centred between the lips; its protected central disc keeps the
    /// middle of the lips in place while the corners draw in.
    fn orbicularis_oris(&self) -> Result<Muscle, PlacementError> {
        let upper = self.landmark("upper_lip_centre")?;
        let lower = self.landmark("lower_lip_centre")?;
        let corner = self.landmark("left_mouth_corner")?;
        let centre = rounded(0.5 * (upper + lower));
        Ok(Muscle {
            name: "Orbicularis_Oris".into(),
            side: Side::Centre,
            mirror: None,
            kind: MuscleKind::Sphincter(Sphincter {
                centre,
                semi_major: round3(corner.x + units(14.0) as f32),
                semi_minor: round3(units(10.0) as f32),
                convergence: Convergence::Centre,
                bulge: 10.0,
                frame: Frame::IDENTITY,
            }),
        })
    }

    /// The marginal part of the mouth sphincter: it converges on the mouth line (not on the
    /// centre), narrowing the red of both lips toward it with the corners nearly still and
    /// hardly any bulge (AU23's thinned, tightened lips). `ly` covers both vermilions so the
    /// lip margins, near the axis, barely move and the lips do not cross.
    fn orbicularis_oris_marginal(&self) -> Result<Muscle, PlacementError> {
        let upper = self.landmark("upper_lip_centre")?;
        let lower = self.landmark("lower_lip_centre")?;
        let corner = self.landmark("left_mouth_corner")?;
        Ok(Muscle {
            name: "Orbicularis_Oris_Marginal".into(),
            side: Side::Centre,
            mirror: None,
            kind: MuscleKind::Sphincter(Sphincter {
                centre: rounded(0.5 * (upper + lower)),
                semi_major: round3(corner.x + units(8.0) as f32),
                semi_minor: round3(units(16.0) as f32),
                convergence: Convergence::MajorAxis,
                bulge: 60.0,
                frame: Frame::IDENTITY,
            }),
        })
    }

    /// The eye sphincters, reaching a little past the eye corners.
    fn orbicularis_oculi(&self) -> Result<[Muscle; 2], PlacementError> {
        let inner = self.landmark("left_inner_eye_corner")?;
        let outer = self.landmark("left_outer_eye_corner")?;
        let upper = self.landmark("left_upper_lid_centre")?;
        let lower = self.landmark("left_lower_lid_centre")?;
        eye_sphincters([inner, outer], [upper, lower], |half_width, _| {
            half_width + units(7.0) as f32
        })
        .ok_or_else(|| PlacementError::MissingLandmark("left_upper_lid_centre (open)".into()))
    }

    /// Reshapes the default rig's eye sphincters so that closing the eye is mostly the upper
    /// lid's travel, and adds `Orbicularis_Oculi_Lower`, which tightens the lower lid alone.
    ///
    /// `Orbicularis_Oculi` gets its axis (where the lids meet) moved down to
    /// `1 - UPPER_LID_SHARE` of the opening above the lower lid, and reaches up to the brow:
    /// a closing upper lid unfolds the skin between its margin and the brow, so its travel is
    /// carried by that whole band rather than by the few millimetres above the margin (where
    /// it tore the skin 3.5 times its length). A mask shapes the pull column by column
    /// ([`LidProfile`]): each margin closes to 3 % of its way to where the lids meet, and the
    /// skin beyond it follows less and less, to nothing at the brow (the lower lid over a
    /// band as tall beyond its margin), so the lid skin stretches evenly. The mask's gain lets the ring reach that travel across the lid's width
    /// ([`closing_gain`]). `Orbicularis_Oculi_Lower` is the paper's centred sphincter masked
    /// to the lower lid side.
    fn eyelids(&self, rig: &mut Rig) -> Result<(), PlacementError> {
        let inner = self.landmark("left_inner_eye_corner")?;
        let outer = self.landmark("left_outer_eye_corner")?;
        let upper = self.landmark("left_upper_lid_centre")?;
        let lower = self.landmark("left_lower_lid_centre")?;
        let brow = self.landmark("left_brow_centre")?;
        let missing = || PlacementError::MissingLandmark("left_upper_lid_centre (open)".into());
        let opening = upper.y - lower.y;
        if opening.is_nan() || opening <= 0.0 || brow.y <= upper.y {
            return Err(missing());
        }
        let reach = |half_width: f32, _| half_width + units(7.0) as f32;
        // the lower lid's own sphincter: the paper's geometry, only below its axis
        let [lower_left, lower_right] =
            eye_sphincters([inner, outer], [upper, lower], reach).ok_or_else(missing)?;
        let upper_travel = UPPER_LID_SHARE * opening;
        let lower_travel = opening - upper_travel;
        let centre = rounded(Vec3::new(
            0.5 * (inner.x + outer.x),
            lower.y + lower_travel,
            0.5 * (upper.z + lower.z),
        ));
        // The ring's up direction runs from the lower lid margin to the upper one in the
        // ring's middle column, so the lids
        // close along the slit's own slope and meet at the lower lid's depth; heights are
        // measured along it (`local`).
        let up = self.lid_up(centre).ok_or_else(missing)?;
        let up_unit = up.normalize();
        let local = |p: Vec3| Vec3::new(p.x.abs(), centre.y + (p - centre).dot(up_unit), 0.0);
        // the lid skin: from each margin as far as the upper margin lies below the brow
        let lid_skin = brow.y - upper.y;
        let margin = |group: &str| -> Vec<Vec3> {
            let lid = self.mesh.groups.get(group).map_or(&[][..], Vec::as_slice);
            lid.iter()
                .map(|&v| local(self.mesh.positions[v as usize]))
                .collect()
        };
        let (upper_margin, lower_margin) = (margin("left_upper_lid"), margin("left_lower_lid"));
        let corners = [local(inner), local(outer)];
        let profile = LidProfile {
            upper: Margin::new(upper_margin.iter().chain(&corners).copied()),
            lower: Margin::new(lower_margin.iter().chain(&corners).copied()),
            axis: centre.y,
            lid: [upper_travel + lid_skin, lower_travel + lid_skin],
        };
        let closing = Sphincter {
            centre,
            semi_major: round3(reach(0.5 * (outer.x - inner.x).abs(), 0.0)),
            semi_minor: round3(profile.lid[0]),
            convergence: Convergence::MajorAxis,
            bulge: 30.0,
            frame: Frame { x: Vec3::X, y: up },
        };
        let gain = closing_gain(&closing, &upper_margin, &profile).ok_or_else(missing)?;
        set_closing_rings(rig, &closing);
        rig.muscles.extend(pair(
            "Orbicularis_Oculi_Lower",
            lower_left.kind.clone(),
            lower_right.kind,
        ));
        let closing_weights = self
            .mesh
            .positions
            .iter()
            .enumerate()
            .filter_map(|(i, p)| {
                let w = profile.weight(&closing, round3(gain), local(*p))?;
                (w < 1.0).then(|| (i as u32, round3(w)))
            })
            .collect();
        rig.masks.push(Mask {
            muscles: vec!["L_Orbicularis_Oculi".into(), "R_Orbicularis_Oculi".into()],
            gain: round3(gain),
            weights: closing_weights,
        });
        let MuscleKind::Sphincter(lower_ring) = &lower_left.kind else {
            return Err(missing());
        };
        rig.masks.push(self.lower_lid_mask(lower_ring));
        Ok(())
    }

    /// The closing ring's up direction: from the lower lid margin to the upper one in the
    /// ring's middle column (the lid vertices nearest the centre's x).
    fn lid_up(&self, centre: Vec3) -> Option<Vec3> {
        let in_column = |group: &str| {
            let lid = self.mesh.groups.get(group).map_or(&[][..], Vec::as_slice);
            lid.iter()
                .map(|&v| self.mesh.positions[v as usize])
                .min_by(|a, b| (a.x - centre.x).abs().total_cmp(&(b.x - centre.x).abs()))
        };
        let (top, bottom) = (in_column("left_upper_lid")?, in_column("left_lower_lid")?);
        Some(rounded(
            Vec3::new(0.0, top.y - bottom.y, top.z - bottom.z).normalize(),
        ))
    }

    /// The lower lid's own ring acts only below its axis: the vertices above it, within its
    /// reach, are held at 0.
    fn lower_lid_mask(&self, lower_ring: &Sphincter) -> Mask {
        Mask {
            muscles: vec![
                "L_Orbicularis_Oculi_Lower".into(),
                "R_Orbicularis_Oculi_Lower".into(),
            ],
            gain: 1.0,
            weights: self
                .mesh
                .positions
                .iter()
                .enumerate()
                .filter(|(_, p)| {
                    p.y >= lower_ring.centre.y
                        && (p.x.abs() - lower_ring.centre.x).abs() <= lower_ring.semi_major
                        && p.y - lower_ring.centre.y <= lower_ring.semi_minor
                })
                .map(|(i, _)| (i as u32, 0.0))
                .collect(),
        }
    }

    /// A mask keeping the muscle `name` to the upper (`upper`) or the lower lip on its own
    /// side: weight 0 on the other lip, across the slit, and round each mouth corner a weight
    /// that turns with the angle about the corner ([`lip_side_weight`]), so the one-piece
    /// skin beside and below (or above) the corner is not torn; across the midline the weight
    /// fades out over [`LIP_MASK_MIDLINE_MM`] if `own_half`. Only vertices within
    /// [`LIP_MASK_REACH`] times the muscle's reach are listed.
    fn lip_mask(
        &self,
        rig: &Rig,
        name: &str,
        upper: bool,
        own_half: bool,
    ) -> Result<Mask, PlacementError> {
        let corner = self.landmark("left_mouth_corner")?;
        let mouth_y =
            0.5 * (self.landmark("upper_lip_centre")?.y + self.landmark("lower_lip_centre")?.y);
        let Some(Muscle {
            kind: MuscleKind::Linear(muscle),
            ..
        }) = rig.muscles.iter().find(|m| m.name == name)
        else {
            return Err(PlacementError::MissingLandmark(format!(
                "{name} (a linear muscle)"
            )));
        };
        let own_side = muscle.insertion.x.signum();
        let fade = units(LIP_MASK_FADE_MM);
        let midline = units(LIP_MASK_MIDLINE_MM);
        let weights = self
            .mesh
            .positions
            .iter()
            .enumerate()
            .filter(|(_, p)| muscle.attachment.distance(**p) <= LIP_MASK_REACH * muscle.falloff_end)
            .filter_map(|(i, p)| {
                let beyond = f64::from(if upper { mouth_y - p.y } else { p.y - mouth_y });
                let outward = f64::from(p.x.abs() - corner.x);
                let lip = lip_side_weight(outward, beyond, fade, units(LIP_MASK_CORNER_MM));
                let side = if own_half {
                    surface::smoothstep(-midline, midline, f64::from(p.x * own_side))
                } else {
                    1.0
                };
                let w = round3((lip * side) as f32);
                (w < 1.0).then_some((i as u32, w))
            })
            .collect();
        Ok(Mask {
            muscles: vec![name.to_string()],
            gain: 1.0,
            weights,
        })
    }

    /// The procerus: a midline muscle from the nasal bones up into the glabella skin; it
    /// draws the skin between the brows down (AU4, AU9).
    fn procerus(&self) -> Result<Muscle, PlacementError> {
        let name = "Procerus";
        Ok(Muscle {
            name: name.into(),
            side: Side::Centre,
            mirror: None,
            kind: MuscleKind::Linear({
                let attachment = self.anchor(name, Anchor::Skin(0.0, -14.0, 3.0))?;
                let insertion = self.anchor(name, Anchor::Skin(0.0, 10.0, 1.0))?;
                let length = attachment.distance(insertion);
                Linear {
                    attachment,
                    insertion,
                    zone: 35.0,
                    falloff_start: round3(0.5 * length),
                    falloff_end: round3(1.25 * length),
                }
            }),
        })
    }

    /// The jaw: a turn about the condyles with their slide down the articular eminence, and
    /// weights over the lower face and the parts of the mouth that the mandible carries.
    fn jaw(&self) -> Result<Jaw, PlacementError> {
        let corner = self.landmark("left_mouth_corner")?;
        let upper = self.landmark("upper_lip_centre")?;
        let lower = self.landmark("lower_lip_centre")?;
        let mouth_y = 0.5 * (upper.y + lower.y);
        let skin = super::groups::skin_len(self.mesh);
        let weights = jaw_weights(&self.mesh.positions[..skin], mouth_y, corner.x);
        let slit = MouthSlit {
            corner,
            mouth_y,
            corner_weight: JAW_CORNER_WEIGHT,
            corner_reach: units(JAW_CORNER_REACH_MM),
        };
        let mut weights = relax_jaw_weights(self.mesh, skin, &weights, &slit, |p| {
            p.y >= mouth_y
                && p.x.abs() < corner.x
                && Vec3::new(p.x.abs(), p.y, p.z).distance(corner)
                    > units(JAW_CORNER_REACH_MM) as f32
        });
        weights.extend(
            super::groups::jaw_parts(self.mesh)
                .into_iter()
                .map(|v| (v, 1.0)),
        );
        let (down, forward) = jaw_slide_mm();
        Ok(Jaw {
            axis: glam::Vec3::X,
            pivot: rounded(Vec3::new(
                0.0,
                y_units(CONDYLE_MM.0) as f32,
                units(-HEAD_DEPTH + CONDYLE_MM.1) as f32,
            )),
            degrees_per_unit: JAW_DEGREES_PER_UNIT,
            weights,
            slide: Vec3::new(0.0, -units(down) as f32, units(forward) as f32),
        })
    }
}

/// The highest-z point of the skin under front-view position `(x, y)` (mesh units), found
/// on the triangles that face the viewer.
pub fn skin_under(mesh: &Mesh, x: f32, y: f32) -> Option<Vec3> {
    let mut best: Option<Vec3> = None;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        let n = (b - a).cross(c - a);
        if n.z <= 0.0 {
            continue;
        }
        let det = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
        if det.abs() < 1e-12 {
            continue;
        }
        let l0 = ((b.y - c.y) * (x - c.x) + (c.x - b.x) * (y - c.y)) / det;
        let l1 = ((c.y - a.y) * (x - c.x) + (a.x - c.x) * (y - c.y)) / det;
        let l2 = 1.0 - l0 - l1;
        if l0 < -1e-6 || l1 < -1e-6 || l2 < -1e-6 {
            continue;
        }
        let z = l0 * a.z + l1 * b.z + l2 * c.z;
        if best.is_none_or(|p| z > p.z) {
            best = Some(Vec3::new(x, y, z));
        }
    }
    best
}

/// Both orbicularis oculi become the closing ring `closing` (placed on the subject's left),
/// the right one mirrored.
fn set_closing_rings(rig: &mut Rig, closing: &Sphincter) {
    for muscle in &mut rig.muscles {
        let left = muscle.name == "L_Orbicularis_Oculi";
        if left || muscle.name == "R_Orbicularis_Oculi" {
            muscle.kind = MuscleKind::Sphincter(Sphincter {
                centre: if left {
                    closing.centre
                } else {
                    mirror(closing.centre)
                },
                ..closing.clone()
            });
        }
    }
}

/// Both eye sphincters from the left eye's corners and lid-margin centres: centred on the
/// line where the lids meet when they close (halfway between the margins), so both lids
/// converge on it. A lid margin at `t = |Py| / ly` on the centre line moves `K t (1 - t)`
/// toward the major axis; `ly` is chosen so that the margins just reach it at K = 2:
/// `2 t (1 - t) = h` with h the half opening, taking the smaller root so the band of orbital
/// skin between lid and brow moves with the lid. `semi_major` gets the eye's half width and
/// the semi-minor axis. `None` for an eye that is not open.
pub(crate) fn eye_sphincters(
    [inner, outer]: [Vec3; 2],
    [upper, lower]: [Vec3; 2],
    semi_major: impl Fn(f32, f32) -> f32,
) -> Option<[Muscle; 2]> {
    let half_opening = 0.5 * (upper.y - lower.y);
    if half_opening.is_nan() || half_opening <= 0.0 {
        return None;
    }
    let t = 0.5 * (1.0 - (1.0 - 2.0 * half_opening).max(0.0).sqrt());
    let semi_minor = half_opening / t;
    let centre = rounded(Vec3::new(
        0.5 * (inner.x + outer.x),
        0.5 * (upper.y + lower.y),
        0.5 * (upper.z + lower.z),
    ));
    let left = Sphincter {
        centre,
        semi_major: round3(semi_major(0.5 * (outer.x - inner.x).abs(), semi_minor)),
        semi_minor: round3(semi_minor),
        convergence: Convergence::MajorAxis,
        bulge: 30.0,
        frame: Frame::IDENTITY,
    };
    let right = Sphincter {
        centre: mirror(centre),
        ..left.clone()
    };
    Some(pair(
        "Orbicularis_Oculi",
        MuscleKind::Sphincter(left),
        MuscleKind::Sphincter(right),
    ))
}

/// A pair of frontalis sheets (`L_name`, `R_name`) from the left one: the right mirrors its
/// corners (listed in the same order around the sheet, so the mirror keeps the sheet's
/// orientation).
pub(crate) fn frontalis_pair(name: &str, left: Sheet) -> [Muscle; 2] {
    let [a1, a2] = left.attachment;
    let [l1, l2] = left.insertion;
    let right = Sheet {
        attachment: [mirror(a2), mirror(a1)],
        insertion: [mirror(l2), mirror(l1)],
        ..left.clone()
    };
    pair(name, MuscleKind::Sheet(left), MuscleKind::Sheet(right))
}

/// The subject's left (x > 0) and right muscles of a pair, named `L_name` and `R_name`.
pub(crate) fn pair(name: &str, left: MuscleKind, right: MuscleKind) -> [Muscle; 2] {
    let (l, r) = (format!("L_{name}"), format!("R_{name}"));
    [
        Muscle {
            name: l.clone(),
            side: Side::Left,
            mirror: Some(r.clone()),
            kind: left,
        },
        Muscle {
            name: r,
            side: Side::Right,
            mirror: Some(l),
            kind: right,
        },
    ]
}

/// The point reflected across the face's midline (x = 0).
pub(crate) use crate::model::muscle::mirror_x as mirror;
