//! The muscle model: meshes, muscles, the jaw, rigs and the deformation.
//!
//! Nothing here knows about files or terminals.

pub mod activations;
pub mod deform;
pub mod deformation;
pub mod envelope;
pub mod field;
pub mod jaw;
pub mod mesh;
pub mod muscle;
pub mod rig;

pub use activations::{ActivationError, Activations, JAW_RANGE, MUSCLE_RANGE};
pub use deform::{deform, BindError, BoundRig, SampledPose, Sampler, SkinRules};
pub use deformation::Deformation;
pub use field::Field;
pub use jaw::Jaw;
pub use mesh::{Mesh, MeshError};
pub use muscle::{Convergence, Frame, Linear, Muscle, MuscleKind, Sheet, Side, Sphincter};
pub use rig::{Combine, Mask, Rig, RIG_VERSION};
