//! Skin split at its texture seams, joined again for fitting.
//!
//! Many exporters write a vertex once per texture island, so a head arrives cut along its
//! UV seams into pieces that only touch. Everything the fit finds by walking the skin's
//! edges (its pieces, the lip and lid lines, the slide's patches, the area bound) stops at
//! such a seam: the lips are not found when a seam crosses them, and the two sides drift
//! apart as the face moves (a crack, though no triangle tears).
//!
//! A seam here is a pair of boundary edges (each in one triangle) whose ends lie at exactly
//! the same places, run in opposite directions (the two sides wind alike, as one surface
//! does) and whose triangles face the same way. Each pair is joined: every triangle takes the
//! lowest-numbered vertex of the coincident ones it names, and the copies are left in no
//! face, where a deformation moves each with its vertex ([`crate::model::Mesh::followers`]),
//! so the user's numbering still holds every vertex. A triangle with two corners at one place
//! (a degenerate sliver) keeps its own vertices.
//!
//! Not joined: pairs running along the inner lip line or a lid line (from the landmarks) where
//! the landmarks say it is cut (an upper and the lower landmark across from it are two
//! vertices at one place). Lips or lids cut apart on purpose touch there at rest (a mesh
//! `fit-rig` opened, a scan cut by hand) and must part when the face moves; where the
//! landmarks name one vertex for both, the line is joined like the rest of the seam, and the
//! fit cuts it as it cuts any joined lips. Nor are the mouth pocket and the eyes' insides a
//! fit added (a mesh `fit-rig` opened, fitted again) joined to the skin they touch.

use glam::Vec3;

use super::parts::Parts;
use super::seam::{key, nearest_segment};
use crate::landmarks::{Landmarks, EYES, INNER_UPPER};
use crate::model::mesh::{lead_of, position_key};
use crate::model::{Mesh, Rig};

/// How near the landmarks' opening line (times the opening's width) both ends of a seam edge
/// lie when the edge runs along it.
const ALONG_OPENING: f32 = 0.1;

/// How closely (cosine of the angle) a seam edge follows the opening line to run along it.
const ALONG_COSINE: f32 = 0.7;

/// A mesh whose seams are joined.
#[derive(Debug, Clone, PartialEq)]
pub struct Weld {
    /// The mesh with its triangles naming one vertex per joined place; every vertex kept at
    /// its number.
    pub mesh: Mesh,
    /// The landmarks as vertices of the joined mesh.
    pub landmarks: Vec<u32>,
}

/// Joins the seams of `mesh` ([module docs](self)), keeping the lip and lid lines of its 68
/// `landmarks` apart; `None` when it has none.
pub fn weld(mesh: &Mesh, landmarks: &[u32]) -> Option<Weld> {
    let openings = Openings::of(mesh, landmarks);
    let mut join = Union::new(mesh.vertex_count());
    let mut joined = false;
    for (a, b, c, d) in seam_pairs(mesh) {
        let (p, q) = (mesh.positions[a as usize], mesh.positions[b as usize]);
        if openings.along(p, q) {
            continue;
        }
        join.union(a, d);
        join.union(b, c);
        joined = true;
    }
    if !joined {
        return None;
    }
    // a triangle with two corners at one place (a degenerate sliver, as scans have) keeps
    // its own vertices: joined, it would name one vertex twice
    let triangles: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .map(|t| {
            let j = t.map(|v| join.find(v));
            match j[0] == j[1] || j[1] == j[2] || j[2] == j[0] {
                true => *t,
                false => j,
            }
        })
        .collect();
    let mut welded = mesh.clone();
    welded.triangles = triangles;
    // a landmark on a vertex now in no face names the vertex it lies on
    let followers = welded.followers();
    Some(Weld {
        landmarks: landmarks
            .iter()
            .map(|&v| lead_of(&followers, join.find(v)))
            .collect(),
        mesh: welded,
    })
}

/// A mesh without the copies of its split vertices ([`Mesh::followers`]), for fitting: a copy
/// in no face is not skin the fit can walk, and left in, it would take part in what is
/// found by position (masks kept off still parts, nearest vertices). The fitted rig is laid
/// back on the whole numbering, each copy weighted as the vertex it moves with.
pub(super) struct Compact {
    /// The mesh without the copies, renumbered.
    pub(super) mesh: Mesh,
    /// Per vertex of the whole mesh: its number in `mesh` (a copy: its lead's).
    number: Vec<u32>,
    /// Per vertex of `mesh`: its number in the whole mesh.
    whole: Vec<u32>,
    /// `[copy, lead]` in the whole mesh's numbering.
    followers: Vec<[u32; 2]>,
}

