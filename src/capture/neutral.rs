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
//! rest, every variable free to go below 0). Each muscle's least state is a low quantile of
//! its readings over the recording ([`LEAST_QUANTILE`]), and a frame's work is the sum of
//! how far each muscle works above its least (a muscle below it pays for no other's work: a
//! narrow mouth does not make an open jaw calm). Muscles that pull against each other
//! (antagonist groups, found from the Jacobian by `super::antagonists`) count together,
//! by their net landmark motion from the recording's median (see `Work`). The new neutral is the per-landmark median
//! of the quarter of frames ([`FRACTION`]) that work least; from it the frames are read
//! again, until the same frames work least (at most [`PASSES`] passes). The neutral is then
//! the face of the recording's least-working frames (a median of a quarter, not the one
//! lowest frame, which noise decides), from which the others are reached by muscles
//! pulling, not by muscles pulling less.
//!
//! Not kept (docs/capture.md): alternating the frames' non-negative activations with the
//! neutral moved by their mean residual. A frame that works less than the neutral is mostly
//! explained by antagonists (a narrower mouth by the lip sphincter instead of a lesser
//! smile), so the residual that would move the neutral is small and the neutral barely moves.

use glam::{DVec3, Vec3};

use super::antagonists::{self, Group};
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
/// Also tried and not kept: moving the neutral by every muscle's least state at once (the
/// face at which each muscle rests as far as the recording shows, through the Jacobian);
/// the least states of muscles the landmarks barely tell apart are read independently and
/// do not settle (on a real recording they swing between -1.3 and the -2 bound).
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
    let groups = antagonists::groups(model);
    for pass in 1..=PASSES {
        let source = NeutralSource::FirstFrame(0);
        let mut session = Session::new(bound, model, neutral.clone(), source, regularisation)?;
        let read: Vec<(usize, Vec<f64>, Vec<DVec3>)> = frames
            .iter()
            .enumerate()
            .filter_map(|(k, f)| session.signed(f).map(|(a, p)| (k, a, p)))
            .collect();
        if read.is_empty() {
            return Err(CaptureError::NoUsableFrames);
        }
        let work = Work::new(model, &groups, &read);
        let mut work: Vec<(f64, usize)> = read
            .iter()
            .enumerate()
            .map(|(r, (_, a, _))| (work.of(model, a), r))
            .collect();
        work.sort_by(|a, b| a.0.total_cmp(&b.0));
        let used = ((work.len() as f64 * FRACTION).ceil() as usize).clamp(1, work.len());
        let mut chosen: Vec<usize> = work[..used].iter().map(|w| read[w.1].0).collect();
        chosen.sort_unstable();
        found = LeastWork {
            used,
            of: read.len(),
            passes: pass,
        };
        if chosen == before {
            break;
        }
        let shapes: Vec<&[DVec3]> = work[..used]
            .iter()
            .map(|w| read[w.1].2.as_slice())
            .collect();
        neutral = super::pose::median_shape(&shapes);
        before = chosen;
    }
    Ok((neutral, found))
}

/// The quantile of each variable's signed reading over the frames taken as its least state:
/// low, but not the lowest frame, which noise decides.
pub const LEAST_QUANTILE: f64 = 0.05;

/// Each variable's least state over the frames read: its [`LEAST_QUANTILE`].
fn least_states(read: &[(usize, Vec<f64>, Vec<DVec3>)]) -> Vec<f64> {
    let n = read.first().map_or(0, |r| r.1.len());
    let at = ((read.len() as f64 * LEAST_QUANTILE) as usize).min(read.len().saturating_sub(1));
    (0..n)
        .map(|i| {
            let mut values: Vec<f64> = read.iter().map(|r| r.1[i]).collect();
            values.sort_by(f64::total_cmp);
            values[at]
        })
        .collect()
}

/// How a frame's muscle work is measured over one pass's readings.
///
/// - A muscle alone (no antagonist) works above its least state: what it does from a face
///   where it rests as far as the recording shows it can. Only work above counts: a muscle
///   below its least does not pay for another's work (a narrow mouth does not make an open
///   jaw calm); the jaw counts at half, its range being twice a muscle's.
/// - An antagonist group ([`antagonists`]) works by its net landmark motion away from the
///   recording's middle (the per-coordinate median of the group's net motion over the
///   frames), in activation units ([`Group::unit`]). Moving either way is work, one side's
///   muscles or the other's; the position from which the recording's motions cost least in
///   total is their median, the L1 centre. A group has no least state of its own: its
///   members' readings trade one for the other (a raised brow reads as a brow raiser
///   working or as a lowerer working less than in the neutral), so each member's low
///   quantile says more about that trade than about the face.
struct Work {
    least: Vec<f64>,
    /// Whether each variable is a muscle alone (then it counts by its least state).
    alone: Vec<bool>,
    /// Each group with the median of its net motion over the frames.
    groups: Vec<(Group, Vec<DVec3>)>,
    muscles: usize,
}

impl Work {
    fn new(
        model: &LandmarkModel,
        groups: &[Group],
        read: &[(usize, Vec<f64>, Vec<DVec3>)],
    ) -> Work {
        let mut alone = vec![true; model.variable_count()];
        for g in groups {
            g.members.iter().for_each(|&i| alone[i] = false);
        }
        let groups = groups
            .iter()
            .map(|g| {
                let nets: Vec<Vec<DVec3>> = read.iter().map(|r| g.net(model, &r.1)).collect();
                let shapes: Vec<&[DVec3]> = nets.iter().map(Vec::as_slice).collect();
                (g.clone(), super::pose::median_shape(&shapes))
            })
            .collect();
        Work {
            least: least_states(read),
            alone,
            groups,
            muscles: model.muscle_count(),
        }
    }

    /// The work of a frame whose signed reading is `signed`.
    fn of(&self, model: &LandmarkModel, signed: &[f64]) -> f64 {
        let alone: f64 = signed
            .iter()
            .zip(&self.least)
            .enumerate()
            .filter(|&(i, _)| self.alone[i])
            .map(|(i, (a, l))| (a - l).max(0.0) * if i < self.muscles { 1.0 } else { 0.5 })
            .sum();
        let grouped: f64 = self
            .groups
            .iter()
            .map(|(g, centre)| antagonists::distance(&g.net(model, signed), centre) / g.unit)
            .sum();
        alone + grouped
    }
}
