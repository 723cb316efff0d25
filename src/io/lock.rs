//! Lock files: a warning when the same table is already open in another grimace.
//!
//! For a table `DIR/NAME` the lock is `DIR/.NAME.lock`, holding the owner's process id. A
//! lock whose process no longer runs is stale and taken over. The lock warns; it does not
//! forbid (the other editor may be on a machine that is gone), and saving still refuses to
//! overwrite a file changed on disk without asking.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// A lock this process holds; dropping it removes the lock file.
#[derive(Debug)]
pub struct Lock {
    path: PathBuf,
}

impl Lock {
    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        // Only remove the lock if it is still ours.
        if read_pid(&self.path) == Some(std::process::id()) {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// The outcome of trying to lock a table.
#[derive(Debug)]
pub enum LockOutcome {
    /// The table is ours.
    Acquired(Lock),
    /// Another running grimace holds it.
    HeldBy {
        /// Its process id.
        pid: u32,
    },
    /// No lock could be written (read-only folder, ...): editing goes on without one.
    Unavailable(String),
}

/// The lock file of a table file; for a symbolic link, that of the file it points to, so
/// editors on the link and on the file see each other.
pub fn lock_path(table: &Path) -> Option<PathBuf> {
    let table = &super::atomic::save_target(table).unwrap_or_else(|_| table.to_path_buf());
    let name = table.file_name()?.to_string_lossy();
    let dir = table.parent().unwrap_or_else(|| Path::new(""));
    Some(dir.join(format!(".{name}.lock")))
}

/// Tries to lock a table file.
pub fn acquire(table: &Path) -> LockOutcome {
    let Some(path) = lock_path(table) else {
        return LockOutcome::Unavailable(format!("{} is not a file name", table.display()));
    };
    for _ in 0..2 {
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
        {
            Ok(mut file) => {
                return match writeln!(file, "{}", std::process::id()) {
                    Ok(()) => LockOutcome::Acquired(Lock { path }),
                    Err(e) => {
                        // An empty lock would outlive this editor; leave none.
                        drop(file);
                        let _ = fs::remove_file(&path);
                        LockOutcome::Unavailable(format!(
                            "{}: {}",
                            path.display(),
                            super::error::io_reason(&e)
                        ))
                    }
                };
            }
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => match read_pid(&path) {
                Some(pid) if pid != std::process::id() && is_running(pid) => {
                    return LockOutcome::HeldBy { pid }
                }
                // Stale (or unreadable) lock: take it over.
                _ => {
                    let _ = fs::remove_file(&path);
                }
            },
            Err(e) => return LockOutcome::Unavailable(format!("{}: {e}", path.display())),
        }
    }
    LockOutcome::Unavailable(format!("{}: could not be created", path.display()))
}

fn read_pid(path: &Path) -> Option<u32> {
    fs::read_to_string(path).ok()?.trim().parse().ok()
}

/// Whether a process runs. Where this cannot be told (no /proc), assume it does: a false
/// warning is better than a missing one.
pub fn is_running(pid: u32) -> bool {
    let proc = Path::new("/proc");
    if proc.join("self").exists() {
        proc.join(pid.to_string()).exists()
    } else {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_editor_is_warned_and_a_stale_lock_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let table = dir.path().join("t.au.ron");
        let lock_file = lock_path(&table).unwrap();
        // A lock held by a running process (pid 1 always runs on Linux).
        fs::write(&lock_file, "1\n").unwrap();
        match acquire(&table) {
            LockOutcome::HeldBy { pid } => assert_eq!(pid, 1),
            other => panic!("expected HeldBy, got {other:?}"),
        }
        // A stale lock: a process id that does not run.
        fs::write(&lock_file, "4294967290\n").unwrap();
        let lock = match acquire(&table) {
            LockOutcome::Acquired(lock) => lock,
            other => panic!("expected Acquired, got {other:?}"),
        };
        assert_eq!(read_pid(&lock_file), Some(std::process::id()));
        drop(lock);
        assert!(!lock_file.exists());
    }
}
