//! OpenFace 2.0 CSV output: per-frame AU intensities written by OpenFace's FeatureExtraction.
//!
//! The reader takes what real files contain as normal:
//! - header names separated by `", "` (names are trimmed), data fields padded with spaces;
//! - LF, CRLF or CR line ends, a missing final newline, blank lines (ignored), a UTF-8 BOM;
//! - older column layouts: only `AUxx_r` intensity columns are required; `frame`,
//!   `timestamp` and `success` are used when present (without `success`, every row counts);
//!   everything else (`AUxx_c` presence, gaze, pose, landmarks) is ignored;
//! - `face_id` (OpenFace's multi-face tracker writes one row per face and frame): one face is
//!   followed ([`super::faces`]) and the other faces' rows are passed over and counted.
//! - for `grimace capture` ([`OpenFaceReader::with_landmarks`]): the 68 3D landmarks
//!   `X_0..X_67`, `Y_*`, `Z_*` (millimetres, camera coordinates; the lower-case `x_*`, `y_*`
//!   are the 2D image points) and the head pose `pose_Tx..pose_Rz` when present; the AU
//!   columns are then optional.
//!
//! Rows are read one at a time, so the same reader serves a file and a live stream on stdin.
//! A row that cannot be read is reported as [`RowOutcome::Malformed`] with its line number and
//! column, never as a panic; the caller decides whether to skip it or stop.

use std::io::BufRead;
use std::path::{Path, PathBuf};

use glam::Vec3;
use thiserror::Error;

use super::error::LoadError;
use super::faces::Faces;
use super::lines::{Line, LineReader};

/// The highest AU intensity OpenFace writes (`AUxx_r` runs from 0 to 5).
pub const OPENFACE_MAX_INTENSITY: f32 = 5.0;

/// The longest line the reader accepts, in bytes (a real row is under 16 KiB).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The largest frame number accepted (about a year of frames at 30 per second).
pub const MAX_FRAME: f64 = 1e9;

/// An error that stops reading: the header is unusable, or the input cannot be read. It
/// names the file (`-` for stdin), line and column like every other load error.
pub type OpenFaceError = LoadError;

/// One AU intensity column of the header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AuColumn {
    /// The FACS AU number (`AU12_r` is 12).
    pub number: u8,
    /// 0-based field index in each row.
    pub index: usize,
}

/// The columns the player uses, found by name in the header line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OpenFaceColumns {
    /// `frame` (1-based in OpenFace output), if present.
    pub frame: Option<usize>,
    /// `timestamp` in seconds, if present.
    pub timestamp: Option<usize>,
    /// `success` (0 or 1), if present; without it every row counts as tracked.
    pub success: Option<usize>,
    /// `face_id`, if present; without it the recording is one face.
    pub face_id: Option<usize>,
    /// `confidence`, if present (read with the landmarks only: `capture` passes it on).
    pub confidence: Option<usize>,
    /// The `AUxx_r` intensity columns, in header order.
    pub aus: Vec<AuColumn>,
    /// The 3D landmark columns, when read ([`OpenFaceReader::with_landmarks`]).
    pub landmarks: Option<LandmarkColumns>,
    /// `pose_Tx, pose_Ty, pose_Tz, pose_Rx, pose_Ry, pose_Rz`, when read with the landmarks
    /// and all present.
    pub pose: Option<[usize; 6]>,
    /// The number of fields every row must have.
    pub field_count: usize,
}

/// The field indices of the 68 3D landmarks (`X_i`, `Y_i`, `Z_i`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LandmarkColumns {
    /// `[X_i, Y_i, Z_i]` for landmark `i`.
    pub xyz: Vec<[usize; 3]>,
}

/// Number of 3D landmarks OpenFace writes (the iBUG 68-point scheme).
pub const LANDMARK_COUNT: usize = 68;

/// The pose column names, in [`OpenFaceColumns::pose`] order.
const POSE_NAMES: [&str; 6] = [
    "pose_Tx", "pose_Ty", "pose_Tz", "pose_Rx", "pose_Ry", "pose_Rz",
];

