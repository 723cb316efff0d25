//! Live streams: lines on stdin (an OpenFace CSV header then rows, a Live Link Face take, or
//! one JSON object per line) and JSON datagrams on a loopback UDP port, read on a thread and
//! handed out under the stream rules ([`super::rules`]).

use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, SyncSender};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::thread;
use std::time::{Duration, Instant};

use crate::facs::AuKey;
use crate::io::arkit::{self, ArkitMap};
use crate::io::faces::Faces;
use crate::io::lines::LineReader;
use crate::io::livelink::{is_header, LiveLinkColumns};
use crate::io::openface::{OpenFaceColumns, RowOutcome, MAX_LINE_BYTES};

use super::event::{Event, FrameSource, Poll, SourceError, DEFAULT_FRAME_RATE};
use super::json::parse_flat_object;
use super::livelink::{LiveLinkRows, LIVELINK_FRAME_RATE};
use super::map::{AuMapper, IntensityScale};
use super::rules::{printable_poll, shown, NameSet, Seen, NAMES_KEPT, NAME_CHARS};
use super::source::{row_event, AuFrames, RowClock};

/// The largest UDP datagram read.
const MAX_DATAGRAM: usize = 65_536;

/// What a reader thread sends: one line (or datagram) with its number, a line too long to
/// read (its number and why), or a read failure.
enum Message {
    Line(usize, String),
    TooLong(usize, String),
    Failed(String),
}

/// The most lines (or datagrams) of a live stream waiting to be shown.
pub const QUEUE_LINES: usize = 1024;

/// The most bytes of lines (or datagrams) waiting to be shown: with lines of up to 1 MiB, a
/// queue bounded by count alone could hold a gigabyte.
pub const QUEUE_BYTES: usize = 8 << 20;

/// A live stream's queue: at most [`QUEUE_LINES`] messages and about [`QUEUE_BYTES`] bytes
/// (one line larger than that still passes, alone). The reader thread waits when it is full.
struct Queue {
    queued: Mutex<usize>,
    freed: Condvar,
}

impl Queue {
    /// The sending and receiving ends of a new queue.
    fn ends() -> (QueueSender, QueueReceiver) {
        let (sender, receiver) = mpsc::sync_channel(QUEUE_LINES);
        let queue = Arc::new(Queue {
            queued: Mutex::new(0),
            freed: Condvar::new(),
        });
        (
            QueueSender {
                sender,
                queue: Arc::clone(&queue),
            },
            QueueReceiver { receiver, queue },
        )
    }
}

fn size(message: &Message) -> usize {
    match message {
        Message::Line(_, text) => text.len(),
        Message::TooLong(..) | Message::Failed(_) => 0,
    }
}

/// The reader thread's end of a [`Queue`].
struct QueueSender {
    sender: SyncSender<Message>,
    queue: Arc<Queue>,
}

impl QueueSender {
    /// Sends once the message fits; `false` when the source is gone.
    fn send(&self, message: Message) -> bool {
        let bytes = size(&message);
        let mut queued = self
            .queue
            .queued
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        while *queued > 0 && *queued + bytes > QUEUE_BYTES {
            // Waking now and then notices a source that went away while the queue was full.
            let (guard, _) = self
                .queue
                .freed
                .wait_timeout(queued, Duration::from_millis(200))
                .unwrap_or_else(PoisonError::into_inner);
            queued = guard;
            if Arc::strong_count(&self.queue) == 1 {
                return false;
            }
        }
        *queued += bytes;
        drop(queued);
        self.sender.send(message).is_ok()
    }
}

/// The source's end of a [`Queue`].
struct QueueReceiver {
    receiver: Receiver<Message>,
    queue: Arc<Queue>,
}

impl QueueReceiver {
    fn recv_timeout(&self, wait: Duration) -> Result<Message, RecvTimeoutError> {
        let message = self.receiver.recv_timeout(wait)?;
        let mut queued = self
            .queue
            .queued
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        *queued = queued.saturating_sub(size(&message));
        self.queue.freed.notify_all();
        Ok(message)
    }
}

/// How a live stream is written, decided by its first line.
enum LiveFormat {
    Undecided,
    Csv(OpenFaceColumns),
    LiveLink(LiveLinkColumns, LiveLinkRows),
    Json,
}

/// A live stream: lines on stdin (CSV with a header line, or one JSON object per line) or
/// JSON datagrams on a loopback UDP port.
pub struct LiveSource {
    receiver: QueueReceiver,
    format: LiveFormat,
    builder: AuFrames,
    clock: RowClock,
    name: String,
    opened: Instant,
    /// Names of fields and columns that do not play, kept bounded.
    ignored: NameSet,
    /// The frame rate given (`--fps`), else each format's own.
    fps: Option<f64>,
    /// The count of names not kept has been said.
    counted: bool,
    csv_allowed: bool,
    stashed: Option<Event>,
    arkit: ArkitMap,
    /// The face followed in OpenFace rows of several faces.
    faces: Faces,
}

