//! Loading by reference: a rig with the mesh it names, a table with the rig it names, where
//! each reference is `builtin:NAME` (embedded in grimace, [`super::builtin`]) or a file
//! relative to the real folder of the file that names it ([`super::reference`]).
//!
//! The formats themselves are [`super::rig_file`] and [`super::table_file`]; the built-in
//! presets are parsed with them. This module sits above both and above [`super::builtin`].

use std::path::{Path, PathBuf};

use super::builtin;
use super::error::{read_text, LoadError, MAX_FILE_BYTES};
use super::rig_file::{
    check_rig_mesh, locate, parse_rig_with, BuiltinMeshes, RigIssue, BUILTIN_PREFIX,
};
use super::table_file::{check_table_rig, load_table_for, parse_table, table_to_ron};
use super::{obj, ron_text};
use crate::facs::AuTable;
use crate::model::{Mesh, Rig};

/// A rig loaded from a file, with its mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedRig {
    /// The rig, checked.
    pub rig: Rig,
    /// The mesh the rig names (or the override given), checked against the rig.
    pub mesh: Mesh,
    /// The rig file it came from.
    pub path: PathBuf,
    /// The mesh file read, or `None` for a built-in mesh.
    pub mesh_path: Option<PathBuf>,
    /// What loading did to an older file (a version 1 rig converted), to show the user once;
    /// `None` for a current file.
    pub notice: Option<String>,
    /// The landmark points on the mesh, found once when loading ([`LoadedRig::landmark_points`]).
    points: Result<Option<Vec<glam::Vec3>>, LoadError>,
}

impl LoadedRig {
    /// A rig and its mesh as loading makes them, from parts already in memory: `path` is the
    /// rig's file (relative mesh names resolve against it), `mesh_path` the mesh's file
    /// (`None`: the built-in mesh the rig names). Its landmark points are found as loading
    /// finds them, and a mesh file's brows marked from them.
    pub fn new(rig: Rig, mesh: Mesh, path: PathBuf, mesh_path: Option<PathBuf>) -> LoadedRig {
        loaded(rig, mesh, &path, mesh_path, None)
    }

    /// The landmarks of a loaded rig's mesh when none are given: the built-in face's own for a
    /// built-in mesh, else the file [`beside`] the mesh. Gives the landmarks and where they came
    /// from; the error says what is missing and names `flag`, the option that gives them.
    pub fn landmarks(
        &self,
        flag: &str,
    ) -> Result<(crate::landmarks::Landmarks, PathBuf), LoadError> {
        if let Some(file) = named_landmarks(&self.path, &self.rig) {
            return Ok((super::landmarks::load_landmarks(&file)?, file));
        }
        match mesh_ref(&self.path, &self.rig.mesh) {
            MeshRef::Builtin(name) => builtin::landmarks(&name)
                .map(|marks| {
                    (
                        marks,
                        PathBuf::from(format!("builtin:{name}.landmarks.ron")),
                    )
                })
                .ok_or_else(|| {
                    LoadError::new(
                        &self.path,
                        format!("the built-in mesh `{name}` has no landmarks; give {flag}"),
                    )
                }),
            MeshRef::File(mesh) => {
                let path = super::landmarks::beside(&mesh);
                if !path.is_file() {
                    return Err(LoadError::new(
                        &mesh,
                        format!(
                            "no landmarks beside the mesh ({}); give {flag} FILE",
                            path.display()
                        ),
                    ));
                }
                Ok((super::landmarks::load_landmarks(&path)?, path))
            }
        }
    }

    /// The landmark points on the loaded mesh when it has any, for what only looks at the
    /// face (the views' framing): the built-in face's own, the file [`beside`] the mesh read,
    /// else MediaPipe's numbering on a mesh with a MediaPipe face mesh's vertex count when
    /// that makes a face. `Ok(None)` without landmarks; an error for a landmark file that is
    /// there but cannot be read or does not fit the mesh. Found once, when the rig is loaded
    /// (the brows are marked from the same points).
    pub fn landmark_points(&self) -> Result<Option<Vec<glam::Vec3>>, LoadError> {
        self.points.clone()
    }
}

