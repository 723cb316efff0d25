//! Rig files (`*.rig.ron`): muscles and jaw placed on a mesh, in RON.
//!
//! The file is read through private mirror types that refuse unknown fields, then checked
//! (version first, then every muscle's parameters, names and mirror partners), and written by
//! hand in a fixed layout so that a save is stable, readable and reads back bit for bit. The
//! format is documented in `docs/formats.md`.
//!
//! The `mesh` field is a path relative to the rig file, or `builtin:NAME` for a mesh embedded
//! in grimace. This module is the format only: loading a rig with the mesh it names is
//! [`super::load`]'s, and built-in names reach the parser as a [`BuiltinMeshes`] function, so
//! the format does not depend on where the embedded meshes live.
//!
//! Version 1 files (the classic convention, the subject's left at negative x) are converted
//! as they are read ([`upgrade_v1`]) and the load says so once
//! ([`super::load::LoadedRig::notice`]).

use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::{Deserialize, Deserializer};

use super::error::{LoadError, SaveError};
use super::{atomic, ron_text};
use crate::model::muscle::mirror_x;
mod check;
mod weights;

pub use check::{check_rig, check_rig_mesh, RigIssue, MAX_MUSCLES};

use crate::model::{
    Combine, Convergence, Frame, Jaw, Linear, Mask, Mesh, Muscle, MuscleKind, Rig, Sheet, Side,
    Sphincter, RIG_VERSION,
};

/// The prefix of a mesh (or rig) reference that names an embedded preset instead of a file.
pub const BUILTIN_PREFIX: &str = "builtin:";

/// Resolves the name after `builtin:` to an embedded mesh, or `None` if there is no such mesh.
pub type BuiltinMeshes = fn(&str) -> Option<Mesh>;

/// The oldest rig file version this build reads; older files than [`RIG_VERSION`] are
/// converted on load.
pub const OLDEST_RIG_VERSION: u32 = 1;

/// Parses and checks the text of a rig file (the mesh is not loaded), converting a version 1
/// file (see [`upgrade_v1`]) with the built-in meshes `builtin`, and returns the notice of a
/// conversion (see [`super::load::LoadedRig::notice`]). `path` is used in error messages only.
pub fn parse_rig_with(
    text: &str,
    path: &Path,
    builtin: BuiltinMeshes,
) -> Result<(Rig, Option<String>), LoadError> {
    // One pass over the text when it reads (a big head's rig is megabytes): the version is
    // looked for on its own only when the file fails or is of another version, so a newer
    // grimace's file is named as such rather than by what this one cannot parse in it.
    let versions = OLDEST_RIG_VERSION..=RIG_VERSION;
    let file = match parse_file(path, text) {
        Ok(file) if versions.contains(&file.version) => file,
        other => {
            ron_text::check_version_in(path, text, versions, "rig")?;
            other?
        }
    };
    let mut rig = file.into_rig();
    let notice = (rig.version == 1).then(|| {
        let what = upgrade_v1(&mut rig, builtin);
        format!("{}: {what}", path.display())
    });
    if let Err(issue) = check_rig(&rig) {
        return Err(locate(path, text, &issue));
    }
    Ok((rig, notice))
}

/// RON's reading of a rig file; its big weight lists are read by [`weights`], which gives
/// the same values faster (a fitted big head's rig is megabytes of them).
fn parse_file(path: &Path, text: &str) -> Result<RigFile, LoadError> {
    if let Some(lifted) = weights::lift(text) {
        if let Ok(mut file) = ron_text::parse::<RigFile>(path, &lifted.text, "a rig") {
            let jaw = file.jaw.iter_mut().map(|j| &mut j.weights);
            let lists = jaw.chain(file.masks.iter_mut().map(|m| &mut m.weights));
            if lifted.restore(lists) {
                return Ok(file);
            }
        }
    }
    ron_text::parse::<RigFile>(path, text, "a rig")
}

