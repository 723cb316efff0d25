//! Recovery files: the editor's unsaved state (activations and table), kept on disk so a
//! dropped connection or a crash loses nothing.
//!
//! Where: for a table file `DIR/NAME`, the recovery file is `DIR/.NAME.recover` (beside the
//! table, so it travels with it); for the built-in table, `$XDG_STATE_HOME/grimace/builtin.recover`
//! (default `~/.local/state/grimace/`). The file is written atomically (a temporary file, fsync,
//! rename), so it is always either the old or the new state. The table file itself is never
//! touched until the user saves.

use std::collections::BTreeMap;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::facs::AuTable;
use crate::model::{Activations, Rig, JAW_RANGE, MUSCLE_RANGE};

/// The recovery file format version.
pub const RECOVERY_VERSION: u32 = 1;

/// The largest recovery file read back (a table of 64 AUs is far smaller).
const MAX_RECOVERY_BYTES: u64 = 16 * 1024 * 1024;

/// The unsaved state of one editing session.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecoveryState {
    /// Format version; see [`RECOVERY_VERSION`].
    pub version: u32,
    /// The table file being edited, if any.
    pub table_file: Option<PathBuf>,
    /// When the state was written, seconds since the Unix epoch.
    pub written_at: u64,
    /// Activation per muscle name (names keep the state meaningful if the rig's order changes).
    pub muscles: BTreeMap<String, f32>,
    /// Jaw activation.
    pub jaw: f32,
    /// The AU table as edited.
    pub table: AuTable,
    /// The process that wrote the state. While it runs the file is its own: another editor
    /// neither offers nor removes it. Absent in files from older versions.
    #[serde(default)]
    pub pid: Option<u32>,
    /// The table file the edits started from: its length and content hash, `None` when it did
    /// not exist (or the recovery file predates this field). After recovering, a save asks
    /// before replacing a file that no longer matches.
    #[serde(default)]
    pub base: Option<(u64, u64)>,
    /// The rig as edited in rig mode, when it differs from its file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rig: Option<Rig>,
}

impl RecoveryState {
    /// The state of an editing session now.
    pub fn new(
        table_file: Option<&Path>,
        rig: &Rig,
        activations: &Activations,
        table: &AuTable,
    ) -> RecoveryState {
        RecoveryState {
            version: RECOVERY_VERSION,
            table_file: table_file.map(Path::to_path_buf),
            written_at: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
            muscles: rig
                .muscles
                .iter()
                .zip(&activations.muscles)
                .map(|(m, &a)| (m.name.clone(), a))
                .collect(),
            jaw: activations.jaw,
            table: table.clone(),
            pid: Some(std::process::id()),
            base: None,
            rig: None,
        }
    }

    /// The process id of the grimace that wrote the state, if that process still runs and is
    /// not this one: the state is then in use and must be left alone.
    pub fn live_owner(&self) -> Option<u32> {
        self.pid
            .filter(|&pid| pid != std::process::id() && super::lock::is_running(pid))
    }

    /// The activations for `rig`: muscles the rig lacks are dropped, values outside their
    /// range or not finite are reset to zero, so a damaged file cannot yield a bad state.
    pub fn activations(&self, rig: &Rig) -> Activations {
        let mut activations = Activations::zero(rig);
        for (i, muscle) in rig.muscles.iter().enumerate() {
            if let Some(&v) = self.muscles.get(&muscle.name) {
                if v.is_finite() && MUSCLE_RANGE.contains(&v) {
                    activations.muscles[i] = v;
                }
            }
        }
        if self.jaw.is_finite() && JAW_RANGE.contains(&self.jaw) && rig.jaw.is_some() {
            activations.jaw = self.jaw;
        }
        activations
    }
}

/// The recovery file for a table file, or for the built-in table when `table` is `None`
/// (`None` back when no state folder can be found). For a symbolic link, the recovery file
/// sits beside the file it points to.
pub fn recovery_path(table: Option<&Path>) -> Option<PathBuf> {
    match table {
        Some(path) => {
            // Beside the file a symbolic link points to, like the lock and the backup.
            let path = &super::atomic::save_target(path).unwrap_or_else(|_| path.to_path_buf());
            let name = path.file_name()?.to_string_lossy();
            let dir = path.parent().unwrap_or_else(|| Path::new(""));
            Some(dir.join(format!(".{name}.recover")))
        }
        None => state_dir().map(|d| d.join("builtin.recover")),
    }
}

/// `$XDG_STATE_HOME/grimace`, else `$HOME/.local/state/grimace`.
fn state_dir() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_STATE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|v| !v.is_empty())
                .map(|h| PathBuf::from(h).join(".local").join("state"))
        })?;
    Some(base.join("grimace"))
}