impl Compact {
    /// `mesh` without its copies; `None` when it has none.
    pub(super) fn of(mesh: &Mesh) -> Option<Compact> {
        let followers = mesh.followers();
        if followers.is_empty() {
            return None;
        }
        let mut is_copy = vec![false; mesh.vertex_count()];
        for f in &followers {
            is_copy[f[0] as usize] = true;
        }
        let whole: Vec<u32> = (0..mesh.vertex_count() as u32)
            .filter(|&v| !is_copy[v as usize])
            .collect();
        let mut number = vec![0u32; mesh.vertex_count()];
        for (new, &old) in whole.iter().enumerate() {
            number[old as usize] = new as u32;
        }
        for &[copy, lead] in &followers {
            number[copy as usize] = number[lead as usize];
        }
        let groups = mesh
            .groups
            .iter()
            .map(|(name, members)| {
                let kept = members
                    .iter()
                    .filter(|&&v| !is_copy[v as usize])
                    .map(|&v| number[v as usize])
                    .collect();
                (name.clone(), kept)
            })
            .collect();
        let compact = Mesh {
            positions: whole.iter().map(|&v| mesh.positions[v as usize]).collect(),
            triangles: mesh
                .triangles
                .iter()
                .map(|t| t.map(|v| number[v as usize]))
                .collect(),
            groups,
        };
        Some(Compact {
            mesh: compact,
            number,
            whole,
            followers,
        })
    }

    /// `landmarks` on the compact mesh (a landmark on a copy names its lead).
    pub(super) fn landmarks(&self, landmarks: &Landmarks) -> Landmarks {
        match landmarks {
            Landmarks::Vertices(v) => Landmarks::Vertices(
                v.iter()
                    .map(|&v| self.number.get(v as usize).copied().unwrap_or(v))
                    .collect(),
            ),
            points => points.clone(),
        }
    }

    /// A rig and parts fitted to the compact mesh, on the whole mesh: its weights and parts
    /// at the whole mesh's numbers, each copy as its lead.
    pub(super) fn expand(&self, rig: &mut Rig, parts: &mut Parts) {
        for mask in &mut rig.masks {
            mask.weights = self.expand_weights(&mask.weights);
        }
        if let Some(jaw) = &mut rig.jaw {
            jaw.weights = self.expand_weights(&jaw.weights);
        }
        parts.of_vertex = self
            .number
            .iter()
            .map(|&n| parts.of_vertex[n as usize])
            .collect();
    }

    /// Per-vertex `(vertex, weight)` pairs of the compact mesh at the whole mesh's numbers,
    /// each copy with its lead's weight, sorted by vertex.
    fn expand_weights(&self, weights: &[(u32, f32)]) -> Vec<(u32, f32)> {
        let mut out: Vec<(u32, f32)> = weights
            .iter()
            .map(|&(v, w)| (self.whole[v as usize], w))
            .collect();
        for &[copy, lead] in &self.followers {
            let n = self.number[lead as usize];
            if let Ok(i) = weights.binary_search_by_key(&n, |p| p.0) {
                out.push((copy, weights[i].1));
            }
        }
        out.sort_unstable_by_key(|p| p.0);
        out
    }
}

/// Each pair of boundary edges `a -> b` and `c -> d` with `c` at `b` and `d` at `a`, its
/// triangles facing the same way, once (`a -> b` from the lower-numbered triangle). Edges of
/// the mouth pocket and the eyes' insides a fit added (groups `mouth_interior`,
/// `eye_interior`) are no seam: they lie on the lips' and lids' edges on purpose.
fn seam_pairs(mesh: &Mesh) -> Vec<(u32, u32, u32, u32)> {
    let mut uses = std::collections::HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *uses.entry(key(a, b)).or_insert(0u32) += 1;
        }
    }
    let at = |v: u32| position_key(mesh.positions[v as usize]);
    // the insides the fit adds behind opened lips and eyes are apart from the skin by design
    let mut inside = vec![false; mesh.vertex_count()];
    for group in [super::pocket::GROUP, super::eyecut::GROUP] {
        for &v in mesh.groups.get(group).map_or(&[][..], |g| &g[..]) {
            inside[v as usize] = true;
        }
    }
    // boundary edges by where their ends lie: (triangle, from, to)
    let mut boundary = std::collections::HashMap::<_, Vec<(usize, u32, u32)>>::new();
    for (i, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let outside = !(inside[a as usize] && inside[b as usize]);
            if uses[&key(a, b)] == 1 && at(a) != at(b) && outside {
                boundary.entry((at(a), at(b))).or_default().push((i, a, b));
            }
        }
    }
    let normals = mesh.face_normals(&mesh.positions);
    let mut pairs = Vec::new();
    for (&(from, to), edges) in &boundary {
        let Some(partners) = boundary.get(&(to, from)) else {
            continue;
        };
        for &(i, a, b) in edges {
            for &(j, c, d) in partners {
                if i < j && normals[i].dot(normals[j]) > 0.0 {
                    pairs.push((a, b, c, d));
                }
            }
        }
    }
    // the map's order is arbitrary; the joins do not depend on it, the list is kept tidy
    pairs.sort_unstable();
    pairs
}

/// The lines that open (inner lip line, both lid lines) and are cut where they touch, as
/// closed polylines, each with its width (corner to corner).
struct Openings {
    lines: Vec<(Vec<Vec3>, f32)>,
}

