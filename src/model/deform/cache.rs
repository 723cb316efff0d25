//! What a bind cache keeps of a bound rig, and a bound rig made again from it.
//!
//! A bind's cost on a big head is the muscles' fields and, mostly, the rest-surface patches
//! the slide rule fits around every moved vertex (`slide::fit_patches`). Those two are kept
//! ([`BoundRig::cache_parts`]); everything else (the CSR rows, the jaw, the area bound's
//! triangles) is found again from the rig and the mesh by the same code a fresh bind runs,
//! so [`BoundRig::from_cache`] gives a bound rig equal to a fresh one, bit for bit, when the
//! parts are those a fresh bind of the same rig, mesh and rules made.
//!
//! Whether they are is for the cache's key to say (`io::bind_cache`): it hashes the rig,
//! the mesh, the skin rules and [`BIND_CODE`], the source text of the code that computes
//! the parts, so a change of the deformation's rules or of their parameters makes every
//! cache made before it a miss. The parts themselves are checked here against the rig and
//! the mesh (counts, sorted vertices, finite numbers), so a damaged cache that slipped
//! past the key and its checksum gives an error, never a panic or a wrong index.

use std::sync::Arc;

use glam::Vec3;

use super::checks::{bind_jaw, check_reach, validate_names};
use super::slide::{Patch, PATCH_FLOATS};
use super::spread::Surface;
use super::{BoundRig, SkinRules};
use crate::model::field::Field;
use crate::model::mesh::Mesh;
use crate::model::rig::Rig;

/// Numbers per kept patch.
pub const CACHE_PATCH_FLOATS: usize = PATCH_FLOATS;

/// The source text of everything that computes what a bind cache keeps: the fields, the
/// masks' scales, the spread, the patches, the checks and the rows. A cache's key hashes it,
/// so any change to this code invalidates caches written before.
pub const BIND_CODE: [&str; 13] = [
    include_str!("../deform.rs"),
    include_str!("cache.rs"),
    include_str!("checks.rs"),
    include_str!("skin.rs"),
    include_str!("slide.rs"),
    include_str!("spread.rs"),
    include_str!("stretch.rs"),
    include_str!("../field.rs"),
    include_str!("../muscle.rs"),
    include_str!("../jaw.rs"),
    include_str!("../rig.rs"),
    include_str!("../mesh.rs"),
    include_str!("../envelope.rs"),
];

/// The costly parts of a bind, borrowed from a bound rig for writing.
#[derive(Debug)]
pub struct CacheParts<'a> {
    /// Each muscle's field, in rig order (masks applied, spread when the rules spread).
    pub fields: &'a [Field],
    /// The slide's rest-surface patch of each CSR row, [`CACHE_PATCH_FLOATS`] numbers each
    /// (empty when nothing slides).
    pub patches: Vec<[f32; CACHE_PATCH_FLOATS]>,
}

