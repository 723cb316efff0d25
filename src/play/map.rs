//! From tracker intensities to AU factors; the factors become activations through the one
//! AU mapper ([`crate::facs::mapper::AuMapper`], re-exported here).
//!
//! A tracker's intensity `r` on OpenFace's 0-5 scale is the factor `r/5`; on an already
//! normalised 0-1 stream it is `r` itself.

pub use crate::facs::mapper::{clamp_to_ranges, AuMapper};
use crate::facs::AuKey;

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_clamp_and_divide() {
        assert_eq!(IntensityScale::ZeroToFive.factor(2.5), 0.5);
        assert_eq!(IntensityScale::ZeroToFive.clamp(7.0), (5.0, true));
        assert_eq!(IntensityScale::ZeroToOne.factor(0.3), 0.3);
        assert_eq!(IntensityScale::ZeroToOne.clamp(-0.1), (0.0, true));
    }
}
