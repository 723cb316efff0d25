//! Frame sources: an OpenFace CSV file, a timeline, and live streams on stdin or UDP.
//!
//! Every source hands out [`Event`]s through [`FrameSource::poll`]: a frame ready to show
//! (already mapped to activations), a row skipped (untracked or malformed, with its line), or a
//! notice to print once (AUs the table lacks, values clamped). Files and timelines are always
//! ready; live sources are fed by a reader thread and wait up to the time given.

use std::collections::BTreeSet;
use std::fs::File;
use std::io::BufReader;
use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};
use std::path::Path;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::thread;
use std::time::{Duration, Instant};

use thiserror::Error;

use crate::facs::combo::parse_combo;
use crate::facs::{AuKey, AuTable};
use crate::io::arkit::{self, ArkitMap};
use crate::io::lines::LineReader;
use crate::io::openface::{
    OpenFaceColumns, OpenFaceError, OpenFaceReader, RowOutcome, MAX_LINE_BYTES, MAX_TIMESTAMP,
};
use crate::io::printable::printable;
use crate::io::timeline::{Timeline, TimelineError};
use crate::model::{Activations, Rig};

use super::json::parse_flat_object;
use super::map::{clamp_to_ranges, AuIntensity, AuMapper, IntensityScale};

/// The frame rate assumed for rows without timestamps, unless one is given.
pub const DEFAULT_FRAME_RATE: f64 = 30.0;

/// The largest UDP datagram read.
const MAX_DATAGRAM: usize = 65_536;

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

impl Poll {
    /// The poll with the text of its messages made safe to print: they quote rows, fields
    /// and keys of the input, which may hold terminal escapes (see [`printable`]).
    fn printable(self) -> Poll {
        let safe = |text: String| printable(&text).into_owned();
        match self {
            Poll::Event(Event::Malformed { message }) => Poll::Event(Event::Malformed {
                message: safe(message),
            }),
            Poll::Event(Event::Notice(text)) => Poll::Event(Event::Notice(safe(text))),
            other => other,
        }
    }
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
        let mut pending = Vec::new();
        if !mapper.unknown_muscles().is_empty() {
            let names: Vec<&str> = mapper
                .unknown_muscles()
                .iter()
                .map(String::as_str)
                .collect();
            pending.push(format!(
                "the AU table names muscles the rig lacks (ignored): {}",
                names.join(", ")
            ));
        }
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

/// Times rows by timestamp, else by frame number, else by order, at a frame rate.
#[derive(Debug, Clone)]
struct RowClock {
    frame_rate: f64,
    first_frame: Option<f64>,
    ordinal: usize,
}

impl RowClock {
    fn new(frame_rate: f64) -> RowClock {
        RowClock {
            frame_rate,
            first_frame: None,
            ordinal: 0,
        }
    }

    fn time(&mut self, timestamp: Option<f64>, frame: Option<f64>) -> f64 {
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
}

fn row_event(
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
            clock.time(row.timestamp, row.frame);
            Event::Untracked { line: row.line }
        }
        RowOutcome::Row(row) => {
            let time = clock.time(row.timestamp, row.frame);
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
    reader: OpenFaceReader<BufReader<File>>,
    builder: AuFrames,
    clock: RowClock,
    name: String,
    stashed: Option<Event>,
}

impl OpenFaceSource {
    /// Opens a file and reads its header.
    pub fn open(
        path: &Path,
        mapper: AuMapper,
        scale: IntensityScale,
        frame_rate: f64,
    ) -> Result<OpenFaceSource, SourceError> {
        refuse_special(path)?;
        let file = File::open(path).map_err(|source| SourceError::Io {
            what: format!("cannot open {}", path.display()),
            source,
        })?;
        let reader = OpenFaceReader::new(BufReader::new(file), path)?;
        let name = path.display().to_string();
        let mut builder = AuFrames::new(mapper, scale, &name);
        builder.report_missing(reader.columns().aus.iter().map(|c| AuKey::new(c.number)));
        Ok(OpenFaceSource {
            reader,
            builder,
            clock: RowClock::new(frame_rate),
            name,
            stashed: None,
        })
    }
}

impl FrameSource for OpenFaceSource {
    fn poll(&mut self, _wait: Duration) -> Result<Poll, SourceError> {
        self.next_event().map(Poll::printable)
    }