/// The reason a header line is unusable.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum HeaderError {
    /// The line has no `AUxx_r` column.
    #[error("the header has no AU intensity column (AU01_r ... AU45_r); is this OpenFace output?")]
    NoAuColumns,
    /// A column name appears twice.
    #[error("column `{0}` appears twice in the header")]
    Duplicate(String),
    /// 3D landmarks were asked for, and some or all of their columns are missing.
    #[error(
        "the header lacks {missing} of the 204 3D landmark columns (first missing: {first}); \
         capture needs X_0..X_67, Y_0..Y_67, Z_0..Z_67 in millimetres: run OpenFace's \
         FeatureExtraction with its default outputs or with -3Dfp"
    )]
    NoLandmarks {
        /// How many are missing.
        missing: usize,
        /// The first missing name.
        first: String,
    },
}

impl OpenFaceColumns {
    /// Finds the used columns in a header line (`frame, face_id, timestamp, ...`).
    pub fn from_header(line: &str) -> Result<OpenFaceColumns, HeaderError> {
        let columns = OpenFaceColumns::scan(line)?;
        if columns.aus.is_empty() {
            return Err(HeaderError::NoAuColumns);
        }
        Ok(columns)
    }

    /// Finds the used columns and the 3D landmarks (all 204 required) and pose (optional);
    /// the AU columns are optional.
    pub fn from_header_3d(line: &str) -> Result<OpenFaceColumns, HeaderError> {
        let mut columns = OpenFaceColumns::scan(line)?;
        let names = header_names(line);
        let find = |wanted: &str| names.iter().position(|n| *n == wanted);
        let mut xyz = Vec::with_capacity(LANDMARK_COUNT);
        let mut missing = Vec::new();
        for i in 0..LANDMARK_COUNT {
            let mut point = [0; 3];
            for (axis, slot) in ["X", "Y", "Z"].iter().zip(&mut point) {
                let name = format!("{axis}_{i}");
                match find(&name) {
                    Some(index) => *slot = index,
                    None => missing.push(name),
                }
            }
            xyz.push(point);
        }
        if let Some(first) = missing.first() {
            return Err(HeaderError::NoLandmarks {
                missing: missing.len(),
                first: first.clone(),
            });
        }
        columns.landmarks = Some(LandmarkColumns { xyz });
        let pose: Option<Vec<usize>> = POSE_NAMES.iter().map(|n| find(n)).collect();
        columns.pose = pose.and_then(|p| p.try_into().ok());
        Ok(columns)
    }

    /// The columns every reader uses: frame, timestamp, success and the AU intensities.
    fn scan(line: &str) -> Result<OpenFaceColumns, HeaderError> {
        let names = header_names(line);
        let mut columns = OpenFaceColumns {
            frame: None,
            timestamp: None,
            success: None,
            face_id: None,
            confidence: None,
            aus: Vec::new(),
            landmarks: None,
            pose: None,
            field_count: names.len(),
        };
        for (index, name) in names.iter().enumerate() {
            let slot = match name.to_ascii_lowercase().as_str() {
                "frame" => &mut columns.frame,
                "timestamp" => &mut columns.timestamp,
                "success" => &mut columns.success,
                "face_id" => &mut columns.face_id,
                "confidence" => &mut columns.confidence,
                _ => {
                    if let Some(number) = au_intensity_number(name) {
                        if columns.aus.iter().any(|c| c.number == number) {
                            return Err(HeaderError::Duplicate(name.to_string()));
                        }
                        columns.aus.push(AuColumn { number, index });
                    }
                    continue;
                }
            };
            if slot.is_some() {
                return Err(HeaderError::Duplicate(name.to_string()));
            }
            *slot = Some(index);
        }
        Ok(columns)
    }

