//! Binary glTF 2.0 (`.glb`): the rest mesh and its morph targets, for engines and DCC tools.
//!
//! One mesh with one primitive: `POSITION`, `NORMAL` (the rest pose's area-weighted vertex
//! normals) and 32-bit triangle indices, then one morph target per [`MorphTarget`], holding
//! the `POSITION` and `NORMAL` displacements from rest. A target where most vertices do not
//! move is a sparse accessor (only the moved vertices are stored; one that moves nothing
//! stores one zero). The target names go in the
//! mesh's `extras.targetNames`, where Blender, three.js and Babylon.js read them, and every
//! weight starts at 0.
//!
//! Positions are written in the mesh's own units and axes, unconverted; the node's uniform
//! `scale` turns them into glTF's metres (`metres_per_unit`), and its `rotation` stands a
//! face whose mesh is not y up (a z-up scan or Blender export) upright in glTF's y-up viewers,
//! so the file's numbers stay the ones `grimace export` writes as OBJ.

use std::path::Path;

use ::gltf::json::{self, validation::Checked::Valid, validation::USize64};
use glam::{Quat, Vec3};
use serde_json::json;

use super::atomic;
use super::error::SaveError;
use crate::model::mesh::bounds_of as bounds;
use crate::model::Mesh;

/// A morph target: a name and the mesh's positions in that state (not yet displacements).
#[derive(Debug, Clone, PartialEq)]
pub struct MorphTarget {
    /// The name written to `extras.targetNames`.
    pub name: String,
    /// One deformed position per vertex of the mesh.
    pub positions: Vec<Vec3>,
}

/// Displacements smaller than this (in mesh units) are written as zero, so float noise in
/// an unmoved region does not make a target dense.
pub const MOVE_EPSILON: f32 = 1e-7;

/// The generator string written to `asset.generator`.
const GENERATOR: &str = concat!("grimace ", env!("CARGO_PKG_VERSION"));

/// Where the mesh's node puts the mesh in glTF's world (metres, y up, facing +z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The node's uniform scale.
    pub metres_per_unit: f32,
    /// The node's rotation (identity: the mesh's own axes are kept).
    pub rotation: Quat,
}

impl Placement {
    /// Scaled, in the mesh's own axes.
    pub fn scaled(metres_per_unit: f32) -> Placement {
        Placement {
            metres_per_unit,
            rotation: Quat::IDENTITY,
        }
    }
}

/// The largest file a binary glTF can be: its length fields are 32-bit.
pub const MAX_GLB_BYTES: u64 = u32::MAX as u64;

/// Builds the binary glTF for a mesh and its targets, placed by `placement` (the node's scale
/// and rotation). Every target must have one position per vertex. A file that would not fit
/// in a GLB's 32-bit length fields is refused before anything is built, with its estimated
/// size.
pub fn write_glb(
    mesh: &Mesh,
    targets: &[MorphTarget],
    placement: Placement,
) -> Result<Vec<u8>, String> {
    write_glb_within(mesh, targets, placement, MAX_GLB_BYTES)
}

/// [`write_glb`] with the size limit given (tests use a small one).
fn write_glb_within(
    mesh: &Mesh,
    targets: &[MorphTarget],
    placement: Placement,
    limit: u64,
) -> Result<Vec<u8>, String> {
    let estimate = estimated_bytes(mesh, targets);
    if estimate > limit {
        return Err(too_big(estimate));
    }
    let mut builder = Builder::default();
    let rest_normals = unit_or_up(&mesh.vertex_normals(&mesh.positions));

    let (min, max) = bounds(&mesh.positions);
    let position = builder.dense_vec3(&mesh.positions, Some((min, max)));
    let normal = builder.dense_vec3(&rest_normals, None);
    let indices = builder.indices(&mesh.triangles);

    let morphs: Vec<_> = targets
        .iter()
        .map(|target| morph(&mut builder, mesh, &rest_normals, target))
        .collect();

    let names: Vec<&str> = targets.iter().map(|t| t.name.as_str()).collect();
    let primitive = json::mesh::Primitive {
        attributes: [
            (Valid(json::mesh::Semantic::Positions), position),
            (Valid(json::mesh::Semantic::Normals), normal),
        ]
        .into_iter()
        .collect(),
        extensions: None,
        extras: None,
        indices: Some(indices),
        material: None,
        mode: Valid(json::mesh::Mode::Triangles),
        targets: if morphs.is_empty() {
            None
        } else {
            Some(morphs)
        },
    };
    let mesh_index = builder.root.push(json::Mesh {
        extensions: None,
        extras: raw(json!({ "targetNames": names })),
        name: Some("face".into()),
        primitives: vec![primitive],
        weights: if targets.is_empty() {
            None
        } else {
            Some(vec![0.0; targets.len()])
        },
    });
    let node = builder.root.push(json::Node {
        mesh: Some(mesh_index),
        name: Some("face".into()),
        scale: Some([placement.metres_per_unit; 3]),
        rotation: (placement.rotation != Quat::IDENTITY)
            .then(|| json::scene::UnitQuaternion(placement.rotation.normalize().to_array())),
        ..Default::default()
    });
    let scene = builder.root.push(json::Scene {
        extensions: None,
        extras: None,
        name: None,
        nodes: vec![node],
    });
    builder.root.scene = Some(scene);
    builder.finish()
}

