//! The player: takes frames from a source when the clock says they are due, drops the ones a
//! slow display cannot show in time, and handles pause, step, speed and looping.
//!
//! The front end calls [`Player::tick`] each time round its loop, draws the frame it gets (if
//! any), reports how late the drawing finished with [`Player::shown`], then waits for input
//! until [`Player::next_due`]. Nothing here draws or sleeps, so the timing logic is tested
//! with made-up instants.

use std::time::{Duration, Instant};

use super::clock::{FrameStats, PlayClock};
use super::event::{Event, Frame, FrameSource, Poll, SourceError, DEFAULT_FRAME_RATE};

/// Opens the source again, for `--loop`.
pub type Reopen = Box<dyn FnMut() -> Result<Box<dyn FrameSource>, SourceError>>;

/// Something for the front end to show in its message line (and print at the end).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Message {
    /// A warning from the source (missing AUs, clamped values).
    Notice(String),
    /// A malformed row, skipped.
    Malformed(String),
}

/// A malformed row under `--strict`, or a source failure.
#[derive(Debug, thiserror::Error)]
pub enum PlayError {
    /// The source failed.
    #[error(transparent)]
    Source(#[from] SourceError),
    /// A malformed row stopped the run (`--strict`).
    #[error("{0}")]
    Strict(String),
}

/// Where playback stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlayState {
    /// Frames are taken as they come due.
    Playing,
    /// Stopped until resumed or stepped.
    Paused,
    /// The source has nothing more (and `--loop` did not restart it).
    Ended,
}

/// Plays a source against a clock.
pub struct Player {
    source: Box<dyn FrameSource>,
    reopen: Option<Reopen>,
    live: bool,
    strict: bool,
    speed: f64,
    state: PlayState,
    clock: Option<PlayClock>,
    lookahead: Option<Frame>,
    limit: Option<usize>,
    /// The last frame taken: its source time and when it was due.
    last: Option<(f64, Instant)>,
    /// Source seconds between the last two frames (the pause before a loop restarts).
    gap: f64,
    /// When the first frame of a restarted loop is due.
    restart_at: Option<Instant>,
    /// Frames taken from the source (shown or dropped).
    pub played: usize,
    /// Rows skipped: untracked and malformed.
    pub skipped: usize,
    /// Timing of the frames shown.
    pub stats: FrameStats,
    messages: Vec<Message>,
}

impl Player {
    /// A player at `speed` (1 = the source's own rate). `reopen` restarts a finished file
    /// (`--loop`); `strict` makes a malformed row an error; `limit` stops after that many
    /// frames.
    pub fn new(
        source: Box<dyn FrameSource>,
        reopen: Option<Reopen>,
        speed: f64,
        strict: bool,
        limit: Option<usize>,
    ) -> Player {
        let live = source.is_live();
        Player {
            source,
            reopen,
            live,
            strict,
            speed,
            state: PlayState::Playing,
            clock: None,
            lookahead: None,
            limit,
            last: None,
            gap: 1.0 / DEFAULT_FRAME_RATE,
            restart_at: None,
            played: 0,
            skipped: 0,
            stats: FrameStats::default(),
            messages: Vec::new(),
        }
    }

    /// Messages since the last call.
    pub fn take_messages(&mut self) -> Vec<Message> {
        std::mem::take(&mut self.messages)
    }

    /// True when the source is exhausted (or the frame limit reached) and nothing is left.
    pub fn is_finished(&self) -> bool {
        (self.state == PlayState::Ended && self.lookahead.is_none()) || self.limit_reached()
    }

    fn limit_reached(&self) -> bool {
        self.limit.is_some_and(|n| self.played >= n)
    }

    /// Whether the source is live (frames shown on arrival).
    pub fn is_live(&self) -> bool {
        self.live
    }

    /// Whether playback is paused.
    pub fn is_paused(&self) -> bool {
        self.state == PlayState::Paused
    }

    /// Where playback stands.
    pub fn state(&self) -> PlayState {
        self.state
    }

    /// The playback speed.
    pub fn speed(&self) -> f64 {
        self.clock.map_or(self.speed, |c| c.speed())
    }

    /// Pauses or resumes.
    pub fn toggle_pause(&mut self, now: Instant) {
        self.state = match self.state {
            PlayState::Playing => PlayState::Paused,
            PlayState::Paused => PlayState::Playing,
            PlayState::Ended => return,
        };
        let paused = self.is_paused();
        if let Some(clock) = &mut self.clock {
            clock.set_paused(paused, now);
        }
    }

    /// Multiplies the speed by `factor` (clamped to the clock's range).
    pub fn change_speed(&mut self, factor: f64, now: Instant) {
        match &mut self.clock {
            Some(clock) => {
                clock.set_speed(clock.speed() * factor, now);
                self.speed = clock.speed();
            }
            None => self.speed = PlayClock::new(0.0, self.speed * factor, now).speed(),
        }
    }

