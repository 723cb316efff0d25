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
//!
//! A save writes through symbolic links: the file the link points to is replaced (and backed
//! up beside itself), the link stays a link. Anything that is not a regular file (a folder, a
//! named pipe, a device, a socket) is refused, never replaced.

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
    write_atomic_steps(path, bytes, Care::Backup, &mut |_| Ok(()))
}

/// Writes `bytes` to `path` atomically without keeping a backup: for grimace's own
/// bookkeeping files (recovery files), never for a file a user names. Every command output
/// keeps the file it replaces as `FILE~` ([`write_atomic`], [`replace_unsynced`]).
pub fn write_atomic_no_backup(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_steps(path, bytes, Care::NoBackup, &mut |_| Ok(()))
}

/// Replaces `path` by a whole new file without waiting for the disk: a temporary file
/// renamed over it, so a full disk or a killed process leaves the old file, but no fsync (a
/// power cut may lose the new version). For many regenerated files at once (`render --all`),
/// where two fsyncs per file would dominate the run time. A replaced file is kept as
/// `FILE~`, as [`write_atomic`] keeps it.
pub fn replace_unsynced(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_steps(path, bytes, Care::Unsynced, &mut |_| Ok(()))
}

/// The file a save to `path` replaces: `path` itself, or, when it is a symbolic link, the
/// file the link points to (followed through chains of links; a relative link is read from
/// the link's folder). The file need not exist yet.
pub fn save_target(path: &Path) -> io::Result<PathBuf> {
    let mut target = path.to_path_buf();
    // As many links as the kernel follows before it gives up (ELOOP).
    for _ in 0..40 {
        match fs::symlink_metadata(&target) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = fs::read_link(&target)?;
                target = match target.parent() {
                    Some(folder) => folder.join(link),
                    None => link,
                };
            }
            Ok(_) => return Ok(target),
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(target),
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

/// Refuses to replace anything but a regular file (or nothing).
fn check_replaceable(target: &Path) -> io::Result<()> {
    match fs::metadata(target) {
        Ok(meta) => match super::error::special_kind(&meta.file_type()) {
            None => Ok(()),
            Some(kind) => Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("it is {kind}; grimace only replaces regular files"),
            )),
        },
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    }
}

/// How careful a save is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Care {
    /// Synced, with the previous version kept as `FILE~`.
    Backup,
    /// Synced, no backup.
    NoBackup,
    /// Renamed into place without fsync, with the previous version kept as `FILE~`.
    Unsynced,
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
    care: Care,
    fail: &mut dyn FnMut(Step) -> io::Result<()>,
) -> io::Result<()> {
    let path = &save_target(path)?;
    check_replaceable(path)?;
    let temp = temp_path(path)?;
    let result = write_and_rename(path, &temp, bytes, care, fail);
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
    care: Care,
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
    if care != Care::Unsynced {
        file.sync_all()?;
    }
    drop(file);
    if care != Care::NoBackup && path.is_file() {
        fail(Step::Backup)?;
        backup(path, care)?;
    }
    fail(Step::Rename)?;
    fs::rename(temp, path)?;
    if care != Care::Unsynced {
        sync_folder(path);
    }
    Ok(())
}

/// Copies the current version to `path~` through its own temporary file, so a crash while
/// backing up never leaves a half-written backup either.
fn backup(path: &Path, care: Care) -> io::Result<()> {
    let backup = backup_path(path);
    let temp = temp_path(&backup)?;
    let result = (|| {
        fs::copy(path, &temp)?;
        if care != Care::Unsynced {
            File::open(&temp)?.sync_all()?;
        }
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
            let err = write_atomic_steps(&path, b"new", Care::Backup, &mut |s| {
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

    #[cfg(unix)]
    #[test]
    fn writes_through_a_chain_of_links_and_backs_up_the_target() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("sub");
        fs::create_dir(&sub).unwrap();
        let target = sub.join("real.au.ron");
        fs::write(&target, b"old").unwrap();
        std::os::unix::fs::symlink("sub/real.au.ron", dir.path().join("a")).unwrap();
        std::os::unix::fs::symlink("a", dir.path().join("b")).unwrap();
        let link = dir.path().join("b");
        assert_eq!(
            save_target(&link).unwrap(),
            dir.path().join("sub/real.au.ron")
        );
        write_atomic(&link, b"new").unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read(&target).unwrap(), b"new");
        assert_eq!(fs::read(backup_path(&target)).unwrap(), b"old");
        assert_eq!(files_in(&sub), ["real.au.ron", "real.au.ron~"]);
        // A loop of links is an error, not a hang.
        std::os::unix::fs::symlink("loop2", dir.path().join("loop1")).unwrap();
        std::os::unix::fs::symlink("loop1", dir.path().join("loop2")).unwrap();
        assert!(write_atomic(&dir.path().join("loop1"), b"x").is_err());
    }

    #[test]
    fn refuses_to_replace_a_device() {
        let err = replace_unsynced(Path::new("/dev/null"), b"x").unwrap_err();
        assert_eq!(
            err.to_string(),
            "it is a character device; grimace only replaces regular files"
        );
    }
}
