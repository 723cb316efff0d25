//! The rules every stream source keeps, whatever it reads (OpenFace CSV, Live Link Face CSV,
//! JSON lines or datagrams, timelines):
//!
//! - time is finite, bounded ([`MAX_TIME`]) and never goes backwards: a time-of-day clock
//!   (Live Link Face timecodes) wraps at midnight into the next day, and any other step back
//!   is a malformed row that names both times, never played silently ([`TimeRule`]);
//! - names seen in the input (unknown fields, ignored columns) are kept in bounded memory:
//!   the first [`NAMES_KEPT`], each cut to [`NAME_CHARS`] characters, and the rest counted
//!   ([`NameSet`]);
//! - every message quoting the input goes out through [`crate::io::printable`], cut to a
//!   bounded length ([`shown`], [`printable_poll`]).
//!
//! Reading non-seekable input once is [`crate::io::lines::sniff_first_line`]'s job; the same
//! verdict whatever the key order is the JSON source's (see `source.rs`).

use std::collections::BTreeSet;

use super::event::{Event, Poll};
use crate::io::printable::printable;

/// The largest time a frame may have, in seconds (about 11.6 days): a recording is far
/// shorter, and a frame due later than this would never be shown.
pub const MAX_TIME: f64 = 1e6;

/// Seconds in a day: a time-of-day clock wraps at this.
pub const DAY: f64 = 86_400.0;

/// How many distinct names a source keeps (and names in messages).
pub const NAMES_KEPT: usize = 32;

/// The most characters of a name kept or printed.
pub const NAME_CHARS: usize = 64;

/// `text` made safe to print (control characters escaped) and cut to `max` characters
/// (`...` marks the cut), so a message quoting input stays small whatever the input.
pub fn shown(text: &str, max: usize) -> String {
    let mut chars = text.char_indices();
    match chars.nth(max) {
        None => printable(text).into_owned(),
        Some((cut, _)) => format!("{}...", printable(&text[..cut])),
    }
}

/// A poll with the text of its messages made safe to print: they quote rows, fields and keys
/// of the input, which may hold terminal escapes. Every source hands its polls through this.
pub fn printable_poll(poll: Poll) -> Poll {
    let safe = |text: String| printable(&text).into_owned();
    match poll {
        Poll::Event(Event::Malformed { message }) => Poll::Event(Event::Malformed {
            message: safe(message),
        }),
        Poll::Event(Event::Notice(text)) => Poll::Event(Event::Notice(safe(text))),
        other => other,
    }
}

/// What a frame's time counts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeBase {
    /// Seconds given as they are (timestamps, frame numbers, arrival times).
    Absolute,
    /// A time of day (timecodes): it wraps at midnight, and frames count from the first.
    TimeOfDay,
}

/// Checks each frame's time against the rules: finite, within [`MAX_TIME`], and not before
/// the previous frame's.
#[derive(Debug, Clone)]
pub struct TimeRule {
    base: TimeBase,
    /// The first time seen (time-of-day clocks count from it).
    origin: Option<f64>,
    /// Days added for the midnights passed.
    offset: f64,
    /// The last time accepted, with `offset` added.
    last: Option<f64>,
}

impl TimeRule {
    /// A rule for times on `base`.
    pub fn new(base: TimeBase) -> TimeRule {
        TimeRule {
            base,
            origin: None,
            offset: 0.0,
            last: None,
        }
    }

    /// The time to play a frame given at `raw` seconds, or why the frame is refused.
    pub fn accept(&mut self, raw: f64) -> Result<f64, String> {
        if !raw.is_finite() || raw.abs() > MAX_TIME {
            return Err(format!(
                "time {raw:e} s is out of range (at most {MAX_TIME} in size)"
            ));
        }
        let mut offset = self.offset;
        let mut time = raw + offset;
        if let Some(last) = self.last {
            // A time of day far before the last one is the next day (a take across
            // midnight); a step back of less than half a day is the clock going backwards.
            if time < last && self.base == TimeBase::TimeOfDay && last - time > DAY / 2.0 {
                offset += DAY;
                time += DAY;
            }
            if time < last {
                let origin = self.origin.unwrap_or(0.0);
                return Err(format!(
                    "time {:.3} s is before the previous frame's {:.3} s: time must not go backwards",
                    time - origin,
                    last - origin
                ));
            }
        }
        let origin = match self.base {
            TimeBase::Absolute => 0.0,
            TimeBase::TimeOfDay => *self.origin.get_or_insert(time),
        };
        let played = time - origin;
        if played > MAX_TIME {
            return Err(format!(
                "time {played:.3} s from the start is past the limit of {MAX_TIME} s"
            ));
        }
        self.offset = offset;
        self.last = Some(time);
        Ok(played)
    }
}