    /// The frame due now, if any: every frame whose time has come is taken from the source and
    /// all but the newest are counted as dropped. Returns the frame with the instant it was
    /// due. Paused players return nothing (see [`Player::step`]).
    pub fn tick(&mut self, now: Instant) -> Result<Option<(Frame, Instant)>, PlayError> {
        if self.state == PlayState::Paused {
            return Ok(None);
        }
        let mut newest: Option<(Frame, Instant)> = None;
        while !self.limit_reached() {
            let Some(time) = self.peek()?.map(|f| f.time) else {
                break;
            };
            let due = if self.live {
                now
            } else {
                let speed = self.speed;
                let start = self.restart_at.take().unwrap_or(now);
                let clock = *self
                    .clock
                    .get_or_insert_with(|| PlayClock::new(time, speed, start));
                match clock.due(time) {
                    Some(due) if due <= now => due,
                    _ => break,
                }
            };
            let frame = self.lookahead.take().expect("peeked");
            self.taken(frame.time, due);
            if newest.replace((frame, due)).is_some() {
                self.stats.dropped += 1;
            }
        }
        Ok(newest)
    }

    /// Takes the next frame regardless of the clock and pauses there (the step key).
    pub fn step(&mut self, now: Instant) -> Result<Option<Frame>, PlayError> {
        if self.state == PlayState::Playing {
            self.toggle_pause(now);
        }
        if self.limit_reached() {
            return Ok(None);
        }
        if self.peek()?.is_none() {
            return Ok(None);
        }
        let frame = self.lookahead.take().expect("peeked");
        self.taken(frame.time, now);
        if let Some(clock) = &mut self.clock {
            clock.jump(frame.time, now);
        } else {
            let mut clock = PlayClock::new(frame.time, self.speed, now);
            clock.set_paused(true, now);
            self.clock = Some(clock);
        }
        Ok(Some(frame))
    }

    fn taken(&mut self, time: f64, due: Instant) {
        self.played += 1;
        if let Some((previous, _)) = self.last {
            if time > previous {
                self.gap = time - previous;
            }
        }
        self.last = Some((time, due));
    }

    /// Records that a frame due at `due` finished drawing at `now`, drawing having taken
    /// `draw`.
    pub fn shown(&mut self, due: Instant, now: Instant, draw: Duration) {
        self.stats.shown(now.saturating_duration_since(due), draw);
    }

    /// When the next frame will be due (`None`: unknown, e.g. live, paused or finished).
    pub fn next_due(&self) -> Option<Instant> {
        let frame = self.lookahead.as_ref()?;
        self.clock?.due(frame.time)
    }

