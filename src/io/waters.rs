//! The classic Waters data (`faceline.dat`, `index.dat`, `muscle.dat`, the "geoface" files
//! of Parke & Waters' book as shipped with GLUT 3.7): reading, and building the full face.
//!
//! The files hold whitespace-separated tokens; line breaks, blank lines and carriage returns
//! carry no meaning (the original reads them with `scanf`). Errors name the file, line and
//! column of the offending token. Data after the last record is refused, since it means the
//! counts at the top of the file are wrong.
//!
//! The full face is built exactly as the original program builds it (see [`build_face`]),
//! then exactly coincident vertices are merged (never by tolerance: the two lips of the
//! mouth opening are 0.004 apart). Vertices are numbered in order of first appearance while
//! walking the triangles, so the result matches the classic reference outputs index for
//! index.
//!
//! The classic data puts the subject's left at negative x. grimace uses glTF's convention
//! (right-handed, y up, the face toward +z, the subject's left at positive x), so every point
//! is converted as it is read, by [`from_classic`] (x negated): the half face lies at x >= 0,
//! the `L_` muscles at positive x. Triangles keep the file's corner order, so indices still
//! match the reference outputs; the reflection turns their right-hand normals from pointing
//! into the head (as in the original) to pointing out of it. A classic reference position
//! `p` corresponds to `from_classic(p)` here.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::error::{read_text, LoadError, MAX_FILE_BYTES};
use super::rig_file::check_rig;
use crate::model::{Combine, Jaw, Linear, Mesh, Muscle, MuscleKind, Rig, Side, RIG_VERSION};

/// A muscle record of `muscle.dat`.
#[derive(Debug, Clone, PartialEq)]
pub struct WatersMuscle {
    /// The name, e.g. `L_Zygomatic_Major`.
    pub name: String,
    /// The record's first point: the skin insertion (the original calls it `head`).
    pub insertion: Vec3,
    /// The record's second point: the bone attachment (the original calls it `tail`).
    pub attachment: Vec3,
    /// Falloff start `fs`, a distance from the attachment.
    pub falloff_start: f32,
    /// Falloff end `fe`, a distance from the attachment.
    pub falloff_end: f32,
    /// Half-angle of the cone of influence, degrees.
    pub zone: f32,
    /// `clampv`: read by the original but never used.
    pub clampv: f32,
}

/// The three classic files, parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct WatersData {
    /// Half-face vertices (x >= 0 once converted, see [`from_classic`]), in file order.
    pub vertices: Vec<Vec3>,
    /// Polygons of the half face, zero-based: a quad `[a, b, c, d]` or a triangle `[b, c, d]`.
    pub polygons: Vec<Polygon>,
    /// The linear muscles, in file order.
    pub muscles: Vec<WatersMuscle>,
}

/// A polygon of `index.dat`, with zero-based vertex indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Polygon {
    /// A quad `a b c d`, split into `(a, b, c)` and `(a, c, d)`.
    Quad([u32; 4]),
    /// A triangle, written `1000 b c d` in the file.
    Triangle([u32; 3]),
}

/// Extra muscles and a jaw for the imported classic face (the paper's sheet and sphincter
/// muscles), computed from the imported mesh. See [`ImportOptions::extras`].
pub type ExtraMuscles = fn(&Mesh) -> (Vec<Muscle>, Option<Jaw>);

/// Choices for [`import_dir`].
#[derive(Debug, Clone, Copy, Default)]
pub struct ImportOptions {
    /// Drop the 6 triangles that repeat earlier ones exactly (`index.dat` repeats two
    /// records). Kept by default, as in the original program and the reference outputs;
    /// dropping them gives a mesh where no edge is shared by more than two triangles. Vertex
    /// numbering is the same either way.
    pub drop_duplicate_triangles: bool,
    /// Adds muscles and a jaw beyond the 18 linear muscles of `muscle.dat`. `None` gives the
    /// classic rig of 18 linear muscles.
    pub extras: Option<ExtraMuscles>,
}

/// The imported classic face: the full mesh and its rig (the rig's `mesh` field is
/// `mesh.obj`, the name [`import_dir`]'s callers write the mesh under).
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// The full, reflected, merged face.
    pub mesh: Mesh,
    /// The rig: the linear muscles of `muscle.dat` (plus any extras).
    pub rig: Rig,
}

