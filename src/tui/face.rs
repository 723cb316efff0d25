//! The editor's link to the model: the bound rig, its mesh and the current deformed positions.
//!
//! All deformation is done by the core library ([`crate::model::BoundRig`]); this module only
//! keeps the results.
//!
//! The editor starts a big mesh with [`Face::start`]: the rest pose needs no bind (zero
//! activations give it exactly), so the first screen shows it at once while the rig is bound on
//! a thread; activations changed meanwhile are kept and applied when the bind lands
//! ([`Face::poll_bind`]), so no face is shown that the bound model would not give.
//!
//! A big mesh has levels of detail ([`Lod`]), made on a thread of their own so the first
//! screen does not wait for them (until they are there the full mesh is drawn): the viewport
//! draws one of them, so only its vertices are deformed for a frame ([`Face::sample`]);
//! the whole mesh's positions are computed when something asks for them
//! ([`Face::positions`]). The level's pose is kept between frames, so a key press that
//! changes one muscle recomputes only the level's vertices that muscle reaches. A small mesh
//! keeps its whole deformation up to date, one muscle's region at a time.

use std::cell::{OnceCell, RefCell};
use std::sync::{Arc, OnceLock};

use glam::Vec3;

use crate::model::{
    Activations, BoundRig, Deformation, Mesh, MuscleKind, Rig, SampledPose, Sampler,
};
use crate::render::lod::LOD_MIN_VERTICES;
use crate::render::{Framing, Level, Lod};

/// The face being edited: bound rig, rest mesh and the deformed positions for the current
/// activations.
#[derive(Debug, Clone)]
pub struct Face {
    /// The bound rig, or the rig while it is bound on a thread.
    binding: Binding,
    /// Shared with the thread that makes the levels of detail (no copy of a big mesh).
    mesh: Arc<Mesh>,
    /// The whole mesh's deformed positions: always there without levels of detail, else
    /// computed on first use after each change.
    positions: OnceCell<Vec<Vec3>>,
    /// The activations of the last deformation (what [`Face::sample`] deforms by).
    activations: Activations,
    /// The levels of detail, once made (a small mesh's are there at once: none).
    lod: Arc<OnceLock<Lod>>,
    /// Whether the mesh is big enough for levels of detail (its whole deformation is then
    /// computed only when asked for).
    big: bool,
    /// Per level of detail: what deforming its vertices reads, found on first use after
    /// each bind.
    samplers: OnceCell<Vec<OnceCell<Sampler>>>,
    /// The pose of the level drawn last, kept for the next frame.
    kept: RefCell<KeptPose>,
    generation: u64,
    framing: Framing,
    /// Millimetres per mesh unit when the mesh's scale is known (the built-in face), found
    /// once: the displacement legend reads it every frame.
    mm_per_unit: Option<f32>,
    /// The bind cache's warnings not yet shown.
    bind_warnings: Vec<String>,
}

/// A bound rig and the bind cache's warnings.
type Bound = (BoundRig, Vec<String>);

/// The rig bound to the mesh, or being bound.
#[derive(Debug, Clone)]
enum Binding {
    Bound(Box<BoundRig>),
    /// Bound on a thread that fills `slot` (with the bind's error as a message); `rig` is
    /// what the editor shows meanwhile.
    Pending {
        rig: Arc<Rig>,
        slot: Arc<OnceLock<Result<Bound, String>>>,
    },
}

/// The sampled pose of the level drawn last, and what changed since.
#[derive(Debug, Clone, Default)]
struct KeptPose {
    /// The level (its index) the pose is of; `None` when nothing is kept.
    level: Option<usize>,
    pose: SampledPose,
    /// The muscles changed since the pose was made (the muscle count stands for the jaw);
    /// `None`: everything may have changed.
    changed: Option<Vec<usize>>,
}

impl KeptPose {
    /// Notes a change of muscle `which` (the muscle count: the jaw).
    fn change(&mut self, which: usize) {
        if let Some(list) = &mut self.changed {
            if !list.contains(&which) {
                list.push(which);
            }
        }
    }
}

