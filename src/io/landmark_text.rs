//! Landmark files written by other tools, read as they are: MeshLab's picked points
//! (`*.pp`, from its PickPoints editor), menpo's and landmarker.io's LJSON (`*.ljson`) and
//! plain text (`*.txt`, `*.csv`, `*.xyz`), so landmarks picked elsewhere need no conversion
//! before `fit-rig`.
//!
//! - Picked points: the `<point x=".." y=".." z=".." .../>` elements, in file order (their
//!   `name`s are not read: MeshLab numbers from 0 or 1 as its user chose). A point with
//!   `active="0"` was never placed and is refused.
//! - LJSON: the 3D points of its landmark group (`landmarks: {points: [[x, y, z], ...]}`, or
//!   `landmarks: [{point: [x, y, z]}, ...]`), at the top level (version 2) or in `groups` (a
//!   file with several groups must have one of 68 points). When the group's labels are the
//!   iBUG 68 scheme's parts under menpo's names (`jaw` or `chin`, `left_eyebrow` or
//!   `leyebrow`, ..., `mouth`; left is the picture's left, the subject's right), their
//!   masks put the points in the iBUG order, whatever order the file lists them in; else
//!   the file's order is the iBUG order. A point that is `null` (never placed) or has two
//!   coordinates (an image's landmarks) is refused.
//! - Plain text: one landmark a line, in the iBUG order; a line is three numbers (x y z in the
//!   mesh's coordinates), a label and three numbers (`17,x,y,z` or `brow_r1 x y z`: the label
//!   is not read), or one whole number (a vertex number, from 0), separated by spaces, tabs,
//!   commas or semicolons. Blank lines (separators alone too) and lines starting with `#`
//!   or `//` are passed over, and so is a first line of words (a CSV header such as `x,y,z`). Every line takes
//!   the same form.
//!
//! Errors name the file, line and column of the entry at fault; each entry's place is kept so
//! that a check against the mesh (a vertex number past its end) points at the line too.

use std::path::Path;

use glam::Vec3;

use super::error::LoadError;
use crate::landmarks::Landmarks;

/// A landmark file's form, by its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// grimace's own `*.landmarks.ron` (and any name not below).
    Ron,
    /// MeshLab's picked points, `*.pp`.
    PickedPoints,
    /// One landmark a line, `*.txt`, `*.csv`, `*.xyz`.
    Lines,
    /// menpo's and landmarker.io's LJSON, `*.ljson`.
    Ljson,
}

/// The form of the landmark file at `path`, from its extension.
pub fn form_of(path: &Path) -> Form {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("pp") => Form::PickedPoints,
        Some("txt" | "csv" | "xyz") => Form::Lines,
        Some("ljson") => Form::Ljson,
        _ => Form::Ron,
    }
}

/// Landmarks read from another tool's file, with each entry's byte offset in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct Read {
    /// The landmarks, unchecked (the caller checks count and values as for RON files).
    pub landmarks: Landmarks,
    /// Byte offset of each entry, in order.
    pub offsets: Vec<usize>,
}

/// Parses `text` in `form` (not [`Form::Ron`]); `path` names the file in errors.
pub fn parse(text: &str, path: &Path, form: Form) -> Result<Read, LoadError> {
    match form {
        Form::PickedPoints => picked_points(text, path),
        Form::Ljson => ljson(text, path),
        Form::Lines | Form::Ron => lines(text, path),
    }
}

