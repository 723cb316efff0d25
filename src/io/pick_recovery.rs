//! The landmark picker's recovery file: the points picked so far, written after every pick,
//! so a dropped connection or a crash loses none of them.
//!
//! For a landmark file `DIR/NAME` the recovery file is `DIR/.NAME.recover`, as for tables
//! ([`super::recovery::recovery_path`]). It is written atomically and removed once the
//! landmarks are saved.

use std::io;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use crate::landmarks::COUNT;

/// The picker recovery format version.
pub const PICK_RECOVERY_VERSION: u32 = 1;

/// The largest recovery file read back (68 picks need far less).
const MAX_BYTES: u64 = 1024 * 1024;

/// The picks of one picking session.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PickRecovery {
    /// Format version; see [`PICK_RECOVERY_VERSION`].
    pub version: u32,
    /// The mesh being picked on.
    pub mesh: PathBuf,
    /// Its vertex count (a recovery file for another mesh is not offered).
    pub vertices: usize,
    /// When the state was written, seconds since the Unix epoch.
    pub written_at: u64,
    /// The process that wrote it; while that process runs the file is its own.
    pub pid: Option<u32>,
    /// The vertex picked for each of the 68 landmarks, if any.
    pub picks: Vec<Option<u32>>,
    /// The landmarks skipped so far.
    #[serde(default)]
    pub skipped: Vec<usize>,
}

impl PickRecovery {
    /// The state now.
    pub fn new(mesh: &Path, vertices: usize, picks: &[Option<u32>], skipped: &[bool]) -> Self {
        PickRecovery {
            version: PICK_RECOVERY_VERSION,
            mesh: mesh.to_path_buf(),
            vertices,
            written_at: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
            pid: Some(std::process::id()),
            picks: picks.to_vec(),
            skipped: (0..skipped.len()).filter(|&i| skipped[i]).collect(),
        }
    }

    /// How many landmarks have a vertex.
    pub fn picked(&self) -> usize {
        self.picks.iter().flatten().count()
    }

    /// The process id of the picker that wrote the state, if it still runs and is not this
    /// one.
    pub fn live_owner(&self) -> Option<u32> {
        self.pid
            .filter(|&pid| pid != std::process::id() && super::lock::is_running(pid))
    }

    /// Checks that the state fits a mesh of `vertices` vertices.
    pub fn check(&self, path: &Path, vertices: usize) -> Result<(), String> {
        let bad = |why: String| Err(format!("{}: {why}", path.display()));
        if self.picks.len() != COUNT {
            return bad(format!("{} picks; expected {COUNT}", self.picks.len()));
        }
        if self.vertices != vertices {
            return bad(format!(
                "written for a mesh of {} vertices, this one has {vertices}",
                self.vertices
            ));
        }
        if let Some((i, v)) = self
            .picks
            .iter()
            .enumerate()
            .find_map(|(i, v)| v.filter(|&v| v as usize >= vertices).map(|v| (i, v)))
        {
            return bad(format!("landmark {i} is vertex {v}, beyond the mesh"));
        }
        if let Some(&i) = self.skipped.iter().find(|&&i| i >= COUNT) {
            return bad(format!("skipped landmark {i} does not exist"));
        }
        Ok(())
    }
}

/// The recovery file for a landmark file.
pub fn path_for(landmarks: &Path) -> Option<PathBuf> {
    super::recovery::recovery_path(Some(landmarks))
}

/// Writes the state atomically.
pub fn write(path: &Path, state: &PickRecovery) -> io::Result<()> {
    super::recovery::write_ron(path, state)
}

/// Reads a recovery file: `Ok(None)` when there is none, a message naming the file (and the
/// line and column) when it cannot be read.
pub fn read(path: &Path) -> Result<Option<PickRecovery>, String> {
    super::recovery::read_ron(
        path,
        MAX_BYTES,
        "picker recovery file",
        PICK_RECOVERY_VERSION,
        |s: &PickRecovery| s.version,
    )
}

/// Removes a recovery file (no error when it is already gone).
pub fn remove(path: &Path) -> io::Result<()> {
    super::recovery::remove(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    #[test]
    fn picks_round_trip_and_are_checked_against_the_mesh() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("head.landmarks.ron");
        let path = path_for(&out).unwrap();
        assert_eq!(path, dir.path().join(".head.landmarks.ron.recover"));
        let mut picks = vec![None; COUNT];
        picks[45] = Some(12);
        let mut skipped = vec![false; COUNT];
        skipped[3] = true;
        let state = PickRecovery::new(Path::new("head.obj"), 100, &picks, &skipped);
        write(&path, &state).unwrap();
        let back = read(&path).unwrap().unwrap();
        assert_eq!(back, state);
        assert_eq!((back.picked(), back.skipped.clone()), (1, vec![3]));
        assert_eq!(back.live_owner(), None, "this process's own file");
        back.check(&path, 100).unwrap();
        let err = back.check(&path, 50).unwrap_err();
        assert!(err.contains("50"), "{err}");
        let mut beyond = back.clone();
        beyond.vertices = 10;
        assert!(beyond.check(&path, 10).unwrap_err().contains("landmark 45"));
        remove(&path).unwrap();
        assert_eq!(read(&path).unwrap(), None);
    }

    #[test]
    fn a_damaged_file_names_file_line_and_column() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(".x.recover");
        fs::write(&path, "(\n version: 1,\n what\n").unwrap();
        let err = read(&path).unwrap_err();
        assert!(err.starts_with(&format!("{}:3:", path.display())), "{err}");
    }
}