    /// The next frame without taking it, reading the source as needed (live sources do not
    /// wait). Skipped rows and notices on the way are counted and collected.
    fn peek(&mut self) -> Result<Option<&Frame>, PlayError> {
        while self.lookahead.is_none() && self.state != PlayState::Ended {
            match self.source.poll(Duration::ZERO)? {
                Poll::Event(Event::Frame(frame)) => self.lookahead = Some(frame),
                Poll::Event(Event::Untracked { .. }) => self.skipped += 1,
                Poll::Event(Event::Malformed { message }) => {
                    if self.strict {
                        return Err(PlayError::Strict(message));
                    }
                    self.skipped += 1;
                    self.messages.push(Message::Malformed(message));
                }
                Poll::Event(Event::Notice(text)) => self.messages.push(Message::Notice(text)),
                Poll::Pending => break,
                Poll::End => match &mut self.reopen {
                    Some(reopen) if !self.live && self.played > 0 => {
                        self.source = reopen()?;
                        // The file starts again from its first timestamp, one frame period
                        // after the last frame.
                        self.clock = None;
                        let speed = self.speed();
                        self.restart_at = self.last.map(|(_, due)| {
                            due + Duration::from_secs_f64((self.gap / speed).min(60.0))
                        });
                    }
                    _ => self.state = PlayState::Ended,
                },
            }
        }
        Ok(self.lookahead.as_ref())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Activations;
    use std::collections::VecDeque;

    struct Fake {
        events: VecDeque<Poll>,
        live: bool,
    }

    impl FrameSource for Fake {
        fn poll(&mut self, _wait: Duration) -> Result<Poll, SourceError> {
            Ok(self.events.pop_front().unwrap_or(Poll::End))
        }
        fn is_live(&self) -> bool {
            self.live
        }
    }

    fn frame(time: f64) -> Poll {
        Poll::Event(Event::Frame(Frame {
            time,
            line: None,
            aus: vec![],
            activations: Activations::default(),
        }))
    }

    fn fake(times: &[f64]) -> Box<dyn FrameSource> {
        Box::new(Fake {
            events: times.iter().map(|&t| frame(t)).collect(),
            live: false,
        })
    }

    fn ms(n: u64) -> Duration {
        Duration::from_millis(n)
    }

    #[test]
    fn frames_come_when_due_and_late_ones_are_dropped() {
        // 100 fps for 0.1 s.
        let times: Vec<f64> = (0..=10).map(|i| i as f64 * 0.01).collect();
        let mut player = Player::new(fake(&times), None, 1.0, false, None);
        let t0 = Instant::now();
        let (first, due) = player.tick(t0).unwrap().unwrap();
        assert_eq!((first.time, due), (0.0, t0));
        assert!(
            player.tick(t0 + ms(5)).unwrap().is_none(),
            "next is due at 10 ms"
        );
        assert_eq!(player.next_due(), Some(t0 + ms(10)));
        // A slow display comes back at 35 ms: frames at 10, 20, 30 ms are due; 30 is shown.
        let (shown, due) = player.tick(t0 + ms(35)).unwrap().unwrap();
        assert!((shown.time - 0.03).abs() < 1e-9);
        assert_eq!(due, t0 + ms(30));
        assert_eq!((player.played, player.stats.dropped), (4, 2));
        player.shown(due, t0 + ms(36), ms(1));
        assert_eq!(player.stats.late, 0);
        let (last, _) = player.tick(t0 + ms(500)).unwrap().unwrap();
        assert!((last.time - 0.1).abs() < 1e-9);
        assert!(player.is_finished());
        assert_eq!((player.played, player.stats.dropped), (11, 8));
    }

    #[test]
    fn speed_pause_and_step() {
        let mut player = Player::new(fake(&[0.0, 1.0, 2.0, 3.0]), None, 1.0, false, None);
        let t0 = Instant::now();
        player.tick(t0).unwrap().unwrap();
        player.change_speed(2.0, t0);
        assert_eq!(player.speed(), 2.0);
        assert!(player.tick(t0 + ms(400)).unwrap().is_none());
        assert_eq!(player.tick(t0 + ms(500)).unwrap().unwrap().0.time, 1.0);
        player.toggle_pause(t0 + ms(600));
        assert!(player.tick(t0 + ms(5000)).unwrap().is_none(), "paused");
        assert_eq!(player.step(t0 + ms(5000)).unwrap().unwrap().time, 2.0);
        assert!(player.is_paused());
        player.toggle_pause(t0 + ms(6000));
        // Resumed from 2.0 at 2x: 3.0 is due 500 ms later.
        assert!(player.tick(t0 + ms(6400)).unwrap().is_none());
        assert_eq!(player.tick(t0 + ms(6500)).unwrap().unwrap().0.time, 3.0);
        assert!(player.step(t0 + ms(7000)).unwrap().is_none());
        assert!(player.is_finished());
        // The source has ended; pausing does not bring playback back.
        assert_eq!(player.state(), PlayState::Ended);
        player.toggle_pause(t0 + ms(8000));
        assert_eq!(player.state(), PlayState::Ended);
        assert!(!player.is_paused());
    }

    #[test]
    fn skipped_rows_notices_strict_and_loop() {
        let events = || -> Box<dyn FrameSource> {
            Box::new(Fake {
                events: VecDeque::from([
                    Poll::Event(Event::Notice("n".into())),
                    frame(0.0),
                    Poll::Event(Event::Untracked { line: 3 }),
                    Poll::Event(Event::Malformed {
                        message: "f:4: bad".into(),
                    }),
                    frame(0.004),
                ]),
                live: false,
            })
        };
        let mut player = Player::new(
            events(),
            Some(Box::new(move || Ok(events()))),
            1.0,
            false,
            Some(5),
        );
        let t0 = Instant::now();
        let mut shown = 0;
        for i in 0..20 {
            if player.tick(t0 + ms(i)).unwrap().is_some() {
                shown += 1;
            }
        }
        assert!(
            player.is_finished(),
            "the limit of 5 frames ends a looping run"
        );
        assert_eq!(player.played, 5);
        assert_eq!(player.skipped, 4);
        // Frames at 0 and 4 ms, looping with a 4 ms gap: every frame is shown in time.
        assert_eq!(shown, 5);
        assert_eq!(player.stats.dropped, 0);
        let messages = player.take_messages();
        assert!(messages.contains(&Message::Malformed("f:4: bad".into())));
        assert!(messages.contains(&Message::Notice("n".into())));

        let mut strict = Player::new(events(), None, 1.0, true, None);
        let err = loop {
            match strict.tick(t0 + ms(1)) {
                Err(e) => break e,
                Ok(_) => assert!(!strict.is_finished()),
            }
        };
        assert_eq!(err.to_string(), "f:4: bad");
    }

    #[test]
    fn live_frames_show_on_arrival_newest_first() {
        let source = Box::new(Fake {
            events: VecDeque::from([frame(5.0), frame(6.0), Poll::Pending, frame(7.0)]),
            live: true,
        });
        let mut player = Player::new(source, None, 1.0, false, None);
        let t0 = Instant::now();
        let (f, due) = player.tick(t0).unwrap().unwrap();
        assert_eq!((f.time, due), (6.0, t0));
        assert_eq!(player.stats.dropped, 1);
        assert_eq!(player.tick(t0).unwrap().unwrap().0.time, 7.0);
        assert!(player.tick(t0).unwrap().is_none());
        assert!(player.is_finished());
    }
}
