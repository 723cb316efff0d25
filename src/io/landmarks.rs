//! Landmark files (`*.landmarks.ron`): the 68 iBUG points of a mesh, as vertex numbers or as
//! points in the mesh's coordinates.
//!
//! ```text
//! (
//!     version: 1,
//!     vertices: [2035, 1791, ...],      // or points: [(0.1, 2.0, 3.5), ...]
//! )
//! ```
//!
//! Exactly one of `vertices` and `points`, with 68 entries. Errors name the file, line and
//! column: of the entry for a bad landmark, of the list for a wrong count. The format is in
//! `docs/formats.md`. Files other tools write (MeshLab's `*.pp`, plain `*.txt`/`*.csv`/`*.xyz`
//! lists) are read by [`super::landmark_text`] and checked the same way.

use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::Deserialize;

use super::error::{read_text, LoadError, SaveError, MAX_FILE_BYTES};
use super::landmark_text::{self, form_of, Form};
use super::{atomic, ron_text};
use crate::landmarks::{LandmarkError, Landmarks, COUNT};
use crate::model::Mesh;

/// The landmark file format version this build reads and writes.
pub const LANDMARKS_VERSION: u32 = 1;

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename = "landmarks")]
struct LandmarksFile {
    version: u32,
    #[serde(default, deserialize_with = "bare_some")]
    vertices: Option<Vec<u32>>,
    #[serde(default, deserialize_with = "bare_some")]
    points: Option<Vec<[f32; 3]>>,
}

/// A list written bare (`vertices: [...]`), not as `Some([...])`.
fn bare_some<'de, D: serde::Deserializer<'de>, T: Deserialize<'de>>(
    d: D,
) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

/// Where a mesh's landmarks are looked for: `head.obj` -> `head.landmarks.ron`, in the same
/// folder.
pub fn beside(mesh: &Path) -> PathBuf {
    let stem = mesh
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    mesh.with_file_name(format!("{stem}.landmarks.ron"))
}

/// Reads and checks a landmark file (count, finite points; vertex numbers are checked
/// against a mesh by [`check_against`]).
pub fn load_landmarks(path: &Path) -> Result<Landmarks, LoadError> {
    let text = read_text(path, MAX_FILE_BYTES)?;
    parse_landmarks(&text, path)
}

/// Parses the text of a landmark file; `path` is used in messages only.
pub fn parse_landmarks(text: &str, path: &Path) -> Result<Landmarks, LoadError> {
    let form = landmark_text::form_of(path);
    if form != Form::Ron {
        let read = landmark_text::parse(text, path, form)?;
        read.landmarks.check().map_err(|e| locate(path, text, &e))?;
        return Ok(read.landmarks);
    }
    ron_text::check_version(path, text, LANDMARKS_VERSION, "landmark file")?;
    let file: LandmarksFile = ron_text::parse(path, text, "landmarks")?;
    let landmarks = match (file.vertices, file.points) {
        (Some(v), None) => Landmarks::Vertices(v),
        (None, Some(p)) => Landmarks::Points(p.into_iter().map(Vec3::from).collect()),
        (Some(_), Some(_)) => {
            let at = ron_text::find_field(text, 0, "points").unwrap_or(0);
            return Err(LoadError::at_offset(
                path,
                text,
                at,
                "give either `vertices` or `points`, not both",
            ));
        }
        (None, None) => {
            return Err(LoadError::new(
                path,
                format!(
                "no landmarks: expected `vertices: [...]` or `points: [...]` with {COUNT} entries"
            ),
            ))
        }
    };
    if file.version != LANDMARKS_VERSION {
        return Err(LoadError::new(
            path,
            format!("landmark file version {} is not supported", file.version),
        ));
    }
    landmarks.check().map_err(|e| locate(path, text, &e))?;
    Ok(landmarks)
}

/// Checks landmarks against the mesh they belong to: every vertex in range, and a set that
/// spans a face. Errors point at the landmark in the file's text.
pub fn check_against(
    landmarks: &Landmarks,
    mesh: &Mesh,
    path: &Path,
    text: Option<&str>,
) -> Result<Vec<Vec3>, LoadError> {
    landmarks.positions(mesh).map_err(|e| match text {
        Some(text) => locate(path, text, &e),
        None => LoadError::new(path, e.to_string()),
    })
}

/// Turns a landmark error into a load error at the entry (or list) it concerns.
pub fn locate(path: &Path, text: &str, error: &LandmarkError) -> LoadError {
    let entry = match error {
        LandmarkError::VertexOutOfRange { landmark, .. }
        | LandmarkError::NonFinite { landmark } => Some(*landmark),
        _ => None,
    };
    let offset = match landmark_text::form_of(path) {
        // The entry's own line in another tool's file, else its first.
        Form::PickedPoints | Form::Lines | Form::Ljson => {
            landmark_text::parse(text, path, form_of(path))
                .ok()
                .and_then(|read| {
                    let first = read.offsets.first().copied();
                    entry.and_then(|n| read.offsets.get(n).copied()).or(first)
                })
        }
        Form::Ron => {
            let list = ron_text::find_field(text, 0, "vertices")
                .or_else(|| ron_text::find_field(text, 0, "points"));
            entry
                .and_then(|n| list.and_then(|at| item_offset(text, at, n)))
                .or(list)
        }
    };
    match offset {
        Some(at) => LoadError::at_offset(path, text, at, error.to_string()),
        None => LoadError::new(path, error.to_string()),
    }
}

