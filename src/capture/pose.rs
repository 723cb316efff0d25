//! Head pose out, rig space in: each frame's landmarks are aligned to the subject's neutral
//! on points no muscle moves, and the aligned motion is carried into the rig's space by the
//! map `fit-rig` uses (a similarity, then the thin-plate spline), through its Jacobian at
//! each neutral landmark.

use glam::{DMat3, DVec3, Vec3};

use crate::fit::warp::{Similarity, Warp};
use crate::landmarks::COUNT;

/// Landmarks no facial muscle moves much: the nose bridge down to the tip (27-30) and the
/// eye corners (36, 39, 42, 45). The jaw line (0-16) is left out: OpenFace places it on the
/// face's silhouette, which slides over the face as the head turns.
pub const STABLE: [usize; 8] = [27, 28, 29, 30, 36, 39, 42, 45];

/// The jaw line but the chin and its neighbours: silhouette points (see [`STABLE`]) whose
/// motion counts for less in the solve.
pub fn is_contour(i: usize) -> bool {
    i <= 16 && !(7..=9).contains(&i)
}

/// Weight of a jaw-line landmark's motion against the others' 1.
pub const CONTOUR_WEIGHT: f64 = 0.3;

/// Weight of motion along the rig's depth axis (out of the face) against the others' 1: a
/// single camera sees depth only through the tracker's face model, so the landmarks'
/// non-rigid depth is the least measured of their coordinates.
pub const DEPTH_WEIGHT: f64 = 0.25;

/// The weight of each axis of landmark `i`'s motion in the rig's space (x across, y up, z
/// out of the face).
pub fn landmark_weight(i: usize) -> DVec3 {
    let w = if is_contour(i) { CONTOUR_WEIGHT } else { 1.0 };
    DVec3::new(w, w, w * DEPTH_WEIGHT)
}

/// One frame with its head pose removed: the landmarks in the neutral's coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Aligned {
    /// The 68 landmarks after the similarity that best aligns the stable points.
    pub points: Vec<DVec3>,
    /// The RMS distance from the neutral's, after alignment, of the landmarks the pose was
    /// fitted on (the half that moved least): what tracking noise amounts to in this frame.
    pub noise: f64,
}

/// Aligns a frame's landmarks to `neutral`: a similarity fitted on the [`STABLE`] points,
/// then fitted again on the half of all 68 that moved least under it; `None` when the frame
/// is not a usable face (non-finite, or the stable points do not span space).
pub fn align(frame: &[Vec3], neutral: &[DVec3]) -> Option<Aligned> {
    if frame.len() != COUNT || neutral.len() != COUNT || !frame.iter().all(|p| p.is_finite()) {
        return None;
    }
    let from: Vec<DVec3> = STABLE.iter().map(|&i| frame[i].as_dvec3()).collect();
    let to: Vec<DVec3> = STABLE.iter().map(|&i| neutral[i]).collect();
    let first = Similarity::fit(&from, &to)?;
    // Then again on the half of the landmarks that moved least under the first fit: the
    // points no muscle moved in this frame, wherever they are, hold the pose far better
    // than eight points between the eyes do at the chin.
    let mut moved: Vec<(f64, usize)> = frame
        .iter()
        .zip(neutral)
        .enumerate()
        .map(|(i, (p, q))| (first.apply(p.as_dvec3()).distance_squared(*q), i))
        .collect();
    moved.sort_by(|a, b| a.0.total_cmp(&b.0));
    let calm = &moved[..COUNT / 2];
    let from: Vec<DVec3> = calm.iter().map(|&(_, i)| frame[i].as_dvec3()).collect();
    let to: Vec<DVec3> = calm.iter().map(|&(_, i)| neutral[i]).collect();
    let similarity = Similarity::fit(&from, &to).unwrap_or(first);
    let points: Vec<DVec3> = frame
        .iter()
        .map(|p| similarity.apply(p.as_dvec3()))
        .collect();
    let noise = (calm
        .iter()
        .map(|&(_, i)| points[i].distance_squared(neutral[i]))
        .sum::<f64>()
        / calm.len() as f64)
        .sqrt();
    Some(Aligned { points, noise })
}

/// How the neutral was found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NeutralSource {
    /// The frame given with `--neutral` (its frame number).
    Frame(u64),
    /// The per-landmark median over the low-expression frames of the recording.
    Estimated {
        /// Frames the median was taken over.
        used: usize,
        /// Usable frames in the recording.
        of: usize,
    },
    /// The median of the frames that work least, by the muscles' reading
    /// ([`super::neutral::least_work`]).
    LeastWork {
        /// Frames the median was taken over.
        used: usize,
        /// Usable frames in the recording.
        of: usize,
        /// Passes of reading the frames' work and taking the new neutral.
        passes: usize,
    },
    /// The first usable frame of a live stream.
    FirstFrame(u64),
}