    /// Reads one data line (without its line end) into a row; `line` is its 1-based number.
    pub fn parse_row(&self, text: &str, line: usize) -> Result<OpenFaceRow, RowError> {
        let text = text.trim_end_matches(['\r', '\n']);
        let fields = split_fields(text);
        if fields.len() != self.field_count {
            let message = if fields.len() < self.field_count {
                format!(
                    "{} of {} fields, the row is cut short",
                    fields.len(),
                    self.field_count
                )
            } else {
                format!(
                    "{} fields, but the header has {}",
                    fields.len(),
                    self.field_count
                )
            };
            return Err(RowError {
                line,
                column: None,
                message,
            });
        }
        let row = Fields { line, fields };
        let number = |index: usize, what: &str| row.number(index, what);
        // Frame numbers past the limit are refused here; times, whatever they come from, are
        // bounded by the player's stream rules (`play::rules`).
        let frame = self
            .frame
            .map(|i| row.in_range(i, "frame", MAX_FRAME))
            .transpose()?;
        let timestamp = self.timestamp.map(|i| number(i, "timestamp")).transpose()?;
        let success = match self.success {
            Some(i) => number(i, "success")? != 0.0,
            None => true,
        };
        let face = self.face_id.map(|i| row.face_id(i)).transpose()?;
        let mut intensities = Vec::with_capacity(self.aus.len());
        // Rows OpenFace could not track carry placeholder values; they are skipped unread.
        if success {
            for au in &self.aus {
                let name = format!("AU{:02}_r", au.number);
                let value = number(au.index, &name)? as f32;
                if !value.is_finite() {
                    return Err(RowError {
                        line,
                        column: Some(row.fields[au.index].0),
                        message: format!("{name} `{}` is far out of range", row.fields[au.index].1),
                    });
                }
                intensities.push(value);
            }
        }
        let mut landmarks = Vec::new();
        let mut pose = None;
        let mut confidence = None;
        if let (true, Some(columns)) = (success, &self.landmarks) {
            if let Some(i) = self.confidence {
                confidence = Some(number(i, "confidence")? as f32);
            }
            landmarks.reserve(LANDMARK_COUNT);
            for (i, [x, y, z]) in columns.xyz.iter().enumerate() {
                let axis = |index: usize, name: &str| {
                    number(index, &format!("{name}_{i}")).map(|v| v as f32)
                };
                landmarks.push(Vec3::new(axis(*x, "X")?, axis(*y, "Y")?, axis(*z, "Z")?));
            }
            if let Some(indices) = &self.pose {
                let mut values = [0.0; 6];
                for ((value, &index), name) in values.iter_mut().zip(indices).zip(POSE_NAMES) {
                    *value = number(index, name)?;
                }
                pose = Some(values);
            }
        }
        Ok(OpenFaceRow {
            line,
            frame,
            timestamp,
            success,
            face,
            confidence,
            intensities,
            landmarks,
            pose,
        })
    }
}

/// The trimmed names of a header line.
fn header_names(line: &str) -> Vec<&str> {
    line.trim_end_matches(['\r', '\n'])
        .trim_start_matches('\u{feff}')
        .split(',')
        .map(str::trim)
        .collect()
}

/// `AU12_r` -> 12 (any case); other names -> `None`.
fn au_intensity_number(name: &str) -> Option<u8> {
    // Bytes, not string slices: a name may hold any characters.
    let bytes = name.as_bytes();
    if bytes.len() < 5
        || !bytes[..2].eq_ignore_ascii_case(b"AU")
        || !bytes[bytes.len() - 2..].eq_ignore_ascii_case(b"_r")
    {
        return None;
    }
    let digits = &bytes[2..bytes.len() - 2];
    if digits.len() > 2 || !digits.iter().all(u8::is_ascii_digit) {
        return None;
    }
    let number = digits.iter().fold(0u8, |n, d| n * 10 + (d - b'0'));
    (number >= 1).then_some(number)
}

/// Splits a CSV line on commas, trimming each field; each field comes with its 1-based column.
pub(crate) fn split_fields(text: &str) -> Vec<(usize, &str)> {
    let mut fields = Vec::new();
    let mut column = 1;
    for raw in text.split(',') {
        let padding = raw.len() - raw.trim_start().len();
        let lead = raw[..padding].chars().count();
        fields.push((column + lead, raw.trim()));
        column += raw.chars().count() + 1;
    }
    fields
}