/// What [`NameSet::see`] makes of a name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Seen {
    /// A name not seen before: here as it may be printed (escaped, cut).
    New(String),
    /// A name seen before: say nothing.
    Known,
    /// The first name past the limit: say once that the rest are only counted.
    Full,
    /// A later name past the limit: counted, nothing said.
    Counted,
}

/// The distinct names a source has seen, in bounded memory: the first [`NAMES_KEPT`], each
/// cut to [`NAME_CHARS`] characters; names past them are counted, not kept.
#[derive(Debug, Clone, Default)]
pub struct NameSet {
    kept: BTreeSet<String>,
    /// Occurrences of names that were not kept.
    uncounted: usize,
}

impl NameSet {
    /// Records one occurrence of `name`.
    pub fn see(&mut self, name: &str) -> Seen {
        let name = shown(name, NAME_CHARS);
        if self.kept.contains(&name) {
            return Seen::Known;
        }
        if self.kept.len() < NAMES_KEPT {
            self.kept.insert(name.clone());
            return Seen::New(name);
        }
        self.uncounted += 1;
        if self.uncounted == 1 {
            Seen::Full
        } else {
            Seen::Counted
        }
    }

    /// Occurrences of names past the first [`NAMES_KEPT`].
    pub fn not_kept(&self) -> usize {
        self.uncounted
    }

    /// The names among `names` worth a message, each seen once: the new ones joined with
    /// `, `, followed by a count of those past the limit; `None` when none is new.
    pub fn list<'a>(&mut self, names: impl IntoIterator<Item = &'a str>) -> Option<String> {
        let mut new = Vec::new();
        let mut past = 0usize;
        for name in names {
            match self.see(name) {
                Seen::New(name) => new.push(name),
                Seen::Full | Seen::Counted => past += 1,
                Seen::Known => {}
            }
        }
        if past > 0 {
            new.push(format!("and {past} more not named"));
        }
        (!new.is_empty()).then(|| new.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_must_be_finite_bounded_and_forward() {
        let mut rule = TimeRule::new(TimeBase::Absolute);
        assert_eq!(rule.accept(0.5), Ok(0.5));
        assert_eq!(rule.accept(0.5), Ok(0.5), "a repeated time is a cut");
        for bad in [f64::NAN, f64::INFINITY, 1e300, -2e6] {
            assert!(
                rule.accept(bad).unwrap_err().contains("out of range"),
                "{bad}"
            );
        }
        let back = rule.accept(0.25).unwrap_err();
        assert!(
            back.contains("0.250 s is before the previous frame's 0.500 s"),
            "{back}"
        );
        assert_eq!(
            rule.accept(1.0),
            Ok(1.0),
            "a refused frame leaves the rule as it was"
        );
    }

    #[test]
    fn a_time_of_day_wraps_at_midnight_and_counts_from_the_first() {
        let mut rule = TimeRule::new(TimeBase::TimeOfDay);
        assert_eq!(rule.accept(DAY - 0.5), Ok(0.0));
        assert_eq!(rule.accept(0.0), Ok(0.5), "past midnight");
        assert_eq!(rule.accept(0.25), Ok(0.75));
        let back = rule.accept(0.1).unwrap_err();
        assert!(back.contains("before the previous"), "{back}");
        let mut absolute = TimeRule::new(TimeBase::Absolute);
        absolute.accept(DAY - 0.5).unwrap();
        assert!(absolute.accept(0.0).is_err(), "only a time of day wraps");
    }

    #[test]
    fn names_are_kept_bounded_and_cut() {
        let mut names = NameSet::default();
        let long = "x".repeat(10_000);
        assert_eq!(
            names.see(&long),
            Seen::New(format!("{}...", "x".repeat(NAME_CHARS)))
        );
        assert_eq!(names.see(&long), Seen::Known);
        assert_eq!(
            names.see("a\u{1b}]0;t\u{7}"),
            Seen::New("a\\x1b]0;t\\x07".into())
        );
        for i in 2..NAMES_KEPT {
            assert!(matches!(names.see(&format!("n{i}")), Seen::New(_)));
        }
        assert_eq!(names.see("late"), Seen::Full);
        assert_eq!(names.see("later"), Seen::Counted);
        assert_eq!(names.not_kept(), 2);
        assert_eq!(
            names.list(["n2", "more"]).as_deref(),
            Some("and 1 more not named")
        );
    }
}
