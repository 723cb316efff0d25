//! The FACS Action Unit catalogue: numbers, names and muscular basis.
//!
//! The main codes (1-46) follow the Facial Action Coding System as revised in 2002; numbers
//! FACS never assigned (3, 40) are absent. Head position codes (51-58) and eye position codes
//! (61-64) are included so tables can name them, although a face rig without a head or eyes
//! cannot express them.

/// One Action Unit of the catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AuInfo {
    /// The FACS number.
    pub number: u8,
    /// The FACS name, e.g. `Lip Corner Puller`.
    pub name: &'static str,
    /// The muscles (or movement) underlying the AU, in plain anatomical terms.
    pub basis: &'static str,
}

const fn au(number: u8, name: &'static str, basis: &'static str) -> AuInfo {
    AuInfo {
        number,
        name,
        basis,
    }
}

/// Every Action Unit grimace knows, in number order.
pub const CATALOGUE: &[AuInfo] = &[
    au(1, "Inner Brow Raiser", "frontalis, pars medialis"),
    au(2, "Outer Brow Raiser", "frontalis, pars lateralis"),
    au(4, "Brow Lowerer", "corrugator supercilii, depressor supercilii, procerus"),
    au(5, "Upper Lid Raiser", "levator palpebrae superioris"),
    au(6, "Cheek Raiser", "orbicularis oculi, pars orbitalis"),
    au(7, "Lid Tightener", "orbicularis oculi, pars palpebralis"),
    au(8, "Lips Toward Each Other", "orbicularis oris"),
    au(9, "Nose Wrinkler", "levator labii superioris alaeque nasi"),
    au(10, "Upper Lip Raiser", "levator labii superioris, caput infraorbitalis"),
    au(11, "Nasolabial Deepener", "zygomaticus minor"),
    au(12, "Lip Corner Puller", "zygomaticus major"),
    au(13, "Sharp Lip Puller", "levator anguli oris (caninus)"),
    au(14, "Dimpler", "buccinator"),
    au(15, "Lip Corner Depressor", "depressor anguli oris (triangularis)"),
    au(16, "Lower Lip Depressor", "depressor labii inferioris"),
    au(17, "Chin Raiser", "mentalis"),
    au(18, "Lip Pucker", "incisivii labii superioris and inferioris"),
    au(19, "Tongue Show", "tongue"),
    au(20, "Lip Stretcher", "risorius with platysma"),
    au(21, "Neck Tightener", "platysma"),
    au(22, "Lip Funneler", "orbicularis oris"),
    au(23, "Lip Tightener", "orbicularis oris"),
    au(24, "Lip Pressor", "orbicularis oris"),
    au(
        25,
        "Lips Part",
        "depressor labii inferioris, or relaxation of mentalis or orbicularis oris",
    ),
    au(26, "Jaw Drop", "masseter; relaxed temporalis and internal pterygoid"),
    au(27, "Mouth Stretch", "pterygoids, digastric"),
    au(28, "Lip Suck", "orbicularis oris"),
    au(29, "Jaw Thrust", "pterygoids (jaw movement)"),
    au(30, "Jaw Sideways", "pterygoids (jaw movement)"),
    au(31, "Jaw Clencher", "masseter"),
    au(32, "Lip Bite", "teeth on lip"),
    au(33, "Cheek Blow", "air in the cheeks"),
    au(34, "Cheek Puff", "air in the cheeks, lips closed"),
    au(35, "Cheek Suck", "buccinator, cheeks drawn in"),
    au(36, "Tongue Bulge", "tongue"),
    au(37, "Lip Wipe", "tongue"),
    au(38, "Nostril Dilator", "nasalis, pars alaris"),
    au(39, "Nostril Compressor", "nasalis, pars transversa, and depressor septi nasi"),
    au(
        41,
        "Lid Droop",
        "relaxation of levator palpebrae superioris",
    ),
    au(42, "Slit", "orbicularis oculi"),
    au(
        43,
        "Eyes Closed",
        "relaxation of levator palpebrae superioris; orbicularis oculi, pars palpebralis",
    ),
    au(44, "Squint", "orbicularis oculi, pars palpebralis"),
    au(
        45,
        "Blink",
        "relaxation of levator palpebrae superioris; orbicularis oculi, pars palpebralis",
    ),
    au(
        46,
        "Wink",
        "relaxation of levator palpebrae superioris; orbicularis oculi, pars palpebralis (one side)",
    ),
    au(51, "Head Turn Left", "head movement"),
    au(52, "Head Turn Right", "head movement"),
    au(53, "Head Up", "head movement"),
    au(54, "Head Down", "head movement"),
    au(55, "Head Tilt Left", "head movement"),
    au(56, "Head Tilt Right", "head movement"),
    au(57, "Head Forward", "head movement"),
    au(58, "Head Back", "head movement"),
    au(61, "Eyes Turn Left", "eye movement"),
    au(62, "Eyes Turn Right", "eye movement"),
    au(63, "Eyes Up", "eye movement"),
    au(64, "Eyes Down", "eye movement"),
];

/// The catalogue entry of an AU number.
pub fn info(number: u8) -> Option<&'static AuInfo> {
    CATALOGUE
        .binary_search_by_key(&number, |a| a.number)
        .ok()
        .map(|i| &CATALOGUE[i])
}

/// The FACS name of an AU number, e.g. `name_of(12) == Some("Lip Corner Puller")`.
pub fn name_of(number: u8) -> Option<&'static str> {
    info(number).map(|a| a.name)
}

/// True when `number` is a FACS code in the catalogue.
pub fn is_code(number: u8) -> bool {
    info(number).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalogue_is_sorted_and_unique() {
        assert!(CATALOGUE.windows(2).all(|w| w[0].number < w[1].number));
    }

    #[test]
    fn known_names() {
        assert_eq!(name_of(1), Some("Inner Brow Raiser"));
        assert_eq!(name_of(12), Some("Lip Corner Puller"));
        assert_eq!(name_of(26), Some("Jaw Drop"));
        assert_eq!(name_of(46), Some("Wink"));
        assert_eq!(name_of(64), Some("Eyes Down"));
        assert_eq!(
            info(15).unwrap().basis,
            "depressor anguli oris (triangularis)"
        );
    }

    #[test]
    fn unassigned_numbers_are_absent() {
        for n in [0, 3, 40, 47, 50, 59, 60, 65, 99] {
            assert!(!is_code(n), "{n}");
        }
        assert_eq!(CATALOGUE.len(), 44 + 8 + 4);
    }
}
