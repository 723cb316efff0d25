//! Muscle-level capture: each video frame's muscle activations and jaw, solved from the 68
//! 3D landmarks a face tracker (OpenFace 2.0) writes, on any rig.
//!
//! - [`pose`]: head pose removed by aligning each frame to the subject's neutral on points no
//!   muscle moves; the neutral given or estimated; the motion carried into the rig's space by
//!   the warp `fit-rig` uses;
//! - [`rig_model`]: the rig's landmark Jacobian on the deformation it is bound with;
//! - [`solver`]: bounded least squares per frame ([`crate::fit::lsq`]) with temporal and
//!   sparsity terms, refined on the deformation itself;
//! - [`neutral`]: the neutral the muscles define: the face from which every frame is
//!   reached with the least muscle work;
//! - [`aus`]: AU intensities from the activations, through an AU table;
//! - [`synthetic`]: recordings made by the rig itself (tests, benches, self-checks).
//!
//! `docs/capture.md` describes the method and its limits. Nothing here reads files.

pub mod antagonists;
pub mod aus;
pub mod neutral;
pub mod pose;
pub mod rig_model;
pub mod solver;
pub mod synthetic;

use glam::{DVec3, Vec3};
use thiserror::Error;

pub use aus::AuProjection;
pub use pose::NeutralSource;
pub use rig_model::LandmarkModel;
pub use solver::{FrameSolver, Regularisation, Solution};

use crate::landmarks::COUNT;
use crate::model::{Activations, BoundRig};

/// A frame whose non-rigid motion is below this many times its noise (the misfit of the
/// landmarks its pose was fitted on, [`pose::Aligned::noise`]) has no explained fraction:
/// there is nothing to explain.
pub const NOISE_FACTOR: f64 = 2.0;

/// Why capture cannot start.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CaptureError {
    /// The rig's landmarks are not 68 vertices of its mesh.
    #[error("the rig's landmarks must be 68 vertices of its mesh ({0})")]
    RigLandmarks(String),
    /// No frame of the recording is a usable face.
    #[error("no frame has a usable face: every row is untracked, malformed or degenerate")]
    NoUsableFrames,
    /// The neutral frame is not a usable face.
    #[error("the neutral frame's landmarks are not a usable face (non-finite or degenerate)")]
    BadNeutral,
}

/// One frame's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Captured {
    /// The activations, in range.
    pub activations: Activations,
    /// The fraction of the non-rigid motion explained, `None` below the noise floor.
    pub explained: Option<f64>,
    /// The landmarks' motion the activations make, in the rig's space.
    pub motion: Vec<DVec3>,
}

/// A recording's capture: the subject's neutral, the map into the rig's space and the
/// per-frame solver.
#[derive(Debug)]
pub struct Session<'a> {
    neutral: Vec<DVec3>,
    to_rig: pose::ToRig,
    solver: FrameSolver<'a>,
    /// How the neutral was found.
    pub source: NeutralSource,
}

impl<'a> Session<'a> {
    /// A session for a subject whose neutral landmarks are `neutral` (tracker units).
    pub fn new(
        bound: &'a BoundRig,
        model: &'a LandmarkModel,
        neutral: Vec<DVec3>,
        source: NeutralSource,
        regularisation: Regularisation,
    ) -> Result<Session<'a>, CaptureError> {
        if neutral.len() != COUNT || !neutral.iter().all(|p| p.is_finite()) {
            return Err(CaptureError::BadNeutral);
        }
        let to_rig = pose::ToRig::new(&neutral, model.rest()).ok_or(CaptureError::BadNeutral)?;
        Ok(Session {
            neutral,
            to_rig,
            solver: FrameSolver::new(bound, model, regularisation),
            source,
        })
    }

    /// A session whose neutral is one frame's landmarks.
    pub fn from_frame(
        bound: &'a BoundRig,
        model: &'a LandmarkModel,
        frame: &[Vec3],
        source: NeutralSource,
        regularisation: Regularisation,
    ) -> Result<Session<'a>, CaptureError> {
        let neutral: Vec<DVec3> = frame.iter().map(|p| p.as_dvec3()).collect();
        pose::align(frame, &neutral).ok_or(CaptureError::BadNeutral)?;
        Session::new(bound, model, neutral, source, regularisation)
    }

    /// Solves one frame's landmarks; `None` when they are not a usable face (then the next
    /// frame starts afresh, not near this one).
    pub fn frame(&mut self, landmarks: &[Vec3]) -> Option<Captured> {
        let (_, solution, explained) = self.solve(landmarks)?;
        Some(Captured {
            activations: solution.activations,
            explained,
            motion: solution.predicted,
        })
    }

    /// One frame's signed muscle reading from this session's neutral
    /// ([`FrameSolver::signed`]: below 0, a muscle works less than in the neutral) and its
    /// pose-removed landmarks; `None` for a frame that is not a usable face.
    pub fn signed(&mut self, landmarks: &[Vec3]) -> Option<(Vec<f64>, Vec<DVec3>)> {
        if crate::landmarks::check_shape(landmarks).is_err() {
            return None;
        }
        let aligned = pose::align(landmarks, &self.neutral)?;
        let motion = self.to_rig.motion(&aligned.points, &self.neutral);
        Some((self.solver.signed(&motion), aligned.points))
    }

    /// The subject's neutral landmarks (tracker units).
    pub fn neutral(&self) -> &[DVec3] {
        &self.neutral
    }

    /// Aligns and solves one frame: its pose-removed landmarks, the solution and the
    /// explained fraction (`None` below the noise floor).
    fn solve(&mut self, landmarks: &[Vec3]) -> Option<(pose::Aligned, Solution, Option<f64>)> {
        let usable = crate::landmarks::check_shape(landmarks).is_ok();
        let Some(aligned) = usable
            .then(|| pose::align(landmarks, &self.neutral))
            .flatten()
        else {
            self.solver.reset();
            return None;
        };
        let motion = self.to_rig.motion(&aligned.points, &self.neutral);
        let solution = self.solver.solve(&motion);
        let weights = self.solver.weights();
        let weight: f64 = weights.iter().map(|w| w.element_sum() / 3.0).sum();
        let rms = (solution.motion / weight).sqrt();
        let floor = NOISE_FACTOR * aligned.noise * self.to_rig.scale;
        let explained = (rms > floor).then(|| solution.explained());
        Some((aligned, solution, explained))
    }

    /// Forgets the previous frame: the next is solved without the temporal term.
    pub fn gap(&mut self) {
        self.solver.reset();
    }
}
