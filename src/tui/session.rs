//! Starting a session on a file, the same for the editor and the landmark picker: the file's
//! lock (a warning when another grimace has it open) and the recovery file where unsaved work
//! is kept, left alone when it belongs to another grimace that still runs.

use std::path::{Path, PathBuf};

use crate::io::lock::{self, Lock, LockOutcome};

/// What a running editor or picker holds besides its state.
#[derive(Debug, Default)]
pub struct Session {
    /// Where unsaved work is kept; `None` when another grimace owns that file (or there is
    /// none).
    pub recovery: Option<PathBuf>,
    /// The file's lock, released when the session ends.
    pub lock: Option<Lock>,
}

impl Session {
    /// Takes the lock on `file` (`None`: nothing to lock, the built-in table) and keeps
    /// `recovery` as the session's recovery file, unless another grimace has the file open:
    /// then its recovery file is its own and this session keeps none. Gives the session and
    /// what to tell the user; `work` names what is not kept then (`changes`, `picks`).
    pub fn start(
        file: Option<&Path>,
        recovery: Option<PathBuf>,
        work: &str,
    ) -> (Session, Option<String>) {
        let mut session = Session {
            recovery,
            lock: None,
        };
        let Some(file) = file else {
            return (session, None);
        };
        let warning = match lock::acquire(file) {
            LockOutcome::Acquired(lock) => {
                session.lock = Some(lock);
                None
            }
            LockOutcome::HeldBy { pid } => {
                // The other session's recovery file is its own: neither offered, removed nor
                // overwritten here.
                session.recovery = None;
                Some(format!(
                    "{} is already open in another grimace (process {pid}); its recovery file is left alone, {work} here are not kept for recovery, and saving here may undo its changes",
                    file.display()
                ))
            }
            LockOutcome::Unavailable(why) => Some(format!("no lock file: {why}")),
        };
        (session, warning)
    }

    /// The recovery file belongs to another grimace that still runs (process `owner`): it
    /// is left alone and this session keeps none. Gives what to tell the user.
    pub fn yield_recovery(&mut self, owner: u32, work: &str) -> String {
        let path = self.recovery.take().unwrap_or_default();
        format!(
            "{} belongs to another grimace (process {owner}) that is still running; it is left alone, and {work} here are not kept for recovery",
            path.display()
        )
    }
}

/// How long ago a recovery file was written, for the offer (`3 min ago`).
pub fn describe_age(written_at: u64) -> String {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let age = now.saturating_sub(written_at);
    match age {
        0..=59 => format!("{age} s ago"),
        60..=3599 => format!("{} min ago", age / 60),
        3600..=86399 => format!("{} h ago", age / 3600),
        _ => format!("{} days ago", age / 86400),
    }
}
