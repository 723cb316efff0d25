//! Timelines (`*.timeline.ron`): keyframed animations of AUs or muscle activations.
//!
//! ```ron
//! Timeline(
//!     version: 1,
//!     frame_rate: 30.0,          // frames per second the timeline is sampled at (0 < fps <= 1000)
//!     interpolation: Linear,     // Step, Linear or Smooth (ease in and out); default Linear
//!     keyframes: [
//!         (time: 0.0),                                   // nothing set: the rest face
//!         (time: 0.5, aus: "6+12@0.5"),                  // an AU combination string
//!         (time: 1.0, aus: "smile"),                     // or a named expression of the table
//!         (time: 1.5, muscles: {"zygomatic_major_l": 1.2}, jaw: 0.5), // explicit activations
//!         (time: 2.0, aus: "1+2", muscles: {"frontalis_l": 0.2}),    // both: added, clamped
//!     ],
//! )
//! ```
//!
//! Times are seconds from the start, in non-decreasing order (two keyframes at one time make a
//! cut). Each keyframe is a pose: its AU combination evaluated through the AU table (an
//! intensity letter or `@x` scales a recorded AU, as in the editor), plus any explicit muscle
//! activations and jaw, clamped to the ranges. Between keyframes the pose is interpolated:
//! `Step` holds a keyframe until the next, `Linear` blends, `Smooth` blends with an ease in and
//! out (smoothstep). The timeline is sampled at `frame_rate` from 0 to the last keyframe's time.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The timeline file format version this build reads.
pub const TIMELINE_VERSION: u32 = 1;

/// The highest frame rate a timeline may ask for.
pub const MAX_FRAME_RATE: f64 = 1000.0;

/// The most keyframes a timeline may hold.
pub const MAX_KEYFRAMES: usize = 100_000;

/// How the pose moves from one keyframe to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Interpolation {
    /// Hold each keyframe until the next.
    Step,
    /// Blend in proportion to time.
    #[default]
    Linear,
    /// Blend with an ease in and out (smoothstep).
    Smooth,
}

impl Interpolation {
    /// The weight of the next keyframe at fraction `u` (0-1) of the way to it.
    pub fn weight(self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        match self {
            Interpolation::Step => {
                if u >= 1.0 {
                    1.0
                } else {
                    0.0
                }
            }
            Interpolation::Linear => u,
            Interpolation::Smooth => u * u * (3.0 - 2.0 * u),
        }
    }
}

/// One keyframe: a pose at a time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    /// Seconds from the start.
    pub time: f64,
    /// An AU combination string (`6+12@0.5`, `1+2+5B`) or an expression name of the table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aus: Option<String>,
    /// Explicit activations by muscle name (added to the AUs' activations).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub muscles: BTreeMap<String, f32>,
    /// Explicit jaw activation (added to the AUs' jaw).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub jaw: Option<f32>,
}

/// A keyframed animation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Timeline {
    /// File format version; see [`TIMELINE_VERSION`].
    pub version: u32,
    /// Frames per second the timeline is sampled at.
    pub frame_rate: f64,
    /// How poses blend between keyframes.
    #[serde(default)]
    pub interpolation: Interpolation,
    /// The keyframes, in time order.
    pub keyframes: Vec<Keyframe>,
}

/// A timeline that cannot be read.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{}{}: {message}", path.display(), position.map(|(l, c)| format!(":{l}:{c}")).unwrap_or_default())]
pub struct TimelineError {
    /// The file.
    pub path: PathBuf,
    /// 1-based line and column, when the problem has a place in the text.
    pub position: Option<(usize, usize)>,
    /// What is wrong.
    pub message: String,
}

impl Timeline {
    /// The number of frames when sampled at the frame rate: one at 0 and one per frame
    /// period up to the last keyframe.
    pub fn frame_count(&self) -> usize {
        let end = self.keyframes.last().map_or(0.0, |k| k.time);
        // A small tolerance so 2.0 s at 30 fps gives 61 frames despite rounding.
        (end * self.frame_rate + 1e-6).floor() as usize + 1
    }

    /// The keyframe pair around time `t` and the weight of the second: `(i, j, w)` with
    /// pose = (1 - w) * keyframe i + w * keyframe j.
    pub fn bracket(&self, t: f64) -> (usize, usize, f64) {
        let keys = &self.keyframes;
        let after = keys.partition_point(|k| k.time <= t);
        if after == 0 {
            return (0, 0, 0.0);
        }
        if after >= keys.len() {
            return (keys.len() - 1, keys.len() - 1, 0.0);
        }
        let (a, b) = (&keys[after - 1], &keys[after]);
        let span = b.time - a.time;
        let u = if span > 0.0 { (t - a.time) / span } else { 1.0 };
        (after - 1, after, self.interpolation.weight(u))
    }

