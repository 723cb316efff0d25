//! Activation CSV: what `grimace capture` writes, one row per tracked frame, and what
//! `play` and `render --acts` read back onto any rig.
//!
//! ```text
//! frame, face_id, timestamp, confidence, success, explained, L_Zygomatic_Major, ..., jaw, AU01_r, ...
//! 1, 0, 0.000, 0.98, 1, , 0.0000, ..., 0.0000, 0.000, ...
//! ```
//!
//! The first five columns are OpenFace's own (the face followed, the recording's time, the
//! tracker's confidence, empty when the recording has none, and `success`, 1: only solved
//! frames are written), so tools that filter OpenFace output by them read the file as it is.
//! `explained` is empty where the frame barely moved; one column per muscle (the rig's
//! names), `jaw`, then with `capture --aus` the AU intensities in OpenFace's names and 0-5
//! scale, so OpenFace tools read the file too. A reader takes the muscle columns by name:
//! every column that is not `frame`, `timestamp`, `explained`, `jaw`, OpenFace's `success`,
//! `confidence`, `face_id` or an `AUxx_r`/`AUxx_c` column is a muscle.

use std::io::BufRead;
use std::path::{Path, PathBuf};

use super::error::LoadError;
use super::lines::LineReader;
use super::openface::{next_row_line, split_fields, Fields, RowError, MAX_LINE_BYTES};
use crate::model::Activations;

/// The column that marks an activation CSV (with `jaw`).
pub const EXPLAINED: &str = "explained";

/// The header line of an activation CSV.
pub fn header_line(muscles: &[String], aus: &[String]) -> String {
    let mut names = vec![
        "frame",
        "face_id",
        "timestamp",
        "confidence",
        "success",
        EXPLAINED,
    ];
    names.extend(muscles.iter().map(String::as_str));
    names.push("jaw");
    names.extend(aus.iter().map(String::as_str));
    names.join(", ")
}

/// Where a row comes from in the recording: OpenFace's bookkeeping, written before the
/// activations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Source {
    /// OpenFace's `frame`.
    pub frame: u64,
    /// The face followed (`face_id`; 0 for a recording of one face).
    pub face: u32,
    /// Seconds into the recording.
    pub timestamp: f64,
    /// The tracker's confidence, when the recording gives it.
    pub confidence: Option<f32>,
}

/// One data line (without its end).
pub fn row_line(source: Source, explained: Option<f64>, act: &Activations, aus: &[f64]) -> String {
    use std::fmt::Write as _;
    let Source {
        frame,
        face,
        timestamp,
        confidence,
    } = source;
    let confidence = confidence.map(|c| format!("{c:.3}")).unwrap_or_default();
    let mut line = format!("{frame}, {face}, {timestamp:.3}, {confidence}, 1, ");
    if let Some(e) = explained {
        let _ = write!(line, "{e:.4}");
    }
    for a in act.muscles.iter().chain(std::iter::once(&act.jaw)) {
        let _ = write!(line, ", {a:.4}");
    }
    for v in aus {
        let _ = write!(line, ", {v:.3}");
    }
    line
}

/// Whether a header line is an activation CSV's (it has `explained` and `jaw` columns).
pub fn is_header(line: &str) -> bool {
    let names: Vec<&str> = line.split(',').map(str::trim).collect();
    names.contains(&EXPLAINED) && names.contains(&"jaw")
}

/// The columns of an activation CSV.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ActsColumns {
    /// `frame`, if present.
    pub frame: Option<usize>,
    /// `timestamp`, if present.
    pub timestamp: Option<usize>,
    /// The muscle columns: name and field index, in header order.
    pub muscles: Vec<(String, usize)>,
    /// The `jaw` column.
    pub jaw: usize,
    /// The number of fields every row must have.
    pub field_count: usize,
}

impl ActsColumns {
    /// Reads a header line; the message says why it is not an activation CSV's.
    pub fn from_header(line: &str) -> Result<ActsColumns, String> {
        let line = line
            .trim_end_matches(['\r', '\n'])
            .trim_start_matches('\u{feff}');
        let names: Vec<&str> = line.split(',').map(str::trim).collect();
        let find = |n: &str| names.iter().position(|x| *x == n);
        let jaw = find("jaw").ok_or("the header has no `jaw` column: not an activation CSV")?;
        let mut muscles: Vec<(String, usize)> = Vec::new();
        for (index, name) in names.iter().enumerate() {
            if is_reserved(name) {
                continue;
            }
            if name.is_empty() || muscles.iter().any(|(m, _)| m == name) {
                return Err(format!(
                    "column {} is empty or repeated (`{name}`)",
                    index + 1
                ));
            }
            muscles.push((name.to_string(), index));
        }
        Ok(ActsColumns {
            frame: find("frame"),
            timestamp: find("timestamp"),
            muscles,
            jaw,
            field_count: names.len(),
        })
    }

