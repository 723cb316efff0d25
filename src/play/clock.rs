//! The player clock: maps source time (a frame's timestamp) to wall time, with speed, pause
//! and jumps; and the counts of frames shown late or dropped.

use std::time::{Duration, Instant};

/// The slowest and fastest playback speeds.
pub const SPEED_RANGE: (f64, f64) = (1.0 / 16.0, 16.0);

/// A frame counts as late when shown more than this after it was due (half a 60 Hz refresh).
pub const LATE_THRESHOLD: Duration = Duration::from_micros(8_333);

/// Source time against wall time. Source time runs at `speed` seconds per wall second from a
/// base point, and stands still while paused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayClock {
    base_wall: Instant,
    base_time: f64,
    speed: f64,
    paused: bool,
}

impl PlayClock {
    /// A running clock at source time `time` now.
    pub fn new(time: f64, speed: f64, now: Instant) -> PlayClock {
        PlayClock {
            base_wall: now,
            base_time: time,
            speed: clamp_speed(speed),
            paused: false,
        }
    }

    /// The source time at wall time `now`.
    pub fn time(&self, now: Instant) -> f64 {
        if self.paused {
            return self.base_time;
        }
        let elapsed = now.saturating_duration_since(self.base_wall).as_secs_f64();
        self.base_time + elapsed * self.speed
    }

    /// The wall time at which source time `time` is due (`None` while paused).
    pub fn due(&self, time: f64) -> Option<Instant> {
        if self.paused {
            return None;
        }
        let ahead = (time - self.base_time) / self.speed;
        if ahead <= 0.0 {
            // Already due: report the base, the earliest instant this clock knows.
            return Some(self.base_wall);
        }
        Some(self.base_wall + Duration::from_secs_f64(ahead.min(1e9)))
    }

    /// The playback speed.
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Whether the clock stands still.
    pub fn is_paused(&self) -> bool {
        self.paused
    }

    /// Changes speed without a jump in source time.
    pub fn set_speed(&mut self, speed: f64, now: Instant) {
        self.rebase(now);
        self.speed = clamp_speed(speed);
    }

    /// Pauses or resumes without a jump in source time.
    pub fn set_paused(&mut self, paused: bool, now: Instant) {
        self.rebase(now);
        self.paused = paused;
    }

    /// Moves to source time `time`.
    pub fn jump(&mut self, time: f64, now: Instant) {
        self.base_wall = now;
        self.base_time = time;
    }

    fn rebase(&mut self, now: Instant) {
        self.base_time = self.time(now);
        self.base_wall = now;
    }
}

fn clamp_speed(speed: f64) -> f64 {
    if speed.is_finite() {
        speed.clamp(SPEED_RANGE.0, SPEED_RANGE.1)
    } else {
        1.0
    }
}

/// Counts of how well playback kept up.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameStats {
    /// Frames drawn.
    pub shown: usize,
    /// Frames never drawn because a later frame was already due.
    pub dropped: usize,
    /// Frames drawn more than [`LATE_THRESHOLD`] after they were due.
    pub late: usize,
    /// The largest lateness seen.
    pub worst: Duration,
    /// Lateness summed over shown frames (for the mean).
    pub total_lateness: Duration,
    /// Time spent mapping, deforming and drawing, summed over shown frames.
    pub total_draw: Duration,
}

impl FrameStats {
    /// Records a frame drawn `lateness` after it was due, drawing having taken `draw`.
    pub fn shown(&mut self, lateness: Duration, draw: Duration) {
        self.shown += 1;
        if lateness > LATE_THRESHOLD {
            self.late += 1;
        }
        self.worst = self.worst.max(lateness);
        self.total_lateness += lateness;
        self.total_draw += draw;
    }

    /// One line for the end of a run.
    pub fn summary(&self) -> String {
        let per = |total: Duration| {
            if self.shown == 0 {
                0.0
            } else {
                total.as_secs_f64() * 1000.0 / self.shown as f64
            }
        };
        format!(
            "frames shown {}, dropped {}, late {} (> {:.1} ms); lateness mean {:.2} ms, worst {:.2} ms; draw mean {:.2} ms",
            self.shown,
            self.dropped,
            self.late,
            LATE_THRESHOLD.as_secs_f64() * 1000.0,
            per(self.total_lateness),
            self.worst.as_secs_f64() * 1000.0,
            per(self.total_draw),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn source_time_follows_speed_and_pause() {
        let t0 = Instant::now();
        let mut clock = PlayClock::new(1.0, 2.0, t0);
        let t1 = t0 + Duration::from_millis(500);
        assert!((clock.time(t1) - 2.0).abs() < 1e-9);
        clock.set_paused(true, t1);
        let t2 = t1 + Duration::from_secs(3);
        assert!((clock.time(t2) - 2.0).abs() < 1e-9);
        assert_eq!(clock.due(5.0), None);
        clock.set_paused(false, t2);
        clock.set_speed(0.5, t2);
        let t3 = t2 + Duration::from_secs(2);
        assert!((clock.time(t3) - 3.0).abs() < 1e-9);
        let due = clock.due(4.0).unwrap();
        assert_eq!(due.duration_since(t2), Duration::from_secs(4));
        assert_eq!(clock.due(0.0), Some(t2), "a past frame is due at once");
        clock.jump(10.0, t3);
        assert!((clock.time(t3) - 10.0).abs() < 1e-9);
    }

    #[test]
    fn speed_is_clamped() {
        let now = Instant::now();
        assert_eq!(PlayClock::new(0.0, 100.0, now).speed(), 16.0);
        assert_eq!(PlayClock::new(0.0, f64::NAN, now).speed(), 1.0);
        assert_eq!(PlayClock::new(0.0, 0.0, now).speed(), 1.0 / 16.0);
    }

    #[test]
    fn stats_count_late_frames() {
        let mut stats = FrameStats::default();
        stats.shown(Duration::from_millis(1), Duration::from_millis(2));
        stats.shown(Duration::from_millis(20), Duration::from_millis(2));
        stats.dropped += 3;
        assert_eq!((stats.shown, stats.late, stats.dropped), (2, 1, 3));
        assert_eq!(stats.worst, Duration::from_millis(20));
        let line = stats.summary();
        assert!(line.contains("dropped 3, late 1"), "{line}");
        assert!(line.contains("lateness mean 10.50 ms"), "{line}");
    }
}
