//! Facial proportions of the default face, from published anthropometry.
//!
//! All lengths are in millimetres and follow Farkas' norms for young adults (Farkas 1994;
//! Farkas, Katic & Forrest 2005), averaged over both sexes and rounded; `docs/face.md` lists
//! each measurement with its source value. Heights are measured from the nasion (`n`), up
//! positive; widths are half-widths from the midline. The generator turns millimetres into
//! mesh units with [`MM_PER_UNIT`] so the face is about 16 units tall, like the classic face
//! the paper's muscle constants were tuned on.

/// Millimetres per mesh unit: the 185 mm from the chin to the top of the forehead become
/// about 16 units.
pub const MM_PER_UNIT: f64 = 11.5;

/// Height (above the nasion, mm) of the mesh's y = 0: roughly the middle of the face, so
/// the face spans about -8.7 to 7.4 units like the classic one.
pub const Y_ORIGIN_MM: f64 = -20.0;

/// Gnathion: the lowest point of the chin. `n-gn` (morphological face height) = 120 mm.
pub const GNATHION_Y: f64 = -120.0;
/// Stomion: the mouth line. `n-sto` (upper face height) = 71 mm.
pub const STOMION_Y: f64 = -71.0;
/// Subnasale: where the columella meets the upper lip. `n-sn` (nose height) = 51 mm.
pub const SUBNASALE_Y: f64 = -51.0;
/// Pronasale (nose tip) height: about 8 mm above the subnasale.
pub const PRONASALE_Y: f64 = -43.0;
/// Nasal tip protrusion `sn-prn` = 20 mm.
pub const TIP_PROTRUSION: f64 = 20.0;
/// Labiale superius: the upper vermilion border on the midline (`ls-sto` = 8 mm).
pub const LABIALE_SUPERIUS_Y: f64 = STOMION_Y + 8.0;
/// Labiale inferius: the lower vermilion border on the midline (`sto-li` = 9 mm).
pub const LABIALE_INFERIUS_Y: f64 = STOMION_Y - 9.0;
/// Sublabiale: the deepest point of the mentolabial sulcus.
pub const SUBLABIALE_Y: f64 = -93.0;
/// Pogonion: the most prominent point of the chin.
pub const POGONION_Y: f64 = -109.0;
/// Trichion (hairline): forehead height `tr-n` = 62 mm; the mesh ends a little above it.
pub const TRICHION_Y: f64 = 62.0;
/// Top edge of the mesh on the midline.
pub const TOP_Y: f64 = 66.0;

/// The palpebral fissure (eye slit) height at the inner corner: the endocanthion lies about
/// 9 mm below the nasion.
pub const EYE_LINE_Y: f64 = -9.0;
/// Endocanthion half-width: intercanthal width `en-en` = 32 mm.
pub const ENDOCANTHION_X: f64 = 16.0;
/// Exocanthion half-width: biocular width `ex-ex` = 90 mm (eye fissure `ex-en` = 29 mm).
pub const EXOCANTHION_X: f64 = 45.0;
/// Lateral canthus rise over the medial one (a canthal tilt of about 5 degrees).
pub const CANTHAL_TILT: f64 = 2.5;
/// Upper lid: how far the upper lid margin lies above the corner line at its highest.
pub const UPPER_LID_OPENING: f64 = 5.5;
/// Lower lid: how far the lower lid margin lies below the corner line at its lowest; with
/// the upper opening this gives an eye fissure height `ps-pi` of about 9 mm.
pub const LOWER_LID_OPENING: f64 = 3.5;
/// Brow (superciliary) line height above the nasion.
pub const BROW_Y: f64 = 11.0;

/// Alare half-width: nose width `al-al` = 34 mm.
pub const ALARE_X: f64 = 17.0;
/// Cheilion half-width: mouth width `ch-ch` = 52 mm.
pub const CHEILION_X: f64 = 26.0;
/// Zygion half-width: face width `zy-zy` = 134 mm.
pub const ZYGION_X: f64 = 67.0;
/// Gonion half-width: mandible width `go-go` = 96 mm.
pub const GONION_X: f64 = 48.0;
/// Gonion height: the angle of the mandible lies a little below the mouth line.
pub const GONION_Y: f64 = -88.0;
/// Frontotemporale half-width: minimum forehead width `ft-ft` = 112 mm.
pub const FRONTOTEMPORALE_X: f64 = 56.0;
/// Depth from the face's front plane back to the ears (tragion), about 85 mm.
pub const HEAD_DEPTH: f64 = 85.0;

/// Converts a height in millimetres above the nasion to mesh units.
pub fn y_units(y_mm: f64) -> f64 {
    (y_mm - Y_ORIGIN_MM) / MM_PER_UNIT
}

/// Converts a length in millimetres to mesh units.
pub fn units(mm: f64) -> f64 {
    mm / MM_PER_UNIT
}