    fn check(&self) -> Result<(), String> {
        if self.version != TIMELINE_VERSION {
            return Err(format!(
                "timeline version {} is not supported (this build reads version {TIMELINE_VERSION})",
                self.version
            ));
        }
        if !(self.frame_rate.is_finite()
            && self.frame_rate > 0.0
            && self.frame_rate <= MAX_FRAME_RATE)
        {
            return Err(format!(
                "frame_rate {} is outside 0 to {MAX_FRAME_RATE} frames per second",
                self.frame_rate
            ));
        }
        if self.keyframes.is_empty() {
            return Err("the timeline has no keyframes".into());
        }
        if self.keyframes.len() > MAX_KEYFRAMES {
            return Err(format!("more than {MAX_KEYFRAMES} keyframes"));
        }
        let mut previous = 0.0;
        for (i, key) in self.keyframes.iter().enumerate() {
            let which = format!("keyframe {} (time {})", i + 1, key.time);
            if !key.time.is_finite() || key.time < 0.0 {
                return Err(format!("{which}: time must be a number of seconds from 0"));
            }
            if key.time < previous {
                return Err(format!(
                    "{which}: times must not go backwards (previous {previous})"
                ));
            }
            if key.time * self.frame_rate > 1e8 {
                return Err(format!("{which}: the timeline is too long to sample"));
            }
            previous = key.time;
            let values = key.muscles.iter().map(|(n, v)| (n.as_str(), *v));
            for (name, value) in values.chain(key.jaw.map(|j| ("jaw", j))) {
                if !value.is_finite() || value < 0.0 {
                    return Err(format!("{which}: activation of `{name}` is {value}"));
                }
            }
        }
        Ok(())
    }
}

/// Parses a timeline from text; `path` names it in errors.
pub fn parse_timeline(text: &str, path: &Path) -> Result<Timeline, TimelineError> {
    // Optional fields are written bare (`aus: "6+12"`), not as `Some("6+12")`.
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let timeline: Timeline = options.from_str(text).map_err(|e| TimelineError {
        path: path.to_path_buf(),
        position: Some((e.span.start.line, e.span.start.col)),
        message: e.code.to_string(),
    })?;
    timeline.check().map_err(|message| TimelineError {
        path: path.to_path_buf(),
        position: None,
        message,
    })?;
    Ok(timeline)
}

/// Reads and parses a timeline file.
pub fn load_timeline(path: &Path) -> Result<Timeline, TimelineError> {
    // Size-checked like every other file: reading a huge (or sparse) file whole would
    // exhaust memory.
    let text =
        super::error::read_text(path, super::error::MAX_FILE_BYTES).map_err(|e| TimelineError {
            path: path.to_path_buf(),
            position: e.line.map(|line| (line, e.column.unwrap_or(1))),
            message: e.message,
        })?;
    parse_timeline(&text, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Timeline, TimelineError> {
        parse_timeline(text, Path::new("t.timeline.ron"))
    }

    const SAMPLE: &str = r#"Timeline(
        version: 1,
        frame_rate: 10.0,
        keyframes: [
            (time: 0.0),
            (time: 1.0, aus: "6+12@0.5"),
            (time: 2.0, muscles: {"a": 1.0}, jaw: 0.5),
        ],
    )"#;

    #[test]
    fn reads_the_documented_format() {
        let t = parse(SAMPLE).unwrap();
        assert_eq!(t.interpolation, Interpolation::Linear);
        assert_eq!(t.keyframes.len(), 3);
        assert_eq!(t.keyframes[1].aus.as_deref(), Some("6+12@0.5"));
        assert_eq!(t.keyframes[2].muscles["a"], 1.0);
        assert_eq!(t.keyframes[2].jaw, Some(0.5));
        assert_eq!(t.frame_count(), 21);
    }

    #[test]
    fn brackets_and_weights() {
        let mut t = parse(SAMPLE).unwrap();
        assert_eq!(t.bracket(0.0), (0, 1, 0.0));
        let (i, j, w) = t.bracket(1.25);
        assert_eq!((i, j), (1, 2));
        assert!((w - 0.25).abs() < 1e-12);
        assert_eq!(t.bracket(2.0), (2, 2, 0.0));
        assert_eq!(t.bracket(9.0), (2, 2, 0.0));
        t.interpolation = Interpolation::Step;
        assert_eq!(t.bracket(1.99).2, 0.0);
        t.interpolation = Interpolation::Smooth;
        assert!((t.bracket(1.5).2 - 0.5).abs() < 1e-12);
        assert!((t.bracket(1.25).2 - 0.15625).abs() < 1e-12);
    }

    #[test]
    fn errors_name_the_place() {
        let e = parse("Timeline(\n  version: 1,\n  frame_rate: x,\n)").unwrap_err();
        assert_eq!(e.position.map(|p| p.0), Some(3), "{e}");
        assert!(e.to_string().starts_with("t.timeline.ron:3:"), "{e}");
        let e = parse(&SAMPLE.replace("version: 1", "version: 9")).unwrap_err();
        assert!(e.message.contains("version 9"), "{e}");
        let e = parse(&SAMPLE.replace("time: 2.0", "time: 0.5")).unwrap_err();
        assert!(e.message.contains("keyframe 3"), "{e}");
        let e = parse(&SAMPLE.replace("10.0", "0.0")).unwrap_err();
        assert!(e.message.contains("frame_rate"), "{e}");
        let e = parse(&SAMPLE.replace("jaw: 0.5", "jaw: -1.0")).unwrap_err();
        assert!(e.message.contains("`jaw`"), "{e}");
        assert!(parse(&SAMPLE.replace("(time: 0.0)", "(time: 0.0, colour: 1)")).is_err());
    }
}