/// Writes the state atomically, creating the folder if needed.
pub fn write(path: &Path, state: &RecoveryState) -> io::Result<()> {
    write_ron(path, state)
}

/// Reads a recovery file: `Ok(None)` when there is none, an error message naming the file
/// when it cannot be read.
pub fn read(path: &Path) -> Result<Option<RecoveryState>, String> {
    read_ron(
        path,
        MAX_RECOVERY_BYTES,
        "recovery file",
        RECOVERY_VERSION,
        |s: &RecoveryState| s.version,
    )
}

/// Writes any recovery state as RON, atomically and without a backup, creating the folder
/// if needed. Shared by the editor's and the picker's recovery files.
pub(crate) fn write_ron<T: Serialize>(path: &Path, state: &T) -> io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir)?;
    }
    let text = ron::ser::to_string_pretty(state, ron::ser::PrettyConfig::new())
        .map_err(|e| io::Error::other(e.to_string()))?;
    super::atomic::write_atomic_no_backup(path, text.as_bytes())
}

/// Reads any recovery state written by [`write_ron`]: `Ok(None)` when there is no file; a
/// message naming the file (with line and column for bad RON) when it is too large, does
/// not parse, or is not of `version` (`what` names the kind of file in that message).
pub(crate) fn read_ron<T: DeserializeOwned>(
    path: &Path,
    max_bytes: u64,
    what: &str,
    version: u32,
    version_of: impl Fn(&T) -> u32,
) -> Result<Option<T>, String> {
    let meta = match fs::metadata(path) {
        Ok(meta) => meta,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(format!("{}: {e}", path.display())),
    };
    if meta.len() > max_bytes {
        return Err(format!(
            "{}: too large to be a recovery file",
            path.display()
        ));
    }
    let text = fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let state: T = ron::from_str(&text).map_err(|e| {
        format!(
            "{}:{}:{}: {}",
            path.display(),
            e.span.start.line,
            e.span.start.col,
            e.code
        )
    })?;
    let found = version_of(&state);
    if found != version {
        return Err(format!(
            "{}: {what} version {found} is not {version}",
            path.display()
        ));
    }
    Ok(Some(state))
}

/// Removes a recovery file (no error when it is already gone).
pub fn remove(path: &Path) -> io::Result<()> {
    match fs::remove_file(path) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> AuTable {
        AuTable {
            version: 1,
            rig: PathBuf::from("builtin:default"),
            aus: BTreeMap::new(),
            expressions: BTreeMap::from([("smile".to_string(), "6+12".to_string())]),
        }
    }

    #[test]
    fn recovery_file_sits_beside_the_table_hidden() {
        let path = recovery_path(Some(Path::new("/data/happy.au.ron"))).unwrap();
        assert_eq!(path, PathBuf::from("/data/.happy.au.ron.recover"));
    }

    #[test]
    fn state_round_trips_through_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(".t.recover");
        let state = RecoveryState {
            version: RECOVERY_VERSION,
            table_file: Some(dir.path().join("t.au.ron")),
            written_at: 42,
            muscles: BTreeMap::from([("A".to_string(), 0.75)]),
            jaw: 1.5,
            table: table(),
            pid: Some(7),
            base: Some((12, 34)),
            rig: None,
        };
        write(&path, &state).unwrap();
        assert_eq!(read(&path).unwrap(), Some(state));
        remove(&path).unwrap();
        assert_eq!(read(&path).unwrap(), None);
        remove(&path).unwrap();
    }

    #[test]
    fn an_older_recovery_file_reads_without_owner_or_base() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(".t.recover");
        let text = "(version: 1, table_file: None, written_at: 1, muscles: {}, jaw: 0.0, \
                    table: (version: 1, rig: \"builtin:default\", aus: {}, expressions: {}))";
        fs::write(&path, text).unwrap();
        let state = read(&path).unwrap().unwrap();
        assert_eq!((state.pid, state.base), (None, None));
        assert_eq!(state.live_owner(), None);
        // pid 1 always runs; this process is never its own other owner.
        let mut state = state;
        state.pid = Some(1);
        assert_eq!(state.live_owner(), Some(1));
        state.pid = Some(std::process::id());
        assert_eq!(state.live_owner(), None);
    }

    #[test]
    fn a_damaged_recovery_file_names_file_line_and_column() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(".t.recover");
        fs::write(&path, "(\n  version: 1,\n  nonsense\n").unwrap();
        let err = read(&path).unwrap_err();
        assert!(err.starts_with(&format!("{}:3:", path.display())), "{err}");
    }
}
