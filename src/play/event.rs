//! What every frame source hands out: [`Event`]s through [`FrameSource::poll`], and the
//! errors a source can end with. The sources themselves are in [`super::source`] (files and
//! timelines), [`super::live`] (stdin and UDP), [`super::livelink`] and [`super::acts`].

use std::io::BufRead;
use std::time::Duration;

use thiserror::Error;

use crate::io::openface::OpenFaceError;
use crate::io::timeline::TimelineError;
use crate::model::Activations;

use super::map::AuIntensity;

/// A file or stream read once, from its start (see [`crate::io::lines::sniff_first_line`]).
pub type Input = Box<dyn BufRead>;

/// The frame rate assumed for rows without timestamps, unless one is given.
pub const DEFAULT_FRAME_RATE: f64 = 30.0;

/// A frame ready to show.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Seconds: the source's timestamp (files, timelines, streams that send one), or the
    /// arrival time since the stream opened.
    pub time: f64,
    /// The 1-based line (or packet) number in the input, when there is one.
    pub line: Option<usize>,
    /// The AU intensities given, clamped to the scale (empty for timelines).
    pub aus: Vec<AuIntensity>,
    /// The pose: AUs mapped through the table, or the timeline's interpolated activations.
    pub activations: Activations,
}

/// What a source produced.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// A frame to show.
    Frame(Frame),
    /// A row the tracker marked `success` 0: it carries no AU values.
    Untracked {
        /// Its 1-based line.
        line: usize,
    },
    /// A row that cannot be read, skipped (or fatal under `--strict`).
    Malformed {
        /// `SOURCE:LINE[:COLUMN]: message`.
        message: String,
    },
    /// Something to say once: AUs the table lacks, clamped values, ignored fields.
    Notice(String),
}

/// The result of one poll.
#[derive(Debug, Clone, PartialEq)]
pub enum Poll {
    /// An event.
    Event(Event),
    /// A live source has nothing yet.
    Pending,
    /// The source is finished.
    End,
}

/// A source that cannot be opened or read on.
#[derive(Debug, Error)]
pub enum SourceError {
    /// An OpenFace CSV header or read failure.
    #[error(transparent)]
    OpenFace(#[from] OpenFaceError),
    /// A timeline that cannot be read or resolved.
    #[error(transparent)]
    Timeline(#[from] TimelineError),
    /// A file or socket that cannot be opened.
    #[error("{what}: {source}")]
    Io {
        /// What was being opened.
        what: String,
        /// The cause.
        source: std::io::Error,
    },
    /// A UDP address that is not on this machine.
    #[error("refusing to listen on {0}: only loopback addresses (127.0.0.1, ::1) are allowed, so no other machine can drive the face")]
    NotLoopback(String),
    /// An address that does not parse.
    #[error("`{0}` is not an address such as 127.0.0.1:9000")]
    BadAddress(String),
}

/// A producer of frames.
pub trait FrameSource {
    /// The next event, waiting at most `wait` for a live source.
    fn poll(&mut self, wait: Duration) -> Result<Poll, SourceError>;

    /// Whether frames arrive in real time (then they are shown on arrival, not scheduled).
    fn is_live(&self) -> bool;
}