impl Openings {
    /// The openings of the 68 `landmarks` that are cut: an upper landmark and the lower one
    /// across from it are two vertices at one place. Where the landmarks name one vertex
    /// there, the line is joined, or cut by the fit later, as on a mesh in one piece.
    fn of(mesh: &Mesh, landmarks: &[u32]) -> Openings {
        let point = |i: usize| {
            landmarks
                .get(i)
                .and_then(|&v| mesh.positions.get(v as usize).copied())
        };
        let cut =
            |(upper, lower): (usize, usize)| match (landmarks.get(upper), landmarks.get(lower)) {
                (Some(&a), Some(&b)) => a != b && point(upper) == point(lower),
                _ => false,
            };
        let loop_of = |indices: &[usize]| -> Option<(Vec<Vec3>, f32)> {
            let mut line: Vec<Vec3> = indices.iter().map(|&i| point(i)).collect::<Option<_>>()?;
            let width = line[0].distance(line[line.len() / 2]);
            line.push(line[0]);
            Some((line, width))
        };
        // each contour from one corner round to it, the upper half first
        let mouth: Vec<usize> = (INNER_UPPER[0]..INNER_UPPER[0] + 8).collect();
        let contours = std::iter::once(mouth).chain(EYES.iter().map(|eye| eye.to_vec()));
        let lines = contours
            .filter(|c| {
                let half = c.len() / 2;
                (1..half).any(|k| cut((c[k], c[c.len() - k])))
            })
            .filter_map(|c| loop_of(&c))
            .collect();
        Openings { lines }
    }

    /// Whether the edge `p`-`q` runs along one of the lines.
    fn along(&self, p: Vec3, q: Vec3) -> bool {
        self.lines.iter().any(|(line, width)| {
            let near = ALONG_OPENING * width;
            let (dp, sp) = nearest_segment(p, line);
            let (dq, _) = nearest_segment(q, line);
            let direction = (q - p).normalize_or_zero();
            dp <= near && dq <= near && direction.dot(sp).abs() >= ALONG_COSINE
        })
    }
}

/// Disjoint sets of vertices, each named by its lowest-numbered vertex.
struct Union {
    parent: Vec<u32>,
}

impl Union {
    fn new(n: usize) -> Union {
        Union {
            parent: (0..n as u32).collect(),
        }
    }

    fn find(&self, mut v: u32) -> u32 {
        while self.parent[v as usize] != v {
            v = self.parent[v as usize];
        }
        v
    }

    fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        let (low, high) = (a.min(b), a.max(b));
        self.parent[high as usize] = low;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of four quads along x, its right half split from its left at x = 2 (vertices
    /// 10 and 11 copy 2 and 7).
    fn split_strip() -> Mesh {
        let mut positions: Vec<Vec3> = (0..5)
            .map(|i| Vec3::new(i as f32, 0.0, 0.0))
            .chain((0..5).map(|i| Vec3::new(i as f32, 1.0, 0.0)))
            .collect();
        positions.push(Vec3::new(2.0, 0.0, 0.0));
        positions.push(Vec3::new(2.0, 1.0, 0.0));
        let quad = |a: u32, b: u32, c: u32, d: u32| [[a, b, c], [a, c, d]];
        let triangles = [
            quad(0, 1, 6, 5),
            quad(1, 2, 7, 6),
            quad(10, 3, 8, 11),
            quad(3, 4, 9, 8),
        ]
        .concat();
        Mesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn a_split_strip_is_joined_and_its_copies_follow() {
        let mesh = split_strip();
        let weld = weld(&mesh, &[]).expect("a seam");
        assert!(weld.mesh.triangles.iter().flatten().all(|&v| v < 10));
        assert_eq!(weld.mesh.followers(), vec![[10, 2], [11, 7]]);
        // the joined strip is one piece: its edge at x = 2 is used twice
        let uses = weld
            .mesh
            .triangles
            .iter()
            .filter(|t| t.contains(&2) && t.contains(&7))
            .count();
        assert_eq!(uses, 2);
    }

    #[test]
    fn a_sliver_with_two_corners_at_one_place_keeps_its_vertices() {
        // a zero-area triangle across the seam, from vertex 2 to its copy 10 and on to 3
        let mut mesh = split_strip();
        mesh.triangles.push([2, 10, 3]);
        let weld = weld(&mesh, &[]).expect("the seam is joined all the same");
        assert_eq!(weld.mesh.triangles.last(), Some(&[2, 10, 3]));
        assert!(weld.mesh.triangles[..8].iter().flatten().all(|&v| v < 10));
        assert_eq!(weld.mesh.followers(), vec![[11, 7]]);
    }

    #[test]
    fn a_whole_mesh_has_no_seam() {
        let mut mesh = split_strip();
        let original = |v: u32| match v {
            10 => 2,
            11 => 7,
            v => v,
        };
        mesh.triangles = mesh.triangles.iter().map(|t| t.map(original)).collect();
        assert_eq!(weld(&mesh, &[]), None);
    }

    #[test]
    fn a_fold_is_not_a_seam() {
        // the right half turned back under the left: its triangles face the other way
        let mut mesh = split_strip();
        for v in [3, 4, 8, 9] {
            let p = &mut mesh.positions[v];
            p.x = 4.0 - p.x;
        }
        assert_eq!(weld(&mesh, &[]), None);
    }
}
