//! References from one file to another: a rig's `mesh`, a table's `rig`.
//!
//! A relative reference is read from the **real** folder of the file that holds it: the
//! folder of the file itself, symbolic links followed. The writer uses the same rule
//! ([`written_reference`]), so a file resolves the same way whether it is opened through a
//! link, from another working directory or after being saved under a new name.
//!
//! References are written relative (with `..` where needed) so a folder of rigs, tables and
//! meshes can be moved or copied as a whole; only where no relative path exists (another
//! drive) is the absolute path written. Built-in references (`builtin:NAME`) stay as they are.
//!
//! Files written before this rule may hold a reference relative to the folder of a link they
//! were reached through; when the real folder has nothing at the reference and the link's
//! folder has, the link's folder is used.

use std::path::{Component, Path, PathBuf};

use super::atomic::save_target;
use super::builtin::builtin_name;
use crate::facs::AuTable;
use crate::model::Rig;

/// The real folder of `file` (links followed), absolute where it can be resolved.
pub fn real_folder(file: &Path) -> PathBuf {
    let target = save_target(file).unwrap_or_else(|_| file.to_path_buf());
    let folder = match target.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::canonicalize(&folder)
        .or_else(|_| std::path::absolute(&folder))
        .unwrap_or(folder)
}

/// The file a reference written in `file` names (absolute and built-in references as they
/// are).
pub fn resolve(file: &Path, reference: &Path) -> PathBuf {
    if reference.is_absolute() || builtin_name(reference).is_some() {
        return reference.to_path_buf();
    }
    // Folders on the way are resolved by the system itself (a `..` after a linked folder
    // goes up from where the folder really is); only a link to the file itself moves it.
    let beside = file.parent().unwrap_or(Path::new("")).join(reference);
    let target = save_target(file).unwrap_or_else(|_| file.to_path_buf());
    if target == file {
        return beside;
    }
    let real = target.parent().unwrap_or(Path::new("")).join(reference);
    if real.exists() || !beside.exists() {
        real
    } else {
        beside
    }
}

/// How a file about to be written at `file` names `target`: built-in references as they are,
/// else `target` relative to `file`'s real folder (absolute only where no relative path
/// exists).
pub fn written_reference(file: &Path, target: &Path) -> PathBuf {
    if builtin_name(target).is_some() {
        return target.to_path_buf();
    }
    let target = std::fs::canonicalize(target)
        .or_else(|_| std::path::absolute(target))
        .unwrap_or_else(|_| target.to_path_buf());
    relative_path(&real_folder(file), &target).unwrap_or(target)
}

/// `table` as written at `file`: an absolute rig reference becomes relative to `file`'s
/// real folder. (The editor keeps references absolute while it runs, so that saving under
/// another name, in another folder, still names the same rig.)
pub fn table_for_file(file: &Path, table: &AuTable) -> AuTable {
    let mut table = table.clone();
    if table.rig.is_absolute() {
        table.rig = written_reference(file, &table.rig);
    }
    table
}

/// `rig` as written at `file`: an absolute mesh or landmark reference becomes relative to
/// `file`'s real folder (see [`table_for_file`]).
pub fn rig_for_file(file: &Path, rig: &Rig) -> Rig {
    let mut rig = rig.clone();
    if rig.mesh.is_absolute() {
        rig.mesh = written_reference(file, &rig.mesh);
    }
    if let Some(landmarks) = rig.landmarks.as_mut().filter(|l| l.is_absolute()) {
        *landmarks = written_reference(file, landmarks);
    }
    rig
}

/// The file at `path` with links followed, absolute (as far as it exists).
pub fn real_path(path: &Path) -> PathBuf {
    let target = save_target(path).unwrap_or_else(|_| path.to_path_buf());
    std::fs::canonicalize(&target)
        .or_else(|_| std::path::absolute(&target))
        .unwrap_or(target)
}

/// A reference read from `file`, made absolute (built-in references as they are): the form
/// the editor keeps while it runs.
pub fn absolute(file: &Path, reference: &Path) -> PathBuf {
    let resolved = resolve(file, reference);
    if builtin_name(&resolved).is_some() {
        return resolved;
    }
    real_path(&resolved)
}

/// The path from folder `from` to `to`, both absolute and free of `.` and `..`; `None` when
/// they share no root (two drives).
fn relative_path(from: &Path, to: &Path) -> Option<PathBuf> {
    let from: Vec<Component> = from.components().collect();
    let to: Vec<Component> = to.components().collect();
    if from.first() != to.first() {
        return None;
    }
    let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
    let mut path = PathBuf::new();
    for _ in common..from.len() {
        path.push("..");
    }
    for part in &to[common..] {
        path.push(part);
    }
    Some(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    #[test]
    fn relative_paths_climb_where_needed() {
        let rel = |a: &str, b: &str| relative_path(Path::new(a), Path::new(b)).unwrap();
        assert_eq!(rel("/a/b", "/a/b/m.obj"), Path::new("m.obj"));
        assert_eq!(rel("/a/b", "/a/c/m.obj"), Path::new("../c/m.obj"));
        assert_eq!(rel("/a/b/c", "/m.obj"), Path::new("../../../m.obj"));
    }

    #[test]
    fn a_written_reference_resolves_from_the_written_file() {
        let dir = tempfile::tempdir().unwrap();
        let root = fs::canonicalize(dir.path()).unwrap();
        fs::create_dir_all(root.join("meshes")).unwrap();
        fs::create_dir_all(root.join("rigs/deep")).unwrap();
        let mesh = root.join("meshes/head.obj");
        fs::write(&mesh, "v 0 0 0\n").unwrap();
        let rig = root.join("rigs/deep/head.rig.ron");
        let reference = written_reference(&rig, &mesh);
        assert_eq!(reference, Path::new("../../meshes/head.obj"));
        assert_eq!(
            fs::canonicalize(resolve(&rig, &reference)).unwrap(),
            fs::canonicalize(&mesh).unwrap()
        );
    }

    #[test]
    fn a_rig_saved_elsewhere_names_its_mesh_and_landmarks_from_there() {
        let dir = tempfile::tempdir().unwrap();
        let root = fs::canonicalize(dir.path()).unwrap();
        fs::create_dir_all(root.join("rigs")).unwrap();
        let mut rig = crate::io::builtin::default_rig();
        rig.mesh = root.join("head.obj");
        rig.landmarks = Some(root.join("marks/head.ron"));
        let written = rig_for_file(&root.join("rigs/head.rig.ron"), &rig);
        assert_eq!(written.mesh, Path::new("../head.obj"));
        assert_eq!(written.landmarks.unwrap(), Path::new("../marks/head.ron"));
    }

    #[cfg(unix)]
    #[test]
    fn references_go_from_the_real_folder_through_links() {
        let dir = tempfile::tempdir().unwrap();
        let root = fs::canonicalize(dir.path()).unwrap();
        fs::create_dir_all(root.join("real")).unwrap();
        fs::create_dir_all(root.join("links")).unwrap();
        let mesh = root.join("real/head.obj");
        fs::write(&mesh, "v 0 0 0\n").unwrap();
        fs::write(root.join("real/head.rig.ron"), "").unwrap();
        let link = root.join("links/head.rig.ron");
        std::os::unix::fs::symlink(root.join("real/head.rig.ron"), &link).unwrap();
        // Written through the link: relative to the real folder, where the file lives.
        assert_eq!(written_reference(&link, &mesh), Path::new("head.obj"));
        assert_eq!(resolve(&link, Path::new("head.obj")), mesh);
    }
}
