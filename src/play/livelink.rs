//! A Live Link Face CSV recording as a frame source: each row's ARKit weights (0-1) become
//! AU intensities through the ARKit map, then activations through the AU table, as OpenFace
//! rows do.

use std::collections::BTreeSet;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;
use std::time::Duration;

use super::map::{AuMapper, IntensityScale};
use super::source::{AuFrames, Event, FrameSource, Poll, SourceError};
use crate::facs::AuKey;
use crate::io::arkit::ArkitMap;
use crate::io::livelink::LiveLinkReader;

/// The frame rate Live Link Face records at unless set otherwise in the app.
pub const LIVELINK_FRAME_RATE: f64 = 60.0;

/// A Live Link Face CSV file.
pub struct LiveLinkSource {
    reader: LiveLinkReader<BufReader<File>>,
    name: String,
    /// The AU of each shape column (`None`: the shape has no AU).
    keys: Vec<Option<AuKey>>,
    builder: AuFrames,
    first: Option<f64>,
    stashed: Option<Event>,
}

impl LiveLinkSource {
    /// Opens a recording and reads its header; `fps` is the frame rate of its timecodes.
    pub fn open(
        path: &Path,
        mapper: AuMapper,
        arkit: &ArkitMap,
        fps: f64,
    ) -> Result<LiveLinkSource, SourceError> {
        let file = File::open(path).map_err(|source| SourceError::Io {
            what: format!("cannot open {}", path.display()),
            source,
        })?;
        let reader = LiveLinkReader::new(BufReader::new(file), path, fps)?;
        let name = path.display().to_string();
        let mut builder = AuFrames::new(mapper, IntensityScale::ZeroToOne, &name);
        let shapes = &reader.columns().shapes;
        let keys: Vec<Option<AuKey>> = shapes.iter().map(|(_, s)| arkit.au(s)).collect();
        let without: Vec<&str> = shapes
            .iter()
            .zip(&keys)
            .filter(|(_, k)| k.is_none())
            .map(|((_, s), _)| *s)
            .collect();
        if !without.is_empty() {
            builder.push_notice(format!(
                "{name}: ARKit shapes with no AU (ignored): {}",
                without.join(", ")
            ));
        }
        let ignored: BTreeSet<&str> = reader
            .columns()
            .ignored
            .iter()
            .map(String::as_str)
            .collect();
        if !ignored.is_empty() {
            let list: Vec<&str> = ignored.into_iter().collect();
            builder.push_notice(format!(
                "{name}: columns that are not blendshapes (ignored): {}",
                list.join(", ")
            ));
        }
        builder.report_missing(keys.iter().flatten().copied());
        Ok(LiveLinkSource {
            reader,
            name,
            keys,
            builder,
            first: None,
            stashed: None,
        })
    }
}

impl FrameSource for LiveLinkSource {
    fn poll(&mut self, _wait: Duration) -> Result<Poll, SourceError> {
        if let Some(notice) = self.builder.take_notice() {
            return Ok(Poll::Event(Event::Notice(notice)));
        }
        if let Some(event) = self.stashed.take() {
            return Ok(Poll::Event(event));
        }
        let Some(row) = self.reader.next_row()? else {
            return Ok(Poll::End);
        };
        let event = match row {
            Err(e) => {
                let column = e.column.map(|c| format!(":{c}")).unwrap_or_default();
                Event::Malformed {
                    message: format!("{}:{}{column}: {}", self.name, e.line, e.message),
                }
            }
            Ok(row) => {
                let first = *self.first.get_or_insert(row.seconds);
                let raw = self
                    .keys
                    .iter()
                    .zip(&row.weights)
                    .filter_map(|(key, w)| key.map(|k| (k, *w)));
                Event::Frame(self.builder.frame(row.seconds - first, Some(row.line), raw))
            }
        };
        // A clamp warning raised by this row goes out before the row.
        match self.builder.take_notice() {
            Some(notice) => {
                self.stashed = Some(event);
                Ok(Poll::Event(Event::Notice(notice)))
            }
            None => Ok(Poll::Event(event)),
        }
    }

    fn is_live(&self) -> bool {
        false
    }
}
