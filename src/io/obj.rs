//! Wavefront OBJ meshes: read `v` and `f` (and `g` as vertex groups), write `v` and `f`.
//!
//! Reading: polygons are fan-triangulated (`a b c d` gives `a b c` and `a c d`); face corners
//! may be `v`, `v/vt`, `v//vn` or `v/vt/vn`, with negative (relative) indices; `vt`, `vn`,
//! `s`, `mtllib` and other statements are ignored. Each `g NAME` line starts a group: the
//! vertices of the faces that follow it form the mesh's vertex group `NAME`. Objects and
//! materials group faces the same way: `o NAME` gives the group `object:NAME` and
//! `usemtl NAME` the group `material:NAME` (fitting finds eyes and teeth by them).
//! Errors name the line and column: a bad number, an index out of range, a non-finite
//! coordinate, a face with fewer than three corners, a mesh with no faces.
//!
//! Writing: `v x y z` with Rust's shortest round-trip float formatting (so reading back gives
//! exactly the same `f32`s) and `f a b c`, one-based, in the mesh's order. Vertex groups are
//! not written.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use glam::Vec3;

use super::atomic;
use super::error::{read_text, LoadError, SaveError, MAX_FILE_BYTES};
use crate::model::mesh::{MAX_TRIANGLES, MAX_VERTICES};
use crate::model::{Mesh, MeshError};

/// Reads an OBJ file into a checked mesh.
pub fn read_obj(path: &Path) -> Result<Mesh, LoadError> {
    let text = read_text(path, MAX_FILE_BYTES)?;
    parse_obj(&text, path)
}

/// Parses OBJ text into a checked mesh. `path` is used in error messages only.
pub fn parse_obj(text: &str, path: &Path) -> Result<Mesh, LoadError> {
    let mut reader = Reader {
        path,
        positions: vec![],
        triangles: vec![],
        groups: BTreeMap::new(),
        group: None,
        object: None,
        material: None,
        forward: vec![],
    };
    for (number, line) in text.split('\n').enumerate() {
        reader.line(number + 1, line)?;
    }
    reader.finish()
}

/// A face corner that refers to a vertex not yet defined, checked once all are read.
struct Forward {
    index: u32,
    line: usize,
    column: usize,
}

struct Reader<'a> {
    path: &'a Path,
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    groups: BTreeMap<String, BTreeSet<u32>>,
    group: Option<String>,
    object: Option<String>,
    material: Option<String>,
    forward: Vec<Forward>,
}

/// The first `limit` whitespace-separated tokens of a line with their 1-based character
/// columns.
fn tokens(line: &str, limit: usize) -> Vec<(usize, &str)> {
    let mut out = vec![];
    let mut start: Option<(usize, usize)> = None;
    for (column, (byte, c)) in line.char_indices().enumerate() {
        if c.is_whitespace() {
            if let Some((col, from)) = start.take() {
                out.push((col, &line[from..byte]));
                if out.len() == limit {
                    return out;
                }
            }
        } else if start.is_none() {
            start = Some((column + 1, byte));
        }
    }
    if let Some((col, from)) = start {
        out.push((col, &line[from..]));
    }
    out
}

