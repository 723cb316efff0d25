//! Live Link Face CSV recordings: ARKit blendshape weights per frame, as Epic's Live Link
//! Face app (iPhone, iPad) writes them with each take.
//!
//! The layout (docs/formats.md cites where it is documented): a header line
//! `Timecode,BlendShapeCount,EyeBlinkLeft,...,TongueOut` and, in most versions, nine head
//! and eye rotation columns after the 52 shapes (`HeadYaw`, ..., `RightEyeRoll`), then one
//! row per frame: an SMPTE-style timecode `HH:MM:SS:FF.fff` (hours, minutes, seconds,
//! frame, fraction of a frame), the shape count, and one weight 0-1 per shape.
//!
//! Shapes are found by name (either ARKit spelling, see [`crate::io::arkit::canonical`]),
//! so column order does not matter; other columns are ignored. A row that cannot be read
//! is a [`RowError`] with its line and column, never a panic.

use std::io::BufRead;
use std::path::{Path, PathBuf};

use super::arkit;
use super::error::LoadError;
use super::lines::LineReader;
use super::openface::{next_row_line, shorten, RowError, MAX_LINE_BYTES};

/// The columns of a Live Link Face header.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LiveLinkColumns {
    /// The `Timecode` column.
    pub timecode: usize,
    /// The ARKit shape columns: field index and ARKit name, in header order.
    pub shapes: Vec<(usize, &'static str)>,
    /// Header columns that are neither the timecode, the count nor a shape (head and eye
    /// rotations), ignored.
    pub ignored: Vec<String>,
    /// The number of fields every row must have.
    pub field_count: usize,
}

/// One frame of a recording.
#[derive(Debug, Clone, PartialEq)]
pub struct LiveLinkRow {
    /// The 1-based line.
    pub line: usize,
    /// The timecode in seconds: `(HH*60 + MM)*60 + SS + FF.fff/fps`, at the frame rate
    /// given to [`LiveLinkColumns::parse_row`].
    pub seconds: f64,
    /// One weight per shape column, in [`LiveLinkColumns::shapes`] order.
    pub weights: Vec<f32>,
}

/// Whether a header line is Live Link Face's: its first two columns are `Timecode` and
/// `BlendShapeCount`.
pub fn is_header(line: &str) -> bool {
    let mut names = line
        .trim_start_matches('\u{feff}')
        .split(',')
        .map(str::trim);
    matches!(
        (names.next(), names.next()),
        (Some(a), Some(b)) if a.eq_ignore_ascii_case("timecode") && b.eq_ignore_ascii_case("blendshapecount")
    )
}

