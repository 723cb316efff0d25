//! Atomic saves: a file is either its old version or its new version, never a mix.
//!
//! [`write_atomic`] writes the new contents to a temporary file in the same folder (so the
//! final rename stays on one file system), flushes and fsyncs it, keeps the previous version
//! as `FILE~`, renames the temporary file over `FILE`, and fsyncs the folder so the rename
//! itself survives a crash. If any step fails, the temporary file is removed and `FILE` is
//! untouched.
//!
//! The backup `FILE~` is a copy of the version being replaced, written the same careful way;
//! it is replaced on every save, so it always holds the version before the latest save.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// The backup path of a file: the same name with `~` appended.
pub fn backup_path(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push("~");
    PathBuf::from(name)
}

/// Writes `bytes` to `path` atomically, keeping the previous version as `path~`.
///
/// On error the file at `path` is left exactly as it was and no temporary file remains.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_steps(path, bytes, true, &mut |_| Ok(()))
}

/// Writes `bytes` to `path` atomically without keeping a backup: for outputs that are
/// regenerated (exported meshes), where `FILE~` copies would only be clutter.
pub fn write_atomic_no_backup(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_steps(path, bytes, false, &mut |_| Ok(()))
}

/// The steps of a save, named so tests can make each one fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    Create,
    Write,
    Sync,
    Backup,
    Rename,
}

/// Picks a temporary name beside `path` that no other save (in this or another process) uses.
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name"))?;
    let mut temp = std::ffi::OsString::from(".");
    temp.push(name);
    temp.push(format!(
        ".tmp-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    Ok(path.with_file_name(temp))
}

fn write_atomic_steps(
    path: &Path,
    bytes: &[u8],
    keep_backup: bool,
    fail: &mut dyn FnMut(Step) -> io::Result<()>,
) -> io::Result<()> {
    if path.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "the path is a folder",
        ));
    }
    let temp = temp_path(path)?;
    let result = write_and_rename(path, &temp, bytes, keep_backup, fail);
    if result.is_err() {
        // Best effort: the temporary file may not exist if creating it failed.
        let _ = fs::remove_file(&temp);
    }
    result
}

fn write_and_rename(
    path: &Path,
    temp: &Path,
    bytes: &[u8],
    keep_backup: bool,
    fail: &mut dyn FnMut(Step) -> io::Result<()>,
) -> io::Result<()> {
    fail(Step::Create)?;
    let mut file = OpenOptions::new().write(true).create_new(true).open(temp)?;
    if let Ok(meta) = fs::metadata(path) {
        // Keep the permissions of the file being replaced.
        let _ = file.set_permissions(meta.permissions());
    }
    fail(Step::Write)?;
    file.write_all(bytes)?;
    file.flush()?;
    fail(Step::Sync)?;
    file.sync_all()?;
    drop(file);
    if keep_backup && path.is_file() {
        fail(Step::Backup)?;
        backup(path)?;
    }
    fail(Step::Rename)?;
    fs::rename(temp, path)?;
    sync_folder(path);
    Ok(())
}

/// Copies the current version to `path~` through its own temporary file, so a crash while
/// backing up never leaves a half-written backup either.
fn backup(path: &Path) -> io::Result<()> {
    let backup = backup_path(path);
    let temp = temp_path(&backup)?;
    let result = (|| {
        fs::copy(path, &temp)?;
        File::open(&temp)?.sync_all()?;
        fs::rename(&temp, &backup)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&temp);
    }
    result
}

/// Fsyncs the folder holding `path` so a completed rename survives a power cut. Some file
/// systems refuse to open or sync folders; the data itself is already synced, so that is
/// not an error.
fn sync_folder(path: &Path) {
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if let Ok(dir) = File::open(folder) {
        let _ = dir.sync_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_new_file_and_keeps_backup_of_old() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.au.ron");
        write_atomic(&path, b"one").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"one");
        assert_eq!(files_in(dir.path()), ["t.au.ron"]);
        write_atomic(&path, b"two").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"two");
        assert_eq!(fs::read(backup_path(&path)).unwrap(), b"one");
        write_atomic(&path, b"three").unwrap();
        assert_eq!(fs::read(backup_path(&path)).unwrap(), b"two");
        assert_eq!(files_in(dir.path()), ["t.au.ron", "t.au.ron~"]);
    }

    #[test]
    fn a_failure_at_any_step_leaves_the_old_file_and_no_temporary() {
        for step in [
            Step::Create,
            Step::Write,
            Step::Sync,
            Step::Backup,
            Step::Rename,
        ] {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("rig.rig.ron");
            fs::write(&path, b"old").unwrap();
            let err = write_atomic_steps(&path, b"new", true, &mut |s| {
                if s == step {
                    Err(io::Error::other("no space left on device"))
                } else {
                    Ok(())
                }
            })
            .unwrap_err();
            assert_eq!(err.to_string(), "no space left on device");
            assert_eq!(fs::read(&path).unwrap(), b"old", "{step:?}");
            // A backup made before the failing step is a copy of the old version.
            let names = files_in(dir.path());
            assert_eq!(names[0], "rig.rig.ron", "{step:?}");
            if names.len() > 1 {
                assert_eq!(names[1..], ["rig.rig.ron~"], "{step:?}");
                assert_eq!(fs::read(backup_path(&path)).unwrap(), b"old", "{step:?}");
            }
        }
    }

    #[test]
    fn no_backup_variant_leaves_no_copy() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.obj");
        write_atomic_no_backup(&path, b"one").unwrap();
        write_atomic_no_backup(&path, b"two").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"two");
        assert_eq!(files_in(dir.path()), ["out.obj"]);
    }

    #[test]
    fn refuses_a_folder() {
        let dir = tempfile::tempdir().unwrap();
        assert!(write_atomic(dir.path(), b"x").is_err());
    }
}