impl BoundRig {
    /// The parts a bind cache keeps.
    pub fn cache_parts(&self) -> CacheParts<'_> {
        CacheParts {
            fields: &self.fields,
            patches: self.patches.iter().map(|p| p.to_floats()).collect(),
        }
    }

    /// The rig bound to `mesh` with `skin` from kept parts, without computing the fields or
    /// fitting the patches. Gives what [`BoundRig::bind_with`] gives when the parts are
    /// the ones it made for the same rig, mesh and rules; parts that cannot be those (wrong
    /// counts, unsorted or out-of-range vertices, numbers that are not finite) are refused
    /// with the reason.
    pub fn from_cache(
        rig: &Rig,
        mesh: &Mesh,
        skin: SkinRules,
        fields: Vec<Field>,
        patches: Vec<[f32; CACHE_PATCH_FLOATS]>,
    ) -> Result<BoundRig, String> {
        skin.check()?;
        mesh.validate().map_err(|e| e.to_string())?;
        validate_names(rig).map_err(|e| e.to_string())?;
        check_fields(rig, mesh, &fields)?;
        let rest = mesh.positions.clone();
        check_reach(rig, &rest, &fields).map_err(|e| e.to_string())?;
        let mut jaw = bind_jaw(rig, rest.len()).map_err(|e| e.to_string())?;
        if let Some(jaw) = jaw.as_mut().filter(|_| skin.stretch > 0.0) {
            let adjacency = super::skin::Adjacency::of(mesh);
            super::stretch::limit_jaw(jaw, &rest, &adjacency, skin.stretch);
        }
        let surface = (skin.spread > 0.0).then(|| Arc::new(Surface::of(mesh)));
        let mut bound = BoundRig::unbuilt(rig, rest, fields, jaw, skin, surface);
        bound.build_rows().map_err(|e| e.to_string())?;
        let rows = if skin.slide > 0.0 {
            bound.row_vertex.len()
        } else {
            0
        };
        if patches.len() != rows {
            return Err(format!(
                "{} surface patches kept for {rows} moved vertices",
                patches.len()
            ));
        }
        if patches.iter().flatten().any(|x| !x.is_finite()) {
            return Err("a kept surface patch is not finite".to_string());
        }
        bound.patches = patches.into_iter().map(Patch::from_floats).collect();
        bound.build_guard(mesh);
        bound.followers = mesh.followers();
        Ok(bound)
    }
}

/// Checks kept fields against the rig and the mesh: one per muscle, vertices strictly
/// increasing and in the mesh, a finite displacement for each.
fn check_fields(rig: &Rig, mesh: &Mesh, fields: &[Field]) -> Result<(), String> {
    if fields.len() != rig.muscles.len() {
        return Err(format!(
            "{} fields kept for {} muscles",
            fields.len(),
            rig.muscles.len()
        ));
    }
    let count = mesh.positions.len();
    for (field, muscle) in fields.iter().zip(&rig.muscles) {
        let name = &muscle.name;
        if field.vertices.len() != field.displacements.len() {
            return Err(format!(
                "muscle `{name}`: vertices and displacements differ"
            ));
        }
        let sorted = field.vertices.windows(2).all(|w| w[0] < w[1]);
        let inside = field.vertices.last().is_none_or(|&v| (v as usize) < count);
        if !(sorted && inside) {
            return Err(format!(
                "muscle `{name}`: vertices unsorted or not in the mesh"
            ));
        }
        if !field.displacements.iter().all(|d: &Vec3| d.is_finite()) {
            return Err(format!("muscle `{name}`: a displacement is not finite"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::BIND_CODE;

    /// The deformation's files whose code a cached bind does not depend on: the area bound's
    /// triangles are found again at load, frames and sampled frames are computed from the
    /// bound parts, a rebind edits a bound rig (and equals a fresh bind), and the tests.
    const NOT_CACHED: [&str; 5] = ["guard.rs", "whole.rs", "sample.rs", "rebind.rs", "tests.rs"];

    /// Every file of the deformation is either in [`BIND_CODE`] or named as not cached, so a
    /// new step of the bind cannot leave old caches hitting (the stretch limit's file was
    /// missing: a change of its slope would have kept serving fields capped the old way).
    #[test]
    fn every_file_of_the_bind_is_in_the_cache_key() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/model/deform");
        let mut seen = 0;
        for entry in std::fs::read_dir(&dir).expect("the deformation's sources") {
            let path = entry.expect("a directory entry").path();
            let name = path
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default();
            if !name.ends_with(".rs") || NOT_CACHED.contains(&name) {
                continue;
            }
            let text = std::fs::read_to_string(&path).expect("a source file");
            assert!(
                BIND_CODE.contains(&text.as_str()),
                "{name} is neither in BIND_CODE nor in NOT_CACHED"
            );
            seen += 1;
        }
        assert!(
            seen >= 6,
            "only {seen} of the bind's files were found in {dir:?}"
        );
    }
}
