//! A Live Link Face CSV recording as a frame source: each row's ARKit weights (0-1) become
//! AU intensities through the ARKit map, then activations through the AU table, as OpenFace
//! rows do. Timecodes are times of day: a take across midnight runs on into the next day
//! (see [`super::rules`]).

use std::path::Path;
use std::time::Duration;

use super::event::{Event, FrameSource, Input, Poll, SourceError};
use super::map::{AuMapper, IntensityScale};
use super::rules::{printable_poll, NameSet, TimeBase, TimeRule};
use super::source::AuFrames;
use crate::facs::AuKey;
use crate::io::arkit::ArkitMap;
use crate::io::livelink::{LiveLinkColumns, LiveLinkReader, LiveLinkRow};
use crate::io::openface::RowError;

/// The frame rate Live Link Face records at unless set otherwise in the app.
pub const LIVELINK_FRAME_RATE: f64 = 60.0;

/// What a Live Link Face source keeps between rows, whether it reads a file or stdin.
#[derive(Debug)]
pub(crate) struct LiveLinkRows {
    /// The AU of each shape column (`None`: the shape has no AU).
    keys: Vec<Option<AuKey>>,
    rule: TimeRule,
}

impl LiveLinkRows {
    /// The AUs of the header's shapes; what the header holds that will not play is queued on
    /// `builder` as notices (names kept bounded through `names`).
    pub(crate) fn new(
        columns: &LiveLinkColumns,
        arkit: &ArkitMap,
        builder: &mut AuFrames,
        names: &mut NameSet,
        source: &str,
    ) -> LiveLinkRows {
        let keys: Vec<Option<AuKey>> = columns.shapes.iter().map(|(_, s)| arkit.au(s)).collect();
        let without = columns
            .shapes
            .iter()
            .zip(&keys)
            .filter(|(_, k)| k.is_none())
            .map(|((_, s), _)| *s);
        if let Some(list) = names.list(without) {
            builder.push_notice(format!(
                "{source}: ARKit shapes with no AU (ignored): {list}"
            ));
        }
        if let Some(list) = names.list(columns.ignored.iter().map(String::as_str)) {
            builder.push_notice(format!(
                "{source}: columns that are not blendshapes (ignored): {list}"
            ));
        }
        builder.report_missing(keys.iter().flatten().copied());
        LiveLinkRows {
            keys,
            rule: TimeRule::new(TimeBase::TimeOfDay),
        }
    }

    /// The event for one row: a frame timed from the first row's timecode, or a malformed row.
    pub(crate) fn event(
        &mut self,
        builder: &mut AuFrames,
        row: Result<LiveLinkRow, RowError>,
        source: &str,
    ) -> Event {
        let row = match row {
            Ok(row) => row,
            Err(e) => {
                let column = e.column.map(|c| format!(":{c}")).unwrap_or_default();
                return Event::Malformed {
                    message: format!("{source}:{}{column}: {}", e.line, e.message),
                };
            }
        };
        let time = match self.rule.accept(row.seconds) {
            Ok(time) => time,
            Err(why) => {
                return Event::Malformed {
                    message: format!("{source}:{}: {why}", row.line),
                }
            }
        };
        let raw = self
            .keys
            .iter()
            .zip(&row.weights)
            .filter_map(|(key, w)| key.map(|k| (k, *w)));
        Event::Frame(builder.frame(time, Some(row.line), raw))
    }
}

/// A Live Link Face CSV file.
pub struct LiveLinkSource {
    reader: LiveLinkReader<Input>,
    name: String,
    rows: LiveLinkRows,
    builder: AuFrames,
    stashed: Option<Event>,
}

impl LiveLinkSource {
    /// Reads the header of `input`, the recording at `path`; `fps` is the frame rate of its
    /// timecodes.
    pub fn new(
        input: Input,
        path: &Path,
        mapper: AuMapper,
        arkit: &ArkitMap,
        fps: f64,
    ) -> Result<LiveLinkSource, SourceError> {
        let reader = LiveLinkReader::new(input, path, fps)?;
        let name = path.display().to_string();
        let mut builder = AuFrames::new(mapper, IntensityScale::ZeroToOne, &name);
        let mut names = NameSet::default();
        let rows = LiveLinkRows::new(reader.columns(), arkit, &mut builder, &mut names, &name);
        Ok(LiveLinkSource {
            reader,
            name,
            rows,
            builder,
            stashed: None,
        })
    }

    fn next_event(&mut self) -> Result<Poll, SourceError> {
        if let Some(notice) = self.builder.take_notice() {
            return Ok(Poll::Event(Event::Notice(notice)));
        }
        if let Some(event) = self.stashed.take() {
            return Ok(Poll::Event(event));
        }
        let Some(row) = self.reader.next_row()? else {
            return Ok(Poll::End);
        };
        let event = self.rows.event(&mut self.builder, row, &self.name);
        // A clamp warning raised by this row goes out before the row.
        match self.builder.take_notice() {
            Some(notice) => {
                self.stashed = Some(event);
                Ok(Poll::Event(Event::Notice(notice)))
            }
            None => Ok(Poll::Event(event)),
        }
    }
}

impl FrameSource for LiveLinkSource {
    fn poll(&mut self, _wait: Duration) -> Result<Poll, SourceError> {
        self.next_event().map(printable_poll)
    }

    fn is_live(&self) -> bool {
        false
    }
}