/// MeshLab's `<point .../>` elements.
fn picked_points(text: &str, path: &Path) -> Result<Read, LoadError> {
    let mut points = Vec::new();
    let mut offsets = Vec::new();
    let mut from = 0;
    while let Some(found) = text[from..].find("<point") {
        let start = from + found;
        let after = start + "<point".len();
        // `<pointSet>` or another element that only begins with the word is not a point.
        if !text[after..].starts_with(|c: char| c.is_whitespace() || c == '/' || c == '>') {
            from = after;
            continue;
        }
        let end = text[after..]
            .find('>')
            .map(|e| after + e)
            .ok_or_else(|| LoadError::at_offset(path, text, start, "a `<point` that never ends"))?;
        let element = &text[after..end];
        let number = |name: &str| -> Result<f32, LoadError> {
            let (at, value) = attribute(element, name).ok_or_else(|| {
                LoadError::at_offset(
                    path,
                    text,
                    start,
                    format!("point {} has no `{name}`", points.len() + 1),
                )
            })?;
            value.trim().parse::<f32>().map_err(|_| {
                LoadError::at_offset(
                    path,
                    text,
                    after + at,
                    format!("{name}=\"{value}\" is not a number"),
                )
            })
        };
        let point = Vec3::new(number("x")?, number("y")?, number("z")?);
        if let Some((_, active)) = attribute(element, "active") {
            if active.trim() == "0" {
                return Err(LoadError::at_offset(
                    path,
                    text,
                    start,
                    format!(
                        "point {} is not placed (active=\"0\"): place every landmark in MeshLab before saving",
                        points.len() + 1
                    ),
                ));
            }
        }
        points.push(point);
        offsets.push(start);
        from = end;
    }
    if points.is_empty() {
        return Err(LoadError::new(
            path,
            "no `<point x=\"..\" y=\"..\" z=\"..\"/>` elements: is this a MeshLab picked points file?",
        ));
    }
    Ok(Read {
        landmarks: Landmarks::Points(points),
        offsets,
    })
}

/// The parts of the iBUG 68 scheme under menpo's label names (its `face_ibug_68` labeller
/// and the older short names), with their first landmark and size.
const IBUG_PARTS: [(&[&str], usize, usize); 7] = [
    (&["jaw", "chin"], 0, 17),
    (&["left_eyebrow", "leyebrow"], 17, 5),
    (&["right_eyebrow", "reyebrow"], 22, 5),
    (&["nose"], 27, 9),
    (&["left_eye", "leye"], 36, 6),
    (&["right_eye", "reye"], 42, 6),
    (&["mouth"], 48, 20),
];

/// An LJSON file's top level: version 2 holds one group's `landmarks` and `labels` there,
/// version 3 (and menpo's exports) hold named `groups`.
#[derive(serde::Deserialize)]
struct LjsonFile<'a> {
    #[serde(borrow, default)]
    groups: Option<std::collections::BTreeMap<String, &'a serde_json::value::RawValue>>,
    #[serde(borrow, default)]
    landmarks: Option<&'a serde_json::value::RawValue>,
    #[serde(borrow, default)]
    labels: Option<&'a serde_json::value::RawValue>,
}

/// One LJSON group.
#[derive(serde::Deserialize)]
struct LjsonGroup<'a> {
    #[serde(borrow)]
    landmarks: &'a serde_json::value::RawValue,
    #[serde(borrow, default)]
    labels: Option<&'a serde_json::value::RawValue>,
}

/// A group's points as a list (`{points: [...]}`).
#[derive(serde::Deserialize)]
struct LjsonPoints<'a> {
    #[serde(borrow)]
    points: Vec<&'a serde_json::value::RawValue>,
}

/// A group's point as an entry of a list of entries (`[{point: [...]}, ...]`).
#[derive(serde::Deserialize)]
struct LjsonEntry<'a> {
    #[serde(borrow)]
    point: &'a serde_json::value::RawValue,
}

/// A label: its name and the indices of its points.
#[derive(serde::Deserialize)]
struct LjsonLabel {
    label: String,
    mask: Vec<usize>,
}

/// Where a raw JSON value borrowed from `text` begins in it.
fn offset_in(text: &str, raw: &serde_json::value::RawValue) -> usize {
    raw.get().as_ptr() as usize - text.as_ptr() as usize
}