/// [`LoadedRig::landmark_points`] of a rig file `path` whose mesh is `mesh`, read from
/// `mesh_file` (`None`: the built-in mesh the rig names).
fn find_landmark_points(
    path: &Path,
    rig: &Rig,
    mesh: &Mesh,
    mesh_file: Option<&Path>,
) -> Result<Option<Vec<glam::Vec3>>, LoadError> {
    if let Some(file) = named_landmarks(path, rig) {
        let landmarks = super::landmarks::load_landmarks(&file)?;
        return super::landmarks::check_against(&landmarks, mesh, &file, None).map(Some);
    }
    let Some(mesh_file) = mesh_file else {
        let name = match mesh_ref(path, &rig.mesh) {
            MeshRef::Builtin(name) => name,
            MeshRef::File(_) => return Ok(None),
        };
        return Ok(builtin::landmarks(&name).and_then(|l| l.positions(mesh).ok()));
    };
    let beside = super::landmarks::beside(mesh_file);
    if beside.is_file() {
        let landmarks = super::landmarks::load_landmarks(&beside)?;
        return super::landmarks::check_against(&landmarks, mesh, &beside, None).map(Some);
    }
    // A MediaPipe face mesh needs no landmark file; a mesh that only has its vertex count
    // (Waters' classic face has 478 vertices too) gives points that do not follow the iBUG
    // scheme, and has no landmarks.
    Ok(crate::landmarks::Landmarks::mediapipe(mesh)
        .and_then(|l| l.positions(mesh))
        .ok()
        .filter(|points| crate::landmarks::order_problems(points).is_empty()))
}

/// The landmark file a rig names (`landmarks`), resolved against the rig file's folder.
fn named_landmarks(path: &Path, rig: &Rig) -> Option<PathBuf> {
    rig.landmarks
        .as_deref()
        .map(|file| super::reference::resolve(path, file))
}

/// A loaded rig, its landmark points found and, on a mesh file without brows of its own,
/// the brows marked from them ([`crate::fit::brow_hair`]; without landmarks, or with
/// landmarks that cannot be used, the mesh stays as it is, its brows simply not drawn).
fn loaded(
    rig: Rig,
    mut mesh: Mesh,
    path: &Path,
    mesh_path: Option<PathBuf>,
    notice: Option<String>,
) -> LoadedRig {
    let points = find_landmark_points(path, &rig, &mesh, mesh_path.as_deref());
    if let (Some(_), Ok(Some(points))) = (&mesh_path, &points) {
        crate::fit::brow_hair::mark(&mut mesh, points);
    }
    LoadedRig {
        rig,
        mesh,
        path: path.to_path_buf(),
        mesh_path,
        notice,
        points,
    }
}

/// Where a rig's mesh comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MeshRef {
    /// An embedded mesh, by the name after `builtin:`.
    Builtin(String),
    /// A file, already resolved against the rig file's folder.
    File(PathBuf),
}

/// Resolves a rig's `mesh` field: `builtin:NAME`, or a path relative to the rig file's real
/// folder (see [`super::reference`]; absolute paths are kept).
pub fn mesh_ref(rig_path: &Path, mesh: &Path) -> MeshRef {
    if let Some(name) = mesh.to_str().and_then(|s| s.strip_prefix(BUILTIN_PREFIX)) {
        return MeshRef::Builtin(name.to_string());
    }
    MeshRef::File(super::reference::resolve(rig_path, mesh))
}

/// Loads a rig file and the mesh it names (a file, or a built-in mesh of
/// [`super::builtin`]), and checks them against each other.
pub fn load_rig(path: &Path) -> Result<LoadedRig, LoadError> {
    load_rig_with(path, None, builtin::mesh)
}

