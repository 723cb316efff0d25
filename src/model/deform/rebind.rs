//! Binding again after a change of one or two muscles' parameters, or of the jaw's pose,
//! without recomputing the fields of the muscles that did not change.
//!
//! The result is the [`BoundRig`] that [`BoundRig::bind`] gives for the changed rig, bit for
//! bit, and a change it refuses leaves the bound rig as it was, with the error that `bind`
//! would report for the changed rig.

use glam::Vec3;

use super::skin::Adjacency;
use super::{
    bind_jaw, check_budget, check_reach, spread, stretch, BindError, BoundRig, MAX_INFLUENCES,
};
use crate::model::field::{validate_muscle, Field};
use crate::model::muscle::{Muscle, MuscleKind};
use crate::model::Rig;

impl BoundRig {
    /// Gives muscle `index` new parameters (its kind and geometry; its name, side and
    /// partner stay) and recomputes its field alone: the same as binding the changed rig, at
    /// the cost of one muscle's field and the per-vertex layout.
    pub fn rebind_muscle(&mut self, index: usize, kind: MuscleKind) -> Result<(), BindError> {
        self.rebind_muscles(vec![(index, kind)])
    }

    /// [`BoundRig::rebind_muscle`] for several muscles at once (a muscle and its mirror
    /// partner), laying the fields out once. An index past the last muscle is refused as
    /// an invalid parameter of no muscle.
    pub fn rebind_muscles(&mut self, changes: Vec<(usize, MuscleKind)>) -> Result<(), BindError> {
        let count = self.rest.len();
        if let Some(&(index, _)) = changes.iter().find(|(i, _)| *i >= self.fields.len()) {
            return Err(BindError::InvalidParameter {
                muscle: format!("#{index}"),
                parameter: "index",
                message: format!("is past the rig's {} muscles", self.fields.len()),
            });
        }
        // `bind` checks every muscle in order and reports the first bad one.
        let mut sorted = changes;
        sorted.sort_by_key(|(index, _)| *index);
        for (index, kind) in &sorted {
            let muscle = Muscle {
                kind: kind.clone(),
                ..self.rig.muscles[*index].clone()
            };
            validate_muscle(&muscle)?;
        }
        // Only a rig large enough for the influence budget to matter pays for counting it.
        if self.fields.len().saturating_mul(count) > MAX_INFLUENCES {
            let mut rig = self.rig.clone();
            for (index, kind) in &sorted {
                rig.muscles[*index].kind = kind.clone();
            }
            check_budget(&rig, &self.rest)?;
        }
        let mut rig = self.rig.clone();
        for (index, kind) in &sorted {
            rig.muscles[*index].kind = kind.clone();
        }
        // A changed spread length (a muscle moved the rig's box) spreads every field again.
        let length = spread::spread_length(&rig, self.skin.spread);
        let changed: Vec<usize> = if self.surface.is_some() && length != self.spread_length {
            (0..rig.muscles.len()).collect()
        } else {
            // the stretch limit caps a mirror pair by its sum: a partner's field changes too
            let mut changed: Vec<usize> = sorted.iter().map(|(index, _)| *index).collect();
            if self.skin.stretch > 0.0 {
                let partners: Vec<usize> =
                    changed.iter().filter_map(|&i| rig.mirror_of(i)).collect();
                changed.extend(partners);
                changed.sort_unstable();
                changed.dedup();
            }
            changed
        };
        let mut old = Vec::with_capacity(changed.len());
        for (&index, field) in changed.iter().zip(self.fields_of(&rig, &changed, length)) {
            old.push(std::mem::replace(&mut self.fields[index], field));
        }
        if let Err(error) = check_reach(&rig, &self.rest, &self.fields) {
            for (&index, field) in changed.iter().zip(old) {
                self.fields[index] = field;
            }
            return Err(error);
        }
        self.rig = rig;
        self.spread_length = length;
        self.rebuild_rows()
    }

    /// The fields of muscles `indices` (in that order) on the rest mesh as `bind` computes
    /// them: each muscle's own, masked, spread by `length` when the fields are spread, then
    /// capped with its mirror partner's by the stretch limit (`indices` holds the partners).
    fn fields_of(&self, rig: &Rig, indices: &[usize], length: f64) -> Vec<Field> {
        match (stretch::Limit::of(self.skin.stretch), &self.skin_mesh) {
            (Some(limit), Some(mesh)) => {
                let mut own = vec![Field::default(); rig.muscles.len()];
                for &i in indices {
                    own[i] = self.own_field(rig, i, length);
                }
                let adjacency = Adjacency::of(mesh);
                stretch::limit_all(rig, &own, indices, &mesh.positions, &adjacency, limit)
            }
            _ => indices
                .iter()
                .map(|&i| self.own_field(rig, i, length))
                .collect(),
        }
    }