impl Face {
    /// Binds a rig to its mesh, framed by the rig ([`Framing::of_rig`]). Fails with a
    /// message when the rig does not fit the mesh.
    pub fn new(rig: Rig, mesh: Mesh) -> Result<Face, String> {
        let framing = Framing::of_rig(&rig, &mesh);
        Face::framed(rig, mesh, framing)
    }

    /// [`Face::new`] with the framing given (the editor's: [`Framing::of_loaded`]).
    pub fn framed(rig: Rig, mesh: Mesh, framing: Framing) -> Result<Face, String> {
        let (bound, warnings) = bind(&rig, &mesh)?;
        let mut face = Face::with(Binding::Bound(Box::new(bound)), mesh, framing, None);
        face.share_mesh();
        face.bind_warnings = warnings;
        Ok(face)
    }

    /// Like [`Face::framed`], but a big mesh (one with levels of detail) is bound on a
    /// thread: until [`Face::poll_bind`] takes the bound rig the face shows its rest pose,
    /// and a bind that fails is reported there.
    pub fn start(rig: Rig, mesh: Mesh, framing: Framing) -> Result<Face, String> {
        if mesh.positions.len() < LOD_MIN_VERTICES {
            return Face::framed(rig, mesh, framing);
        }
        let rig = Arc::new(rig);
        let slot = Arc::new(OnceLock::new());
        // The levels of detail are made once the bind is done: the two working sets, each
        // tens of megabytes on a big mesh, are never held at once (peak memory).
        let (bound, after_bind) = std::sync::mpsc::channel::<()>();
        let face = Face::with(
            Binding::Pending {
                rig: Arc::clone(&rig),
                slot: Arc::clone(&slot),
            },
            mesh,
            framing,
            Some(after_bind),
        );
        let mesh = Arc::clone(&face.mesh);
        std::thread::spawn(move || {
            // Only this thread fills the slot.
            let _ = slot.set(bind(&rig, &mesh));
            drop(slot);
            let _ = bound.send(());
        });
        Ok(face)
    }

    /// The face around a binding, framed once as loaded (rig-mode edits do not move the
    /// view), its levels of detail started on a thread (once `after` hears from the bind,
    /// when there is one).
    fn with(
        binding: Binding,
        mesh: Mesh,
        framing: Framing,
        after: Option<std::sync::mpsc::Receiver<()>>,
    ) -> Face {
        let rig = match &binding {
            Binding::Bound(bound) => bound.rig(),
            Binding::Pending { rig, .. } => rig,
        };
        let big = mesh.positions.len() >= LOD_MIN_VERTICES;
        let positions = OnceCell::from(mesh.positions.clone());
        let activations = Activations::zero(rig);
        let mesh = Arc::new(mesh);
        let lod = Arc::new(OnceLock::new());
        if big {
            // The thread gets the labels, the framed points and the shared mesh: no copy of
            // the rig or the mesh.
            let parts = Lod::rig_parts(rig, mesh.positions.len());
            let frame = framing.focus.clone();
            let (cell, mesh) = (Arc::clone(&lod), Arc::clone(&mesh));
            std::thread::spawn(move || {
                // A bind that ends in any way (even by a panic: the sender is dropped)
                // lets the levels start.
                if let Some(after) = after {
                    let _ = after.recv();
                }
                let frame = frame.as_deref().unwrap_or(&mesh.positions);
                cell.set(Lod::build(&mesh, &parts, frame))
            });
        } else {
            let _ = lod.set(Lod::default());
        }
        let mm_per_unit = crate::io::builtin::mm_per_unit(&mesh);
        Face {
            samplers: OnceCell::new(),
            kept: RefCell::default(),
            big,
            activations,
            binding,
            mesh,
            positions,
            lod,
            generation: 0,
            framing,
            mm_per_unit,
            bind_warnings: Vec::new(),
        }
    }

