//! Frame sources for files: an OpenFace CSV file and a timeline, and the row handling every
//! AU source shares ([`AuFrames`], [`RowClock`]); live streams on stdin or UDP are
//! [`super::live`]'s.
//!
//! Every source hands out [`Event`]s (defined in [`super::event`]) through
//! [`FrameSource::poll`]: a frame ready to show
//! (already mapped to activations), a row skipped (untracked or malformed, with its line), or a
//! notice to print once (AUs the table lacks, values clamped). Files and timelines are always
//! ready; live sources are fed by a reader thread and wait up to the time given.

use std::collections::BTreeSet;
use std::path::Path;
use std::time::Duration;

use crate::facs::combo::parse_combo;
use crate::facs::{AuKey, AuTable};
use crate::io::openface::{OpenFaceColumns, OpenFaceReader, RowOutcome};
use crate::io::timeline::{Timeline, TimelineError};
use crate::model::{Activations, Rig};

use super::event::{Event, Frame, FrameSource, Input, Poll, SourceError};
use super::map::{clamp_to_ranges, AuIntensity, AuMapper, IntensityScale};
use super::rules::{printable_poll, TimeBase, TimeRule};

/// Turns AU intensities into frames: clamps with one warning, reports AUs the table lacks
/// once, maps through the table.
#[derive(Debug)]
pub struct AuFrames {
    mapper: AuMapper,
    scale: IntensityScale,
    source: String,
    warned_clamp: bool,
    reported: BTreeSet<AuKey>,
    pending: Vec<String>,
}

impl AuFrames {
    /// A builder for one input named `source` in notices.
    pub fn new(mapper: AuMapper, scale: IntensityScale, source: &str) -> AuFrames {
        let pending: Vec<String> = mapper.unknown_notice().into_iter().collect();
        AuFrames {
            mapper,
            scale,
            source: source.to_string(),
            warned_clamp: false,
            reported: BTreeSet::new(),
            pending,
        }
    }

    /// Reports the AUs of a stream that the table lacks (once per AU).
    pub fn report_missing(&mut self, keys: impl IntoIterator<Item = AuKey>) {
        let missing: Vec<AuKey> = keys
            .into_iter()
            .filter(|k| !self.mapper.knows(*k) && self.reported.insert(*k))
            .collect();
        if !missing.is_empty() {
            let list: Vec<String> = missing.iter().map(|k| format!("AU{k}")).collect();
            self.pending.push(format!(
                "{}: the AU table has no {} (skipped)",
                self.source,
                list.join(", ")
            ));
        }
    }

    /// The scale of the intensities.
    pub fn scale(&self) -> IntensityScale {
        self.scale
    }

    /// Sets the scale of the intensities (a stream tells its format by its first line).
    pub fn set_scale(&mut self, scale: IntensityScale) {
        self.scale = scale;
    }

    /// Queues a notice to hand out before the next frame.
    pub fn push_notice(&mut self, notice: String) {
        self.pending.push(notice);
    }

    /// A notice waiting to be handed out.
    pub fn take_notice(&mut self) -> Option<String> {
        if self.pending.is_empty() {
            None
        } else {
            Some(self.pending.remove(0))
        }
    }

    /// A frame from raw intensities.
    pub fn frame(
        &mut self,
        time: f64,
        line: Option<usize>,
        raw: impl IntoIterator<Item = (AuKey, f32)>,
    ) -> Frame {
        let mut aus = Vec::new();
        let mut clamped_any = None;
        for (key, value) in raw {
            let (clamped, was_out) = self.scale.clamp(value);
            if was_out && clamped_any.is_none() {
                clamped_any = Some((key, value));
            }
            aus.push(AuIntensity {
                key,
                value: clamped,
                factor: clamped / self.scale.max(),
            });
        }
        if let (Some((key, value)), false) = (clamped_any, self.warned_clamp) {
            self.warned_clamp = true;
            let at = line.map(|l| format!(":{l}")).unwrap_or_default();
            self.pending.push(format!(
                "{}{at}: AU{key} intensity {value} is outside 0 to {}; values outside the scale are clamped (warned once)",
                self.source,
                self.scale.max()
            ));
        }
        let mut activations = Activations::default();
        self.mapper
            .map(aus.iter().map(|a| (a.key, a.factor)), &mut activations);
        Frame {
            time,
            line,
            aus,
            activations,
        }
    }
}