    /// Muscle `index`'s field before the stretch limit: its own, masked, then spread by
    /// `length` when the fields are spread.
    fn own_field(&self, rig: &Rig, index: usize, length: f64) -> Field {
        let count = self.rest.len();
        let scale = mask_scale(rig, index, count);
        let field = Field::of(&rig.muscles[index].kind, &self.rest);
        let field = match &scale {
            Some(scale) => field.scaled(scale),
            None => field,
        };
        match &self.surface {
            Some(surface) => spread::spread_one(
                surface,
                &rig.muscles[index].kind,
                field,
                scale.as_deref(),
                length,
            ),
            None => field,
        }
    }

    /// Gives the jaw a new pivot, axis and degrees per unit (its weights stay): the same as
    /// binding the changed rig, without touching any muscle's field. A rig without a jaw
    /// refuses it.
    pub fn rebind_jaw(
        &mut self,
        pivot: Vec3,
        axis: Vec3,
        degrees_per_unit: f32,
    ) -> Result<(), BindError> {
        let Some(jaw) = self.rig.jaw.as_mut() else {
            return Err(BindError::JawParameter {
                parameter: "jaw",
                value: "none (the rig has no jaw)".into(),
            });
        };
        let before = (jaw.pivot, jaw.axis, jaw.degrees_per_unit);
        (jaw.pivot, jaw.axis, jaw.degrees_per_unit) = (pivot, axis, degrees_per_unit);
        match bind_jaw(&self.rig, self.rest.len()) {
            Ok(Some(mut bound)) => {
                if let Some(mesh) = self.skin_mesh.as_ref().filter(|_| self.skin.stretch > 0.0) {
                    let adjacency = Adjacency::of(mesh);
                    stretch::limit_jaw(&mut bound, &mesh.positions, &adjacency, self.skin.stretch);
                }
                // The jaw's vertices did not change (the stretch limit lowers weights but
                // keeps every vertex), so neither did their rows.
                if let Some(old) = &mut self.jaw {
                    bound.rows = std::mem::take(&mut old.rows);
                }
                self.jaw = Some(bound);
                self.rebuild_skin();
                Ok(())
            }
            Ok(None) => unreachable!("the rig has a jaw"),
            Err(error) => {
                if let Some(jaw) = self.rig.jaw.as_mut() {
                    (jaw.pivot, jaw.axis, jaw.degrees_per_unit) = before;
                }
                Err(error)
            }
        }
    }

    /// Lays the fields out per vertex again, from scratch.
    fn rebuild_rows(&mut self) -> Result<(), BindError> {
        self.row_vertex.clear();
        self.row_start.clear();
        self.entries.clear();
        self.muscle_rows.clear();
        self.row_jaw_weight.clear();
        self.row_split.clear();
        self.build_rows()?;
        self.rebuild_skin();
        Ok(())
    }
}

/// The product of the weights of the masks naming muscle `index` (one per vertex), or `None`
/// when no mask names it: `mask_scales(rig, count)[index]`, in the same order of products,
/// for one muscle of a rig whose masks were checked when it was bound.
fn mask_scale(rig: &Rig, index: usize, count: usize) -> Option<Vec<f32>> {
    let name = &rig.muscles[index].name;
    let mut scale: Option<Vec<f32>> = None;
    for mask in &rig.masks {
        for _ in mask.muscles.iter().filter(|n| *n == name) {
            let scale = scale.get_or_insert_with(|| vec![1.0; count]);
            if mask.gain != 1.0 {
                scale.iter_mut().for_each(|s| *s *= mask.gain);
            }
            for &(vertex, weight) in &mask.weights {
                scale[vertex as usize] *= weight;
            }
        }
    }
    scale
}

#[cfg(test)]
mod tests {
    //! A rebound rig equals the rig bound from scratch, bit for bit, on the default face.

    use super::*;
    use crate::model::Activations;