/// One data row's fields with its line, for reading numbers with errors that name their
/// place (OpenFace rows and activation rows alike).
pub(crate) struct Fields<'a> {
    /// The row's 1-based line.
    pub(crate) line: usize,
    /// The trimmed fields with their 1-based columns ([`split_fields`]).
    pub(crate) fields: Vec<(usize, &'a str)>,
}

impl Fields<'_> {
    /// The field at `index` as a finite number; `what` names it in the error.
    pub(crate) fn number(&self, index: usize, what: &str) -> Result<f64, RowError> {
        let (column, field) = self.fields[index];
        parse_number(field).ok_or_else(|| RowError {
            line: self.line,
            column: Some(column),
            message: format!("{what} `{}` is not a number", shorten(field)),
        })
    }

    /// The field at `index` as a face number: a whole number from 0 to
    /// [`super::faces::MAX_FACE_ID`].
    fn face_id(&self, index: usize) -> Result<u32, RowError> {
        let value = self.in_range(index, "face_id", f64::from(super::faces::MAX_FACE_ID))?;
        if value < 0.0 || value.fract() != 0.0 {
            return Err(RowError {
                line: self.line,
                column: Some(self.fields[index].0),
                message: format!(
                    "face_id `{}` is not a face number (0, 1, 2...)",
                    shorten(self.fields[index].1)
                ),
            });
        }
        Ok(value as u32)
    }

    /// [`Fields::number`], refused beyond `limit` in size.
    pub(crate) fn in_range(&self, index: usize, what: &str, limit: f64) -> Result<f64, RowError> {
        let value = self.number(index, what)?;
        if value.abs() <= limit {
            return Ok(value);
        }
        Err(RowError {
            line: self.line,
            column: Some(self.fields[index].0),
            message: format!(
                "{what} {} is out of range (at most {limit} in size)",
                shorten(self.fields[index].1)
            ),
        })
    }
}

/// A finite decimal number (OpenFace writes plain decimals; `nan` and `inf` are refused).
pub(crate) fn parse_number(field: &str) -> Option<f64> {
    let value: f64 = field.parse().ok()?;
    value.is_finite().then_some(value)
}

/// The first characters of a field, for messages.
pub(crate) fn shorten(field: &str) -> String {
    const MAX: usize = 24;
    if field.chars().count() <= MAX {
        field.to_string()
    } else {
        let head: String = field.chars().take(MAX).collect();
        format!("{head}...")
    }
}

/// One data row.
#[derive(Debug, Clone, PartialEq)]
pub struct OpenFaceRow {
    /// 1-based line number in the input.
    pub line: usize,
    /// The `frame` value, if the layout has one.
    pub frame: Option<f64>,
    /// The `timestamp` value in seconds, if the layout has one.
    pub timestamp: Option<f64>,
    /// Whether OpenFace tracked a face in this frame (`success` 1, or no `success` column).
    pub success: bool,
    /// The `face_id` value, if the layout has one.
    pub face: Option<u32>,
    /// The tracker's `confidence` (read with the landmarks, on tracked rows).
    pub confidence: Option<f32>,
    /// Raw intensities, one per [`OpenFaceColumns::aus`] entry (empty when not `success`).
    pub intensities: Vec<f32>,
    /// The 68 3D landmarks in millimetres, camera coordinates (empty unless read with
    /// [`OpenFaceReader::with_landmarks`], and when not `success`).
    pub landmarks: Vec<Vec3>,
    /// `pose_Tx, pose_Ty, pose_Tz` (mm) and `pose_Rx, pose_Ry, pose_Rz` (radians), when read
    /// with the landmarks.
    pub pose: Option<[f64; 6]>,
}

/// A data row that cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("line {line}{}: {message}", column.map(|c| format!(", column {c}")).unwrap_or_default())]
pub struct RowError {
    /// 1-based line number.
    pub line: usize,
    /// 1-based column of the bad field, when one field is to blame.
    pub column: Option<usize>,
    /// What is wrong.
    pub message: String,
}