impl Reader<'_> {
    fn error(&self, line: usize, column: usize, message: String) -> LoadError {
        LoadError::at(self.path, line, column, message)
    }

    fn too_many_triangles(&self, line: usize) -> LoadError {
        self.error(
            line,
            1,
            format!("more than {MAX_TRIANGLES} triangles; grimace refuses meshes this large"),
        )
    }

    fn line(&mut self, number: usize, line: &str) -> Result<(), LoadError> {
        let content = line.split('#').next().unwrap_or("");
        // Only the tokens a statement uses are kept: a single huge line (the file limit
        // allows 256 MiB) would otherwise take about 12 times its size in token positions.
        let Some(keyword) = content.split_whitespace().next() else {
            return Ok(());
        };
        match keyword {
            "v" => self.vertex(number, &tokens(content, 4)),
            "f" => {
                let corners = content.split_whitespace().count() - 1;
                if self.triangles.len() + corners.saturating_sub(2) > MAX_TRIANGLES {
                    return Err(self.too_many_triangles(number));
                }
                self.face(number, &tokens(content, usize::MAX))
            }
            "g" => {
                self.group = tokens(content, 2).get(1).map(|(_, name)| name.to_string());
                Ok(())
            }
            "o" => {
                self.object = tokens(content, 2)
                    .get(1)
                    .map(|(_, name)| format!("object:{name}"));
                Ok(())
            }
            "usemtl" => {
                self.material = tokens(content, 2)
                    .get(1)
                    .map(|(_, name)| format!("material:{name}"));
                Ok(())
            }
            // Texture coordinates, normals, smoothing and anything else carry nothing a
            // muscle rig uses.
            _ => Ok(()),
        }
    }

    fn vertex(&mut self, line: usize, tokens: &[(usize, &str)]) -> Result<(), LoadError> {
        if tokens.len() < 4 {
            let column = tokens.last().map_or(1, |(c, t)| c + t.chars().count());
            return Err(self.error(
                line,
                column,
                format!(
                    "a vertex needs three coordinates `v X Y Z`; found {}",
                    tokens.len() - 1
                ),
            ));
        }
        if self.positions.len() >= MAX_VERTICES {
            return Err(self.error(
                line,
                1,
                format!("more than {MAX_VERTICES} vertices; grimace refuses meshes this large"),
            ));
        }
        let mut xyz = [0.0f32; 3];
        for (slot, &(column, token)) in xyz.iter_mut().zip(&tokens[1..4]) {
            let value: f32 = token.parse().map_err(|_| {
                self.error(
                    line,
                    column,
                    format!("`{token}` is not a number; expected a coordinate such as 1.25"),
                )
            })?;
            if !value.is_finite() {
                return Err(self.error(
                    line,
                    column,
                    format!("coordinate `{token}` is not a finite number"),
                ));
            }
            *slot = value;
        }
        self.positions.push(Vec3::from(xyz));
        Ok(())
    }

    fn face(&mut self, line: usize, tokens: &[(usize, &str)]) -> Result<(), LoadError> {
        if tokens.len() < 4 {
            return Err(self.error(
                line,
                1,
                format!(
                    "a face needs at least three corners; found {}",
                    tokens.len() - 1
                ),
            ));
        }
        let mut corners = Vec::with_capacity(tokens.len() - 1);
        for &(column, token) in &tokens[1..] {
            corners.push(self.corner(line, column, token)?);
        }
        if self.triangles.len() + corners.len() - 2 > MAX_TRIANGLES {
            return Err(self.too_many_triangles(line));
        }
        for i in 1..corners.len() - 1 {
            self.triangles
                .push([corners[0], corners[i], corners[i + 1]]);
        }
        for group in [&self.group, &self.object, &self.material]
            .into_iter()
            .flatten()
        {
            self.groups
                .entry(group.clone())
                .or_default()
                .extend(corners.iter().copied());
        }
        Ok(())
    }

    /// One face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`: the vertex index, zero-based.
    fn corner(&mut self, line: usize, column: usize, token: &str) -> Result<u32, LoadError> {
        let index_text = token.split('/').next().unwrap_or("");
        let index: i64 = index_text.parse().map_err(|_| {
            self.error(
                line,
                column,
                format!(
                    "`{token}` is not a face corner; expected a vertex number such as 12 or 12/3/4"
                ),
            )
        })?;
        let count = self.positions.len() as i64;
        let zero_based = match index {
            0 => {
                return Err(self.error(
                    line,
                    column,
                    "vertex index 0 does not exist; OBJ indices start at 1".to_string(),
                ))
            }
            i if i < 0 => count + i,
            i => i - 1,
        };
        if zero_based < 0 || zero_based >= MAX_VERTICES as i64 {
            return Err(self.error(
                line,
                column,
                format!(
                    "vertex index {index} is out of range; {count} vertices are defined before this line"
                ),
            ));
        }
        let zero_based = zero_based as u32;
        if zero_based as i64 >= count {
            // Defined later, perhaps: checked when the whole file is read.
            self.forward.push(Forward {
                index: zero_based,
                line,
                column,
            });
        }
        Ok(zero_based)
    }

    fn finish(self) -> Result<Mesh, LoadError> {
        let count = self.positions.len();
        if let Some(bad) = self.forward.iter().find(|f| f.index as usize >= count) {
            return Err(self.error(
                bad.line,
                bad.column,
                format!(
                    "vertex index {} is out of range; the file defines {count} vertices",
                    bad.index as u64 + 1
                ),
            ));
        }
        let path = self.path;
        let mut mesh = Mesh::new(self.positions, self.triangles).map_err(|e| match e {
            MeshError::NoFaces => LoadError::new(path, "the mesh has no faces; expected `f` lines"),
            other => LoadError::new(path, other.to_string()),
        })?;
        mesh.groups = self
            .groups
            .into_iter()
            .map(|(name, members)| (name, members.into_iter().collect()))
            .collect();
        Ok(mesh)
    }
}

