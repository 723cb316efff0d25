//! Activation CSVs (`grimace capture`'s output) played on any rig: each row's muscles are
//! taken by name, so a capture solved on one head replays on another fitted from the same
//! template (retargeting at the muscle level). Muscles the rig lacks are named once.

use std::path::Path;
use std::time::Duration;

use super::event::{Event, Frame, FrameSource, Input, Poll, SourceError};
use super::rules::printable_poll;
use super::source::RowClock;
use crate::io::acts::{ActsReader, MuscleMap};
use crate::io::openface::OpenFaceError;

/// An activation CSV file.
pub struct ActsSource {
    reader: ActsReader<Input>,
    map: MuscleMap,
    muscle_count: usize,
    clock: RowClock,
    name: String,
    notice: Option<String>,
}

impl ActsSource {
    /// Reads the header of `input`, the file at `path`, for a rig with these muscles.
    pub fn new(
        input: Input,
        path: &Path,
        muscles: &[String],
        frame_rate: f64,
    ) -> Result<ActsSource, SourceError> {
        let reader = ActsReader::new(input, path).map_err(SourceError::OpenFace)?;
        let map = MuscleMap::new(reader.columns(), muscles);
        let name = path.display().to_string();
        let notice = (!map.unknown.is_empty()).then(|| {
            format!(
                "{name}: the rig has no muscle {} (their columns are ignored)",
                map.unknown.join(", ")
            )
        });
        Ok(ActsSource {
            reader,
            map,
            muscle_count: muscles.len(),
            clock: RowClock::new(frame_rate),
            name,
            notice,
        })
    }

    fn next_event(&mut self) -> Result<Poll, SourceError> {
        if let Some(notice) = self.notice.take() {
            return Ok(Poll::Event(Event::Notice(notice)));
        }
        let read: Result<_, OpenFaceError> = self.reader.next_row();
        let Some(outcome) = read? else {
            return Ok(Poll::End);
        };
        let row = match outcome {
            Ok(row) => row,
            Err(e) => {
                let column = e.column.map(|c| format!(":{c}")).unwrap_or_default();
                return Ok(Poll::Event(Event::Malformed {
                    message: format!("{}:{}{column}: {}", self.name, e.line, e.message),
                }));
            }
        };
        let time = match self.clock.time(row.timestamp, row.frame) {
            Ok(time) => time,
            Err(why) => {
                return Ok(Poll::Event(Event::Malformed {
                    message: format!("{}:{}: {why}", self.name, row.line),
                }))
            }
        };
        Ok(Poll::Event(Event::Frame(Frame {
            time,
            line: Some(row.line),
            aus: Vec::new(),
            activations: self.map.activations(&row, self.muscle_count),
        })))
    }
}

impl FrameSource for ActsSource {
    fn poll(&mut self, _wait: Duration) -> Result<Poll, SourceError> {
        self.next_event().map(printable_poll)
    }

    fn is_live(&self) -> bool {
        false
    }
}