    /// Lets the bound rig keep the face's mesh rather than a copy of its own.
    fn share_mesh(&mut self) {
        if let Binding::Bound(bound) = &mut self.binding {
            bound.share_mesh(&self.mesh);
        }
    }

    /// Takes what the bind cache had to say about the last bind (a file it could not use
    /// or write), for the status line.
    pub fn take_bind_warnings(&mut self) -> Vec<String> {
        std::mem::take(&mut self.bind_warnings)
    }

    /// Whether the rig is still being bound (the face shows its rest pose meanwhile).
    pub fn is_binding(&self) -> bool {
        matches!(self.binding, Binding::Pending { .. })
    }

    /// Takes the rig bound on a thread once it is there: `None` while it is not (or when
    /// there was nothing to wait for), else whether it bound. From then on the face shows
    /// the activations given meanwhile.
    pub fn poll_bind(&mut self) -> Option<Result<(), String>> {
        let Binding::Pending { slot, .. } = &mut self.binding else {
            return None;
        };
        slot.get()?;
        let slot = std::mem::replace(slot, Arc::new(OnceLock::new()));
        // The thread's reference goes with it: the slot is ours alone unless the face was
        // cloned meanwhile, which then copies the bound rig.
        let result = Arc::try_unwrap(slot)
            .map(|cell| cell.into_inner().expect("the slot is filled"))
            .unwrap_or_else(|shared| shared.get().expect("the slot is filled").clone());
        let bound = match result {
            Ok((bound, warnings)) => {
                self.bind_warnings.extend(warnings);
                bound
            }
            Err(message) => {
                if let Binding::Pending { slot, .. } = &mut self.binding {
                    *slot = Arc::new(OnceLock::from(Err(message.clone())));
                }
                return Some(Err(message));
            }
        };
        self.binding = Binding::Bound(Box::new(bound));
        self.share_mesh();
        self.samplers = OnceCell::new();
        self.kept = RefCell::default();
        self.positions = OnceCell::new();
        self.generation += 1;
        Some(Ok(()))
    }

