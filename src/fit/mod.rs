//! Fitting: carrying a muscle rig to any face from its landmarks, and fitting AU entries to
//! target shapes.
//!
//! - the landmarks it fits from are in [`crate::landmarks`];
//! - [`warp`]: the similarity and thin-plate spline from one face to another;
//! - [`propose`]: landmarks proposed from some of them (a warp, a mirror plane);
//! - `brows`: the brow's sheets kept out of the eye sockets and the head's back (`brow_ramp`:
//!   the brow lowerer's rise no steeper than on the template);
//! - [`brow_hair`]: eyebrows marked from the landmarks on heads without their own;
//! - [`parts`]: which parts of a mesh are skin, still, or turn with the jaw;
//! - `reach`: fitted rings kept to the part of the face the template's reach;
//! - `lids`, `lidedge`, `lowerlid`: the closing lids and the lower lid's ring shaped from the
//!   mesh's own lids;
//! - [`regions`]: the mouth and eye lines and which side of them things lie on;
//! - [`jaw`]: jaw weights for a new mesh (`jawfade`: beyond the template's face, along the mesh);
//! - `ease`: weights eased where they change faster than on the template (the jaw's round the mouth corners, the lip muscles' masks);
//! - [`lipcut`]: joined lips found and cut open;
//! - [`eyecut`]: eye openings covered by skin found and cut open, with a dark eye behind;
//! - [`lipsides`]: which lip each vertex is on, by connectivity;
//! - [`pocket`]: the inside of a mouth whose lips were cut;
//! - [`transport`]: the whole fit ([`fit_rig`]);
//! - [`lsq`]: the one bounded least-squares solver (`fit-au`, `capture`);
//! - [`solve`]: activations that best reproduce a target shape ([`fit_au`]);
//! - [`quality`]: tears, lids and jaw of a deformed face (`grimace check`);
//! - [`weld`]: skin split at texture seams joined again.
//!
//! Nothing here reads files or knows about terminals.

pub mod brow_hair;
mod brow_ramp;
mod brows;
mod ease;
pub mod eyecut;
mod insertion;
pub mod jaw;
mod jawfade;
mod lidedge;
mod lids;
pub mod lipcut;
pub mod lipsides;
mod lowerlid;
pub mod lsq;
pub mod nearest;
pub mod parts;
pub mod pocket;
pub mod propose;
pub mod quality;
mod reach;
pub mod regions;
mod seam;
pub mod solve;
mod sources;
pub mod transport;
pub mod warp;
pub mod weld;

pub use parts::{Part, PartOverrides, Parts};
pub use solve::{fit_au, AuFit, SolveError};
pub use transport::{fit_rig, FitError, Fitted};
pub use warp::Warp;

use glam::Vec3;

use crate::model::{Mesh, Rig};

/// A rig with the mesh it is placed on and that mesh's landmarks: what a fit starts from.
#[derive(Debug, Clone, Copy)]
pub struct Template<'a> {
    /// The rig to carry.
    pub rig: &'a Rig,
    /// The mesh it is placed on.
    pub mesh: &'a Mesh,
    /// The 68 landmark positions on that mesh.
    pub landmarks: &'a [Vec3],
}