    fn default_face() -> (Rig, crate::model::Mesh) {
        let loaded = crate::io::load::load_rig_ref(std::path::Path::new("builtin:default"), None)
            .expect("the built-in rig");
        (loaded.rig, loaded.mesh)
    }

    fn bits(points: &[Vec3]) -> Vec<[u32; 3]> {
        points
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    }

    /// Every muscle at 0.7 and the jaw at 1.5: all fields and the jaw take part.
    fn deformed(bound: &BoundRig) -> Vec<[u32; 3]> {
        let act = Activations {
            muscles: vec![0.7; bound.muscle_count()],
            jaw: 1.5,
        };
        let mut out = Vec::new();
        bound.deform(&act, &mut out).expect("in range");
        bits(&out)
    }

    fn moved(kind: &MuscleKind, by: Vec3) -> MuscleKind {
        let mut kind = kind.clone();
        match &mut kind {
            MuscleKind::Linear(m) => {
                m.attachment += by;
                m.zone += 3.0;
            }
            MuscleKind::Sphincter(m) => {
                m.centre += by;
                m.semi_minor *= 0.9;
                m.frame.x = Vec3::new(1.0, 0.2, 0.0);
            }
            MuscleKind::Sheet(m) => {
                m.insertion[0] += by;
                m.width *= 1.1;
            }
        }
        kind
    }

    #[test]
    fn rebinding_each_muscle_equals_binding_the_changed_rig() {
        let (rig, mesh) = default_face();
        let by = Vec3::new(0.004, -0.003, 0.001);
        let mut kinds_seen = [false; 3];
        for index in 0..rig.muscles.len() {
            let kind = moved(&rig.muscles[index].kind, by);
            kinds_seen[match kind {
                MuscleKind::Linear(_) => 0,
                MuscleKind::Sphincter(_) => 1,
                MuscleKind::Sheet(_) => 2,
            }] = true;
            let mut changed = rig.clone();
            changed.muscles[index].kind = kind.clone();
            let want = BoundRig::bind(&changed, &mesh).expect("the changed rig binds");
            let mut got = BoundRig::bind(&rig, &mesh).expect("binds");
            got.rebind_muscle(index, kind).expect("rebinds");
            assert!(got == want, "muscle {}", rig.muscles[index].name);
            assert_eq!(deformed(&got), deformed(&want));
        }
        assert_eq!(kinds_seen, [true; 3], "every kind is exercised");
    }

    /// With the stretch limit a mirror pair is capped by its sum, so moving one muscle of a
    /// pair can change its partner's field too (where the partner alone is cut harder than
    /// the pair; no move here does that on the built-in face): a rebind of each paired
    /// muscle gives what a fresh bind does.
    #[test]
    fn rebinding_one_of_a_pair_under_the_stretch_limit_equals_binding_the_changed_rig() {
        let (rig, mesh) = default_face();
        let skin = crate::model::SkinRules::DEFAULT;
        let before = BoundRig::bind_with(&rig, &mesh, skin).expect("binds");
        for index in 0..rig.muscles.len() {
            if rig.mirror_of(index).is_none() {
                continue;
            }
            let kind = moved(&rig.muscles[index].kind, Vec3::new(0.05, -0.04, 0.02));
            let mut changed = rig.clone();
            changed.muscles[index].kind = kind.clone();
            let want = BoundRig::bind_with(&changed, &mesh, skin).expect("binds");
            let mut got = before.clone();
            got.rebind_muscle(index, kind).expect("rebinds");
            assert!(got == want, "muscle {}", rig.muscles[index].name);
        }
    }

    #[test]
    fn a_masked_muscle_and_its_partner_rebind_together() {
        let (rig, mesh) = default_face();
        let masked = rig
            .masks
            .iter()
            .flat_map(|m| &m.muscles)
            .find_map(|name| rig.muscle_index(name))
            .expect("the default rig masks a muscle");
        let partner = rig
            .mirror_of(masked)
            .expect("the masked muscle has a partner");
        let by = Vec3::new(0.01, 0.0, 0.0);
        let a = moved(&rig.muscles[masked].kind, by);
        let b = moved(&rig.muscles[partner].kind, -by);
        let mut changed = rig.clone();
        changed.muscles[masked].kind = a.clone();
        changed.muscles[partner].kind = b.clone();
        let want = BoundRig::bind(&changed, &mesh).expect("binds");
        let mut got = BoundRig::bind(&rig, &mesh).expect("binds");
        got.rebind_muscles(vec![(partner, b), (masked, a)])
            .expect("rebinds");
        assert!(got == want);
        assert_eq!(deformed(&got), deformed(&want));
    }

