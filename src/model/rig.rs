//! Rigs: a set of named muscles and a jaw, placed on a mesh.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::jaw::Jaw;
use glam::Vec3;

use super::muscle::{Muscle, MuscleKind, Side};

/// The rig file format version this build writes (and reads; older versions are converted
/// on load, see `docs/formats.md`). Version 2 uses glTF's convention, the subject's left at
/// positive x; version 1 had it at negative x.
pub const RIG_VERSION: u32 = 2;

/// How the displacements of several muscles acting on one vertex combine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Combine {
    /// Displacements add up (MODEL-NOTES section 0).
    #[default]
    Sum,
    /// Each vertex's summed displacement is divided by the number of active muscles that
    /// moved it (the paper's section 4.2 remedy).
    Average,
}

/// A rig: named muscles and an optional jaw, placed on a mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Rig {
    /// File format version; see [`RIG_VERSION`].
    pub version: u32,
    /// The mesh the rig is placed on: a path relative to the rig file, or `builtin:NAME`.
    pub mesh: PathBuf,
    /// The mesh's 68 landmarks (a landmark file, relative to the rig file), when they are not
    /// the built-in mesh's own or `MESH.landmarks.ron` beside the mesh: the views frame the
    /// face and draw its brows and eyes from them, `check` and `capture` measure with them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub landmarks: Option<PathBuf>,
    /// How overlapping muscles combine.
    #[serde(default)]
    pub combine: Combine,
    /// The muscles, in display order.
    pub muscles: Vec<Muscle>,
    /// The jaw, if the rig has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub jaw: Option<Jaw>,
    /// Where some muscles may not move the mesh: per-vertex weights that scale their fields
    /// (eyeballs and teeth kept still, one lip kept out of the other lip's muscles).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub masks: Vec<Mask>,
}

/// A gain and per-vertex weights applied to the fields of some muscles.
///
/// A muscle's displacement of every vertex is multiplied by `gain`, and that of a listed
/// vertex also by the vertex's weight. A muscle named by several masks gets the product.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mask {
    /// The muscles the mask applies to.
    pub muscles: Vec<String>,
    /// A factor on the whole field (sheets and sphincters pull by lengths of their own, so a
    /// rig fitted to a face of another size scales them by it).
    #[serde(default = "one")]
    pub gain: f32,
    /// `(vertex, weight)` pairs, weight in 0.0 to 1.0, sorted by vertex with no repeats.
    pub weights: Vec<(u32, f32)>,
}

impl Rig {
    /// The factor the rig's masks put on muscle `name`'s pull at vertex `v`: the product of
    /// every mask naming it, each its gain times the vertex's weight (1 where the mask does
    /// not list the vertex). Computed in f64 so long products of gains stay exact enough to
    /// compare.
    pub fn mask_weight(&self, name: &str, v: u32) -> f64 {
        self.masks
            .iter()
            .filter(|m| m.muscles.iter().any(|n| n == name))
            .map(|m| {
                let w = m
                    .weights
                    .binary_search_by_key(&v, |&(i, _)| i)
                    .map_or(1.0, |k| m.weights[k].1);
                f64::from(m.gain) * f64::from(w)
            })
            .product()
    }

    /// The index of the muscle with this name.
    pub fn muscle_index(&self, name: &str) -> Option<usize> {
        self.muscles.iter().position(|m| m.name == name)
    }

    /// The index of the mirror partner of muscle `index`, if it has one that exists.
    pub fn mirror_of(&self, index: usize) -> Option<usize> {
        let partner = self.muscles.get(index)?.mirror.as_deref()?;
        self.muscle_index(partner)
    }

    /// The normal of the plane the face mirrors across, as the rig's partners show it: the
    /// mean direction from each right-side point to its left partner. On a head fitted in any
    /// orientation this is the face's own left-right axis; on the built-in face it is x
    /// exactly (summed and normalised in f64: in f32 the unit length of some sums along x
    /// rounded to 0.99999994). `None` without partners.
    pub fn mirror_normal(&self) -> Option<Vec3> {
        let mut sum = glam::DVec3::ZERO;
        for (i, muscle) in self.muscles.iter().enumerate() {
            let Some(j) = self.mirror_of(i) else {
                continue;
            };
            if muscle.side != Side::Left {
                continue;
            }
            for (l, r) in points(&muscle.kind)
                .into_iter()
                .zip(points(&self.muscles[j].kind))
            {
                sum += (l - r).as_dvec3();
            }
        }
        let n = sum.normalize_or_zero().as_vec3();
        (n != Vec3::ZERO && n.is_finite()).then_some(n)
    }
}

/// A muscle's defining points, in a fixed order per kind.
fn points(kind: &MuscleKind) -> Vec<Vec3> {
    match kind {
        MuscleKind::Linear(l) => vec![l.attachment, l.insertion],
        MuscleKind::Sphincter(s) => vec![s.centre],
        MuscleKind::Sheet(s) => vec![
            s.attachment[0],
            s.attachment[1],
            s.insertion[0],
            s.insertion[1],
        ],
    }
}

/// `v` reflected across the plane through the origin with unit normal `n`.
pub fn reflect(v: Vec3, n: Vec3) -> Vec3 {
    v - 2.0 * v.dot(n) * n
}

fn one() -> f32 {
    1.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::builtin;

    #[test]
    fn the_mirror_normal_is_the_faces_own_left_right_axis() {
        let rig = builtin::default_rig();
        assert_eq!(rig.mirror_normal(), Some(Vec3::X));
        // Turned 30 degrees about the vertical: the normal turns with the face.
        let turn = glam::Quat::from_rotation_y(30f32.to_radians());
        let mut turned = rig.clone();
        for muscle in &mut turned.muscles {
            match &mut muscle.kind {
                MuscleKind::Linear(l) => {
                    l.attachment = turn * l.attachment;
                    l.insertion = turn * l.insertion;
                }
                MuscleKind::Sphincter(s) => s.centre = turn * s.centre,
                MuscleKind::Sheet(s) => {
                    for p in s.attachment.iter_mut().chain(&mut s.insertion) {
                        *p = turn * *p;
                    }
                }
            }
        }
        let n = turned.mirror_normal().unwrap();
        assert!((n - turn * Vec3::X).length() < 1e-5, "{n}");
        let v = Vec3::new(0.3, 0.2, -0.1);
        assert!(reflect(reflect(v, n), n).distance(v) < 1e-6);
    }
}