/// Converts a version 1 rig to the current version and says what was done.
///
/// Version 1 put the subject's left at negative x (the classic Waters convention, which the
/// built-in face followed then); version 2 uses glTF's, the subject's left at positive x.
///
/// - On a built-in mesh (`builtin:NAME`), whose convention is known: the built-in face is
///   now its own mirror image, so every muscle point and the jaw pivot are reflected across
///   x = 0, the jaw's axis is reflected (and reversed, so the mouth still opens), and each
///   jaw and mask weight moves to the mirror vertex (the vertex at the reflected position).
///   `L_` muscles stay on the subject's left.
/// - On a mesh file: the mesh is read as it is, in its own coordinates, so the muscles are
///   kept exactly where they are on it (reflecting them alone would take them off the mesh).
///   What moves stays the same; only the screen shows the mesh unmirrored now.
pub fn upgrade_v1(rig: &mut Rig, builtin: BuiltinMeshes) -> String {
    rig.version = RIG_VERSION;
    let Some(name) = rig
        .mesh
        .to_str()
        .and_then(|s| s.strip_prefix(BUILTIN_PREFIX))
    else {
        return format!(
            "rig version 1 read as version {RIG_VERSION}: its muscles stay where they are on \
             `{}`, in that mesh's own coordinates; grimace now draws meshes unmirrored \
             (glTF's convention, the subject's left at positive x), so a mesh with the \
             subject's left at negative x (as older `grimace import-waters` wrote) shows as \
             its mirror image: import it again, or mirror it, to fix that",
            rig.mesh.display()
        );
    };
    for muscle in &mut rig.muscles {
        muscle.kind = muscle.kind.mirrored_x();
    }
    let mesh = builtin(name);
    if let Some(jaw) = &mut rig.jaw {
        jaw.pivot = mirror_x(jaw.pivot);
        // A reflection reverses the sense of a turn: turning by an angle about the axis
        // becomes turning by the same angle about minus the reflected axis.
        jaw.axis = -mirror_x(jaw.axis);
        jaw.slide = mirror_x(jaw.slide);
        if let Some(mesh) = &mesh {
            jaw.weights = mirrored_weights(&jaw.weights, mesh);
        }
    }
    if let Some(mesh) = &mesh {
        for mask in &mut rig.masks {
            mask.weights = mirrored_weights(&mask.weights, mesh);
        }
    }
    format!(
        "rig version 1 converted to version {RIG_VERSION}: builtin:{name} now has the \
         subject's left at positive x (glTF's convention), so the rig's muscles, masks and \
         jaw were mirrored across x = 0 to stay on the same side of the face (the file is \
         unchanged)"
    )
}

/// Jaw weights moved to the mirror vertex of each vertex (the one at exactly the reflected
/// position), sorted by vertex. A vertex without a mirror image keeps its weight.
fn mirrored_weights(weights: &[(u32, f32)], mesh: &Mesh) -> Vec<(u32, f32)> {
    let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
    let by_position: std::collections::HashMap<[u32; 3], u32> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| (key(p), i as u32))
        .collect();
    let mut out: Vec<(u32, f32)> = weights
        .iter()
        .map(|&(v, w)| {
            let image = mesh
                .positions
                .get(v as usize)
                .and_then(|&p| by_position.get(&key(mirror_x(p))))
                .copied();
            (image.unwrap_or(v), w)
        })
        .collect();
    out.sort_by_key(|&(v, _)| v);
    out.dedup_by_key(|&mut (v, _)| v);
    out
}

/// Writes a rig file atomically (see [`atomic::write_atomic`]), after checking the rig.
pub fn save_rig(path: &Path, rig: &Rig) -> Result<(), SaveError> {
    check_rig(rig).map_err(|issue| SaveError::new(path, issue.to_string()))?;
    if rig.mesh.to_str().is_none() {
        return Err(SaveError::new(path, "the mesh path is not valid UTF-8"));
    }
    atomic::write_atomic(path, rig_to_ron(rig).as_bytes()).map_err(|e| SaveError::io(path, &e))
}