    /// Reads one data line; `line` is its 1-based number.
    pub fn parse_row(&self, text: &str, line: usize) -> Result<ActsRow, RowError> {
        let fields = split_fields(text.trim_end_matches(['\r', '\n']));
        if fields.len() != self.field_count {
            return Err(RowError {
                line,
                column: None,
                message: format!(
                    "{} fields, but the header has {}",
                    fields.len(),
                    self.field_count
                ),
            });
        }
        let row = Fields { line, fields };
        let number = |index: usize, what: &str| row.number(index, what);
        let frame = self.frame.map(|i| number(i, "frame")).transpose()?;
        let timestamp = self.timestamp.map(|i| number(i, "timestamp")).transpose()?;
        let muscles = self
            .muscles
            .iter()
            .map(|(name, i)| number(*i, name).map(|v| v as f32))
            .collect::<Result<Vec<_>, _>>()?;
        let jaw = number(self.jaw, "jaw")? as f32;
        Ok(ActsRow {
            line,
            frame,
            timestamp,
            muscles,
            jaw,
        })
    }
}

/// Columns that are not muscles.
fn is_reserved(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    let au = lower.len() >= 5
        && lower.starts_with("au")
        && (lower.ends_with("_r") || lower.ends_with("_c"));
    au || matches!(
        lower.as_str(),
        "frame" | "timestamp" | EXPLAINED | "jaw" | "success" | "confidence" | "face_id"
    )
}

/// One row: the values of [`ActsColumns::muscles`] in order, and the jaw.
#[derive(Debug, Clone, PartialEq)]
pub struct ActsRow {
    /// 1-based line number.
    pub line: usize,
    /// `frame`, if the file has it.
    pub frame: Option<f64>,
    /// `timestamp` in seconds, if the file has it.
    pub timestamp: Option<f64>,
    /// One value per muscle column.
    pub muscles: Vec<f32>,
    /// The jaw.
    pub jaw: f32,
}

/// Reads an activation CSV row by row.
#[derive(Debug)]
pub struct ActsReader<R> {
    lines: LineReader<R>,
    path: PathBuf,
    columns: ActsColumns,
}

impl<R: BufRead> ActsReader<R> {
    /// Reads the header; `path` names the input in messages.
    pub fn new(input: R, path: &Path) -> Result<ActsReader<R>, LoadError> {
        let mut lines = LineReader::new(input, MAX_LINE_BYTES);
        let header = loop {
            let read = lines
                .next_line()
                .map_err(|e| LoadError::new(path, format!("cannot read: {e}")))?;
            let Some(line) = read else {
                return Err(LoadError::new(path, "empty input: no header line"));
            };
            if !line.text.trim().is_empty() {
                break line;
            }
        };
        let columns = ActsColumns::from_header(&header.text).map_err(|m| LoadError {
            path: path.to_path_buf(),
            line: Some(header.number),
            column: None,
            message: m,
        })?;
        Ok(ActsReader {
            lines,
            path: path.to_path_buf(),
            columns,
        })
    }

    /// The header's columns.
    pub fn columns(&self) -> &ActsColumns {
        &self.columns
    }

    /// The next row (`Ok(None)` at the end); a row that cannot be read is `Ok(Some(Err))`.
    pub fn next_row(&mut self) -> Result<Option<Result<ActsRow, RowError>>, LoadError> {
        let read = next_row_line(&mut self.lines, &self.path)?;
        Ok(read.map(|line| line.and_then(|l| self.columns.parse_row(&l.text, l.number))))
    }
}

/// Maps a file's muscle columns onto a rig's muscles by name.
#[derive(Debug, Clone, PartialEq)]
pub struct MuscleMap {
    /// For each file column, the rig's muscle index (or `None`: the rig lacks it).
    pub targets: Vec<Option<usize>>,
    /// File columns the rig lacks.
    pub unknown: Vec<String>,
}