    /// Waits for a rig bound on a thread and takes it (for rig edits, tests and
    /// benchmarks); at once when it is bound already.
    pub fn wait_for_bind(&mut self) -> Result<(), String> {
        while self.is_binding() {
            if let Some(result) = self.poll_bind() {
                return result;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        Ok(())
    }

    /// The bound rig, once bound.
    fn bound(&self) -> Option<&BoundRig> {
        match &self.binding {
            Binding::Bound(bound) => Some(bound),
            Binding::Pending { .. } => None,
        }
    }

    /// The bound rig, waiting for a bind still running.
    fn bound_mut(&mut self) -> Result<&mut BoundRig, String> {
        self.wait_for_bind()?;
        match &mut self.binding {
            Binding::Bound(bound) => Ok(bound),
            Binding::Pending { .. } => Err("the rig is not bound".to_string()),
        }
    }

    /// The levels of detail the viewport draws from (none for a small mesh).
    pub fn lod(&self) -> &Lod {
        static NONE: Lod = Lod::none();
        self.lod.get().unwrap_or(&NONE)
    }

    /// Waits until the levels of detail are made (for tests and benchmarks).
    pub fn wait_for_lod(&self) -> &Lod {
        while self.lod.get().is_none() {
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        self.lod()
    }

    /// The deformed positions of `level`'s vertices for the last activations given: the
    /// whole deformation's where it is there, else only those vertices deformed (only those
    /// the muscles changed since the last frame reach, when it drew the same level).
    pub fn sample(&self, level: &Level, out: &mut Vec<Vec3>) {
        let (Some(bound), None) = (self.bound(), self.positions.get()) else {
            // The whole deformation is there (or, while binding, the rest pose).
            level.gather(self.positions.get().unwrap_or(&self.mesh.positions), out);
            return;
        };
        let levels = self.lod().levels();
        let index = levels.iter().position(|l| std::ptr::eq(l, level));
        let samplers = self
            .samplers
            .get_or_init(|| vec![OnceCell::new(); levels.len()]);
        let sampler = index.and_then(|i| {
            let cell = samplers.get(i)?;
            Some(cell.get_or_init(|| bound.sampler(&level.source).unwrap_or_default()))
        });
        let deformed = match (index, sampler) {
            (Some(i), Some(sampler)) if sampler.len() == level.source.len() => {
                let mut kept = self.kept.borrow_mut();
                let changed = kept.changed.take().filter(|_| kept.level == Some(i));
                let done = match changed {
                    Some(list) => {
                        bound.update_sampled(&self.activations, &list, sampler, &mut kept.pose)
                    }
                    None => bound.deform_sampled_pose(&self.activations, sampler, &mut kept.pose),
                }
                .is_ok();
                kept.level = done.then_some(i);
                kept.changed = Some(Vec::new());
                out.clear();
                out.extend_from_slice(kept.pose.positions());
                done
            }
            _ => bound
                .deform_at(&self.activations, &level.source, out)
                .is_ok(),
        };
        if !deformed {
            level.gather(&self.mesh.positions, out);
        }
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        match &self.binding {
            Binding::Bound(bound) => bound.rig(),
            Binding::Pending { rig, .. } => rig,
        }
    }

    /// How the face is shown: its axes and the region views fit.
    pub fn framing(&self) -> &Framing {
        &self.framing
    }

    /// The rest mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Millimetres per mesh unit when the mesh's scale is known, else `None`.
    pub fn mm_per_unit(&self) -> Option<f32> {
        self.mm_per_unit
    }

    /// The deformed vertex positions for the last activations given (computed here for a
    /// mesh with levels of detail, the first time after a change).
    pub fn positions(&self) -> &[Vec3] {
        self.positions.get_or_init(|| {
            let mut out = Vec::new();
            let deformed = self.bound().map(|b| b.deform(&self.activations, &mut out));
            if !matches!(deformed, Some(Ok(()))) {
                out.clone_from(&self.mesh.positions);
            }
            out
        })
    }

    /// Counts changes of the positions, so a view can tell whether it must draw the face again.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Recomputes every deformed position. Activations the model refuses (the editor keeps
    /// them in range, so this does not happen) leave the face as it was.
    pub fn deform(&mut self, activations: &Activations) {
        self.activations.clone_from(activations);
        let Binding::Bound(bound) = &self.binding else {
            // Kept for when the bind lands; the rest pose stays on screen.
            return;
        };
        self.generation += 1;
        if self.big {
            // Deformed when asked for: a frame deforms only the level it draws.
            self.positions = OnceCell::new();
            self.kept.get_mut().changed = None;
        } else if let Some(positions) = self.positions.get_mut() {
            let _ = bound.deform(activations, positions);
        }
    }

    /// Checks that `rig` binds to this scene's mesh, saying why not.
    pub fn check_rig(&self, rig: &Rig) -> Result<(), String> {
        crate::io::rig_file::check_rig_mesh(rig, &self.mesh).map_err(|e| e.to_string())
    }

    /// Replaces the rig (rig mode's edits), keeping the old one when the new one does not
    /// bind to the mesh. The positions are those of the rest pose until the next deform.
    pub fn set_rig(&mut self, rig: Rig) -> Result<(), String> {
        let bound = Deformation::default()
            .bind(&rig, &self.mesh)
            .map_err(|e| e.to_string())?;
        // A bind still running on a thread is of the old rig: its result is let go.
        self.binding = Binding::Bound(Box::new(bound));
        self.positions = OnceCell::from(self.mesh.positions.clone());
        self.activations = Activations::zero(&rig);
        self.samplers = OnceCell::new();
        self.kept = RefCell::default();
        self.generation += 1;
        Ok(())
    }

    /// Gives muscles new parameters (rig mode's edit of a muscle and its partner), binding
    /// only their fields again; when the model refuses, the rig stays as it was and the
    /// reason is returned. The positions are those of the old rig until the next deform.
    pub fn rebind_muscles(&mut self, changes: Vec<(usize, MuscleKind)>) -> Result<(), String> {
        self.bound_mut()?
            .rebind_muscles(changes)
            .map_err(|e| e.to_string())?;
        self.samplers = OnceCell::new();
        self.kept = RefCell::default();
        self.generation += 1;
        Ok(())
    }

    /// Gives the jaw a new pivot, axis and degrees per unit, like
    /// [`Face::rebind_muscles`].
    pub fn rebind_jaw(
        &mut self,
        pivot: Vec3,
        axis: Vec3,
        degrees_per_unit: f32,
    ) -> Result<(), String> {
        self.bound_mut()?
            .rebind_jaw(pivot, axis, degrees_per_unit)
            .map_err(|e| e.to_string())?;
        self.samplers = OnceCell::new();
        self.kept = RefCell::default();
        self.generation += 1;
        Ok(())
    }

    /// Recomputes the region of one muscle (or everything for the jaw, `None`), after
    /// `activations` changed in that muscle only. A big mesh only notes the change: the next
    /// frame recomputes the vertices of its level that the muscle reaches ([`Face::sample`]),
    /// and the whole mesh is deformed again when asked for (keeping it in step would cost
    /// milliseconds a key on a big head).
    pub fn update_muscle(&mut self, activations: &Activations, muscle: Option<usize>) {
        let Binding::Bound(bound) = &self.binding else {
            self.activations.clone_from(activations);
            return;
        };
        if self.big {
            self.generation += 1;
            self.activations.clone_from(activations);
            self.positions = OnceCell::new();
            let which = muscle.unwrap_or(bound.muscle_count());
            self.kept.get_mut().change(which);
            return;
        }
        let updated = match (muscle, self.positions.get_mut()) {
            (Some(i), Some(positions)) => bound.update_muscle(activations, i, positions).is_ok(),
            _ => false,
        };
        if updated {
            self.generation += 1;
            self.activations.clone_from(activations);
        } else {
            self.deform(activations);
        }
    }
}

/// The editor's deformation of `rig` on `mesh` (through the bind cache, which a big head
/// starts from), its error as the editor says it.
fn bind(rig: &Rig, mesh: &Mesh) -> Result<Bound, String> {
    crate::io::bind_cache::bind(Deformation::default(), rig, mesh)
        .map(|done| (done.bound, done.warnings))
        .map_err(|e| format!("the rig does not fit its mesh: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::builtin;
    use crate::tui::fixture::big_face;

    fn bits(p: &[Vec3]) -> Vec<[u32; 3]> {
        p.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
    }

    #[test]
    fn a_big_mesh_is_drawn_from_its_level_deformed_as_the_whole_mesh_is() {
        let rig = builtin::default_rig();
        let mut scene = Face::new(rig.clone(), big_face()).unwrap();
        assert!(!scene.wait_for_lod().is_empty());
        let bound = Deformation::default().bind(&rig, scene.mesh()).unwrap();
        let mut act = builtin::default_table()
            .expression_activations("happiness", &rig)
            .unwrap();
        act.jaw = 2.0;
        let level = scene.lod().levels()[0].clone();
        let jaw = rig.muscles.len();
        // What changes before each frame: everything, one muscle, the jaw and two muscles
        // (the level kept in step by the changes alone), then one muscle at a time with the
        // whole mesh asked for after each.
        let steps: [&[usize]; 5] = [&[], &[0], &[jaw, 3, 5], &[7], &[1]];
        let (mut sampled, mut gathered, mut whole) = (Vec::new(), Vec::new(), Vec::new());
        for (step, changes) in steps.iter().enumerate() {
            if changes.is_empty() {
                scene.deform(&act);
            }
            for &k in *changes {
                if k == jaw {
                    act.jaw = 3.5;
                    scene.update_muscle(&act, None);
                } else {
                    act.muscles[k] = 0.3 + 0.2 * step as f32;
                    scene.update_muscle(&act, Some(k));
                }
            }
            scene.sample(&scene.lod().levels()[0], &mut sampled);
            bound.deform(&act, &mut whole).unwrap();
            level.gather(&whole, &mut gathered);
            assert_eq!(bits(&sampled), bits(&gathered), "step {step}");
            if step >= 3 {
                assert_eq!(bits(scene.positions()), bits(&whole), "step {step}");
            }
        }
    }

    #[test]
    fn a_started_big_face_shows_its_rest_pose_until_the_bind_lands_then_what_was_given_meanwhile() {
        let rig = builtin::default_rig();
        let mut scene = crate::tui::fixture::started(rig.clone(), big_face()).unwrap();
        // The slot is taken only by a poll: until then the face is binding, whatever the
        // thread has done.
        assert!(scene.is_binding());
        let rest = bits(&scene.mesh().positions);
        let mut act = builtin::default_table()
            .expression_activations("happiness", &rig)
            .unwrap();
        scene.deform(&act);
        act.muscles[2] = 0.7;
        scene.update_muscle(&act, Some(2));
        act.jaw = 1.5;
        scene.update_muscle(&act, None);
        assert_eq!(bits(scene.positions()), rest);
        assert_eq!(scene.generation(), 0, "nothing new to draw while binding");
        let level = scene.wait_for_lod().levels()[0].clone();
        let mut sampled = Vec::new();
        scene.sample(&level, &mut sampled);
        let mut gathered = Vec::new();
        level.gather(&scene.mesh().positions, &mut gathered);
        assert_eq!(bits(&sampled), bits(&gathered), "the level at rest too");
        scene.wait_for_bind().unwrap();
        assert!(!scene.is_binding());
        assert!(scene.poll_bind().is_none(), "nothing left to take");
        assert_eq!(scene.generation(), 1);
        let mut whole = Vec::new();
        let bound = Deformation::default().bind(&rig, scene.mesh()).unwrap();
        bound.deform(&act, &mut whole).unwrap();
        scene.sample(&level, &mut sampled);
        level.gather(&whole, &mut gathered);
        assert_eq!(bits(&sampled), bits(&gathered));
        assert_eq!(bits(scene.positions()), bits(&whole));
        assert_ne!(bits(&whole), rest);
    }

    #[test]
    fn a_started_big_face_whose_rig_does_not_bind_says_why_when_polled() {
        let mut rig = builtin::default_rig();
        // A cone wider than a half turn: the load checks pass it, the bind does not.
        let (name, linear) = rig
            .muscles
            .iter_mut()
            .find_map(|m| match &mut m.kind {
                MuscleKind::Linear(linear) => Some((m.name.clone(), linear)),
                _ => None,
            })
            .expect("a linear muscle");
        linear.zone = 120.0;
        let mut scene = crate::tui::fixture::started(rig, big_face()).unwrap();
        let error = scene.wait_for_bind().unwrap_err();
        assert!(
            error.starts_with("the rig does not fit its mesh"),
            "{error}"
        );
        assert!(error.contains(&name), "{error}");
        assert!(scene.is_binding(), "the rest pose stays");
        assert_eq!(scene.poll_bind(), Some(Err(error)), "told again");
        // A small face binds at once, its errors before anything is shown.
        assert!(
            crate::tui::fixture::started(builtin::default_rig(), builtin::default_mesh())
                .is_ok_and(|face| !face.is_binding())
        );
    }

    #[test]
    fn the_built_in_face_knows_its_millimetres_and_another_mesh_does_not() {
        let rig = builtin::default_rig();
        let face = Face::new(rig.clone(), builtin::default_mesh()).unwrap();
        assert_eq!(
            face.mm_per_unit(),
            Some(crate::face::anthropometry::MM_PER_UNIT as f32)
        );
        let big = Face::new(rig, big_face()).unwrap();
        assert_eq!(big.mm_per_unit(), None);
    }
}