/// One target's accessors: position and normal deltas from rest (tiny ones written as 0).
fn morph(
    builder: &mut Builder,
    mesh: &Mesh,
    rest_normals: &[Vec3],
    target: &MorphTarget,
) -> json::mesh::MorphTarget {
    assert_eq!(
        target.positions.len(),
        mesh.positions.len(),
        "morph target `{}` has another vertex count than the mesh",
        target.name
    );
    let moved: Vec<Vec3> = target
        .positions
        .iter()
        .zip(&mesh.positions)
        .map(|(p, r)| small_to_zero(*p - *r))
        .collect();
    let normals = unit_or_up(&mesh.vertex_normals(&target.positions));
    let turned: Vec<Vec3> = normals
        .iter()
        .zip(rest_normals)
        .map(|(n, r)| small_to_zero(*n - *r))
        .collect();
    json::mesh::MorphTarget {
        positions: Some(builder.delta_vec3(&moved, true)),
        normals: Some(builder.delta_vec3(&turned, false)),
        tangents: None,
    }
}

fn too_big(bytes: u64) -> String {
    format!(
        "the file would be about {:.1} GiB, and a binary glTF holds at most 4 GiB (its length fields are 32-bit); export fewer targets (--targets) or a smaller mesh",
        bytes as f64 / (1u64 << 30) as f64
    )
}

/// An upper bound of the file's size: the rest mesh, each target's moved positions as the
/// writer stores them (sparse or dense), its normals as if dense, and room for the JSON.
fn estimated_bytes(mesh: &Mesh, targets: &[MorphTarget]) -> u64 {
    let v = mesh.positions.len() as u64;
    let mut bytes = 2 * 12 * v + 12 * mesh.triangles.len() as u64 + 4096;
    for target in targets {
        let moved = target
            .positions
            .iter()
            .zip(&mesh.positions)
            .filter(|(p, r)| small_to_zero(**p - **r) != Vec3::ZERO)
            .count() as u64;
        let positions = if moved * 4 >= v * 3 {
            12 * v
        } else {
            16 * moved.max(1)
        };
        bytes += positions + 12 * v + 1024 + target.name.len() as u64;
    }
    bytes
}

/// Writes a `.glb` file atomically, keeping a replaced file as `FILE~`.
pub fn save_glb(
    path: &Path,
    mesh: &Mesh,
    targets: &[MorphTarget],
    placement: Placement,
) -> Result<(), SaveError> {
    let bytes = write_glb(mesh, targets, placement).map_err(|e| SaveError::new(path, e))?;
    atomic::write_atomic(path, &bytes).map_err(|e| SaveError::io(path, &e))
}

/// The root being built and its one binary buffer.
#[derive(Default)]
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
}