/// menpo's and landmarker.io's LJSON (module docs).
fn ljson(text: &str, path: &Path) -> Result<Read, LoadError> {
    let offset = |raw: &serde_json::value::RawValue| offset_in(text, raw);
    // a byte-order mark (JSON saved on Windows) is passed over; serde_json refuses it
    let body = text.strip_prefix('\u{feff}').unwrap_or(text);
    let file: LjsonFile = serde_json::from_str(body).map_err(|e| {
        LoadError::at(
            path,
            e.line(),
            e.column(),
            format!("not an LJSON file: {e}"),
        )
    })?;
    let (landmarks, labels) = match (file.landmarks, file.groups) {
        (Some(landmarks), _) => (landmarks, file.labels),
        (None, Some(groups)) => {
            let group = ljson_group(&groups, path)?;
            let group: LjsonGroup = serde_json::from_str(group.get()).map_err(|_| {
                LoadError::at_offset(path, text, offset(group), "the group has no `landmarks`")
            })?;
            (group.landmarks, group.labels)
        }
        (None, None) => {
            return Err(LoadError::new(
                path,
                "no `landmarks` and no `groups`: is this an LJSON file?",
            ))
        }
    };
    let raw_points = ljson_points(landmarks).ok_or_else(|| {
        LoadError::at_offset(
            path,
            text,
            offset(landmarks),
            "`landmarks` is neither `{\"points\": [...]}` nor a list of `{\"point\": [...]}`",
        )
    })?;
    let mut points = Vec::with_capacity(raw_points.len());
    for (i, raw) in raw_points.iter().enumerate() {
        let fail = |message: String| LoadError::at_offset(path, text, offset(raw), message);
        let p: Option<Vec<f64>> = serde_json::from_str(raw.get())
            .map_err(|_| fail(format!("landmark {i}: `{}` is not a point", raw.get())))?;
        match p.as_deref() {
            None => return Err(fail(format!("landmark {i} is not placed (null): place every landmark before saving"))),
            Some([x, y, z]) => points.push(Vec3::new(*x as f32, *y as f32, *z as f32)),
            Some([_, _]) => return Err(fail(format!("landmark {i} has two coordinates: these are an image's landmarks, and grimace needs the mesh's 3D points"))),
            Some(other) => return Err(fail(format!("landmark {i} has {} coordinates; a point has three", other.len()))),
        }
    }
    let mut offsets: Vec<usize> = raw_points.iter().map(|r| offset(r)).collect();
    if let Some(order) = labels
        .map(|l| ibug_order(l, text, path, points.len()))
        .transpose()?
        .flatten()
    {
        points = order.iter().map(|&i| points[i]).collect();
        offsets = order.iter().map(|&i| offsets[i]).collect();
    }
    Ok(Read {
        landmarks: Landmarks::Points(points),
        offsets,
    })
}

/// The group of `groups` to read: the only one, else the only one of 68 points.
fn ljson_group<'a>(
    groups: &std::collections::BTreeMap<String, &'a serde_json::value::RawValue>,
    path: &Path,
) -> Result<&'a serde_json::value::RawValue, LoadError> {
    if groups.len() == 1 {
        return Ok(*groups.values().next().expect("one group"));
    }
    let of_68: Vec<(&String, &&serde_json::value::RawValue)> = groups
        .iter()
        .filter(|(_, g)| {
            serde_json::from_str::<LjsonGroup>(g.get())
                .ok()
                .and_then(|g| ljson_points(g.landmarks))
                .is_some_and(|p| p.len() == 68)
        })
        .collect();
    match of_68.as_slice() {
        [(_, group)] => Ok(**group),
        _ => {
            let names: Vec<&str> = groups.keys().map(String::as_str).collect();
            Err(LoadError::new(
                path,
                format!(
                    "{} landmark groups ({}) and not one alone of 68 points: keep the iBUG 68 group",
                    names.len(),
                    names.join(", ")
                ),
            ))
        }
    }
}

