//! The neutral the muscles define: the subject's face from which every frame of the
//! recording is reached with the least muscle work.
//!
//! A neutral taken from the frames' shapes alone (the median of the calm frames,
//! [`super::pose::estimate_neutral`]) is the subject's typical face; for a subject who smiles
//! through most of a recording it smiles. Muscles cannot pull the other way, so every frame
//! whose mouth corners sit lower than that neutral reads no smile at all, and the low end of
//! the smile is lost.
//!
//! Measured from a neutral that carries work, the frames that work less than it read below
//! 0 in that work's muscles. So each frame's muscles are read signed
//! ([`super::FrameSolver::signed`]: linear least squares on the rig's landmark Jacobian at
//! rest, every variable free to go below 0), and the frame's signed work is their sum. The
//! new neutral is the per-landmark median of the quarter of frames ([`FRACTION`]) that work
//! least; from it the frames are read again, until the same frames work least (at most
//! [`PASSES`] passes). The neutral is then the face of the recording's least-working frames
//! (robustly: a median of a quarter, not the one lowest frame, which noise decides), from
//! which the others are reached by muscles pulling, not by muscles pulling less.
//!
//! Not kept (docs/capture.md): alternating the frames' non-negative activations with the
//! neutral moved by their mean residual. A frame that works less than the neutral is mostly
//! explained by antagonists (a narrower mouth by the lip sphincter instead of a lesser
//! smile), so the residual that would move the neutral is small and the neutral barely moves.

use glam::{DVec3, Vec3};

use super::{CaptureError, LandmarkModel, NeutralSource, Regularisation, Session};
use crate::model::BoundRig;

/// The fraction of frames, those that work least, the neutral is the median of: the same
/// quarter the calm-frame median uses ([`super::pose::NEUTRAL_FRACTION`]).
pub const FRACTION: f64 = super::pose::NEUTRAL_FRACTION;

/// The most passes of reading the frames' work and taking the new neutral.
pub const PASSES: usize = 8;

/// How the neutral was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LeastWork {
    /// Frames the neutral is the median of.
    pub used: usize,
    /// Usable frames read.
    pub of: usize,
    /// Passes made.
    pub passes: usize,
}

/// The neutral of `frames` from which they are reached with the least muscle work, starting
/// from `start` (the calm-frame median); frames that are not a usable face are left out.
pub fn least_work(
    bound: &BoundRig,
    model: &LandmarkModel,
    frames: &[&[Vec3]],
    start: Vec<DVec3>,
    regularisation: Regularisation,
) -> Result<(Vec<DVec3>, LeastWork), CaptureError> {
    let mut neutral = start;
    let mut found = LeastWork {
        used: 0,
        of: 0,
        passes: 0,
    };
    let mut before: Vec<usize> = Vec::new();
    for pass in 1..=PASSES {
        let source = NeutralSource::FirstFrame(0);
        let mut session = Session::new(bound, model, neutral.clone(), source, regularisation)?;
        let mut work: Vec<(f64, usize, Vec<DVec3>)> = frames
            .iter()
            .enumerate()
            .filter_map(|(k, f)| session.signed_work(f).map(|(w, p)| (w, k, p)))
            .collect();
        if work.is_empty() {
            return Err(CaptureError::NoUsableFrames);
        }
        work.sort_by(|a, b| a.0.total_cmp(&b.0));
        let used = ((work.len() as f64 * FRACTION).ceil() as usize).clamp(1, work.len());
        let mut least: Vec<usize> = work[..used].iter().map(|w| w.1).collect();
        least.sort_unstable();
        found = LeastWork {
            used,
            of: work.len(),
            passes: pass,
        };
        if least == before {
            break;
        }
        let shapes: Vec<&[DVec3]> = work[..used].iter().map(|w| w.2.as_slice()).collect();
        neutral = super::pose::median_shape(&shapes);
        before = least;
    }
    Ok((neutral, found))
}