impl Builder {
    /// Appends bytes as a buffer view (4-byte aligned; every component here is 4 bytes).
    fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: None,
        })
    }

    fn accessor(
        &mut self,
        view: Option<json::Index<json::buffer::View>>,
        count: usize,
        component: json::accessor::ComponentType,
        kind: json::accessor::Type,
        min_max: Option<(Vec3, Vec3)>,
        sparse: Option<json::accessor::sparse::Sparse>,
    ) -> json::Index<json::Accessor> {
        self.root.push(json::Accessor {
            buffer_view: view,
            byte_offset: view.map(|_| USize64(0)),
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: None,
            type_: Valid(kind),
            min: min_max.map(|(min, _)| json!(min.to_array())),
            max: min_max.map(|(_, max)| json!(max.to_array())),
            name: None,
            normalized: false,
            sparse,
        })
    }

    /// A tightly packed VEC3 float accessor.
    fn dense_vec3(
        &mut self,
        values: &[Vec3],
        min_max: Option<(Vec3, Vec3)>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(&vec3_bytes(values), Some(json::buffer::Target::ArrayBuffer));
        self.accessor(
            Some(view),
            values.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            min_max,
            None,
        )
    }

    /// Triangle indices as 32-bit unsigned scalars.
    fn indices(&mut self, triangles: &[[u32; 3]]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let view = self.view(&bytes, Some(json::buffer::Target::ElementArrayBuffer));
        self.accessor(
            Some(view),
            triangles.len() * 3,
            json::accessor::ComponentType::U32,
            json::accessor::Type::Scalar,
            None,
            None,
        )
    }

    /// A morph target's displacements: sparse when fewer than
    /// three quarters of the vertices move (16 bytes per moved vertex against 12 per vertex),
    /// dense otherwise. `with_bounds` adds min and max (required for `POSITION`).
    fn delta_vec3(&mut self, deltas: &[Vec3], with_bounds: bool) -> json::Index<json::Accessor> {
        let mut moved: Vec<u32> = (0..deltas.len() as u32)
            .filter(|&i| deltas[i as usize] != Vec3::ZERO)
            .collect();
        let min_max = with_bounds.then(|| bounds(deltas));
        if moved.is_empty() {
            // glTF reads an accessor without data as zeros, but some readers (the gltf
            // crate among them) refuse one; a sparse accessor needs at least one entry.
            moved.push(0);
        }
        if moved.len() * 4 >= deltas.len() * 3 {
            return self.dense_vec3(deltas, min_max);
        }
        let index_bytes: Vec<u8> = moved.iter().flat_map(|i| i.to_le_bytes()).collect();
        let values: Vec<Vec3> = moved.iter().map(|&i| deltas[i as usize]).collect();
        let indices = self.view(&index_bytes, None);
        let values = self.view(&vec3_bytes(&values), None);
        let sparse = json::accessor::sparse::Sparse {
            count: USize64::from(moved.len()),
            indices: json::accessor::sparse::Indices {
                buffer_view: indices,
                byte_offset: USize64(0),
                component_type: Valid(json::accessor::IndexComponentType(
                    json::accessor::ComponentType::U32,
                )),
                extensions: None,
                extras: None,
            },
            values: json::accessor::sparse::Values {
                buffer_view: values,
                byte_offset: USize64(0),
                extensions: None,
                extras: None,
            },
            extensions: None,
            extras: None,
        };
        self.accessor(
            None,
            deltas.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            min_max,
            Some(sparse),
        )
    }

    /// The buffer, the JSON and the GLB container around them.
    fn finish(mut self) -> Result<Vec<u8>, String> {
        self.root.asset = json::Asset {
            generator: Some(GENERATOR.into()),
            ..Default::default()
        };
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.root.push(json::Buffer {
            byte_length: USize64::from(self.bin.len()),
            name: None,
            uri: None,
            extensions: None,
            extras: None,
        });
        let json_text = json::serialize::to_vec(&self.root).expect("a glTF root always serializes");
        let glb = ::gltf::Glb {
            header: ::gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                // to_vec computes the length itself.
                length: 0,
            },
            json: json_text.into(),
            bin: Some(self.bin.into()),
        };
        let total = glb.json.len() as u64 + glb.bin.as_ref().map_or(0, |b| b.len() as u64) + 28;
        if total > MAX_GLB_BYTES {
            // The estimate is an upper bound, so this is not reached; never wrap the lengths.
            return Err(too_big(total));
        }
        glb.to_vec()
            .map_err(|e| format!("cannot write the binary glTF: {e}"))
    }
}

fn raw(value: serde_json::Value) -> json::Extras {
    Some(serde_json::value::to_raw_value(&value).expect("a JSON value always serializes"))
}

fn vec3_bytes(values: &[Vec3]) -> Vec<u8> {
    values
        .iter()
        .flat_map(|v| v.to_array())
        .flat_map(f32::to_le_bytes)
        .collect()
}

fn small_to_zero(delta: Vec3) -> Vec3 {
    if delta.abs().max_element() < MOVE_EPSILON {
        Vec3::ZERO
    } else {
        delta
    }
}

/// glTF normals must have unit length: a vertex no triangle uses gets +z.
fn unit_or_up(normals: &[Vec3]) -> Vec<Vec3> {
    normals
        .iter()
        .map(|n| if *n == Vec3::ZERO { Vec3::Z } else { *n })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_past_the_limit_is_refused_before_it_is_built_and_the_estimate_bounds_it() {
        let mesh = crate::io::builtin::default_mesh();
        let lifted: Vec<Vec3> = mesh.positions.iter().map(|p| *p + Vec3::Y).collect();
        let targets: Vec<MorphTarget> = (0..3)
            .map(|i| MorphTarget {
                name: format!("t{i}"),
                positions: lifted.clone(),
            })
            .collect();
        let bytes = write_glb(&mesh, &targets, Placement::scaled(1.0)).unwrap();
        let estimate = estimated_bytes(&mesh, &targets);
        assert!(
            estimate >= bytes.len() as u64,
            "{estimate} < {}",
            bytes.len()
        );
        let err =
            write_glb_within(&mesh, &targets, Placement::scaled(1.0), estimate - 1).unwrap_err();
        assert!(err.contains("at most 4 GiB"), "{err}");
    }
}
