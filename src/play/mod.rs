//! Playback: frames of AU intensities or activations from files and live streams, mapped
//! through an AU table, on a clock that keeps the source's frame rate.
//!
//! - [`source`]: OpenFace CSV files and timelines; [`acts`]: activation CSVs from
//!   `grimace capture`, played by muscle name; [`live`]: stdin (CSV, Live Link Face or
//!   JSON lines) and loopback UDP JSON; [`open`]: a file read once, its format told from its
//!   first line;
//! - [`rules`]: what every source keeps to: finite, bounded, monotonic time, bounded memory
//!   for names seen, messages made safe to print;
//! - [`map`]: AU intensities to activations through an [`crate::facs::AuTable`];
//! - [`clock`]: source time against wall time (speed, pause, steps) and dropped-frame counts;
//! - [`livelink`]: Live Link Face CSV recordings (ARKit blendshapes) through the ARKit map;
//! - [`json`]: the flat `{"AU1": 0.0, ...}` objects live streams send;
//! - [`skips`]: the rows skipped, named while few and counted by kind at the end.

pub mod acts;
pub mod clock;
pub mod event;
pub mod json;
pub mod live;
pub mod livelink;
pub mod map;
pub mod open;
pub mod player;
pub mod rules;
pub mod skips;
pub mod source;

pub use clock::{FrameStats, PlayClock};
pub use event::{Event, Frame, FrameSource, Poll, SourceError};
pub use live::LiveSource;
pub use map::{AuIntensity, AuMapper, IntensityScale};
pub use player::{Message, PlayError, Player};
pub use source::{OpenFaceSource, TimelineSource};