/// A group's points, in either of LJSON's layouts.
fn ljson_points(
    landmarks: &serde_json::value::RawValue,
) -> Option<Vec<&serde_json::value::RawValue>> {
    if let Ok(list) = serde_json::from_str::<LjsonPoints>(landmarks.get()) {
        return Some(list.points);
    }
    let entries: Vec<LjsonEntry> = serde_json::from_str(landmarks.get()).ok()?;
    Some(entries.into_iter().map(|e| e.point).collect())
}

/// The iBUG order of `count` points from their labels: for each iBUG landmark, the index
/// of the file's point. `None` when the labels are not the iBUG parts under menpo's names
/// (the file's order is then taken as it is); an error when they are but a part's size is
/// not the scheme's.
fn ibug_order(
    labels: &serde_json::value::RawValue,
    text: &str,
    path: &Path,
    count: usize,
) -> Result<Option<Vec<usize>>, LoadError> {
    let at = offset_in(text, labels);
    let Ok(labels) = serde_json::from_str::<Vec<LjsonLabel>>(labels.get()) else {
        return Ok(None);
    };
    let part = |name: &str| {
        IBUG_PARTS
            .iter()
            .find(|(names, _, _)| names.contains(&name.to_ascii_lowercase().as_str()))
    };
    if count != 68
        || labels.len() != IBUG_PARTS.len()
        || labels.iter().any(|l| part(&l.label).is_none())
    {
        return Ok(None);
    }
    let mut order = vec![usize::MAX; 68];
    for label in &labels {
        let (_, first, size) = part(&label.label).expect("checked above");
        if label.mask.len() != *size || label.mask.iter().any(|&i| i >= count) {
            return Err(LoadError::at_offset(
                path,
                text,
                at,
                format!(
                    "label `{}` has {} points where the iBUG 68 scheme has {size}",
                    label.label,
                    label.mask.len()
                ),
            ));
        }
        for (k, &i) in label.mask.iter().enumerate() {
            order[first + k] = i;
        }
    }
    let mut seen = order.clone();
    seen.sort_unstable();
    seen.dedup();
    if seen.len() != 68 || seen.contains(&usize::MAX) {
        return Err(LoadError::at_offset(
            path,
            text,
            at,
            "the labels' masks do not name each of the 68 points once",
        ));
    }
    Ok(Some(order))
}

/// The value of attribute `name` in an element's text, with its byte offset there.
fn attribute<'a>(element: &'a str, name: &str) -> Option<(usize, &'a str)> {
    let mut from = 0;
    while let Some(found) = element[from..].find(name) {
        let at = from + found;
        let before_ok = at == 0 || element[..at].ends_with(char::is_whitespace);
        let rest = element[at + name.len()..].trim_start();
        if before_ok && rest.starts_with('=') {
            let value = rest[1..].trim_start();
            let quote = value.chars().next().filter(|q| *q == '"' || *q == '\'')?;
            let inner = &value[1..];
            let close = inner.find(quote)?;
            return Some((at, &inner[..close]));
        }
        from = at + name.len();
    }
    None
}

/// One entry of a plain-text line: its fields and their byte offsets.
fn fields(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in line.char_indices() {
        let separator = c.is_whitespace() || c == ',' || c == ';';
        match (separator, start) {
            (true, Some(s)) => {
                out.push((s, &line[s..i]));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, &line[s..]));
    }
    out
}

