//! `grimace validate FILE...`: checks rigs, AU tables and meshes, by file name.
//!
//! `*.rig.ron` (and `rig.ron`): syntax, version, muscles, the mesh it names, binding to it.
//! `*.au.ron`: syntax, version, AUs, ranges, expressions, and the rig it names (muscle names).
//! `*.landmarks.ron`: 68 landmarks, checked against `NAME.obj` beside the file if there is one.
//! `*.obj`: a usable mesh. `*.plan.ron`: a batch plan, its faces loaded and every state
//! checked against their tables. The exit status is 0 only when every file is valid.

use crate::io::load::{load_rig, load_table_and_rig};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use crate::io::{obj, LoadError};

use crate::model::Deformation;

/// Arguments of `grimace validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// The files to check (*.rig.ron, *.au.ron, *.landmarks.ron, *.plan.ron, *.obj).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
}

/// What kind of file a name says it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// A rig, `*.rig.ron` or `rig.ron`.
    Rig,
    /// An AU table, `*.au.ron` or `au.ron`.
    Table,
    /// A Wavefront OBJ mesh.
    Mesh,
    /// Landmarks, `*.landmarks.ron`.
    Landmarks,
    /// A batch plan, `*.plan.ron`.
    Plan,
}

/// The kind of file a path names, from its file name.
pub fn kind_of(path: &Path) -> Option<FileKind> {
    let name = path.file_name()?.to_str()?.to_ascii_lowercase();
    if name.ends_with("rig.ron") {
        Some(FileKind::Rig)
    } else if name.ends_with("au.ron") {
        Some(FileKind::Table)
    } else if name.ends_with(".obj") {
        Some(FileKind::Mesh)
    } else if name.ends_with("landmarks.ron") {
        Some(FileKind::Landmarks)
    } else if name.ends_with("plan.ron") {
        Some(FileKind::Plan)
    } else {
        None
    }
}

/// Runs `grimace validate`; prints one line per file (`ok` on stdout, errors on stderr).
pub fn run(args: &ValidateArgs) -> ExitCode {
    let mut failed = 0;
    for path in &args.files {
        match check(path) {
            Ok(summary) => {
                if let Err(err) = super::print(&format!("{}: ok ({summary})\n", path.display())) {
                    super::report("validate", &err);
                    return ExitCode::from(1);
                }
            }
            Err(err) => {
                failed += 1;
                super::report("validate", &err);
            }
        }
    }
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// Checks one file, returning a short summary of what it holds.
pub fn check(path: &Path) -> Result<String, LoadError> {
    match kind_of(path) {
        Some(FileKind::Rig) => check_rig(path),
        Some(FileKind::Table) => check_table(path),
        Some(FileKind::Landmarks) => check_landmarks(path),
        Some(FileKind::Plan) => {
            let batch = super::batch::load(path, Deformation::default())?;
            let states: usize = batch.expanded.states.iter().map(Vec::len).sum();
            Ok(format!(
                "plan: {} faces, {states} states, {} items",
                batch.faces.len(),
                batch.expanded.items.len()
            ))
        }
        Some(FileKind::Mesh) => {
            let mesh = obj::read_obj(path)?;
            Ok(format!(
                "mesh: {} vertices, {} triangles",
                mesh.vertex_count(),
                mesh.triangles.len()
            ))
        }
        None => Err(LoadError::new(
            path,
            "unknown kind of file; expected a name ending in .rig.ron, .au.ron, .landmarks.ron, .plan.ron or .obj",
        )),
    }
}

fn check_rig(path: &Path) -> Result<String, LoadError> {
    let loaded = load_rig(path)?;
    if let Some(notice) = &loaded.notice {
        eprintln!("warning: {notice}");
    }
    Deformation::default()
        .bind(&loaded.rig, &loaded.mesh)
        .map_err(|e| LoadError::new(path, e.to_string()))?;
    // Landmarks the rig names must load and fit its mesh (others are looked for, not required).
    let landmarks = match (&loaded.rig.landmarks, loaded.landmark_points()?) {
        (Some(file), Some(_)) => format!(", landmarks {}", file.display()),
        _ => String::new(),
    };
    Ok(format!(
        "rig: {} muscles{}, mesh {} vertices{landmarks}",
        loaded.rig.muscles.len(),
        if loaded.rig.jaw.is_some() {
            " and a jaw"
        } else {
            ""
        },
        loaded.mesh.vertex_count()
    ))
}

/// A landmark file on its own, and against `NAME.obj` beside it when there is one.
fn check_landmarks(path: &Path) -> Result<String, LoadError> {
    let text = crate::io::error::read_text(path, crate::io::MAX_FILE_BYTES)?;
    let landmarks = crate::io::landmarks::parse_landmarks(&text, path)?;
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    let stem = &name[..name.len() - "landmarks.ron".len()];
    let mesh = path.with_file_name(format!("{}obj", stem));
    if !stem.is_empty() && mesh.is_file() {
        let m = obj::read_obj(&mesh)?;
        crate::io::landmarks::check_against(&landmarks, &m, path, Some(&text))?;
        return Ok(format!(
            "landmarks: {} points, on {}",
            landmarks.len(),
            mesh.display()
        ));
    }
    Ok(format!("landmarks: {} points", landmarks.len()))
}

fn check_table(path: &Path) -> Result<String, LoadError> {
    let table = crate::io::load_table(path)?;
    let counts = format!(
        "table: {} AUs, {} expressions",
        table.aus.len(),
        table.expressions.len()
    );
    let (_, rig) = load_table_and_rig(path, None)?;
    Ok(format!("{counts}, rig {}", rig.path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_from_names() {
        assert_eq!(kind_of(Path::new("a/face.rig.ron")), Some(FileKind::Rig));
        assert_eq!(kind_of(Path::new("out/rig.ron")), Some(FileKind::Rig));
        assert_eq!(kind_of(Path::new("x.AU.RON")), Some(FileKind::Table));
        assert_eq!(kind_of(Path::new("m.obj")), Some(FileKind::Mesh));
        assert_eq!(
            kind_of(Path::new("p/example.plan.ron")),
            Some(FileKind::Plan)
        );
        assert_eq!(kind_of(Path::new("m.ron")), None);
        assert_eq!(kind_of(Path::new("/")), None);
    }
}