/// What one data line held.
#[derive(Debug, Clone, PartialEq)]
pub enum RowOutcome {
    /// A row; see [`OpenFaceRow::success`] for whether it carries AU values.
    Row(OpenFaceRow),
    /// A row that cannot be read.
    Malformed(RowError),
}

/// Reads an OpenFace CSV row by row from any buffered input (a file or stdin).
#[derive(Debug)]
pub struct OpenFaceReader<R> {
    lines: LineReader<R>,
    path: PathBuf,
    columns: OpenFaceColumns,
    faces: Faces,
}

impl<R: BufRead> OpenFaceReader<R> {
    /// Reads the header line (blank lines before it are skipped); `path` names the input in
    /// messages (`-` for stdin).
    pub fn new(input: R, path: &Path) -> Result<OpenFaceReader<R>, OpenFaceError> {
        OpenFaceReader::open(input, path, OpenFaceColumns::from_header)
    }

    /// [`OpenFaceReader::new`] for a recording whose rows must carry the 68 3D landmarks
    /// (`grimace capture`); a header without them is an error that names the columns.
    pub fn with_landmarks(input: R, path: &Path) -> Result<OpenFaceReader<R>, OpenFaceError> {
        OpenFaceReader::open(input, path, OpenFaceColumns::from_header_3d)
    }

    fn open(
        input: R,
        path: &Path,
        scan: fn(&str) -> Result<OpenFaceColumns, HeaderError>,
    ) -> Result<OpenFaceReader<R>, OpenFaceError> {
        let mut lines = LineReader::new(input, MAX_LINE_BYTES);
        let error = |line: Option<usize>, message: String| OpenFaceError {
            path: path.to_path_buf(),
            line,
            column: None,
            message,
        };
        let header = loop {
            let read = lines
                .next_line()
                .map_err(|e| error(Some(lines.number() + 1), format!("cannot read: {e}")))?;
            let Some(line) = read else {
                return Err(error(None, "empty input: no header line".into()));
            };
            if let Some(why) = line.too_long(MAX_LINE_BYTES) {
                return Err(error(Some(line.number), format!("the header: {why}")));
            }
            if !line.text.trim().is_empty() {
                break line;
            }
        };
        let columns = scan(&header.text).map_err(|e| error(Some(header.number), e.to_string()))?;
        Ok(OpenFaceReader {
            lines,
            path: path.to_path_buf(),
            columns,
            faces: Faces::new(None),
        })
    }

    /// Follows face `id` of a recording with several (`None`, the default: the face of the
    /// first tracked row); see [`super::faces`].
    pub fn follow_face(mut self, id: Option<u32>) -> OpenFaceReader<R> {
        self.faces = Faces::new(id);
        self
    }

    /// The face followed and the rows of other faces passed over so far.
    pub fn faces(&self) -> &Faces {
        &self.faces
    }

    /// Once, when a row of another face has been passed over: what is happening.
    pub fn take_face_notice(&mut self) -> Option<String> {
        self.faces.take_notice()
    }

    /// The columns found in the header.
    pub fn columns(&self) -> &OpenFaceColumns {
        &self.columns
    }

    /// The input's name in messages.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The next row, `Ok(None)` at the end of the input; blank lines are passed over. A line
    /// longer than [`MAX_LINE_BYTES`] is a malformed row, read past in bounded memory.
    /// Rows of faces other than the followed one are passed over ([`OpenFaceReader::faces`]
    /// counts them).
    pub fn next_row(&mut self) -> Result<Option<RowOutcome>, OpenFaceError> {
        loop {
            let Some(line) = next_row_line(&mut self.lines, &self.path)? else {
                return Ok(None);
            };
            let outcome = match line {
                Ok(line) => match self.columns.parse_row(&line.text, line.number) {
                    Ok(row) => RowOutcome::Row(row),
                    Err(e) => RowOutcome::Malformed(e),
                },
                Err(e) => RowOutcome::Malformed(e),
            };
            match &outcome {
                RowOutcome::Row(row) if !self.faces.admits(row.face, row.success) => continue,
                _ => return Ok(Some(outcome)),
            }
        }
    }
}

