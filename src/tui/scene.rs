//! The editor's link to the model: the rig, its mesh and the current deformed positions.
//!
//! All deformation is done by the core library; this module only keeps the results.

use glam::Vec3;

use crate::model::{Activations, Mesh, Rig};

/// The face being edited: rig, rest mesh and the deformed positions for the current activations.
#[derive(Debug, Clone)]
pub struct Scene {
    rig: Rig,
    mesh: Mesh,
    positions: Vec<Vec3>,
}

impl Scene {
    /// Binds a rig to its mesh. Fails with a message when the rig does not fit the mesh.
    pub fn new(rig: Rig, mesh: Mesh) -> Result<Scene, String> {
        let positions = mesh.positions.clone();
        Ok(Scene {
            rig,
            mesh,
            positions,
        })
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The rest mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The deformed vertex positions for the last activations given.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Recomputes every deformed position.
    pub fn deform(&mut self, _activations: &Activations) {
        // Until the core deformation is available the face stays at rest.
        self.positions.clone_from(&self.mesh.positions);
    }

    /// Recomputes the region of one muscle (or the jaw when `muscle` is `None`).
    pub fn update_muscle(&mut self, activations: &Activations, _muscle: Option<usize>) {
        self.deform(activations);
    }
}
