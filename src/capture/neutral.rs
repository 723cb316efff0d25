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
//! its readings over the recording ([`LEAST_QUANTILE`]), and a frame's work is the landmark
//! motion its muscles make working above their least (a muscle below it pays for no other's
//! work: a narrow mouth does not make an open jaw calm). Muscles that pull against each other
//! (antagonist groups, found from the Jacobian by `super::antagonists`) count together, by
//! their net landmark motion from the recording's median (see `Work`). The work is measured
//! per region ([`REGIONS`]: the brows, and the rest of the face), each region's landmarks of
//! the new neutral the per-landmark median of the quarter of frames ([`FRACTION`]) that work
//! least there; from it the frames are read again, until the same frames work least (at most
//! [`PASSES`] passes). The neutral is then the face of the recording's least-working frames
//! (a median of a quarter, not the one lowest frame, which noise decides), from which the
//! others are reached by muscles pulling, not by muscles pulling less; a subject whose brows
//! rest only while the mouth works has both at rest.
//!
//! Not kept (docs/capture.md): alternating the frames' non-negative activations with the
//! neutral moved by their mean residual. A frame that works less than the neutral is mostly
//! explained by antagonists (a narrower mouth by the lip sphincter instead of a lesser
//! smile), so the residual that would move the neutral is small and the neutral barely moves.

use glam::{DVec3, Vec3};

use super::antagonists::{self, Group};
use super::pose::landmark_weight;
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
    let mut before: Vec<Vec<usize>> = Vec::new();
    let groups = antagonists::groups(model);
    let columns = Columns::new(model);
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
        let per_frame: Vec<[f64; REGIONS]> = read
            .iter()
            .map(|(_, a, _)| work.of(model, &columns, a))
            .collect();
        let used = ((read.len() as f64 * FRACTION).ceil() as usize).clamp(1, read.len());
        let (next, chosen_all) = least_working(&read, &per_frame, used, &neutral);
        found = LeastWork {
            used,
            of: read.len(),
            passes: pass,
        };
        if chosen_all == before {
            break;
        }
        neutral = next;
        before = chosen_all;
    }
    Ok((neutral, found))
}

/// The neutral whose every region is the per-landmark median of the `used` frames of `read`
/// that work least there (`per_frame`: each frame's work per region), with the chosen frames'
/// numbers per region.
fn least_working(
    read: &[(usize, Vec<f64>, Vec<DVec3>)],
    per_frame: &[[f64; REGIONS]],
    used: usize,
    neutral: &[DVec3],
) -> (Vec<DVec3>, Vec<Vec<usize>>) {
    let mut next = neutral.to_vec();
    let mut chosen_all = Vec::with_capacity(REGIONS);
    for r in 0..REGIONS {
        let mut order: Vec<(f64, usize)> = per_frame
            .iter()
            .enumerate()
            .map(|(k, w)| (w[r], k))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut chosen: Vec<usize> = order[..used].iter().map(|w| read[w.1].0).collect();
        chosen.sort_unstable();
        chosen_all.push(chosen);
        let shapes: Vec<&[DVec3]> = order[..used]
            .iter()
            .map(|w| read[w.1].2.as_slice())
            .collect();
        let median = super::pose::median_shape(&shapes);
        for i in (0..median.len()).filter(|&i| region(i) == r) {
            next[i] = median[i];
        }
    }
    (next, chosen_all)
}

/// The face's regions, each with its own least-working frames: the face but the brows (0)
/// and the brows (1).
///
/// The brows are apart: their raisers and lowerers (an antagonist group) work alone, and a
/// subject whose brows rest only while the mouth works (or the other way round) has no
/// frame where the whole face rests. Every other split tried lost the jaw
/// (docs/capture.md): the mouth, the nose and the eyes share their frames.
pub const REGIONS: usize = 2;

/// The region of landmark `i` (see [`REGIONS`]): the brows (17-26) are region 1.
pub fn region(i: usize) -> usize {
    usize::from((17..=26).contains(&i))
}

/// Each variable's landmark motion per unit in each region (weighted norm, mm in the rig's
/// space); the jaw's at rest.
struct Columns(Vec<[f64; REGIONS]>);

impl Columns {
    fn new(model: &LandmarkModel) -> Columns {
        let jaw = model.jaw_slope(0.0);
        let m = model.muscle_count();
        Columns(
            (0..model.variable_count())
                .map(|v| {
                    let column = if v < m { model.column(v) } else { &jaw };
                    let mut norm = [0.0; REGIONS];
                    for (i, c) in column.iter().enumerate() {
                        norm[region(i)] += landmark_weight(i).dot(*c * *c);
                    }
                    norm.map(f64::sqrt)
                })
                .collect(),
        )
    }
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
/// Work is landmark motion (weighted as the solve weighs it, in the rig's space), summed per
/// region ([`region`]): a muscle's work counts where it moves the face, so a smile does not
/// make the brows' frames busy, and the jaw's weighs what its motion does.
///
/// - A muscle alone (no antagonist) works above its least state: what it does from a face
///   where it rests as far as the recording shows it can. Only work above counts: a muscle
///   below its least does not pay for another's work (a narrow mouth does not make an open
///   jaw calm).
/// - An antagonist group ([`antagonists`]) works by its net landmark motion away from the
///   recording's middle (the per-coordinate median of the group's net motion over the
///   frames). Moving either way is work, one side's
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
        }
    }

    /// The work of a frame whose signed reading is `signed` in each region: the landmark
    /// motion (weighted, mm in the rig's space) its muscles' work above their least makes
    /// there, and its antagonist groups' net motion from their centres.
    fn of(&self, model: &LandmarkModel, columns: &Columns, signed: &[f64]) -> [f64; REGIONS] {
        let mut work = [0.0; REGIONS];
        for (i, (a, l)) in signed.iter().zip(&self.least).enumerate() {
            if self.alone[i] {
                let above = (a - l).max(0.0);
                work.iter_mut()
                    .zip(&columns.0[i])
                    .for_each(|(w, c)| *w += above * c);
            }
        }
        for (g, centre) in &self.groups {
            let mut squared = [0.0; REGIONS];
            for (i, (n, c)) in g.net(model, signed).iter().zip(centre).enumerate() {
                let d = *n - *c;
                squared[region(i)] += landmark_weight(i).dot(d * d);
            }
            work.iter_mut()
                .zip(squared)
                .for_each(|(w, s)| *w += s.sqrt());
        }
        work
    }
}