    #[test]
    fn a_refused_change_leaves_the_bound_rig_as_it_was_with_binds_error() {
        let (rig, mesh) = default_face();
        let original = BoundRig::bind(&rig, &mesh).expect("binds");
        let index = rig
            .muscles
            .iter()
            .position(|m| matches!(m.kind, MuscleKind::Linear(_)))
            .expect("a linear muscle");
        let mut kind = rig.muscles[index].kind.clone();
        if let MuscleKind::Linear(m) = &mut kind {
            m.zone = 95.0;
        }
        let mut changed = rig.clone();
        changed.muscles[index].kind = kind.clone();
        let want = BoundRig::bind(&changed, &mesh).expect_err("a zone of 95 is refused");
        let mut got = original.clone();
        assert_eq!(got.rebind_muscle(index, kind), Err(want));
        assert!(got == original);
        // A muscle that reaches too far is refused by the reach check, also unchanged.
        let mut far = rig.muscles[index].kind.clone();
        if let MuscleKind::Linear(m) = &mut far {
            m.attachment *= 1e33;
            m.insertion = m.attachment + Vec3::Z;
            m.falloff_end = 1e38;
        }
        let mut changed = rig.clone();
        changed.muscles[index].kind = far.clone();
        let want = BoundRig::bind(&changed, &mesh).map(|_| ());
        assert_eq!(got.rebind_muscle(index, far), want);
        assert!(got == original);
        assert!(got
            .rebind_muscle(rig.muscles.len(), rig.muscles[0].kind.clone())
            .is_err());
        assert!(got == original);
    }

    #[test]
    fn rebinding_the_jaw_equals_binding_the_changed_rig() {
        let (rig, mesh) = default_face();
        let jaw = rig.jaw.clone().expect("the default rig has a jaw");
        let pivot = jaw.pivot + Vec3::new(0.0, 0.01, -0.02);
        let axis = Vec3::new(0.98, 0.17, 0.0);
        let mut changed = rig.clone();
        if let Some(j) = changed.jaw.as_mut() {
            (j.pivot, j.axis, j.degrees_per_unit) = (pivot, axis, 2.5);
        }
        let want = BoundRig::bind(&changed, &mesh).expect("binds");
        let mut got = BoundRig::bind(&rig, &mesh).expect("binds");
        got.rebind_jaw(pivot, axis, 2.5).expect("rebinds");
        assert!(got == want);
        assert_eq!(deformed(&got), deformed(&want));
        // A zero axis is refused and nothing changes.
        let before = got.clone();
        assert!(matches!(
            got.rebind_jaw(pivot, Vec3::ZERO, 1.0),
            Err(BindError::JawParameter {
                parameter: "axis",
                ..
            })
        ));
        assert!(got == before);
    }

    #[test]
    fn a_rig_keeps_the_shared_mesh_and_rebinds_from_it() {
        use std::sync::Arc;
        let (rig, mesh) = default_face();
        let skin = crate::model::SkinRules::DEFAULT;
        let mut got = BoundRig::bind_with(&rig, &mesh, skin).expect("binds");
        let mut other = mesh.clone();
        other.positions[0].x += 0.01;
        assert!(
            !got.share_mesh(&Arc::new(other)),
            "another mesh is not kept"
        );
        let shared = Arc::new(mesh.clone());
        assert!(got.share_mesh(&shared));
        let kept = |b: &BoundRig| {
            b.skin_mesh
                .as_ref()
                .is_some_and(|m| Arc::ptr_eq(m, &shared))
        };
        assert!(kept(&got), "the rig holds the caller's mesh, not a copy");
        let kind = moved(&rig.muscles[0].kind, Vec3::new(0.004, -0.003, 0.001));
        let mut changed = rig.clone();
        changed.muscles[0].kind = kind.clone();
        let want = BoundRig::bind_with(&changed, &mesh, skin).expect("binds");
        got.rebind_muscle(0, kind).expect("rebinds");
        assert!(got == want, "a rebind from the shared mesh is a fresh bind");
        assert!(kept(&got), "and keeps sharing it");
        // the paper's model keeps no mesh
        assert!(!BoundRig::bind(&rig, &mesh)
            .expect("binds")
            .share_mesh(&shared));
    }
}