/// Converts a point of the classic data (the subject's left at negative x) to grimace's
/// convention (glTF's: the subject's left at positive x) by negating x. Its own inverse.
pub fn from_classic(p: Vec3) -> Vec3 {
    Vec3::new(-p.x, p.y, p.z)
}

/// The file names of the classic data.
pub const FACELINE: &str = "faceline.dat";
/// See [`FACELINE`].
pub const INDEX: &str = "index.dat";
/// See [`FACELINE`].
pub const MUSCLE: &str = "muscle.dat";

/// Reads the three classic files from a folder and builds the face and its rig.
pub fn import_dir(dir: &Path, options: &ImportOptions) -> Result<Imported, LoadError> {
    let data = read_dir(dir)?;
    build(&data, options, &dir.join(MUSCLE))
}

/// Reads and parses the three classic files from a folder.
pub fn read_dir(dir: &Path) -> Result<WatersData, LoadError> {
    let faceline = dir.join(FACELINE);
    let index = dir.join(INDEX);
    let muscle = dir.join(MUSCLE);
    let vertices = parse_faceline(&read_text(&faceline, MAX_FILE_BYTES)?, &faceline)?;
    let polygons = parse_index(&read_text(&index, MAX_FILE_BYTES)?, &index, vertices.len())?;
    let muscles = parse_muscles(&read_text(&muscle, MAX_FILE_BYTES)?, &muscle)?;
    Ok(WatersData {
        vertices,
        polygons,
        muscles,
    })
}

/// Builds the face and rig from parsed data. `muscle_path` names `muscle.dat` in errors
/// about muscle parameters.
pub fn build(
    data: &WatersData,
    options: &ImportOptions,
    muscle_path: &Path,
) -> Result<Imported, LoadError> {
    let mesh = build_face(
        &data.vertices,
        &data.polygons,
        options.drop_duplicate_triangles,
    )
    .map_err(|e| LoadError::new(muscle_path.with_file_name(INDEX).as_path(), e))?;
    let mut rig = linear_rig(&data.muscles, PathBuf::from("mesh.obj"));
    if let Some(extras) = options.extras {
        let (muscles, jaw) = extras(&mesh);
        rig.muscles.extend(muscles);
        rig.jaw = jaw;
    }
    check_rig(&rig).map_err(|issue| LoadError::new(muscle_path, issue.to_string()))?;
    Ok(Imported { mesh, rig })
}

/// Builds the full face in the original's order: for each record in file order, a quad
/// emits `T1 = (a, b, c)`, `mirror(T1)`, `T2 = (a, c, d)`, `mirror(T2)`; a triangle emits
/// `T`, `mirror(T)`; `mirror(p, q, r) = (q', p', r')` with `'` negating x (the swap keeps the
/// winding). Exactly equal positions are merged (`-0.0` equals `0.0`, stored as `0.0`), and
/// vertices are numbered by first appearance while walking the triangles' corners in order.
pub fn build_face(
    half: &[Vec3],
    polygons: &[Polygon],
    drop_duplicates: bool,
) -> Result<Mesh, String> {
    let count = half.len();
    for polygon in polygons {
        let indices: &[u32] = match polygon {
            Polygon::Quad(q) => q,
            Polygon::Triangle(t) => t,
        };
        if let Some(bad) = indices.iter().find(|&&i| i as usize >= count) {
            return Err(format!(
                "a polygon refers to vertex {} of {count}",
                *bad as u64 + 1
            ));
        }
    }
    let mut corners: Vec<[Vec3; 3]> = Vec::with_capacity(polygons.len() * 4);
    let at = |i: u32| half[i as usize];
    let mirrored = |i: u32| crate::model::muscle::mirror_x(half[i as usize]);
    let mut emit = |[p, q, r]: [u32; 3]| {
        corners.push([at(p), at(q), at(r)]);
        corners.push([mirrored(q), mirrored(p), mirrored(r)]);
    };
    for polygon in polygons {
        match *polygon {
            Polygon::Quad([a, b, c, d]) => {
                emit([a, b, c]);
                emit([a, c, d]);
            }
            Polygon::Triangle(t) => emit(t),
        }
    }
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions: Vec<Vec3> = vec![];
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(corners.len());
    let mut seen: std::collections::HashSet<[u32; 3]> = std::collections::HashSet::new();
    for tri in corners {
        let ids = tri.map(|p| {
            // Adding 0.0 turns -0.0 into 0.0, so the mirror plane merges.
            let p = p + Vec3::ZERO;
            *index
                .entry(p.to_array().map(f32::to_bits))
                .or_insert_with(|| {
                    positions.push(p);
                    (positions.len() - 1) as u32
                })
        });
        if drop_duplicates && !seen.insert(ids) {
            continue;
        }
        triangles.push(ids);
    }
    Mesh::new(positions, triangles).map_err(|e| e.to_string())
}