/// Writes a mesh as OBJ text with the given positions (for example a deformed copy of the
/// rest positions). A vertex without an entry in `positions` is written at rest.
pub fn write_obj(mesh: &Mesh, positions: &[Vec3]) -> String {
    use std::fmt::Write;
    let mut out = String::with_capacity(mesh.vertex_count() * 32 + mesh.triangles.len() * 16);
    let _ = writeln!(
        out,
        "# grimace mesh: {} vertices, {} triangles",
        mesh.vertex_count(),
        mesh.triangles.len()
    );
    for (i, rest) in mesh.positions.iter().enumerate() {
        let p = positions.get(i).unwrap_or(rest);
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    for [a, b, c] in &mesh.triangles {
        let _ = writeln!(out, "f {} {} {}", a + 1, b + 1, c + 1);
    }
    out
}

/// `text`, an OBJ file's own text, with its vertices moved to `positions` (the `n`th `v`
/// line to `positions[n]`) and everything else the file holds kept: texture coordinates,
/// groups, objects, materials, comments, face order. Vertex normals (`vn` lines and the
/// normal index of each face corner) are left out, as they describe the rest surface and a
/// viewer computes them from the moved one. A `v` line keeps what follows its three
/// coordinates (a `w`, vertex colours). `None` when the file has another number of `v` lines
/// than `positions` (it is not the mesh they move).
pub fn with_positions(text: &str, positions: &[Vec3]) -> Option<String> {
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    let mut next = positions.iter();
    for piece in text.split_inclusive('\n') {
        let body = piece.trim_end_matches(['\n', '\r']);
        let ending = &piece[body.len()..];
        let (content, comment) = match body.find('#') {
            Some(i) => body.split_at(i),
            None => (body, ""),
        };
        let mut words = content.split_whitespace();
        match words.next() {
            Some("v") => {
                let p = next.next()?;
                let rest: Vec<&str> = words.skip(3).collect();
                out.push_str(&format!("v {} {} {}", p.x, p.y, p.z));
                for word in rest {
                    out.push(' ');
                    out.push_str(word);
                }
                if !comment.is_empty() {
                    out.push(' ');
                    out.push_str(comment);
                }
                out.push_str(ending);
            }
            Some("vn") => {}
            Some("f") => {
                out.push('f');
                for corner in words {
                    // `v/t/n` -> `v/t`, `v//n` -> `v`: the normal index goes with the `vn` lines
                    let mut parts = corner.splitn(3, '/');
                    let vertex = parts.next().unwrap_or("");
                    out.push(' ');
                    out.push_str(vertex);
                    if let Some(texture) = parts.next().filter(|t| !t.is_empty()) {
                        out.push('/');
                        out.push_str(texture);
                    }
                }
                if !comment.is_empty() {
                    out.push(' ');
                    out.push_str(comment);
                }
                out.push_str(ending);
            }
            _ => out.push_str(piece),
        }
    }
    next.next().is_none().then_some(out)
}

/// The number of `v` lines of an OBJ file's text (as [`with_positions`] finds them).
fn vertex_lines(text: &str) -> usize {
    text.lines()
        .filter(|line| {
            let content = line.split('#').next().unwrap_or("");
            content.split_whitespace().next() == Some("v")
        })
        .count()
}

/// Writes moved copies of one mesh as OBJ text (`export`, `batch`): over the text of the
/// file the mesh was read from when there is one, so its texture coordinates, groups and
/// materials stay ([`with_positions`]); plain ([`write_obj`]) for a built-in mesh, or when
/// that file can no longer be read or no longer holds the mesh's vertices.
#[derive(Debug, Clone, Default)]
pub struct MovedObj {
    /// The mesh file's text, kept when it holds one `v` line per vertex.
    source: Option<String>,
}

impl MovedObj {
    /// The writer for `mesh`, read from `path` (`None`: a built-in mesh).
    pub fn new(path: Option<&Path>, mesh: &Mesh) -> MovedObj {
        let source = path
            .and_then(|p| read_text(p, MAX_FILE_BYTES).ok())
            .filter(|text| vertex_lines(text) == mesh.vertex_count());
        MovedObj { source }
    }

    /// The OBJ text of `mesh` with its vertices at `positions` (one per vertex).
    pub fn write(&self, mesh: &Mesh, positions: &[Vec3]) -> String {
        self.source
            .as_deref()
            .and_then(|text| with_positions(text, positions))
            .unwrap_or_else(|| write_obj(mesh, positions))
    }

    /// [`MovedObj::write`] to `path`, atomically as [`save_obj`].
    pub fn save(&self, path: &Path, mesh: &Mesh, positions: &[Vec3]) -> Result<(), SaveError> {
        atomic::write_atomic(path, self.write(mesh, positions).as_bytes())
            .map_err(|e| SaveError::io(path, &e))
    }
}

/// Writes an OBJ file atomically, keeping a replaced file as `FILE~` (it may be a mesh the
/// user cannot make again; see [`atomic::write_atomic`]).
pub fn save_obj(path: &Path, mesh: &Mesh, positions: &[Vec3]) -> Result<(), SaveError> {
    atomic::write_atomic(path, write_obj(mesh, positions).as_bytes())
        .map_err(|e| SaveError::io(path, &e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Mesh, LoadError> {
        parse_obj(text, Path::new("m.obj"))
    }

    #[test]
    fn reads_vertices_and_fan_triangulates() {
        let mesh = parse(
            "# square\nmtllib x.mtl\no sq\nv 0 0 0\nv 1 0 0\nvt 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\ns off\nusemtl m\nf 1/1/1 2/1/1 3//1 4\n",
        )
        .unwrap();
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn negative_indices_and_crlf() {
        let mesh = parse("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf -3 -2 -1\r\n").unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn groups_collect_face_vertices() {
        let mesh = parse(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng lip upper\nf 1 2 3\ng\nf 2 4 3\ng jaw\nf 4 3 2\n",
        )
        .unwrap();
        assert_eq!(mesh.groups["lip"], vec![0, 1, 2]);
        assert_eq!(mesh.groups["jaw"], vec![1, 2, 3]);
        assert_eq!(mesh.groups.len(), 2);
    }

    #[test]
    fn objects_and_materials_are_groups_too() {
        let mesh = parse(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\no Head\nusemtl skin\nf 1 2 3\no Eyes\nusemtl cornea\nf 2 4 3\n",
        )
        .unwrap();
        assert_eq!(mesh.groups["object:Head"], vec![0, 1, 2]);
        assert_eq!(mesh.groups["material:cornea"], vec![1, 2, 3]);
        assert_eq!(mesh.groups.len(), 4);
    }

    #[test]
    fn errors_have_line_and_column() {
        let cases = [
            ("v 0 0 0\nv 1 x 0\n", 2, Some(5), "`x` is not a number"),
            (
                "v 0 0 0\nv 1 nan 0\n",
                2,
                Some(5),
                "coordinate `nan` is not a finite",
            ),
            (
                "v 0 0 0\nv 1 1e39 0\n",
                2,
                Some(5),
                "coordinate `1e39` is not a finite",
            ),
            ("v 0 0\n", 1, Some(6), "a vertex needs three coordinates"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n",
                4,
                Some(7),
                "vertex index 7 is out of range",
            ),
            (
                "v 0 0 0\nf 1 -2 1\n",
                2,
                Some(5),
                "vertex index -2 is out of range",
            ),
            (
                "v 0 0 0\nf 0 1 1\n",
                2,
                Some(3),
                "vertex index 0 does not exist",
            ),
            (
                "v 0 0 0\nf 1 1\n",
                2,
                Some(1),
                "a face needs at least three corners",
            ),
            ("v 0 0 0\nf 1 a 1\n", 2, Some(5), "`a` is not a face corner"),
        ];
        for (text, line, column, start) in cases {
            let err = parse(text).unwrap_err();
            assert_eq!(
                (err.line, err.column),
                (Some(line), column),
                "{text:?}: {err}"
            );
            assert!(err.message.starts_with(start), "{text:?}: {err}");
        }
        let err = parse("v 0 0 0\n").unwrap_err();
        assert_eq!(
            err.to_string(),
            "m.obj: the mesh has no faces; expected `f` lines"
        );
    }

    #[test]
    fn forward_references_are_allowed() {
        let mesh = parse("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn with_positions_moves_the_vertices_and_keeps_the_rest_of_the_file() {
        let text = "# head\r\nmtllib h.mtl\r\no head\r\nv 0 0 0 # first\r\nv 1 0 0 0.5 0.5 0.5\r\nv 0 1 0\r\nv 1 1 0\r\nvt 0 0\r\nvn 0 0 1\r\ng skin\r\nusemtl face\r\ns 1\r\nf 1/1/1 2/1/1 3/1/1\r\ng teeth\r\nf 2//1 4//1 3//1\r\nf -3 -1 -2\r\n";
        let source = parse(text).unwrap();
        let moved: Vec<Vec3> = source
            .positions
            .iter()
            .map(|p| *p + Vec3::new(0.25, -0.5, 2.0))
            .collect();
        let written = with_positions(text, &moved).unwrap();
        assert_eq!(
            written,
            "# head\r\nmtllib h.mtl\r\no head\r\nv 0.25 -0.5 2 # first\r\nv 1.25 -0.5 2 0.5 0.5 0.5\r\nv 0.25 0.5 2\r\nv 1.25 0.5 2\r\nvt 0 0\r\ng skin\r\nusemtl face\r\ns 1\r\nf 1/1 2/1 3/1\r\ng teeth\r\nf 2 4 3\r\nf -3 -1 -2\r\n"
        );
        let back = parse(&written).unwrap();
        assert_eq!(back.positions, moved);
        assert_eq!(back.triangles, source.triangles);
        assert_eq!(back.groups, source.groups);
        // not the file of these positions
        assert_eq!(with_positions(text, &moved[..3]), None);
        let mut more = moved.clone();
        more.push(Vec3::ZERO);
        assert_eq!(with_positions(text, &more), None);
    }

    #[test]
    fn write_round_trips_exactly() {
        let positions = vec![
            Vec3::new(0.1, -0.0, 1e-7),
            Vec3::new(-4.36, 7.52, 3.4028235e38),
            Vec3::new(1.57, -2.221, 7.82),
        ];
        let mesh = Mesh::new(positions, vec![[0, 1, 2], [2, 1, 0]]).unwrap();
        let text = write_obj(&mesh, &mesh.positions);
        let back = parse(&text).unwrap();
        assert_eq!(back.triangles, mesh.triangles);
        for (a, b) in back.positions.iter().zip(&mesh.positions) {
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits)
            );
        }
        assert_eq!(write_obj(&back, &back.positions), text);
    }
}