impl LiveLinkColumns {
    /// Reads a header line; the error says what is wrong with it.
    pub fn from_header(line: &str) -> Result<LiveLinkColumns, String> {
        if !is_header(line) {
            return Err("not a Live Link Face header (Timecode,BlendShapeCount,...)".into());
        }
        let line = line
            .trim_end_matches(['\r', '\n'])
            .trim_start_matches('\u{feff}');
        let names: Vec<&str> = line.split(',').map(str::trim).collect();
        let mut shapes: Vec<(usize, &'static str)> = Vec::new();
        let mut ignored = Vec::new();
        for (index, name) in names.iter().enumerate().skip(2) {
            match arkit::canonical(name) {
                Some(shape) if shapes.iter().any(|(_, s)| *s == shape) => {
                    return Err(format!("column `{shape}` appears twice in the header"));
                }
                Some(shape) => shapes.push((index, shape)),
                None if name.is_empty() => {}
                None => ignored.push(name.to_string()),
            }
        }
        if shapes.is_empty() {
            return Err(
                "the header names no ARKit blendshape (EyeBlinkLeft, ..., TongueOut)".into(),
            );
        }
        Ok(LiveLinkColumns {
            timecode: 0,
            shapes,
            ignored,
            field_count: names.len(),
        })
    }

    /// Reads one data line; `line` is its 1-based number, `fps` the recording's frame rate
    /// (the timecode's frame field counts frames of it).
    pub fn parse_row(&self, text: &str, line: usize, fps: f64) -> Result<LiveLinkRow, RowError> {
        let text = text.trim_end_matches(['\r', '\n']);
        let fields: Vec<&str> = text.split(',').collect();
        let error = |column: Option<usize>, message: String| RowError {
            line,
            column,
            message,
        };
        if fields.len() != self.field_count {
            return Err(error(
                None,
                format!(
                    "{} fields, but the header has {}",
                    fields.len(),
                    self.field_count
                ),
            ));
        }
        let column_of = |index: usize| {
            Some(
                fields[..index]
                    .iter()
                    .map(|f| f.chars().count() + 1)
                    .sum::<usize>()
                    + 1,
            )
        };
        let timecode = fields[self.timecode].trim();
        let seconds = parse_timecode(timecode, fps).map_err(|why| {
            error(
                column_of(self.timecode),
                format!("timecode `{}` {why}", shorten(timecode)),
            )
        })?;
        let mut weights = Vec::with_capacity(self.shapes.len());
        for &(index, shape) in &self.shapes {
            let field = fields[index].trim();
            match field.parse::<f32>() {
                Ok(value) if value.is_finite() => weights.push(value),
                _ => {
                    return Err(error(
                        column_of(index),
                        format!("{shape}: `{}` is not a number", shorten(field)),
                    ))
                }
            }
        }
        Ok(LiveLinkRow {
            line,
            seconds,
            weights,
        })
    }
}

/// `HH:MM:SS:FF` or `HH:MM:SS:FF.fff` (a fraction of a frame) in seconds at `fps`; `;` is
/// taken for `:` (drop-frame timecode is written with it). A timecode is a time of day: hours
/// run 0-23, minutes and seconds 0-59, and the frame stays below the frame rate (a frame of 45
/// at 30 fps means the take was recorded faster than the rate given). The error says which.
pub fn parse_timecode(text: &str, fps: f64) -> Result<f64, String> {
    let parts: Vec<&str> = text.split([':', ';']).collect();
    let [h, m, s, f] = parts.as_slice() else {
        return Err("is not a timecode HH:MM:SS:FF.fff".into());
    };
    let digits = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
    let whole = |t: &str, what: &str, below: f64| -> Result<f64, String> {
        match t.parse::<f64>() {
            Ok(v) if digits(t) && v < below => Ok(v),
            Ok(_) if digits(t) => Err(format!("{what} {} is not below {below}", shorten(t))),
            _ => Err("is not a timecode HH:MM:SS:FF.fff".into()),
        }
    };
    let (h, m, s) = (
        whole(h, "hours", 24.0)?,
        whole(m, "minutes", 60.0)?,
        whole(s, "seconds", 60.0)?,
    );
    // The frame and its fraction read as one decimal: a fraction of any length stays finite.
    let frame_digits = match f.split_once('.') {
        Some((frames, fraction)) => digits(frames) && digits(fraction),
        None => digits(f),
    };
    let frame = match f.parse::<f64>() {
        Ok(frame) if frame_digits && frame < fps => frame,
        Ok(frame) if frame_digits && frame.is_finite() => {
            return Err(format!(
                "frame {} is not below the frame rate {fps}: the take was recorded faster (give its rate with --fps)",
                shorten(f)
            ))
        }
        _ => return Err("is not a timecode HH:MM:SS:FF.fff".into()),
    };
    Ok((h * 60.0 + m) * 60.0 + s + frame / fps)
}

/// A Live Link Face recording read row by row, each line in bounded memory.
pub struct LiveLinkReader<R> {
    lines: LineReader<R>,
    path: PathBuf,
    columns: LiveLinkColumns,
    fps: f64,
}

impl<R: BufRead> LiveLinkReader<R> {
    /// Reads the header line; `path` names the input in messages, `fps` is the recording's
    /// frame rate.
    pub fn new(input: R, path: &Path, fps: f64) -> Result<LiveLinkReader<R>, LoadError> {
        let mut lines = LineReader::new(input, MAX_LINE_BYTES);
        let error = |line: Option<usize>, message: String| LoadError {
            path: path.to_path_buf(),
            line,
            column: None,
            message,
        };
        let header = lines
            .next_line()
            .map_err(|e| error(Some(1), format!("cannot read: {e}")))?
            .ok_or_else(|| error(None, "empty input: no header line".into()))?;
        if let Some(why) = header.too_long(MAX_LINE_BYTES) {
            return Err(error(Some(1), format!("the header: {why}")));
        }
        let columns = LiveLinkColumns::from_header(&header.text).map_err(|m| error(Some(1), m))?;
        Ok(LiveLinkReader {
            lines,
            path: path.to_path_buf(),
            columns,
            fps,
        })
    }