/// The rig of the classic linear muscles: attachment = the record's second point, insertion
/// = its first; sides from the `L_`/`Left_` and `R_`/`Right_` prefixes; mirror partners are
/// the muscles whose names differ only in that prefix.
pub fn linear_rig(muscles: &[WatersMuscle], mesh: PathBuf) -> Rig {
    let names: Vec<&str> = muscles.iter().map(|m| m.name.as_str()).collect();
    Rig {
        masks: Vec::new(),
        version: RIG_VERSION,
        mesh,
        landmarks: None,
        combine: Combine::Sum,
        muscles: muscles
            .iter()
            .map(|m| {
                let (side, stem) = side_of(&m.name);
                let partner = partner_names(side, stem)
                    .into_iter()
                    .find(|p| names.contains(&p.as_str()));
                Muscle {
                    name: m.name.clone(),
                    side,
                    mirror: partner,
                    kind: MuscleKind::Linear(Linear {
                        attachment: m.attachment,
                        insertion: m.insertion,
                        zone: m.zone,
                        falloff_start: m.falloff_start,
                        falloff_end: m.falloff_end,
                    }),
                }
            })
            .collect(),
        jaw: None,
    }
}

const LEFT: [&str; 2] = ["L_", "Left_"];
const RIGHT: [&str; 2] = ["R_", "Right_"];

/// The side a classic name's prefix gives, and the name without it.
fn side_of(name: &str) -> (Side, &str) {
    for (side, prefixes) in [(Side::Left, LEFT), (Side::Right, RIGHT)] {
        for prefix in prefixes {
            if let Some(stem) = name.strip_prefix(prefix) {
                return (side, stem);
            }
        }
    }
    (Side::Centre, name)
}

fn partner_names(side: Side, stem: &str) -> Vec<String> {
    let prefixes = match side {
        Side::Left => RIGHT,
        Side::Right => LEFT,
        Side::Centre => return vec![],
    };
    prefixes.iter().map(|p| format!("{p}{stem}")).collect()
}

// ---- Tokens

#[derive(Clone, Copy)]
struct Token<'a> {
    text: &'a str,
    line: usize,
    column: usize,
}

struct Tokens<'a> {
    path: &'a Path,
    tokens: Vec<Token<'a>>,
    next: usize,
    end: (usize, usize),
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str, path: &'a Path) -> Tokens<'a> {
        let mut tokens = vec![];
        let mut line_count = 0;
        let mut last_column = 1;
        for (n, line) in text.split('\n').enumerate() {
            line_count = n + 1;
            let mut start: Option<(usize, usize)> = None;
            let mut column = 0;
            for (byte, c) in line.char_indices() {
                column += 1;
                if c.is_whitespace() {
                    if let Some((col, from)) = start.take() {
                        tokens.push(Token {
                            text: &line[from..byte],
                            line: n + 1,
                            column: col,
                        });
                    }
                } else if start.is_none() {
                    start = Some((column, byte));
                }
            }
            if let Some((col, from)) = start {
                tokens.push(Token {
                    text: &line[from..],
                    line: n + 1,
                    column: col,
                });
            }
            last_column = column + 1;
        }
        Tokens {
            path,
            tokens,
            next: 0,
            end: (line_count.max(1), last_column),
        }
    }

    fn remaining(&self) -> usize {
        self.tokens.len() - self.next
    }

    fn take(&mut self, what: &str) -> Result<Token<'a>, LoadError> {
        match self.tokens.get(self.next).copied() {
            Some(token) => {
                self.next += 1;
                Ok(token)
            }
            None => Err(LoadError::at(
                self.path,
                self.end.0,
                self.end.1,
                format!("the file ends early; expected {what}"),
            )),
        }
    }

    fn error(&self, token: &Token, message: String) -> LoadError {
        LoadError::at(self.path, token.line, token.column, message)
    }

    fn count(&mut self, what: &str, per_record: usize) -> Result<usize, LoadError> {
        let token = self.take(&format!("the number of {what}"))?;
        let count: usize = token.text.parse().map_err(|_| {
            self.error(
                &token,
                format!(
                    "`{}` is not a count; expected the number of {what} first",
                    token.text
                ),
            )
        })?;
        if count == 0 {
            return Err(self.error(&token, format!("the file declares no {what}")));
        }
        // More records than tokens left would only fail later; say so now, before any
        // allocation sized by the count.
        let available = self.remaining() / per_record;
        if count > available {
            return Err(self.error(
                &token,
                format!("the file declares {count} {what} but holds data for at most {available}"),
            ));
        }
        Ok(count)
    }

    fn float(&mut self, what: &str) -> Result<f32, LoadError> {
        let token = self.take(what)?;
        match token.text.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.error(
                &token,
                format!("`{}` is not a finite number; expected {what}", token.text),
            )),
            Err(_) => Err(self.error(
                &token,
                format!("`{}` is not a number; expected {what}", token.text),
            )),
        }
    }

    fn point(&mut self, what: &str) -> Result<Vec3, LoadError> {
        Ok(Vec3::new(
            self.float(&format!("the x of {what}"))?,
            self.float(&format!("the y of {what}"))?,
            self.float(&format!("the z of {what}"))?,
        ))
    }

    fn finish(&self, what: &str) -> Result<(), LoadError> {
        match self.tokens.get(self.next) {
            None => Ok(()),
            Some(token) => Err(self.error(
                token,
                format!(
                    "unexpected `{}` after the last {what}; the count at the top of the file is smaller than the data",
                    token.text
                ),
            )),
        }
    }
}