/// Times rows by timestamp, else by frame number, else by order, at a frame rate; the
/// times played keep the stream rules ([`TimeRule`]).
#[derive(Debug, Clone)]
pub(crate) struct RowClock {
    frame_rate: f64,
    first_frame: Option<f64>,
    ordinal: usize,
    rule: TimeRule,
}

impl RowClock {
    pub(crate) fn new(frame_rate: f64) -> RowClock {
        RowClock {
            frame_rate,
            first_frame: None,
            ordinal: 0,
            rule: TimeRule::new(TimeBase::Absolute),
        }
    }

    /// The row's time, before the rules.
    fn raw(&mut self, timestamp: Option<f64>, frame: Option<f64>) -> f64 {
        let ordinal = self.ordinal;
        self.ordinal += 1;
        if let Some(t) = timestamp {
            return t;
        }
        if let Some(f) = frame {
            let first = *self.first_frame.get_or_insert(f);
            return (f - first) / self.frame_rate;
        }
        ordinal as f64 / self.frame_rate
    }

    /// The time to play a frame given at `raw` seconds, or why it is refused.
    pub(crate) fn accept(&mut self, raw: f64) -> Result<f64, String> {
        self.rule.accept(raw)
    }

    /// The time to play a row at, or why it is refused.
    pub(crate) fn time(
        &mut self,
        timestamp: Option<f64>,
        frame: Option<f64>,
    ) -> Result<f64, String> {
        let raw = self.raw(timestamp, frame);
        self.rule.accept(raw)
    }
}

pub(crate) fn row_event(
    builder: &mut AuFrames,
    clock: &mut RowClock,
    columns: &OpenFaceColumns,
    outcome: RowOutcome,
    source: &str,
) -> Event {
    match outcome {
        RowOutcome::Malformed(e) => {
            let column = e.column.map(|c| format!(":{c}")).unwrap_or_default();
            Event::Malformed {
                message: format!("{source}:{}{column}: {}", e.line, e.message),
            }
        }
        RowOutcome::Row(row) if !row.success => {
            clock.raw(row.timestamp, row.frame);
            Event::Untracked { line: row.line }
        }
        RowOutcome::Row(row) => {
            let time = match clock.time(row.timestamp, row.frame) {
                Ok(time) => time,
                Err(why) => {
                    return Event::Malformed {
                        message: format!("{source}:{}: {why}", row.line),
                    }
                }
            };
            let raw = columns
                .aus
                .iter()
                .zip(&row.intensities)
                .map(|(c, &v)| (AuKey::new(c.number), v));
            Event::Frame(builder.frame(time, Some(row.line), raw))
        }
    }
}

/// An OpenFace CSV file.
pub struct OpenFaceSource {
    reader: OpenFaceReader<Input>,
    builder: AuFrames,
    clock: RowClock,
    name: String,
    stashed: Option<Event>,
    /// The end's count of other faces' rows has been given.
    counted: bool,
}

impl OpenFaceSource {
    /// Reads the header of `input`, the file at `path` (see [`super::open::open_file`]).
    pub fn new(
        input: Input,
        path: &Path,
        mapper: AuMapper,
        scale: IntensityScale,
        frame_rate: f64,
    ) -> Result<OpenFaceSource, SourceError> {
        let reader = OpenFaceReader::new(input, path)?;
        let name = path.display().to_string();
        let mut builder = AuFrames::new(mapper, scale, &name);
        builder.report_missing(reader.columns().aus.iter().map(|c| AuKey::new(c.number)));
        Ok(OpenFaceSource {
            reader,
            builder,
            clock: RowClock::new(frame_rate),
            name,
            stashed: None,
            counted: false,
        })
    }
}

impl FrameSource for OpenFaceSource {
    fn poll(&mut self, _wait: Duration) -> Result<Poll, SourceError> {
        self.next_event().map(printable_poll)
    }

    fn is_live(&self) -> bool {
        false
    }
}

impl OpenFaceSource {
    /// Follows face `id` of a recording with several (`None`: the first tracked face).
    pub fn follow_face(mut self, id: Option<u32>) -> OpenFaceSource {
        self.reader = self.reader.follow_face(id);
        self
    }