/// One landmark a line.
fn lines(text: &str, path: &Path) -> Result<Read, LoadError> {
    let mut vertices = Vec::new();
    let mut points = Vec::new();
    let mut offsets = Vec::new();
    let mut offset = 0;
    let mut first = true;
    for raw in text.split_inclusive('\n') {
        let line_start = offset;
        offset += raw.len();
        let line = raw
            .trim_end_matches(['\n', '\r'])
            .trim_start_matches('\u{feff}');
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') || trimmed.starts_with("//") {
            continue;
        }
        let items = fields(line);
        if items.is_empty() {
            // Separators alone (`;`, `,,`): as blank.
            continue;
        }
        let is_header = first && items.iter().all(|(_, f)| f.parse::<f64>().is_err());
        first = false;
        if is_header {
            continue;
        }
        let at = |k: usize| {
            line_start + (raw.len() - raw.trim_start_matches('\u{feff}').len()) + items[k].0
        };
        let fail = |k: usize, message: String| LoadError::at_offset(path, text, at(k), message);
        match items.len() {
            1 if points.is_empty() => {
                let vertex = items[0].1.parse::<u32>().map_err(|_| {
                    fail(
                        0,
                        format!("`{}` is not a vertex number (0, 1, 2...)", items[0].1),
                    )
                })?;
                vertices.push(vertex);
            }
            3 | 4 if vertices.is_empty() => {
                // With four fields the first is a label.
                let first = items.len() - 3;
                let mut p = [0.0f32; 3];
                for (k, slot) in (first..).zip(p.iter_mut()) {
                    *slot = items[k]
                        .1
                        .parse::<f32>()
                        .map_err(|_| fail(k, format!("`{}` is not a number", items[k].1)))?;
                }
                points.push(Vec3::from(p));
            }
            1 | 3 | 4 => {
                return Err(fail(
                    0,
                    "every line must take one form: three numbers (x y z) or one vertex number"
                        .into(),
                ))
            }
            n => {
                return Err(fail(
                    0,
                    format!(
                        "{n} fields: a landmark is three numbers (x y z), a label and three \
                         numbers, or one vertex number"
                    ),
                ))
            }
        }
        offsets.push(at(0));
    }
    let landmarks = if points.is_empty() {
        Landmarks::Vertices(vertices)
    } else {
        Landmarks::Points(points)
    };
    Ok(Read { landmarks, offsets })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("t")
    }

    #[test]
    fn forms_come_from_the_extension() {
        assert_eq!(form_of(Path::new("a.PP")), Form::PickedPoints);
        assert_eq!(form_of(Path::new("a.xyz")), Form::Lines);
        assert_eq!(form_of(Path::new("a.landmarks.ron")), Form::Ron);
        assert_eq!(form_of(Path::new("noext")), Form::Ron);
    }

    /// 68 points `[i, 2i, -i]` listed part by part in the order of menpo's older
    /// labeller (chin, eyes, left brow, nose, right brow, mouth), with its labels.
    fn menpo_order_ljson() -> String {
        let parts = [
            ("chin", 0, 17),
            ("leye", 36, 6),
            ("reye", 42, 6),
            ("leyebrow", 17, 5),
            ("nose", 27, 9),
            ("reyebrow", 22, 5),
            ("mouth", 48, 20),
        ];
        let mut points = Vec::new();
        let mut labels = Vec::new();
        for (name, first, size) in parts {
            let mask: Vec<String> = (points.len()..points.len() + size)
                .map(|i| i.to_string())
                .collect();
            labels.push(format!(
                "{{\"label\": \"{name}\", \"mask\": [{}]}}",
                mask.join(", ")
            ));
            for i in first..first + size {
                points.push(format!("[{i}, {}, {}]", 2 * i, -(i as i32)));
            }
        }
        format!(
            "{{\"groups\": {{\"LJSON\": {{\"labels\": [{}],\n\"landmarks\": {{\"connectivity\": [],\n\"points\": [\n{}]}}}}}}, \"version\": 2}}",
            labels.join(", "),
            points.join(",\n")
        )
    }

    #[test]
    fn ljson_points_come_in_the_ibug_order_its_labels_give() {
        let text = menpo_order_ljson();
        let read = parse(&text, p(), Form::Ljson).unwrap();
        let Landmarks::Points(points) = &read.landmarks else {
            panic!("points expected");
        };
        assert_eq!(points.len(), 68);
        for (i, q) in points.iter().enumerate() {
            assert_eq!(
                *q,
                Vec3::new(i as f32, 2.0 * i as f32, -(i as f32)),
                "landmark {i}"
            );
        }
        // each landmark's place is its own point's in the file
        assert!(text[read.offsets[17]..].starts_with("[17, 34, -17]"));
    }

    #[test]
    fn ljson_without_the_ibug_labels_is_read_in_file_order() {
        // version 3's list of entries, under a group of its own naming
        let text = r#"{"version": 3, "groups": {"face": {"landmarks": [{"point": [1, 2, 3]}, {"point": [4.5, 5, -6e-1]}], "labels": [{"label": "all", "mask": [0, 1]}]}}}"#;
        let read = parse(text, p(), Form::Ljson).unwrap();
        assert_eq!(
            read.landmarks,
            Landmarks::Points(vec![Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.5, 5.0, -0.6)])
        );
        // version 2's top level
        let text = r#"{"version": 2, "landmarks": {"points": [[1, 2, 3]]}, "labels": []}"#;
        let read = parse(text, p(), Form::Ljson).unwrap();
        assert_eq!(
            read.landmarks,
            Landmarks::Points(vec![Vec3::new(1.0, 2.0, 3.0)])
        );
        assert_eq!(form_of(Path::new("head.LJSON")), Form::Ljson);
        // after a byte-order mark, offsets still count from the file's start
        let text = "\u{feff}{\"landmarks\": {\"points\": [[1, 2, 3]]}}";
        let read = parse(text, p(), Form::Ljson).unwrap();
        assert!(text[read.offsets[0]..].starts_with("[1, 2, 3]"));
    }

    #[test]
    fn ljson_errors_name_the_place() {
        let unplaced = "{\"landmarks\": {\"points\": [[1, 2, 3],\n  null]}}";
        let e = parse(unplaced, p(), Form::Ljson).unwrap_err().to_string();
        assert!(
            e.contains("t:2:3") && e.contains("landmark 1 is not placed"),
            "{e}"
        );
        let flat = r#"{"landmarks": {"points": [[10, 20]]}}"#;
        let e = parse(flat, p(), Form::Ljson).unwrap_err().to_string();
        assert!(e.contains("two coordinates"), "{e}");
        let long = r#"{"landmarks": {"points": [[1, 2, 3, 4]]}}"#;
        let e = parse(long, p(), Form::Ljson).unwrap_err().to_string();
        assert!(e.contains("landmark 0 has 4 coordinates"), "{e}");
        let e = parse("{\"landmarks\": [1, 2", p(), Form::Ljson)
            .unwrap_err()
            .to_string();
        assert!(e.contains("not an LJSON file"), "{e}");
        let e = parse(r#"{"version": 2}"#, p(), Form::Ljson)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no `landmarks`"), "{e}");
        let two = r#"{"groups": {"a": {"landmarks": {"points": [[1, 2, 3]]}}, "b": {"landmarks": {"points": []}}}}"#;
        let e = parse(two, p(), Form::Ljson).unwrap_err().to_string();
        assert!(e.contains("2 landmark groups (a, b)"), "{e}");
        let short = menpo_order_ljson().replacen("\"mask\": [0, ", "\"mask\": [", 1);
        let e = parse(&short, p(), Form::Ljson).unwrap_err().to_string();
        assert!(e.contains("label `chin` has 16 points"), "{e}");
    }

    #[test]
    fn picked_points_are_read_in_file_order() {
        let text = "<!DOCTYPE PickedPoints>\n<PickedPoints>\n <DocumentData>\n  <DataFileName name=\"head.obj\"/>\n </DocumentData>\n <point x=\"1\" y=\"2.5\" z=\"-3\" active=\"1\" name=\"0\"/>\n <point name=\"1\" active=\"1\" z=\"6\" y='5' x=\"4e-1\"/>\n</PickedPoints>\n";
        let read = parse(text, p(), Form::PickedPoints).unwrap();
        assert_eq!(
            read.landmarks,
            Landmarks::Points(vec![Vec3::new(1.0, 2.5, -3.0), Vec3::new(0.4, 5.0, 6.0)])
        );
        assert_eq!(read.offsets.len(), 2);
        assert!(text[read.offsets[1]..].starts_with("<point name=\"1\""));
    }

    #[test]
    fn picked_points_errors_name_the_place() {
        let unplaced = "<PickedPoints>\n<point x=\"1\" y=\"2\" z=\"3\" active=\"0\" name=\"0\"/>\n</PickedPoints>";
        let e = parse(unplaced, p(), Form::PickedPoints)
            .unwrap_err()
            .to_string();
        assert!(e.contains("t:2:1") && e.contains("not placed"), "{e}");
        let bad = "<point x=\"1\" y=\"two\" z=\"3\"/>";
        let e = parse(bad, p(), Form::PickedPoints).unwrap_err().to_string();
        assert!(e.contains("t:1:14") && e.contains("y=\"two\""), "{e}");
        let missing = "<point x=\"1\" y=\"2\"/>";
        let e = parse(missing, p(), Form::PickedPoints)
            .unwrap_err()
            .to_string();
        assert!(e.contains("has no `z`"), "{e}");
        let e = parse("<html/>", p(), Form::PickedPoints)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no `<point"), "{e}");
    }

    #[test]
    fn lines_read_points_or_vertex_numbers() {
        let text = "x,y,z\n# the right jaw first\n1.5, 2, 3\r\n\n4\t5\t6\n7;8;9\n";
        let read = parse(text, p(), Form::Lines).unwrap();
        assert_eq!(
            read.landmarks,
            Landmarks::Points(vec![
                Vec3::new(1.5, 2.0, 3.0),
                Vec3::new(4.0, 5.0, 6.0),
                Vec3::new(7.0, 8.0, 9.0)
            ])
        );
        assert!(text[read.offsets[1]..].starts_with("4\t5"));
        let labelled = parse("name,x,y,z\njaw_0,1,2,3\n1,4,5,6\n", p(), Form::Lines).unwrap();
        assert_eq!(
            labelled.landmarks,
            Landmarks::Points(vec![Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0)])
        );
        let read = parse("12\n 7\n", p(), Form::Lines).unwrap();
        assert_eq!(read.landmarks, Landmarks::Vertices(vec![12, 7]));
    }

    proptest::proptest! {
        /// Any text, in either form, is read or refused with an error: never a panic.
        #[test]
        fn any_text_is_read_or_refused(text in "[<>=\"'a-z0-9 .,;#/\\n\\r\u{e9}\u{feff}-]{0,120}") {
            for form in [Form::PickedPoints, Form::Lines] {
                let _ = parse(&format!("1 2 3\n{text}"), p(), form);
                let _ = parse(&text, p(), form);
                let _ = parse(&format!("<point {text}"), p(), form);
            }
        }
    }

    #[test]
    fn lines_errors_name_line_and_column() {
        let e = parse("1 2 3\n4 x 6\n", p(), Form::Lines)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("t:2:3") && e.contains("`x` is not a number"),
            "{e}"
        );
        let e = parse("1 2 3\n7\n", p(), Form::Lines)
            .unwrap_err()
            .to_string();
        assert!(e.contains("t:2:1") && e.contains("one form"), "{e}");
        let e = parse("1 2 3 4 5\n", p(), Form::Lines)
            .unwrap_err()
            .to_string();
        assert!(e.contains("5 fields"), "{e}");
        let e = parse("1 2\n", p(), Form::Lines).unwrap_err().to_string();
        assert!(e.contains("2 fields"), "{e}");
        // A line of separators alone is blank (it once indexed a field it did not have).
        let read = parse("x y z\n;\n1 2 3\n,,\n", p(), Form::Lines).unwrap();
        assert_eq!(
            read.landmarks,
            Landmarks::Points(vec![Vec3::new(1.0, 2.0, 3.0)])
        );
        let e = parse("-4\n", p(), Form::Lines).unwrap_err().to_string();
        assert!(e.contains("not a vertex number"), "{e}");
    }
}