/// Loads a rig by reference: `builtin:NAME` for a rig embedded in grimace (see
/// [`super::builtin`]), or a rig file. `mesh_override` replaces the mesh the rig names.
pub fn load_rig_ref(
    reference: &Path,
    mesh_override: Option<&Path>,
) -> Result<LoadedRig, LoadError> {
    let Some(name) = builtin::builtin_name(reference) else {
        return load_rig_with(reference, mesh_override, builtin::mesh);
    };
    let rig = builtin::rig(name).ok_or_else(|| {
        LoadError::new(
            reference,
            format!("there is no built-in rig named `{name}`; the built-in rigs are builtin:default and builtin:paper"),
        )
    })?;
    let (mesh, mesh_path) = match mesh_override {
        Some(file) => (obj::read_obj(file)?, Some(file.to_path_buf())),
        None => {
            let mesh = builtin::builtin_name(&rig.mesh)
                .and_then(builtin::mesh)
                .ok_or_else(|| {
                    LoadError::new(
                        reference,
                        format!(
                            "the built-in rig names the mesh `{}`, which is not built in",
                            rig.mesh.display()
                        ),
                    )
                })?;
            (mesh, None)
        }
    };
    check_rig_mesh(&rig, &mesh).map_err(|issue| LoadError::new(reference, issue.to_string()))?;
    Ok(loaded(rig, mesh, reference, mesh_path, None))
}

/// Loads a rig file; `mesh_override` replaces the mesh the rig names (as `--mesh` does on the
/// command line); `builtin` resolves `builtin:NAME` mesh references.
pub fn load_rig_with(
    path: &Path,
    mesh_override: Option<&Path>,
    builtin: BuiltinMeshes,
) -> Result<LoadedRig, LoadError> {
    let text = read_text(path, MAX_FILE_BYTES)?;
    // A mesh given by name is read beside the rig's parse (both take a while on a big
    // head); the rig's errors come first, as when they were read one after the other.
    let (parsed, read) = std::thread::scope(|scope| {
        let read = mesh_override.map(|file| scope.spawn(|| obj::read_obj(file)));
        let parsed = parse_rig_with(&text, path, builtin);
        (parsed, read.map(|thread| thread.join()))
    });
    let (mut rig, notice) = parsed?;
    let (mesh, mesh_path) = match (mesh_override, read) {
        (Some(file), Some(Ok(read))) => (read?, Some(file.to_path_buf())),
        (_, Some(Err(panic))) => std::panic::resume_unwind(panic),
        _ => load_named_mesh(&rig, &text, path, builtin)?,
    };
    if let (None, MeshRef::Builtin(name)) = (mesh_override, mesh_ref(path, &rig.mesh)) {
        builtin::hold_eyes_still(&name, &mesh, &mut rig);
    }
    if let Err(issue) = check_rig_mesh(&rig, &mesh) {
        return Err(locate(path, &text, &issue));
    }
    Ok(loaded(rig, mesh, path, mesh_path, notice))
}

fn load_named_mesh(
    rig: &Rig,
    text: &str,
    path: &Path,
    builtin: BuiltinMeshes,
) -> Result<(Mesh, Option<PathBuf>), LoadError> {
    let at_mesh = |message: String| {
        let issue = RigIssue {
            muscle: None,
            field: Some("mesh"),
            message,
        };
        locate(path, text, &issue)
    };
    match mesh_ref(path, &rig.mesh) {
        MeshRef::Builtin(name) => match builtin(&name) {
            Some(mesh) => Ok((mesh, None)),
            None => Err(at_mesh(format!(
                "there is no built-in mesh named `{name}` in this context"
            ))),
        },
        MeshRef::File(file) => {
            if let Some(reason) = super::error::not_a_file(&file) {
                return Err(at_mesh(format!(
                    "the mesh file `{}` {reason} (paths are relative to the rig file)",
                    file.display()
                )));
            }
            let mesh = obj::read_obj(&file)
                .map_err(|e| at_mesh(format!("the mesh it names does not load: {e}")))?;
            Ok((mesh, Some(file)))
        }
    }
}