    /// The header's columns.
    pub fn columns(&self) -> &LiveLinkColumns {
        &self.columns
    }

    /// The next row (blank lines are passed over; a line longer than [`MAX_LINE_BYTES`] is a
    /// malformed row); `None` at the end of the input.
    pub fn next_row(&mut self) -> Result<Option<Result<LiveLinkRow, RowError>>, LoadError> {
        let read = next_row_line(&mut self.lines, &self.path)?;
        Ok(read.map(|line| {
            line.and_then(|line| self.columns.parse_row(&line.text, line.number, self.fps))
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timecodes_read_with_frames_and_their_fraction() {
        assert_eq!(parse_timecode("00:00:01:30.000", 60.0), Ok(1.5));
        assert_eq!(parse_timecode("01:02:03:06", 30.0), Ok(3723.2));
        let t = parse_timecode("00:00:00:01.5", 60.0).unwrap();
        assert!((t - 1.5 / 60.0).abs() < 1e-12);
        assert_eq!(parse_timecode("00:00:00;10", 30.0), Ok(10.0 / 30.0));
        for bad in [
            "",
            "1:2:3",
            "00:00:00:xx",
            "00:61:00:00",
            "00:00:00:01.",
            "-1:00:00:00",
        ] {
            assert!(parse_timecode(bad, 60.0).is_err(), "{bad}");
        }
    }

    #[test]
    fn absurd_timecodes_are_refused_saying_why() {
        let why = |t: &str, fps: f64| parse_timecode(t, fps).unwrap_err();
        assert_eq!(
            why("99999999999999:00:00:00", 60.0),
            "hours 99999999999999 is not below 24"
        );
        let long = format!("00:00:00:01.{}", "9".repeat(400));
        let t = parse_timecode(&long, 60.0).unwrap();
        assert!(t.is_finite() && (t - 2.0 / 60.0).abs() < 1e-9, "{t}");
        assert!(why(&format!("00:00:00:{}", "9".repeat(400)), 60.0).contains("not a timecode"));
        let fast = why("00:00:00:45", 30.0);
        assert!(
            fast.starts_with("frame 45 is not below the frame rate 30"),
            "{fast}"
        );
        assert!(fast.contains("--fps"), "{fast}");
        assert_eq!(
            parse_timecode("23:59:59:59.999", 60.0).map(|t| t < 86_400.0),
            Ok(true)
        );
    }

    #[test]
    fn header_finds_shapes_by_name_and_ignores_rotations() {
        let header = "Timecode,BlendShapeCount,EyeBlinkLeft,JawOpen,MouthSmileLeft,HeadYaw\r\n";
        assert!(is_header(header));
        assert!(!is_header("frame, timestamp, AU01_r"));
        let columns = LiveLinkColumns::from_header(header).unwrap();
        assert_eq!(
            columns.shapes,
            vec![(2, "eyeBlink_L"), (3, "jawOpen"), (4, "mouthSmile_L")]
        );
        assert_eq!(columns.ignored, vec!["HeadYaw"]);
        let row = columns
            .parse_row("00:00:00:02.000,3,0.5,0.25,1,0.1\r\n", 2, 60.0)
            .unwrap();
        assert_eq!(row.weights, vec![0.5, 0.25, 1.0]);
        assert!((row.seconds - 2.0 / 60.0).abs() < 1e-12);
        let e = columns
            .parse_row("00:00:00:02.000,3,0.5,high,1,0.1", 7, 60.0)
            .unwrap_err();
        assert_eq!((e.line, e.column), (7, Some(23)));
        assert!(e.message.contains("jawOpen"), "{}", e.message);
        assert!(columns.parse_row("00:00:00:02.000,3,0.5", 8, 60.0).is_err());
        assert!(LiveLinkColumns::from_header("Timecode,BlendShapeCount,Foo").is_err());
        assert!(LiveLinkColumns::from_header("Timecode,BlendShapeCount,JawOpen,jawOpen").is_err());
    }
}