impl LiveSource {
    /// Follows face `id` of OpenFace rows of several faces (`None`: the first tracked face).
    pub fn follow_face(mut self, id: Option<u32>) -> LiveSource {
        self.faces = Faces::new(id);
        self
    }

    /// Reads stdin on a thread; the first non-blank line says CSV (an OpenFace or Live Link
    /// Face header) or JSON (`{`). `fps` times rows without timestamps, or a Live Link take's
    /// frames (each format has its own default).
    ///
    /// Memory stays bounded whatever the producer does: a line longer than
    /// [`MAX_LINE_BYTES`] is read past and reported, and at most [`QUEUE_LINES`] lines ([`QUEUE_BYTES`]) wait
    /// to be shown; past that the reader stops reading, so a faster producer waits on its
    /// pipe (back-pressure) rather than growing a backlog.
    pub fn stdin(mapper: AuMapper, scale: IntensityScale, fps: Option<f64>) -> LiveSource {
        let (sender, receiver) = Queue::ends();
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
                if !sender.send(message) || failed {
                    break;
                }
            }
        });
        LiveSource::new(receiver, mapper, scale, fps, "stdin", true)
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
        let (sender, receiver) = Queue::ends();
        thread::spawn(move || {
            let mut buffer = vec![0u8; MAX_DATAGRAM];
            let mut number = 0;
            loop {
                match socket.recv_from(&mut buffer) {
                    Ok((size, _)) => {
                        number += 1;
                        let text = String::from_utf8_lossy(&buffer[..size]).into_owned();
                        if !sender.send(Message::Line(number, text)) {
                            break;
                        }
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => {
                        sender.send(Message::Failed(format!("udp receive failed: {e}")));
                        break;
                    }
                }
            }
        });
        let name = format!("udp {bound}");
        let source = LiveSource::new(receiver, mapper, scale, None, &name, false);
        Ok((source, bound))
    }

    fn new(
        receiver: QueueReceiver,
        mapper: AuMapper,
        scale: IntensityScale,
        fps: Option<f64>,
        name: &str,
        csv_allowed: bool,
    ) -> LiveSource {
        LiveSource {
            receiver,
            format: LiveFormat::Undecided,
            builder: AuFrames::new(mapper, scale, name),
            clock: RowClock::new(fps.unwrap_or(DEFAULT_FRAME_RATE)),
            name: name.to_string(),
            opened: Instant::now(),
            ignored: NameSet::default(),
            fps,
            counted: false,
            csv_allowed,
            stashed: None,
            arkit: ArkitMap::builtin(),
            faces: Faces::new(None),
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
                return self.header(number, trimmed);
            }
        }
        match &mut self.format {
            LiveFormat::Csv(columns) => {
                let columns = columns.clone();
                let outcome = match columns.parse_row(trimmed, number) {
                    Ok(row) if !self.faces.admits(row.face, row.success) => {
                        return self.faces.take_notice().map(Event::Notice);
                    }
                    Ok(row) => RowOutcome::Row(row),
                    Err(e) => RowOutcome::Malformed(e),
                };
                Some(self.csv_row(&columns, outcome))
            }
            LiveFormat::LiveLink(columns, rows) => {
                let fps = self.fps.unwrap_or(LIVELINK_FRAME_RATE);
                let row = columns.parse_row(trimmed, number, fps);
                Some(rows.event(&mut self.builder, row, &self.name))
            }
            _ => Some(self.json_line(number, trimmed)),
        }
    }

    /// Reads a CSV header: Live Link Face's (`Timecode,BlendShapeCount,...`) or OpenFace's.
    fn header(&mut self, number: usize, text: &str) -> Option<Event> {
        let refused = |e: String| Event::Malformed {
            message: format!("{}:{number}: {e}", self.name),
        };
        if is_header(text) {
            let columns = match LiveLinkColumns::from_header(text) {
                Ok(columns) => columns,
                Err(e) => return Some(refused(e)),
            };
            let rows = LiveLinkRows::new(
                &columns,
                &self.arkit,
                &mut self.builder,
                &mut self.ignored,
                &self.name,
            );
            // ARKit weights run 0-1, as they do in a Live Link file.
            self.builder.set_scale(IntensityScale::ZeroToOne);
            self.format = LiveFormat::LiveLink(columns, rows);
            return None;
        }
        match OpenFaceColumns::from_header(text) {
            Ok(columns) => {
                self.builder
                    .report_missing(columns.aus.iter().map(|c| AuKey::new(c.number)));
                self.format = LiveFormat::Csv(columns);
                None
            }
            Err(e) => Some(refused(e.to_string())),
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
        let source = self.name.clone();
        let malformed = |message: String| Event::Malformed {
            message: format!("{source}:{number}: {message}"),
        };
        let pairs = match parse_flat_object(text) {
            Ok(pairs) => pairs,
            Err(e) => {
                return Event::Malformed {
                    message: format!("{source}:{number}:{}: {}", e.column, e.message),
                }
            }
        };
        let mut time: Option<(String, f64)> = None;
        let mut given = Given::default();
        for (name, value) in pairs {
            if name.eq_ignore_ascii_case("timestamp") {
                if let Some((first, _)) = &time {
                    return malformed(format!(
                        "the time is given twice, as `{}` and `{}`",
                        shown(first, NAME_CHARS),
                        shown(&name, NAME_CHARS)
                    ));
                }
                time = Some((name, value));
            } else if let Some(key) = json_au_key(&name) {
                if let Err(why) = given.add(key, value as f32, name, false) {
                    return malformed(why);
                }
            } else if let Some(shape) = arkit::canonical(&name) {
                // ARKit weights are 0-1 whatever the stream's AU scale.
                match self.arkit.au(shape) {
                    Some(key) => {
                        let value = value as f32 * self.builder.scale().max();
                        if let Err(why) = given.add(key, value, name, true) {
                            return malformed(why);
                        }
                    }
                    None => self.ignore(&name, "ARKit shape", "has no AU"),
                }
            } else if !name.eq_ignore_ascii_case("frame") {
                self.ignore(&name, "field", "is not an AU");
            }
        }
        let raw = given.0.iter().map(|g| (g.key, g.value));
        self.builder.report_missing(raw.clone().map(|(k, _)| k));
        let time = time.map_or_else(|| self.opened.elapsed().as_secs_f64(), |(_, t)| t);
        match self.clock.accept(time) {
            Ok(time) => Event::Frame(self.builder.frame(time, Some(number), raw)),
            Err(why) => malformed(why),
        }
    }

    /// Says once that a field is ignored, while few names have been; the rest are counted.
    fn ignore(&mut self, name: &str, what: &str, why: &str) {
        match self.ignored.see(name) {
            Seen::New(name) => self
                .builder
                .push_notice(format!("{}: {what} `{name}` {why} (ignored)", self.name)),
            Seen::Full => self.builder.push_notice(format!(
                "{}: more than {NAMES_KEPT} names ignored; the rest are counted, not named",
                self.name
            )),
            Seen::Known | Seen::Counted => {}
        }
    }
}