/// Turns an issue into a load error at the muscle's (or field's) place in the text.
pub(super) fn locate(path: &Path, text: &str, issue: &RigIssue) -> LoadError {
    let muscle_at = match &issue.muscle {
        Some(name) => ron_text::find_field(text, 0, "muscles")
            .and_then(|from| find_name_field(text, from, name)),
        None => Some(0),
    };
    let offset = match (muscle_at, issue.field) {
        (Some(from), Some(field)) => ron_text::find_field(text, from, field).or(Some(from)),
        (at, None) => at,
        (None, Some(_)) => None,
    };
    let message = issue.to_string();
    match offset {
        Some(offset) if issue.muscle.is_some() || issue.field.is_some() => {
            LoadError::at_offset(path, text, offset, message)
        }
        _ => LoadError::new(path, message),
    }
}

/// The offset of `name: "NAME"` for a muscle (its last definition, so a duplicate name points
/// at the duplicate).
fn find_name_field(text: &str, from: usize, name: &str) -> Option<usize> {
    let mut found = None;
    let mut search = from;
    while let Some(at) = ron_text::find_field(text, search, "name") {
        let after_colon = text[at..].find(':').map(|i| at + i + 1)?;
        let value_at =
            after_colon + (text[after_colon..].len() - text[after_colon..].trim_start().len());
        if ron_text::find_string(text, value_at, name) == Some(value_at) {
            found = Some(at);
        }
        search = at + 4;
    }
    found
}

/// Writes a rig as pretty RON in the stable layout of `docs/formats.md`. Every number is
/// written so that it reads back as exactly the same `f32`.
pub fn rig_to_ron(rig: &Rig) -> String {
    // Destructured in full (here and in each part's writer) so that a field added to the
    // model fails to compile here rather than being silently dropped from saved files.
    let Rig {
        version,
        mesh,
        landmarks,
        combine,
        muscles,
        jaw,
        masks,
    } = rig;
    let mut out = String::new();
    out.push_str("// grimace rig: muscles placed on a mesh; see docs/formats.md\n(\n");
    out.push_str(&format!("    version: {version},\n"));
    out.push_str(&format!(
        "    mesh: {},\n",
        ron_text::string(&mesh.to_string_lossy())
    ));
    if let Some(landmarks) = landmarks {
        out.push_str(&format!(
            "    landmarks: {},\n",
            ron_text::string(&landmarks.to_string_lossy())
        ));
    }
    out.push_str(&format!("    combine: {combine:?},\n"));
    out.push_str("    muscles: [\n");
    for muscle in muscles {
        write_muscle(&mut out, muscle);
    }
    out.push_str("    ],\n");
    if let Some(jaw) = jaw {
        write_jaw(&mut out, jaw);
    }
    if !masks.is_empty() {
        out.push_str("    masks: [\n");
        for mask in masks {
            write_mask(&mut out, mask);
        }
        out.push_str("    ],\n");
    }
    out.push_str(")\n");
    out
}

fn write_muscle(out: &mut String, muscle: &Muscle) {
    use ron_text::string;
    let Muscle {
        name,
        side,
        mirror,
        kind,
    } = muscle;
    out.push_str("        (\n");
    out.push_str(&format!("            name: {},\n", string(name)));
    out.push_str(&format!("            side: {side:?},\n"));
    if let Some(mirror) = mirror {
        out.push_str(&format!("            mirror: {},\n", string(mirror)));
    }
    out.push_str(&format!("            kind: {}(\n", kind_name(kind)));
    for (field, value) in kind_fields(kind) {
        out.push_str(&format!("                {field}: {value},\n"));
    }
    out.push_str("            ),\n        ),\n");
}

