//! Batches: a plan of faces, states, views, styles and outputs rendered into a labelled data
//! set, split into shards that any machine can run alone (`grimace batch`, docs/batch.md).
//!
//! [`plan`] reads the plan file; [`items`] expands it into items with stable IDs and splits
//! them into shards; [`run`] draws a shard's items into files (atomically, resuming after a
//! kill); [`labels`] writes and merges the label rows.

pub mod items;
pub mod labels;
pub mod plan;
pub mod run;

use std::fmt;
use std::path::Path;

pub use items::{expand, Expanded, FaceRef, Item, Shard, State};
pub use plan::{Output, Plan, PlanFile};
pub use run::{Batch, Face, Progress, RunOptions, Summary};

/// Why a batch could not run or merge: the message names the file or place.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BatchError {
    /// What went wrong, and where.
    pub message: String,
}

impl BatchError {
    /// An error with this message.
    pub fn new(message: impl Into<String>) -> BatchError {
        BatchError {
            message: message.into(),
        }
    }

    /// A file or folder operation that failed: `PATH: WHAT: REASON`.
    pub fn io(path: &Path, what: &str, error: &std::io::Error) -> BatchError {
        BatchError::new(format!(
            "{}: {what}: {}",
            path.display(),
            crate::io::error::io_reason(error)
        ))
    }
}

impl fmt::Display for BatchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for BatchError {}

impl From<crate::io::LoadError> for BatchError {
    fn from(e: crate::io::LoadError) -> BatchError {
        BatchError::new(e.to_string())
    }
}

impl From<crate::io::SaveError> for BatchError {
    fn from(e: crate::io::SaveError) -> BatchError {
        BatchError::new(e.to_string())
    }
}