/// One AU of a JSON frame and the field that gave it.
struct GivenAu {
    key: AuKey,
    value: f32,
    name: String,
    /// Given by an ARKit shape (several may name one AU) rather than an AU name.
    shape: bool,
}

/// The AUs of a JSON frame. The verdict does not depend on the order of the keys: an AU
/// given by two AU names (`AU12`, `AU12_r`), or by an AU name and an ARKit shape, refuses
/// the frame (adding them, or picking one, would guess what the sender meant); several ARKit
/// shapes naming one AU give it the stronger weight.
#[derive(Default)]
struct Given(Vec<GivenAu>);

impl Given {
    fn add(&mut self, key: AuKey, value: f32, name: String, shape: bool) -> Result<(), String> {
        let Some(seen) = self.0.iter_mut().find(|g| g.key == key) else {
            self.0.push(GivenAu {
                key,
                value,
                name,
                shape,
            });
            return Ok(());
        };
        if seen.shape && shape {
            seen.value = seen.value.max(value);
            return Ok(());
        }
        // Named in one order whichever came first: AU names before shapes, then by name.
        let mut names = [(seen.shape, seen.name.as_str()), (shape, name.as_str())];
        names.sort();
        Err(format!(
            "AU{key} is given twice, as `{}` and `{}`",
            shown(names[0].1, NAME_CHARS),
            shown(names[1].1, NAME_CHARS)
        ))
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

/// Resolves an address and refuses anything but loopback (also `capture --live --udp`).
pub fn loopback_address(text: &str) -> Result<SocketAddr, SourceError> {
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
        self.next_event(wait).map(printable_poll)
    }

    fn is_live(&self) -> bool {
        true
    }
}

impl LiveSource {
    /// The end of the stream, after one notice counting the names not kept, if any.
    fn end(&mut self) -> Poll {
        let more = self.ignored.not_kept();
        if more == 0 || self.counted {
            return Poll::End;
        }
        self.counted = true;
        Poll::Event(Event::Notice(format!(
            "{}: {more} more ignored names were not named (only the first {NAMES_KEPT} are)",
            self.name
        )))
    }

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
                Err(RecvTimeoutError::Disconnected) => return Ok(self.end()),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_queue_holds_a_bounded_number_of_bytes() {
        let (sender, receiver) = Queue::ends();
        let line = "x".repeat(QUEUE_BYTES / 2 + 1);
        let writer = thread::spawn(move || {
            for number in 1..=3 {
                assert!(sender.send(Message::Line(number, line.clone())));
            }
        });
        thread::sleep(Duration::from_millis(300));
        // The second line would pass the budget: it waits until the first is taken.
        assert_eq!(*receiver.queue.queued.lock().unwrap(), QUEUE_BYTES / 2 + 1);
        for number in 1..=3 {
            match receiver.recv_timeout(Duration::from_secs(10)) {
                Ok(Message::Line(n, _)) => assert_eq!(n, number),
                _ => panic!("line {number} did not come"),
            }
        }
        writer.join().unwrap();
    }
}