/// A muscle kind's parameters as `(field, RON value)`, in the file's order.
fn kind_fields(kind: &MuscleKind) -> Vec<(&'static str, String)> {
    use ron_text::{float, point};
    match kind {
        MuscleKind::Linear(Linear {
            attachment,
            insertion,
            zone,
            falloff_start,
            falloff_end,
        }) => vec![
            ("attachment", point(*attachment)),
            ("insertion", point(*insertion)),
            ("zone", float(*zone)),
            ("falloff_start", float(*falloff_start)),
            ("falloff_end", float(*falloff_end)),
        ],
        MuscleKind::Sphincter(Sphincter {
            centre,
            semi_major,
            semi_minor,
            convergence,
            bulge,
            frame,
        }) => {
            let mut fields = vec![
                ("centre", point(*centre)),
                ("semi_major", float(*semi_major)),
                ("semi_minor", float(*semi_minor)),
                ("convergence", format!("{convergence:?}")),
                ("bulge", float(*bulge)),
            ];
            if !frame.is_identity() {
                let Frame { x, y } = frame;
                fields.push(("frame", format!("(x: {}, y: {})", point(*x), point(*y))));
            }
            fields
        }
        MuscleKind::Sheet(Sheet {
            attachment,
            insertion,
            length,
            width,
        }) => vec![
            (
                "attachment",
                format!("({}, {})", point(attachment[0]), point(attachment[1])),
            ),
            (
                "insertion",
                format!("({}, {})", point(insertion[0]), point(insertion[1])),
            ),
            ("length", float(*length)),
            ("width", float(*width)),
        ],
    }
}

fn write_jaw(out: &mut String, jaw: &Jaw) {
    use ron_text::{float, point};
    let Jaw {
        pivot,
        degrees_per_unit,
        weights,
        axis,
        slide,
    } = jaw;
    out.push_str("    jaw: (\n");
    out.push_str(&format!("        pivot: {},\n", point(*pivot)));
    if *axis != Vec3::X {
        out.push_str(&format!("        axis: {},\n", point(*axis)));
    }
    out.push_str(&format!(
        "        degrees_per_unit: {},\n",
        float(*degrees_per_unit)
    ));
    if *slide != Vec3::ZERO {
        out.push_str(&format!("        slide: {},\n", point(*slide)));
    }
    out.push_str("        weights: [\n");
    write_weights(out, weights, "            ");
    out.push_str("        ],\n    ),\n");
}

fn write_mask(out: &mut String, mask: &Mask) {
    use ron_text::{float, string};
    let Mask {
        muscles,
        gain,
        weights,
    } = mask;
    out.push_str("        (\n            muscles: [\n");
    for name in muscles {
        out.push_str(&format!("                {},\n", string(name)));
    }
    out.push_str("            ],\n");
    if *gain != 1.0 {
        out.push_str(&format!("            gain: {},\n", float(*gain)));
    }
    out.push_str("            weights: [\n");
    write_weights(out, weights, "                ");
    out.push_str("            ],\n        ),\n");
}

/// `(vertex, weight)` pairs, six per line: a dense jaw or mask stays readable.
fn write_weights(out: &mut String, weights: &[(u32, f32)], indent: &str) {
    for chunk in weights.chunks(6) {
        let pairs: Vec<String> = chunk
            .iter()
            .map(|(v, w)| format!("({v}, {})", ron_text::float(*w)))
            .collect();
        out.push_str(&format!("{indent}{},\n", pairs.join(", ")));
    }
}

fn kind_name(kind: &MuscleKind) -> &'static str {
    match kind {
        MuscleKind::Linear(_) => "Linear",
        MuscleKind::Sphincter(_) => "Sphincter",
        MuscleKind::Sheet(_) => "Sheet",
    }
}

// ---- The file's shape, as read. Private so that the model types stay free of file
// concerns (unknown fields are refused here, and optional values are written bare).

type P3 = [f32; 3];

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename = "rig")]
struct RigFile {
    version: u32,
    mesh: String,
    #[serde(default, deserialize_with = "bare_some")]
    landmarks: Option<String>,
    #[serde(default)]
    combine: Combine,
    muscles: Vec<MuscleFile>,
    #[serde(default, deserialize_with = "bare_some")]
    jaw: Option<JawFile>,
    #[serde(default)]
    masks: Vec<MaskFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename = "mask")]