impl std::fmt::Display for NeutralSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NeutralSource::Frame(n) => write!(f, "frame {n} (given with --neutral)"),
            NeutralSource::Estimated { used, of } => write!(
                f,
                "estimated: the per-landmark median of the {used} frames of {of} that move least from the recording's median face"
            ),
            NeutralSource::LeastWork { used, of, passes } => write!(
                f,
                "estimated by the muscles: the per-landmark median of the {used} frames of {of} that work least, the brows' and the rest of the face's each from their own (the landmark motion of muscle work above each muscle's least state; {passes} passes from the median of the calm frames)"
            ),
            NeutralSource::FirstFrame(n) => write!(f, "the first tracked frame ({n}) of the stream"),
        }
    }
}

/// The fraction of frames, those that move least, the neutral is the median of.
pub const NEUTRAL_FRACTION: f64 = 0.25;

/// The subject's neutral from a recording's frames (each 68 finite points): align them all
/// to the first, take the per-landmark median, align again to it, and take the median of the
/// quarter of frames that differ least from it. `None` when no frame is usable.
pub fn estimate_neutral(frames: &[&[Vec3]]) -> Option<(Vec<DVec3>, NeutralSource)> {
    let first: Vec<DVec3> = frames.first()?.iter().map(|p| p.as_dvec3()).collect();
    let aligned: Vec<Aligned> = frames.iter().filter_map(|f| align(f, &first)).collect();
    if aligned.is_empty() {
        return None;
    }
    let all: Vec<&[DVec3]> = aligned.iter().map(|a| a.points.as_slice()).collect();
    let median = median_shape(&all);
    let again: Vec<Aligned> = frames.iter().filter_map(|f| align(f, &median)).collect();
    let mut motion: Vec<(f64, usize)> = again
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let m = a
                .points
                .iter()
                .zip(&median)
                .map(|(p, q)| p.distance_squared(*q))
                .sum::<f64>();
            (m, k)
        })
        .collect();
    motion.sort_by(|a, b| a.0.total_cmp(&b.0));
    let used = ((again.len() as f64 * NEUTRAL_FRACTION).ceil() as usize).clamp(1, again.len());
    let calm: Vec<&[DVec3]> = motion[..used]
        .iter()
        .map(|&(_, k)| again[k].points.as_slice())
        .collect();
    let neutral = median_shape(&calm);
    Some((
        neutral,
        NeutralSource::Estimated {
            used,
            of: again.len(),
        },
    ))
}

/// The per-coordinate median of several shapes of equal length.
pub(crate) fn median_shape(shapes: &[&[DVec3]]) -> Vec<DVec3> {
    let n = shapes.first().map_or(0, |s| s.len());
    let mut values = Vec::with_capacity(shapes.len());
    (0..n)
        .map(|i| {
            let mut axis = |pick: fn(DVec3) -> f64| {
                values.clear();
                values.extend(shapes.iter().map(|s| pick(s[i])));
                // A selection, not a sort: the least-work neutral takes medians of every
                // antagonist group's motion over the whole recording on every pass.
                let mid = values.len() / 2;
                let (below, middle, _) = values.select_nth_unstable_by(mid, f64::total_cmp);
                let upper = *middle;
                match below.iter().copied().max_by(f64::total_cmp) {
                    Some(lower) if mid * 2 == shapes.len() => 0.5 * (lower + upper),
                    _ => upper,
                }
            };
            DVec3::new(axis(|p| p.x), axis(|p| p.y), axis(|p| p.z))
        })
        .collect()
}

/// The map of the subject's motion into the rig's space: per landmark, the Jacobian of the
/// subject-to-rig warp (fitted on every landmark but the jaw line's sides) at the subject's
/// neutral landmark.
#[derive(Debug, Clone, PartialEq)]
pub struct ToRig {
    jacobians: Vec<DMat3>,
    /// The warp's similarity scale (rig units per subject unit).
    pub scale: f64,
}

impl ToRig {
    /// The map from the subject's `neutral` to the rig's rest landmarks; `None` when the
    /// warp cannot be fitted (a neutral with no spread).
    pub fn new(neutral: &[DVec3], rig: &[DVec3]) -> Option<ToRig> {
        // The jaw line is the silhouette: where the tracker puts it depends on the head's
        // turn in the neutral frame, so it would bend the warp; the chin is kept.
        let kept = (0..neutral.len().min(rig.len())).filter(|&i| !is_contour(i));
        let (from, to): (Vec<Vec3>, Vec<Vec3>) = kept
            .map(|i| (neutral[i].as_vec3(), rig[i].as_vec3()))
            .unzip();
        let warp = Warp::fit(&from, &to)?;
        let jacobians = neutral.iter().map(|&p| warp.jacobian(p)).collect();
        Some(ToRig {
            jacobians,
            scale: warp.similarity.scale,
        })
    }

    /// The motion of each landmark in the rig's space, from aligned points and the neutral.
    pub fn motion(&self, aligned: &[DVec3], neutral: &[DVec3]) -> Vec<DVec3> {
        self.jacobians
            .iter()
            .zip(aligned.iter().zip(neutral))
            .map(|(j, (p, q))| *j * (*p - *q))
            .collect()
    }
}