/// Parses `faceline.dat`: a vertex count, then that many `x y z` triples, converted with
/// [`from_classic`].
pub fn parse_faceline(text: &str, path: &Path) -> Result<Vec<Vec3>, LoadError> {
    let mut tokens = Tokens::new(text, path);
    let count = tokens.count("vertices", 3)?;
    let mut vertices = Vec::with_capacity(count);
    for i in 1..=count {
        vertices.push(from_classic(tokens.point(&format!("vertex {i}"))?));
    }
    tokens.finish("vertex")?;
    Ok(vertices)
}

/// Parses `index.dat`: a record count, then records of four one-based vertex numbers; a
/// record starting with 1000 is the triangle of its other three numbers.
pub fn parse_index(
    text: &str,
    path: &Path,
    vertex_count: usize,
) -> Result<Vec<Polygon>, LoadError> {
    let mut tokens = Tokens::new(text, path);
    let count = tokens.count("polygons", 4)?;
    let mut polygons = Vec::with_capacity(count);
    for record in 1..=count {
        let mut numbers = [0u32; 4];
        let mut triangle = false;
        for (i, slot) in numbers.iter_mut().enumerate() {
            let token = tokens.take(&format!("vertex number {} of polygon {record}", i + 1))?;
            let value: u32 = token.text.parse().map_err(|_| {
                tokens.error(
                    &token,
                    format!(
                        "`{}` is not a vertex number; expected a whole number from 1 to {vertex_count}",
                        token.text
                    ),
                )
            })?;
            let is_marker = i == 0 && value == 1000;
            triangle |= is_marker;
            if !is_marker && (value == 0 || value as usize > vertex_count) {
                return Err(tokens.error(
                    &token,
                    format!(
                        "vertex number {value} is out of range; faceline.dat has vertices 1 to {vertex_count}"
                    ),
                ));
            }
            *slot = value.wrapping_sub(1);
        }
        let [a, b, c, d] = numbers;
        polygons.push(if triangle {
            Polygon::Triangle([b, c, d])
        } else {
            Polygon::Quad([a, b, c, d])
        });
    }
    tokens.finish("polygon")?;
    Ok(polygons)
}

