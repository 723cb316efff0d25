//! The editor's link to the model: the bound rig, its mesh and the current deformed positions.
//!
//! All deformation is done by the core library ([`crate::model::BoundRig`]); this module only
//! keeps the results.

use glam::Vec3;

use crate::model::{Activations, BoundRig, Deformation, Mesh, MuscleKind, Rig};
use crate::render::Framing;

/// The face being edited: bound rig, rest mesh and the deformed positions for the current
/// activations.
#[derive(Debug, Clone)]
pub struct Scene {
    bound: BoundRig,
    mesh: Mesh,
    positions: Vec<Vec3>,
    generation: u64,
    framing: Framing,
}

impl Scene {
    /// Binds a rig to its mesh. Fails with a message when the rig does not fit the mesh.
    pub fn new(rig: Rig, mesh: Mesh) -> Result<Scene, String> {
        let bound = Deformation::default()
            .bind(&rig, &mesh)
            .map_err(|e| format!("the rig does not fit its mesh: {e}"))?;
        let positions = mesh.positions.clone();
        // Once, from the rig as loaded: rig-mode edits do not move the view.
        let framing = Framing::of_rig(&rig, &mesh);
        Ok(Scene {
            bound,
            mesh,
            positions,
            generation: 0,
            framing,
        })
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        self.bound.rig()
    }

    /// How the face is shown: its axes and the region views fit.
    pub fn framing(&self) -> &Framing {
        &self.framing
    }

    /// Shows the face with the axes given (`--up`, `--front`) instead of the rig's.
    pub fn face(&mut self, basis: glam::Mat3) {
        self.framing = Framing::of_rig_facing(self.rig(), &self.mesh, Some(basis));
    }

    /// The rest mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The deformed vertex positions for the last activations given.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Counts changes of the positions, so a view can tell whether it must draw the face again.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Recomputes every deformed position. Activations the model refuses (the editor keeps
    /// them in range, so this does not happen) leave the face as it was.
    pub fn deform(&mut self, activations: &Activations) {
        self.generation += 1;
        let _ = self.bound.deform(activations, &mut self.positions);
    }

    /// Checks that `rig` binds to this scene's mesh, saying why not.
    pub fn check_rig(&self, rig: &Rig) -> Result<(), String> {
        crate::io::rig_file::check_rig_mesh(rig, &self.mesh).map_err(|e| e.to_string())
    }

    /// Replaces the rig (rig mode's edits), keeping the old one when the new one does not
    /// bind to the mesh. The positions are those of the rest pose until the next deform.
    pub fn set_rig(&mut self, rig: Rig) -> Result<(), String> {
        self.bound = Deformation::default()
            .bind(&rig, &self.mesh)
            .map_err(|e| e.to_string())?;
        self.positions.clone_from(&self.mesh.positions);
        self.generation += 1;
        Ok(())
    }

    /// Gives muscles new parameters (rig mode's edit of a muscle and its partner), binding
    /// only their fields again; when the model refuses, the rig stays as it was and the
    /// reason is returned. The positions are those of the old rig until the next deform.
    pub fn rebind_muscles(&mut self, changes: Vec<(usize, MuscleKind)>) -> Result<(), String> {
        self.bound
            .rebind_muscles(changes)
            .map_err(|e| e.to_string())?;
        self.generation += 1;
        Ok(())
    }

    /// Gives the jaw a new pivot, axis and degrees per unit, like
    /// [`Scene::rebind_muscles`].
    pub fn rebind_jaw(
        &mut self,
        pivot: Vec3,
        axis: Vec3,
        degrees_per_unit: f32,
    ) -> Result<(), String> {
        self.bound
            .rebind_jaw(pivot, axis, degrees_per_unit)
            .map_err(|e| e.to_string())?;
        self.generation += 1;
        Ok(())
    }

    /// Recomputes the region of one muscle (or everything for the jaw, `None`), after
    /// `activations` changed in that muscle only.
    pub fn update_muscle(&mut self, activations: &Activations, muscle: Option<usize>) {
        self.generation += 1;
        let updated = match muscle {
            Some(i) => self
                .bound
                .update_muscle(activations, i, &mut self.positions)
                .is_ok(),
            None => false,
        };
        if !updated {
            self.deform(activations);
        }
    }
}