/// The byte offset of item `n` (0-based) of the list that follows `from`: items are
/// separated by commas at the list's own depth; `//` comments are skipped.
fn item_offset(text: &str, from: usize, n: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut i = from + text[from..].find('[')? + 1;
    let mut depth = 0usize;
    let mut index = 0usize;
    let mut start: Option<usize> = None;
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                i += text[i..].find('\n').unwrap_or(text.len() - i);
                continue;
            }
            b'(' | b'[' => {
                if depth == 0 && start.is_none() {
                    start = Some(i);
                }
                depth += 1;
            }
            b')' => depth = depth.saturating_sub(1),
            b']' if depth == 0 => return if index == n { start } else { None },
            b']' => depth -= 1,
            b',' if depth == 0 && start.is_some() => {
                if index == n {
                    return start;
                }
                index += 1;
                start = None;
            }
            c if !c.is_ascii_whitespace() && depth == 0 && start.is_none() => start = Some(i),
            _ => {}
        }
        i += 1;
    }
    None
}

/// Writes landmarks as RON text.
pub fn landmarks_to_ron(landmarks: &Landmarks) -> String {
    let mut out =
        String::from("// grimace landmarks: the 68 iBUG points; see docs/formats.md\n(\n");
    out.push_str(&format!("    version: {LANDMARKS_VERSION},\n"));
    match landmarks {
        Landmarks::Vertices(v) => {
            out.push_str("    vertices: [\n");
            for chunk in v.chunks(17) {
                let items: Vec<String> = chunk.iter().map(u32::to_string).collect();
                out.push_str(&format!("        {},\n", items.join(", ")));
            }
        }
        Landmarks::Points(p) => {
            out.push_str("    points: [\n");
            for point in p {
                out.push_str(&format!("        {},\n", ron_text::point(*point)));
            }
        }
    }
    out.push_str("    ],\n)\n");
    out
}

/// Writes a landmark file atomically, as RON (a name in another tool's form is refused).
pub fn save_landmarks(path: &Path, landmarks: &Landmarks) -> Result<(), SaveError> {
    // Another tool's form would be written as RON under its name and not read back.
    if form_of(path) != Form::Ron {
        return Err(SaveError::new(
            path,
            "landmarks are saved as RON: name the file NAME.landmarks.ron (MeshLab's .pp and \
             plain .txt, .csv, .xyz lists are read, not written)",
        ));
    }
    landmarks
        .check()
        .map_err(|e| SaveError::new(path, e.to_string()))?;
    atomic::write_atomic(path, landmarks_to_ron(landmarks).as_bytes())
        .map_err(|e| SaveError::io(path, &e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(vertices: &[u32]) -> String {
        landmarks_to_ron(&Landmarks::Vertices(vertices.to_vec()))
    }

    #[test]
    fn round_trips_vertices_and_points() {
        let v: Vec<u32> = (0..68).collect();
        let back = parse_landmarks(&text(&v), Path::new("a.landmarks.ron")).unwrap();
        assert_eq!(back, Landmarks::Vertices(v));
        let p: Vec<Vec3> = (0..68).map(|i| Vec3::new(i as f32, 0.5, -1.25)).collect();
        let t = landmarks_to_ron(&Landmarks::Points(p.clone()));
        assert_eq!(
            parse_landmarks(&t, Path::new("p.landmarks.ron")).unwrap(),
            Landmarks::Points(p)
        );
    }

    #[test]
    fn errors_point_at_the_place() {
        let path = Path::new("f.landmarks.ron");
        let err = parse_landmarks(&text(&[1, 2, 3]), path).unwrap_err();
        assert!(err.message.contains("3 landmarks given"), "{err}");
        assert_eq!(err.line, Some(4));
        let err = parse_landmarks("(version: 1)", path).unwrap_err();
        assert!(err.message.contains("no landmarks"), "{err}");
        let err = parse_landmarks("(version: 1, vertices: [1, x])", path).unwrap_err();
        assert!(err.line.is_some(), "{err}");
        let err = parse_landmarks("(version: 2, vertices: [])", path).unwrap_err();
        assert!(err.message.contains("version 2"), "{err}");

        // A vertex out of range points at its entry: landmark 20 is on the second line.
        let v: Vec<u32> = (0..68).map(|i| if i == 20 { 99_999 } else { i }).collect();
        let t = text(&v);
        let landmarks = parse_landmarks(&t, path).unwrap();
        let mesh = Mesh::new(vec![Vec3::ZERO; 100], vec![[0, 1, 2]]).unwrap();
        let err = check_against(&landmarks, &mesh, path, Some(&t)).unwrap_err();
        assert!(err.message.contains("landmark 20 is vertex 99999"), "{err}");
        let (line, column) = (err.line.unwrap(), err.column.unwrap());
        let at = t.lines().nth(line - 1).unwrap();
        assert!(at[column - 1..].starts_with("99999"), "{at} @ {column}");
    }
}