struct MaskFile {
    muscles: Vec<String>,
    #[serde(default = "one")]
    gain: f32,
    #[serde(default)]
    weights: Vec<(u32, f32)>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename = "muscle")]
struct MuscleFile {
    name: String,
    #[serde(default)]
    side: Side,
    #[serde(default, deserialize_with = "bare_some")]
    mirror: Option<String>,
    kind: KindFile,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename = "kind")]
enum KindFile {
    Linear {
        attachment: P3,
        insertion: P3,
        zone: f32,
        falloff_start: f32,
        falloff_end: f32,
    },
    Sphincter {
        centre: P3,
        semi_major: f32,
        semi_minor: f32,
        convergence: Convergence,
        bulge: f32,
        #[serde(default)]
        frame: FrameFile,
    },
    Sheet {
        attachment: [P3; 2],
        insertion: [P3; 2],
        length: f32,
        width: f32,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename = "jaw")]
struct JawFile {
    pivot: P3,
    degrees_per_unit: f32,
    #[serde(default)]
    weights: Vec<(u32, f32)>,
    #[serde(default = "crate::model::jaw::x_axis_p3")]
    axis: P3,
    /// The slide per degree; absent in files written before it (a pure turn).
    #[serde(default)]
    slide: P3,
}

/// A sphincter's frame: both directions are required when the field is written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename = "frame")]
struct FrameFile {
    x: P3,
    y: P3,
}

impl Default for FrameFile {
    fn default() -> FrameFile {
        FrameFile {
            x: Frame::IDENTITY.x.into(),
            y: Frame::IDENTITY.y.into(),
        }
    }
}

fn one() -> f32 {
    1.0
}

/// An optional field written as its bare value (`mirror: "R_x"` rather than `Some("R_x")`).
fn bare_some<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

impl RigFile {
    fn into_rig(self) -> Rig {
        Rig {
            version: self.version,
            mesh: PathBuf::from(self.mesh),
            landmarks: self.landmarks.map(PathBuf::from),
            combine: self.combine,
            muscles: self
                .muscles
                .into_iter()
                .map(MuscleFile::into_muscle)
                .collect(),
            jaw: self.jaw.map(|j| Jaw {
                pivot: Vec3::from(j.pivot),
                degrees_per_unit: j.degrees_per_unit,
                weights: j.weights,
                axis: Vec3::from(j.axis),
                slide: Vec3::from(j.slide),
            }),
            masks: self
                .masks
                .into_iter()
                .map(|m| Mask {
                    muscles: m.muscles,
                    gain: m.gain,
                    weights: m.weights,
                })
                .collect(),
        }
    }
}

impl MuscleFile {
    fn into_muscle(self) -> Muscle {
        let kind = match self.kind {
            KindFile::Linear {
                attachment,
                insertion,
                zone,
                falloff_start,
                falloff_end,
            } => MuscleKind::Linear(Linear {
                attachment: attachment.into(),
                insertion: insertion.into(),
                zone,
                falloff_start,
                falloff_end,
            }),
            KindFile::Sphincter {
                centre,
                semi_major,
                semi_minor,
                convergence,
                bulge,
                frame,
            } => MuscleKind::Sphincter(Sphincter {
                centre: centre.into(),
                semi_major,
                semi_minor,
                convergence,
                bulge,
                frame: Frame {
                    x: frame.x.into(),
                    y: frame.y.into(),
                },
            }),
            KindFile::Sheet {
                attachment,
                insertion,
                length,
                width,
            } => MuscleKind::Sheet(Sheet {
                attachment: attachment.map(Vec3::from),
                insertion: insertion.map(Vec3::from),
                length,
                width,
            }),
        };
        Muscle {
            name: self.name,
            side: self.side,
            mirror: self.mirror,
            kind,
        }
    }
}