impl<R: BufRead> Iterator for OpenFaceReader<R> {
    type Item = Result<RowOutcome, OpenFaceError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_row().transpose()
    }
}

/// The next line of a CSV recording's rows, `None` at the end: blank lines are passed over,
/// and a line longer than [`MAX_LINE_BYTES`] is a malformed row, read past in bounded memory.
/// Shared by the OpenFace, Live Link Face and activation readers; a read that fails is an
/// error naming `path` and the line it stopped at.
pub(crate) fn next_row_line<R: BufRead>(
    lines: &mut LineReader<R>,
    path: &Path,
) -> Result<Option<Result<Line, RowError>>, LoadError> {
    loop {
        let number = lines.number() + 1;
        let read = lines.next_line().map_err(|e| LoadError {
            path: path.to_path_buf(),
            line: Some(number),
            column: None,
            message: format!("cannot read: {e}"),
        })?;
        let Some(line) = read else {
            return Ok(None);
        };
        if let Some(message) = line.too_long(MAX_LINE_BYTES) {
            return Ok(Some(Err(RowError {
                line: line.number,
                column: None,
                message,
            })));
        }
        if !line.text.trim().is_empty() {
            return Ok(Some(Ok(line)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_all(text: &str) -> (OpenFaceColumns, Vec<RowOutcome>) {
        let mut reader = OpenFaceReader::new(text.as_bytes(), Path::new("t.csv")).unwrap();
        let rows = reader.by_ref().map(Result::unwrap).collect();
        (reader.columns().clone(), rows)
    }

    #[test]
    fn header_names_are_trimmed_and_au_columns_found() {
        let columns = OpenFaceColumns::from_header(
            "frame, face_id, timestamp, confidence, success, AU01_r, AU12_r, AU01_c\r\n",
        )
        .unwrap();
        assert_eq!(columns.frame, Some(0));
        assert_eq!(columns.timestamp, Some(2));
        assert_eq!(columns.success, Some(4));
        assert_eq!(
            columns.aus,
            vec![
                AuColumn {
                    number: 1,
                    index: 5
                },
                AuColumn {
                    number: 12,
                    index: 6
                }
            ]
        );
        assert_eq!(columns.field_count, 8);
    }

    #[test]
    fn rows_of_a_second_face_are_passed_over_and_counted() {
        let text = "frame, face_id, timestamp, success, AU12_r\n\
                    1, 0, 0.0, 1, 1.0\n1, 1, 0.0, 1, 4.0\n\
                    2, 1, 0.1, 1, 4.0\n2, 0, 0.1, 1, 2.0\n3, 0, 0.2, x, 2.0\n";
        let mut reader = OpenFaceReader::new(text.as_bytes(), Path::new("t.csv")).unwrap();
        let rows: Vec<RowOutcome> = reader.by_ref().map(Result::unwrap).collect();
        let values: Vec<f32> = rows
            .iter()
            .filter_map(|r| match r {
                RowOutcome::Row(row) => Some(row.intensities[0]),
                RowOutcome::Malformed(_) => None,
            })
            .collect();
        assert_eq!(values, vec![1.0, 2.0]);
        assert_eq!(
            rows.len(),
            3,
            "the malformed row is still reported: {rows:?}"
        );
        assert_eq!(reader.faces().skipped(), 2);
        assert!(reader.take_face_notice().is_some());

        let mut second = OpenFaceReader::new(text.as_bytes(), Path::new("t.csv"))
            .unwrap()
            .follow_face(Some(1));
        let values: Vec<f32> = second
            .by_ref()
            .filter_map(|r| match r.unwrap() {
                RowOutcome::Row(row) => Some(row.intensities[0]),
                RowOutcome::Malformed(_) => None,
            })
            .collect();
        assert_eq!(values, vec![4.0, 4.0]);

        let (_, rows) = read_all("face_id, AU12_r\n0.5, 1.0\n");
        let RowOutcome::Malformed(e) = &rows[0] else {
            panic!("{rows:?}")
        };
        assert!(e.message.contains("not a face number"), "{e}");
    }

    #[test]
    fn header_without_au_columns_is_refused() {
        assert_eq!(
            OpenFaceColumns::from_header("frame, timestamp, AU01_c"),
            Err(HeaderError::NoAuColumns)
        );
        assert!(matches!(
            OpenFaceColumns::from_header("AU01_r, AU01_r"),
            Err(HeaderError::Duplicate(_))
        ));
    }

    #[test]
    fn padded_fields_crlf_and_missing_final_newline_are_read() {
        let (_, rows) = read_all(
            "frame, timestamp, success, AU06_r, AU12_r\r\n1,  0.000,  1,  1.50,  2.25\r\n2, 0.040, 1, 0, 5",
        );
        assert_eq!(rows.len(), 2);
        let RowOutcome::Row(first) = &rows[0] else {
            panic!("{rows:?}")
        };
        assert_eq!(first.line, 2);
        assert_eq!(first.timestamp, Some(0.0));
        assert_eq!(first.intensities, vec![1.5, 2.25]);
        let RowOutcome::Row(last) = &rows[1] else {
            panic!("{rows:?}")
        };
        assert_eq!(last.line, 3);
        assert_eq!(last.frame, Some(2.0));
        assert_eq!(last.intensities, vec![0.0, 5.0]);
    }

    #[test]
    fn success_zero_rows_carry_no_values() {
        let (_, rows) = read_all("success,AU01_r\n0,junk\n1,2\n");
        assert_eq!(
            rows[0],
            RowOutcome::Row(OpenFaceRow {
                line: 2,
                frame: None,
                timestamp: None,
                success: false,
                face: None,
                confidence: None,
                intensities: vec![],
                landmarks: vec![],
                pose: None,
            })
        );
        assert!(matches!(&rows[1], RowOutcome::Row(r) if r.success && r.intensities == [2.0]));
    }

    #[test]
    fn without_success_column_every_row_counts() {
        let (columns, rows) = read_all("AU04_r\n1\n\n2\n");
        assert_eq!(columns.success, None);
        assert_eq!(rows.len(), 2, "the blank line is passed over");
        assert!(rows
            .iter()
            .all(|r| matches!(r, RowOutcome::Row(r) if r.success)));
    }

    #[test]
    fn absurd_frame_numbers_are_refused_at_their_field() {
        let (_, rows) = read_all("frame, timestamp, AU01_r\n2e12, 0.1, 1\n3, 1e6, 1\n");
        let RowOutcome::Malformed(e) = &rows[0] else {
            panic!("{rows:?}")
        };
        assert_eq!((e.line, e.column), (2, Some(1)));
        assert!(e.message.starts_with("frame 2e12"), "{}", e.message);
        assert!(matches!(&rows[1], RowOutcome::Row(r) if r.timestamp == Some(1e6)));
    }

    #[test]
    fn cr_line_ends_read_every_row() {
        let (_, rows) = read_all("frame, AU01_r\r1, 0.5\r2, 1.5\r");
        assert_eq!(rows.len(), 2);
        assert!(matches!(&rows[1], RowOutcome::Row(r) if r.line == 3 && r.intensities == [1.5]));
    }

    #[test]
    fn malformed_rows_name_line_and_column() {
        let (_, rows) = read_all("frame, AU01_r, AU02_r\n1, 0.5\n2, 0.5, abc\n3, 0.5, nan\n");
        assert_eq!(
            rows[0],
            RowOutcome::Malformed(RowError {
                line: 2,
                column: None,
                message: "2 of 3 fields, the row is cut short".into()
            })
        );
        let RowOutcome::Malformed(e) = &rows[1] else {
            panic!("{rows:?}")
        };
        assert_eq!((e.line, e.column), (3, Some(9)));
        assert_eq!(
            e.to_string(),
            "line 3, column 9: AU02_r `abc` is not a number"
        );
        assert!(matches!(&rows[2], RowOutcome::Malformed(e) if e.line == 4));
    }

    #[test]
    fn empty_input_and_bad_header_are_errors_with_the_path() {
        let e = OpenFaceReader::new(&b""[..], Path::new("x.csv")).unwrap_err();
        assert_eq!(e.to_string(), "x.csv: empty input: no header line");
        let e = OpenFaceReader::new(&b"\nframe, x\n"[..], Path::new("x.csv")).unwrap_err();
        assert!(
            e.to_string().starts_with("x.csv:2: the header has no AU"),
            "{e}"
        );
    }

    #[test]
    fn bom_and_au_name_variants() {
        let columns = OpenFaceColumns::from_header(
            "\u{feff}frame,au9_R,AU100_r,AU_r,AU00_r,aU\u{fffd}/,AU\u{e9}_r",
        )
        .unwrap();
        assert_eq!(columns.frame, Some(0));
        assert_eq!(
            columns.aus,
            vec![AuColumn {
                number: 9,
                index: 1
            }]
        );
    }

    fn landmark_header(extra: &str) -> String {
        let mut names = vec!["frame".to_string(), "success".into(), "x_0".into()];
        for axis in ["X", "Y", "Z"] {
            names.extend((0..LANDMARK_COUNT).map(|i| format!("{axis}_{i}")));
        }
        names.push(extra.to_string());
        names.join(", ")
    }

    #[test]
    fn landmarks_are_read_in_3d_and_only_when_asked() {
        let header = landmark_header("AU12_r");
        let mut row: Vec<String> = vec!["1".into(), "1".into(), "99".into()];
        row.extend((0..3 * LANDMARK_COUNT).map(|k| format!("{k}.5")));
        row.push("2.0".into());
        let text = format!("{header}\n{}\n", row.join(", "));
        let mut reader =
            OpenFaceReader::with_landmarks(text.as_bytes(), Path::new("l.csv")).unwrap();
        assert_eq!(reader.columns().pose, None);
        let Some(RowOutcome::Row(r)) = reader.next_row().unwrap() else {
            panic!()
        };
        assert_eq!(r.landmarks.len(), LANDMARK_COUNT);
        assert_eq!(r.landmarks[1], Vec3::new(1.5, 69.5, 137.5));
        assert_eq!(r.intensities, vec![2.0]);
        let (columns, rows) = read_all(&text);
        assert_eq!(columns.landmarks, None);
        assert!(matches!(&rows[0], RowOutcome::Row(r) if r.landmarks.is_empty()));
    }

    #[test]
    fn a_header_without_3d_landmarks_names_what_capture_needs() {
        let e =
            OpenFaceReader::with_landmarks(&b"frame, x_0, y_0, AU01_r\n"[..], Path::new("2d.csv"))
                .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("2d.csv:1: the header lacks 204 of the 204 3D landmark columns (first missing: X_0)"),
            "{e}"
        );
        // Without AU columns the landmarks are enough; a NaN landmark is a malformed row.
        let header = landmark_header("confidence");
        let mut row: Vec<String> = vec!["1".into(), "1".into(), "0".into()];
        row.extend((0..3 * LANDMARK_COUNT).map(|_| "nan".to_string()));
        row.push("0.9".into());
        let text = format!("{header}\n{}\n", row.join(","));
        let mut reader =
            OpenFaceReader::with_landmarks(text.as_bytes(), Path::new("n.csv")).unwrap();
        assert!(matches!(
            reader.next_row().unwrap(),
            Some(RowOutcome::Malformed(RowError {
                line: 2,
                column: Some(_),
                ..
            }))
        ));
    }

    #[test]
    fn invalid_utf8_is_a_malformed_row_not_an_error() {
        let input: &[u8] = b"AU01_r\n\xff\xfe\n1\n";
        let mut reader = OpenFaceReader::new(input, Path::new("b.csv")).unwrap();
        assert!(matches!(
            reader.next_row().unwrap(),
            Some(RowOutcome::Malformed(RowError { line: 2, .. }))
        ));
        assert!(matches!(
            reader.next_row().unwrap(),
            Some(RowOutcome::Row(_))
        ));
        assert_eq!(reader.next_row().unwrap(), None);
    }
}