impl MuscleMap {
    /// The map of `columns` onto the rig's muscle names.
    pub fn new(columns: &ActsColumns, muscles: &[String]) -> MuscleMap {
        let targets: Vec<Option<usize>> = columns
            .muscles
            .iter()
            .map(|(name, _)| muscles.iter().position(|m| m == name))
            .collect();
        let unknown = columns
            .muscles
            .iter()
            .zip(&targets)
            .filter(|(_, t)| t.is_none())
            .map(|((n, _), _)| n.clone())
            .collect();
        MuscleMap { targets, unknown }
    }

    /// A row's activations on the rig (`count` muscles), each clamped to its range.
    pub fn activations(&self, row: &ActsRow, count: usize) -> Activations {
        let mut act = Activations {
            muscles: vec![0.0; count],
            jaw: row.jaw,
        };
        for (target, value) in self.targets.iter().zip(&row.muscles) {
            if let Some(slot) = target.and_then(|t| act.muscles.get_mut(t)) {
                *slot = *value;
            }
        }
        crate::facs::mapper::clamp_to_ranges(&mut act);
        act
    }
}

/// The activations of frame `frame` (the `frame` column; the 1-based row without one) of
/// the activation CSV at `path`, on a rig with these muscles.
pub fn read_frame(path: &Path, frame: u64, muscles: &[String]) -> Result<Activations, LoadError> {
    let file =
        std::fs::File::open(path).map_err(|e| LoadError::new(path, format!("cannot open: {e}")))?;
    let mut reader = ActsReader::new(std::io::BufReader::new(file), path)?;
    let map = MuscleMap::new(reader.columns(), muscles);
    let mut ordinal = 0u64;
    while let Some(row) = reader.next_row()? {
        ordinal += 1;
        let Ok(row) = row else { continue };
        if row.frame.map_or(ordinal, |f| f as u64) == frame {
            return Ok(map.activations(&row, muscles.len()));
        }
    }
    Err(LoadError::new(
        path,
        format!("no frame {frame} in the file"),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_written_are_read_back_by_name() {
        let muscles = vec!["A".to_string(), "B".to_string()];
        let header = header_line(&muscles, &["AU12_r".to_string()]);
        let act = Activations {
            muscles: vec![0.25, 1.5],
            jaw: 2.0,
        };
        let source = |frame: u64, confidence: Option<f32>| Source {
            frame,
            face: 1,
            timestamp: frame as f64 * 0.04,
            confidence,
        };
        let (first, second) = (
            row_line(source(1, None), None, &act, &[2.5]),
            row_line(source(2, Some(0.875)), Some(0.9), &act, &[2.5]),
        );
        assert_eq!(
            header,
            "frame, face_id, timestamp, confidence, success, explained, A, B, jaw, AU12_r"
        );
        assert_eq!(first, "1, 1, 0.040, , 1, , 0.2500, 1.5000, 2.0000, 2.500");
        assert!(
            second.starts_with("2, 1, 0.080, 0.875, 1, 0.9000, "),
            "{second}"
        );
        let text = format!("{header}\n{first}\n{second}\n");
        let mut reader = ActsReader::new(text.as_bytes(), Path::new("a.csv")).unwrap();
        assert!(is_header(&header));
        assert_eq!(reader.columns().muscles.len(), 2);
        let row = reader.next_row().unwrap().unwrap().unwrap();
        assert_eq!((row.muscles.clone(), row.jaw), (vec![0.25, 1.5], 2.0));
        // Another rig: B first, A missing, C unknown to the file.
        let map = MuscleMap::new(reader.columns(), &["B".into(), "C".into()]);
        assert_eq!(map.unknown, vec!["A".to_string()]);
        assert_eq!(map.activations(&row, 2).muscles, vec![1.5, 0.0]);
        assert!(reader.next_row().unwrap().unwrap().is_ok());
        assert!(reader.next_row().unwrap().is_none());
    }

    #[test]
    fn bad_rows_and_headers_say_where() {
        assert!(ActsColumns::from_header("frame, A, A, jaw").is_err());
        assert!(ActsColumns::from_header("frame, AU12_r").is_err());
        let mut reader = ActsReader::new(
            &b"frame, explained, A, jaw\n1, , x, 0\n"[..],
            Path::new("b.csv"),
        )
        .unwrap();
        let e = reader.next_row().unwrap().unwrap().unwrap_err();
        assert_eq!((e.line, e.column), (2, Some(6)));
    }
}