/// Parses `muscle.dat`: a muscle count, then per muscle a name, the first point (insertion),
/// the second point (attachment), `fs fe zone clampv`. Points are converted with
/// [`from_classic`].
pub fn parse_muscles(text: &str, path: &Path) -> Result<Vec<WatersMuscle>, LoadError> {
    let mut tokens = Tokens::new(text, path);
    let count = tokens.count("muscles", 11)?;
    let mut muscles: Vec<WatersMuscle> = Vec::with_capacity(count);
    for record in 1..=count {
        let token = tokens.take(&format!("the name of muscle {record}"))?;
        let name = token.text.to_string();
        if muscles.iter().any(|m| m.name == name) {
            return Err(tokens.error(&token, format!("muscle name `{name}` is used twice")));
        }
        if name.parse::<f32>().is_ok() {
            return Err(tokens.error(
                &token,
                format!("expected the name of muscle {record}, found the number `{name}`"),
            ));
        }
        let insertion = from_classic(tokens.point(&format!("{name}'s first point"))?);
        let attachment = from_classic(tokens.point(&format!("{name}'s second point"))?);
        let falloff_start = tokens.float(&format!("{name}'s falloff start"))?;
        let falloff_end = tokens.float(&format!("{name}'s falloff end"))?;
        let zone = tokens.float(&format!("{name}'s zone"))?;
        let clampv = tokens.float(&format!("{name}'s clamp value"))?;
        muscles.push(WatersMuscle {
            name,
            insertion,
            attachment,
            falloff_start,
            falloff_end,
            zone,
            clampv,
        });
    }
    tokens.finish("muscle")?;
    Ok(muscles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("x.dat")
    }

    #[test]
    fn tokens_ignore_line_structure_and_cr() {
        // x is negated as read: the classic subject's left (x < 0) becomes positive x
        let v = parse_faceline("2\r\n\r\n 0.0 1.5\r\n2 -1 0 0.25\r\n", p()).unwrap();
        assert_eq!(v, vec![Vec3::new(0.0, 1.5, 2.0), Vec3::new(1.0, 0.0, 0.25)]);
        let m = parse_muscles("1\nL_m -1 2 3 -4 5 6 0.1 2 40 1\n", p()).unwrap();
        assert_eq!(
            (m[0].insertion, m[0].attachment),
            (Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0))
        );
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = parse_faceline("2\n0 0 0\n1 x 2\n", p()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.dat:3:3: `x` is not a number; expected the y of vertex 2"
        );
        let e = parse_faceline("3\n0 0 0\n1 1 2\n", p()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.dat:1:1: the file declares 3 vertices but holds data for at most 2"
        );
        let e = parse_faceline("1\n0 0 0 7\n", p()).unwrap_err();
        assert!(e
            .to_string()
            .starts_with("x.dat:2:7: unexpected `7` after the last vertex"));
        let e = parse_index("1\n1 2 3 9\n", p(), 4).unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.dat:2:7: vertex number 9 is out of range; faceline.dat has vertices 1 to 4"
        );
        let e = parse_muscles("1\nm 0 0 0 1 1 1 0.1 2 40\n", p()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.dat:1:1: the file declares 1 muscles but holds data for at most 0"
        );
    }

    #[test]
    fn builds_in_the_original_order_with_mirror_swap() {
        // A quad straddling the midline: vertices 0 and 3 on x = 0.
        let half = vec![
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(-1.0, 1.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ];
        let mesh = build_face(&half, &[Polygon::Quad([0, 1, 2, 3])], false).unwrap();
        // T1 = (0,1,2) -> ids 0,1,2; mirror = (1',0',2') -> new 3, merged 0, new 4;
        // T2 = (0,2,3) -> 0,2,5 (vertex 3 on the midline); mirror = (2',0',3') -> 4,0,5.
        assert_eq!(
            mesh.triangles,
            vec![[0, 1, 2], [3, 0, 4], [0, 2, 5], [4, 0, 5]]
        );
        assert_eq!(mesh.positions[3], Vec3::new(1.0, 0.0, 1.0));
        assert_eq!(mesh.positions[5].x.to_bits(), 0.0f32.to_bits());
        assert_eq!(mesh.vertex_count(), 6);
        assert!(build_face(&half, &[Polygon::Triangle([0, 1, 4])], false).is_err());
    }

    #[test]
    fn partners_and_sides() {
        let m = |name: &str| WatersMuscle {
            name: name.into(),
            insertion: Vec3::X,
            attachment: Vec3::ZERO,
            falloff_start: 0.1,
            falloff_end: 1.0,
            zone: 30.0,
            clampv: 1.0,
        };
        let rig = linear_rig(&[m("L_a"), m("Right_a"), m("L_b"), m("c")], "m.obj".into());
        let summary: Vec<_> = rig
            .muscles
            .iter()
            .map(|m| (m.side, m.mirror.clone()))
            .collect();
        assert_eq!(
            summary,
            vec![
                (Side::Left, Some("Right_a".into())),
                (Side::Right, Some("L_a".into())),
                (Side::Left, None),
                (Side::Centre, None),
            ]
        );
    }
}