    fn next_event(&mut self) -> Result<Poll, SourceError> {
        if let Some(notice) = self.builder.take_notice() {
            return Ok(Poll::Event(Event::Notice(notice)));
        }
        if let Some(notice) = self.reader.take_face_notice() {
            return Ok(Poll::Event(Event::Notice(notice)));
        }
        if let Some(event) = self.stashed.take() {
            return Ok(Poll::Event(event));
        }
        let Some(outcome) = self.reader.next_row()? else {
            // At the end, once: how many rows of other faces were passed over.
            if let (false, Some(summary)) = (self.counted, self.reader.faces().summary()) {
                self.counted = true;
                return Ok(Poll::Event(Event::Notice(summary)));
            }
            return Ok(Poll::End);
        };
        let columns = self.reader.columns();
        let event = row_event(
            &mut self.builder,
            &mut self.clock,
            columns,
            outcome,
            &self.name,
        );
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

/// A timeline sampled at its frame rate, its keyframes resolved through the table.
pub struct TimelineSource {
    timeline: Timeline,
    poses: Vec<Activations>,
    next: usize,
    count: usize,
}

impl TimelineSource {
    /// Resolves every keyframe to activations: its AU combination (or the table's expression
    /// of that name) evaluated through the table, plus explicit muscles and jaw, clamped.
    pub fn new(
        timeline: Timeline,
        path: &Path,
        table: &AuTable,
        rig: &Rig,
    ) -> Result<TimelineSource, SourceError> {
        let mut poses = Vec::with_capacity(timeline.keyframes.len());
        for (i, key) in timeline.keyframes.iter().enumerate() {
            let fail = |message: String| TimelineError {
                path: path.to_path_buf(),
                position: None,
                message: format!("keyframe {} (time {}): {message}", i + 1, key.time),
            };
            let mut pose = match &key.aus {
                Some(text) => keyframe_aus(text, table, rig).map_err(fail)?,
                None => Activations::zero(rig),
            };
            for (name, value) in &key.muscles {
                let index = rig
                    .muscle_index(name)
                    .ok_or_else(|| fail(format!("the rig has no muscle named `{name}`")))?;
                pose.muscles[index] += value;
            }
            pose.jaw += key.jaw.unwrap_or(0.0);
            clamp_to_ranges(&mut pose);
            poses.push(pose);
        }
        // The rules bound every source's time; a timeline's is known before it plays.
        let end = timeline.keyframes.last().map_or(0.0, |k| k.time);
        TimeRule::new(TimeBase::Absolute)
            .accept(end)
            .map_err(|why| TimelineError {
                path: path.to_path_buf(),
                position: None,
                message: format!("the last keyframe: {why}"),
            })?;
        let count = timeline.frame_count();
        Ok(TimelineSource {
            timeline,
            poses,
            next: 0,
            count,
        })
    }

    /// The pose at time `t`, interpolated between the keyframes around it.
    pub fn sample(&self, t: f64) -> Activations {
        let (i, j, w) = self.timeline.bracket(t);
        let (a, b) = (&self.poses[i], &self.poses[j]);
        let w = w as f32;
        Activations {
            muscles: a
                .muscles
                .iter()
                .zip(&b.muscles)
                .map(|(x, y)| x + (y - x) * w)
                .collect(),
            jaw: a.jaw + (b.jaw - a.jaw) * w,
        }
    }

    /// The number of frames the timeline plays.
    pub fn frame_count(&self) -> usize {
        self.count
    }
}

impl FrameSource for TimelineSource {
    fn poll(&mut self, _wait: Duration) -> Result<Poll, SourceError> {
        if self.next >= self.count {
            return Ok(Poll::End);
        }
        let time = self.next as f64 / self.timeline.frame_rate;
        self.next += 1;
        Ok(printable_poll(Poll::Event(Event::Frame(Frame {
            time,
            line: None,
            aus: Vec::new(),
            activations: self.sample(time),
        }))))
    }

    fn is_live(&self) -> bool {
        false
    }
}

/// A keyframe's `aus`: an expression name of the table, or a combination string.
fn keyframe_aus(text: &str, table: &AuTable, rig: &Rig) -> Result<Activations, String> {
    let combo = table
        .expressions
        .get(text.trim())
        .map_or(text, String::as_str);
    let combo = parse_combo(combo).map_err(|e| format!("`{combo}`: {e}"))?;
    table.evaluate(&combo, rig).map_err(|e| e.to_string())
}