    fn is_live(&self) -> bool {
        false
    }
}

impl OpenFaceSource {
    fn next_event(&mut self) -> Result<Poll, SourceError> {
        if let Some(notice) = self.builder.take_notice() {
            return Ok(Poll::Event(Event::Notice(notice)));
        }
        if let Some(event) = self.stashed.take() {
            return Ok(Poll::Event(event));
        }
        let Some(outcome) = self.reader.next_row()? else {
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

/// Refuses a folder, a device or a socket as an OpenFace CSV, saying what it is. A named pipe
/// is fine: the file is read once, as a stream (`grimace play <(tracker ...)`).
fn refuse_special(path: &Path) -> Result<(), SourceError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if std::fs::metadata(path).is_ok_and(|m| m.file_type().is_fifo()) {
            return Ok(());
        }
    }
    match crate::io::error::not_a_file(path) {
        // A missing or unreadable file is reported by the open itself.
        Some(reason) if std::fs::metadata(path).is_ok() => {
            Err(SourceError::OpenFace(OpenFaceError::new(path, reason)))
        }
        _ => Ok(()),
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
        Ok(Poll::Event(Event::Frame(Frame {
            time,
            line: None,
            aus: Vec::new(),
            activations: self.sample(time),
        })))
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

/// What a reader thread sends: one line (or datagram) with its number, a line too long to
/// read (its number and why), or a read failure.
enum Message {
    Line(usize, String),
    TooLong(usize, String),
    Failed(String),
}

/// The most lines (or datagrams) of a live stream waiting to be shown.
pub const QUEUE_LINES: usize = 1024;

/// How a live stream is written, decided by its first line.
enum LiveFormat {
    Undecided,
    Csv(OpenFaceColumns),
    Json,
}

/// A live stream: lines on stdin (CSV with a header line, or one JSON object per line) or
/// JSON datagrams on a loopback UDP port.
pub struct LiveSource {
    receiver: Receiver<Message>,
    format: LiveFormat,
    builder: AuFrames,
    clock: RowClock,
    name: String,
    opened: Instant,
    ignored: BTreeSet<String>,
    csv_allowed: bool,
    stashed: Option<Event>,
    arkit: ArkitMap,
}

impl LiveSource {
    /// Reads stdin on a thread; the first non-blank line says CSV (a header) or JSON (`{`).
    ///
    /// Memory stays bounded whatever the producer does: a line longer than
    /// [`MAX_LINE_BYTES`] is read past and reported, and at most [`QUEUE_LINES`] lines wait
    /// to be shown; past that the reader stops reading, so a faster producer waits on its
    /// pipe (back-pressure) rather than growing a backlog.
    pub fn stdin(mapper: AuMapper, scale: IntensityScale, frame_rate: f64) -> LiveSource {
        let (sender, receiver) = mpsc::sync_channel(QUEUE_LINES);
        thread::spawn(move || {
            let mut lines = LineReader::new(std::io::stdin().lock(), MAX_LINE_BYTES);
            loop {
                let message = match lines.next_line() {
                    Ok(None) => break,
                    Ok(Some(line)) => match line.too_long(MAX_LINE_BYTES) {
                        Some(why) => Message::TooLong(line.number, why),
                        None => Message::Line(line.number, line.text),
                    },
                    Err(e) => Message::Failed(format!("cannot read stdin: {e}")),
                };
                let failed = matches!(message, Message::Failed(_));
                if sender.send(message).is_err() || failed {
                    break;
                }
            }
        });
        LiveSource::new(receiver, mapper, scale, frame_rate, "stdin", true)
    }

    /// Listens on a loopback UDP address (port 0 picks a free port); returns the source and
    /// the address bound. Each datagram holds one JSON object (or several, one per line).
    pub fn udp(
        address: &str,
        mapper: AuMapper,
        scale: IntensityScale,
    ) -> Result<(LiveSource, SocketAddr), SourceError> {
        let address = loopback_address(address)?;
        let socket = UdpSocket::bind(address).map_err(|source| SourceError::Io {
            what: format!("cannot listen on udp {address}"),
            source,
        })?;
        let bound = socket.local_addr().map_err(|source| SourceError::Io {
            what: "cannot read the bound address".into(),
            source,
        })?;
        // Bounded like stdin: when the queue is full the reader waits and the system drops
        // datagrams that overflow the socket's buffer, as UDP does.
        let (sender, receiver) = mpsc::sync_channel(QUEUE_LINES);
        thread::spawn(move || {
            let mut buffer = vec![0u8; MAX_DATAGRAM];
            let mut number = 0;
            loop {
                match socket.recv_from(&mut buffer) {
                    Ok((size, _)) => {
                        number += 1;
                        let text = String::from_utf8_lossy(&buffer[..size]).into_owned();
                        if sender.send(Message::Line(number, text)).is_err() {
                            break;
                        }
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => {
                        let _ = sender.send(Message::Failed(format!("udp receive failed: {e}")));
                        break;
                    }
                }
            }
        });
        let name = format!("udp {bound}");
        let source = LiveSource::new(receiver, mapper, scale, DEFAULT_FRAME_RATE, &name, false);
        Ok((source, bound))
    }

    fn new(
        receiver: Receiver<Message>,
        mapper: AuMapper,
        scale: IntensityScale,
        frame_rate: f64,
        name: &str,
        csv_allowed: bool,
    ) -> LiveSource {
        LiveSource {
            receiver,
            format: LiveFormat::Undecided,
            builder: AuFrames::new(mapper, scale, name),
            clock: RowClock::new(frame_rate),
            name: name.to_string(),
            opened: Instant::now(),
            ignored: BTreeSet::new(),
            csv_allowed,
            stashed: None,
            arkit: ArkitMap::builtin(),
        }
    }

    /// Handles one line; `None` when it produced nothing (blank, or a CSV header).
    fn line(&mut self, number: usize, text: &str) -> Option<Event> {
        let trimmed = text.trim().trim_start_matches('\u{feff}');
        if trimmed.is_empty() {
            return None;
        }
        if let LiveFormat::Undecided = self.format {
            if trimmed.starts_with('{') || !self.csv_allowed {
                self.format = LiveFormat::Json;
            } else {
                return match OpenFaceColumns::from_header(trimmed) {
                    Ok(columns) => {
                        self.builder
                            .report_missing(columns.aus.iter().map(|c| AuKey::new(c.number)));
                        self.format = LiveFormat::Csv(columns);
                        None
                    }
                    Err(e) => Some(Event::Malformed {
                        message: format!("{}:{number}: {e}", self.name),
                    }),
                };
            }
        }
        match &self.format {
            LiveFormat::Csv(columns) => {
                let columns = columns.clone();
                let outcome = match columns.parse_row(trimmed, number) {
                    Ok(row) => RowOutcome::Row(row),
                    Err(e) => RowOutcome::Malformed(e),
                };
                Some(self.csv_row(&columns, outcome))
            }
            _ => Some(self.json_line(number, trimmed)),
        }
    }

    fn csv_row(&mut self, columns: &OpenFaceColumns, outcome: RowOutcome) -> Event {
        // Rows without a timestamp are timed by arrival.
        if let RowOutcome::Row(row) = &outcome {
            if row.timestamp.is_none() && row.frame.is_none() {
                let mut row = row.clone();
                row.timestamp = Some(self.opened.elapsed().as_secs_f64());
                return row_event(
                    &mut self.builder,
                    &mut self.clock,
                    columns,
                    RowOutcome::Row(row),
                    &self.name,
                );
            }
        }
        row_event(
            &mut self.builder,
            &mut self.clock,
            columns,
            outcome,
            &self.name,
        )
    }

    fn json_line(&mut self, number: usize, text: &str) -> Event {
        let pairs = match parse_flat_object(text) {
            Ok(pairs) => pairs,
            Err(e) => {
                return Event::Malformed {
                    message: format!("{}:{number}:{}: {}", self.name, e.column, e.message),
                }
            }
        };
        let mut time = None;
        let mut raw = Vec::new();
        let mut au_names: Vec<String> = Vec::new();
        for (name, value) in pairs {
            if name.eq_ignore_ascii_case("timestamp") {
                if value.is_nan() || value.abs() > MAX_TIMESTAMP {
                    return Event::Malformed {
                        message: format!(
                            "{}:{number}: timestamp {value:e} is out of range (at most {MAX_TIMESTAMP} in size)",
                            self.name
                        ),
                    };
                }
                time = Some(value);
            } else if let Some(key) = json_au_key(&name) {
                // Two spellings of one AU (`AU12`, `AU12_r`) would add up: refuse the frame,
                // as for a key given twice.
                if let Some(k) = raw.iter().position(|(seen, _)| *seen == key) {
                    return Event::Malformed {
                        message: format!(
                            "{}:{number}: AU{key} is given twice, as `{}` and `{name}`",
                            self.name, au_names[k]
                        ),
                    };
                }
                raw.push((key, value as f32));
                au_names.push(name);
            } else if let Some(shape) = arkit::canonical(&name) {
                // ARKit weights are 0-1 whatever the stream's AU scale. Several shapes may
                // name one AU (both give it): the stronger one counts.
                match self.arkit.au(shape) {
                    Some(key) => {
                        let value = value as f32 * self.builder.scale.max();
                        match raw.iter_mut().find(|(seen, _)| *seen == key) {
                            Some((_, v)) => *v = v.max(value),
                            None => {
                                raw.push((key, value));
                                au_names.push(name);
                            }
                        }
                    }
                    None if self.ignored.insert(name.clone()) => self.builder.pending.push(
                        format!("{}: ARKit shape `{name}` has no AU (ignored)", self.name),
                    ),
                    None => {}
                }
            } else if self.ignored.insert(name.clone()) && !name.eq_ignore_ascii_case("frame") {
                self.builder.pending.push(format!(
                    "{}: field `{name}` is not an AU (ignored)",
                    self.name
                ));
            }
        }
        self.builder.report_missing(raw.iter().map(|(k, _)| *k));
        let time = time.unwrap_or_else(|| self.opened.elapsed().as_secs_f64());
        Event::Frame(self.builder.frame(time, Some(number), raw))
    }
}

/// `AU12`, `AU01`, `AU12_r`, `AUL12`/`AUR12` -> the AU key.
fn json_au_key(name: &str) -> Option<AuKey> {
    let rest = name
        .strip_prefix("AU")
        .or_else(|| name.strip_prefix("au"))?;
    let rest = rest
        .strip_suffix("_r")
        .or_else(|| rest.strip_suffix("_R"))
        .unwrap_or(rest);
    rest.parse().ok()
}

/// Resolves an address and refuses anything but loopback.
fn loopback_address(text: &str) -> Result<SocketAddr, SourceError> {
    let addresses: Vec<SocketAddr> = text
        .to_socket_addrs()
        .map_err(|_| SourceError::BadAddress(text.to_string()))?
        .collect();
    let first = *addresses
        .first()
        .ok_or_else(|| SourceError::BadAddress(text.to_string()))?;
    if addresses.iter().all(|a| a.ip().is_loopback()) {
        Ok(first)
    } else {
        Err(SourceError::NotLoopback(text.to_string()))
    }
}

impl FrameSource for LiveSource {
    fn poll(&mut self, wait: Duration) -> Result<Poll, SourceError> {
        self.next_event(wait).map(Poll::printable)
    }

    fn is_live(&self) -> bool {
        true
    }
}

impl LiveSource {
    fn next_event(&mut self, wait: Duration) -> Result<Poll, SourceError> {
        let deadline = Instant::now() + wait;
        loop {
            // Notices a line raised go out before the line's own event.
            if let Some(notice) = self.builder.take_notice() {
                return Ok(Poll::Event(Event::Notice(notice)));
            }
            if let Some(event) = self.stashed.take() {
                return Ok(Poll::Event(event));
            }
            let left = deadline.saturating_duration_since(Instant::now());
            let message = match self.receiver.recv_timeout(left) {
                Ok(message) => message,
                Err(RecvTimeoutError::Timeout) => return Ok(Poll::Pending),
                Err(RecvTimeoutError::Disconnected) => return Ok(Poll::End),
            };
            match message {
                Message::Line(number, text) => self.stashed = self.line(number, &text),
                Message::TooLong(number, why) => {
                    self.stashed = Some(Event::Malformed {
                        message: format!("{}:{number}: {why}", self.name),
                    })
                }
                Message::Failed(message) => {
                    return Err(SourceError::Io {
                        what: self.name.clone(),
                        source: std::io::Error::other(message),
                    })
                }
            }
        }
    }
}