/// Parses and checks the text of a rig file (the mesh is not loaded), converting a version 1
/// file (see [`upgrade_v1`]). `path` is used in error messages only.
pub fn parse_rig(text: &str, path: &Path) -> Result<Rig, LoadError> {
    parse_rig_with(text, path, builtin::mesh).map(|(rig, _)| rig)
}

/// Where a table's rig comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RigRef {
    /// An embedded rig, by the name after `builtin:`.
    Builtin(String),
    /// A file, already resolved against the table file's folder.
    File(PathBuf),
}

impl RigRef {
    /// The reference as [`super::rig_file::load_rig_ref`] takes it: `builtin:NAME` or the file.
    pub fn to_path(&self) -> PathBuf {
        match self {
            RigRef::Builtin(name) => PathBuf::from(format!("{BUILTIN_PREFIX}{name}")),
            RigRef::File(path) => path.clone(),
        }
    }
}

/// Resolves a table's `rig` field: `builtin:NAME`, or a path relative to the table file's
/// real folder (see [`super::reference`]; absolute paths are kept).
pub fn rig_ref(table_path: &Path, rig: &Path) -> RigRef {
    if let Some(name) = rig.to_str().and_then(|s| s.strip_prefix(BUILTIN_PREFIX)) {
        return RigRef::Builtin(name.to_string());
    }
    RigRef::File(super::reference::resolve(table_path, rig))
}

/// Loads a table by reference (`builtin:NAME` for a table embedded in grimace, or a table
/// file) and the rig it names (built in, or a file relative to the table), with that rig's
/// mesh or `mesh_override`, and checks them against each other. Errors about the rig
/// reference point at the table's `rig` field.
pub fn load_table_and_rig(
    path: &Path,
    mesh_override: Option<&Path>,
) -> Result<(AuTable, LoadedRig), LoadError> {
    let (table, text) = match builtin::builtin_name(path) {
        Some(name) => {
            let table = builtin::table(name).ok_or_else(|| {
                LoadError::new(
                    path,
                    format!("there is no built-in table named `{name}`; the built-in table is builtin:default"),
                )
            })?;
            let text = table_to_ron(&table);
            (table, text)
        }
        None => {
            let text = read_text(path, MAX_FILE_BYTES)?;
            (parse_table(&text, path)?, text)
        }
    };
    let at_rig = |message: String| match ron_text::find_field(&text, 0, "rig") {
        Some(offset) => LoadError::at_offset(path, &text, offset, message),
        None => LoadError::new(path, message),
    };
    let rig_path = match rig_ref(path, &table.rig) {
        RigRef::File(file) => {
            if let Some(reason) = super::error::not_a_file(&file) {
                return Err(at_rig(format!(
                    "the rig file `{}` {reason} (paths are relative to the table file)",
                    file.display()
                )));
            }
            file
        }
        RigRef::Builtin(_) => table.rig.clone(),
    };
    let rig = load_rig_ref(&rig_path, mesh_override)
        .map_err(|e| at_rig(format!("the rig it names does not load: {e}")))?;
    check_table_rig(&table, &rig.rig, &text, path)?;
    Ok((table, rig))
}

/// Loads a table by reference (`builtin:NAME` or a file) and checks it against a rig.
pub fn load_table_ref_for(path: &Path, rig: &Rig) -> Result<AuTable, LoadError> {
    match builtin::builtin_name(path) {
        Some(name) => {
            let table = builtin::table(name).ok_or_else(|| {
                LoadError::new(path, format!("there is no built-in table named `{name}`"))
            })?;
            check_table_rig(&table, rig, &table_to_ron(&table), path)?;
            Ok(table)
        }
        None => load_table_for(path, rig),
    }
}
