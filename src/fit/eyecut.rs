//! Covered eye openings cut open: some meshes (MediaPipe's canonical face, many scans) lay
//! skin across each eye, a band of triangles from the upper lid's margin to the lower one's.
//! Such lids cannot close over an eye: the band ties the margins together, and the open eye
//! is as lit as the cheek, so it does not read as an eye. [`find`] finds, per eye, the lid
//! margins from the landmarks and the mesh and the band between them; [`open`] takes the
//! band out of the skin: its triangles move onto copies of their vertices, set back behind
//! the opening and closed by a dome behind it into an eye (the group [`GROUP`], kept still by
//! the muscles; `shaded` paints an iris on it where the landmarks are known and draws it dark
//! where they are not). The lids are then separate surfaces that
//! meet at the corners.
//!
//! The margins are found as the lip line is ([`super::lipcut`]): the shortest chain of mesh
//! edges from one corner through the upper lid landmarks (36-39, 42-45) to the other, each
//! step weighed up by its distance from the landmarks' polyline, and the same through the
//! lower lid landmarks (36, 41, 40, 39; 42, 47, 46, 45). The eye is covered when skin lies
//! inside the upper margin and that skin is a disk closing on the two margins without
//! leaving the slit between the lid landmarks and without reaching an edge of the mesh. A
//! real opening (the margins are edges of the mesh, or the lids fold into a socket with a
//! hole in it: MakeHuman's base mesh, the built-in face) is left alone.
//!
//! The cut keeps every original vertex and triangle at its number: the copies and the dome
//! are appended, and the band's triangles (at their own places) name the copies.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::f32::consts::FRAC_PI_2;

use glam::Vec3;

use super::seam::{distance_to_polyline, grown_from_each, key, Graph};
use crate::landmarks::{
    FaceFrame, COUNT, LEFT_EYE_LOWER, LEFT_EYE_UPPER, RIGHT_EYE_LOWER, RIGHT_EYE_UPPER,
};
use crate::model::Mesh;

/// The eye's inside: its group name, drawn by `shaded` as an eye with a painted iris (nearly
/// black without landmarks), a still part for `fit-rig` (the name holds `eye`).
pub const GROUP: &str = "eye_interior";

/// How far from the eye's centre its margins are looked for, in eye widths (corner to
/// corner; the corners lie at a half).
const REACH: f32 = 1.0;
/// The distance from the lid landmarks' polyline at which a step of a margin costs twice its
/// length, in eye widths.
const GUIDE: f32 = 0.04;
/// Slack of the slit test, in eye widths: a band vertex's distances to the upper and lower
/// lid polylines add up to at most 1.5 times the widest lid gap plus this.
const SLIT_SLACK: f32 = 0.05;
/// How much lower (nearer the lower lid's polyline and further from the upper one, as a
/// share of the edge's length) one triangle's third corner lies than the other's for an
/// edge of the upper margin to seed the band. A margin found on a fine mesh steps up and
/// down between rows of vertices, and on a steep step its two triangles lie side by side:
/// taking one there seeded the band on the lid (MediaPipe's face cut in sixteen), the band
/// spread over the face and the eye was taken for open.
const DECISIVE: f32 = 0.5;
/// How far behind the opening the band is set, in eye widths: the closing lids pass in front
/// of it.
const INSET: f32 = 0.06;
/// How far behind the opening the back of the eye lies, in eye widths.
const DEPTH: f32 = 0.4;
/// Rings of the dome behind the eye, from its rim to its back (a point).
const ROWS: usize = 4;

/// What [`find`] found at one eye.
#[derive(Debug, Clone, PartialEq)]
pub enum Lids {
    /// The upper margin is an edge of the mesh: the eye is open already.
    Open,
    /// Skin lies inside the upper margin but it is not a band across the opening (lids that
    /// fold into a socket, a hole deeper in): nothing to cut.
    Apart,
    /// The two margins are one row of vertices (lids modelled shut): not cut.
    OneRow,
    /// No chain of edges joins the lid landmarks.
    NotFound,
    /// Skin covers the opening: the margins and the band between them.
    Covered(Cover),
}

/// A covered eye opening.
#[derive(Debug, Clone, PartialEq)]
pub struct Cover {
    /// The upper lid's margin from one corner to the other (original vertex numbers).
    pub upper: Vec<u32>,
    /// The lower lid's margin between the same corners.
    pub lower: Vec<u32>,
    /// The band's triangles (numbers in the mesh), sorted.
    pub band: Vec<usize>,
}

/// Both eyes opened: what was appended to the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct EyeCut {
    /// What was found at the subject's right eye (landmarks 36-41), then the left (42-47).
    pub found: [Lids; 2],
    /// The first appended vertex: every vertex from there on is the eyes' inside.
    pub first: u32,
    /// The eyes' own triangles (the domes), the last ones of the mesh.
    pub triangles: usize,
    /// The original vertex of each band copy, in the order appended from `first` (both
    /// eyes' copies, then the domes' vertices).
    pub copies: Vec<u32>,
}

impl EyeCut {
    /// How many eyes were cut open.
    pub fn opened(&self) -> usize {
        self.found
            .iter()
            .filter(|l| matches!(l, Lids::Covered(_)))
            .count()
    }
}

/// Finds each eye's lid margins in `mesh` from its 68 landmark vertices and whether skin
/// covers the opening between them: the subject's right eye, then the left.
pub fn find(mesh: &Mesh, landmarks: &[u32]) -> [Lids; 2] {
    [
        (RIGHT_EYE_UPPER, RIGHT_EYE_LOWER),
        (LEFT_EYE_UPPER, LEFT_EYE_LOWER),
    ]
    .map(|(upper, lower)| find_one(mesh, landmarks, &upper, &lower))
}

/// Opens every covered eye of `found` in `mesh`, whose 68 landmark vertices are `landmarks`:
/// each band's triangles move onto copies of their vertices set back behind the opening, and
/// a dome behind closes each into a dark eye. `None` (and `mesh` unchanged) when no eye is
/// covered or the landmarks have no frame.
pub fn open(mesh: &mut Mesh, landmarks: &[u32], found: [Lids; 2]) -> Option<EyeCut> {
    if !found.iter().any(|l| matches!(l, Lids::Covered(_))) {
        return None;
    }
    let points: Vec<Vec3> = landmarks
        .iter()
        .map(|&v| mesh.positions[v as usize])
        .collect();
    let forward = FaceFrame::of(&points)?.forward.as_vec3();
    let first = mesh.vertex_count() as u32;
    let before = mesh.triangles.len();
    let mut copies = Vec::new();
    let mut domes = Vec::new();
    for lids in &found {
        if let Lids::Covered(cover) = lids {
            let (a, b) = (cover.upper[0], cover.upper[cover.upper.len() - 1]);
            let width = mesh.positions[a as usize].distance(mesh.positions[b as usize]);
            let rim = set_back(mesh, cover, forward, width * INSET, &mut copies);
            domes.push((rim, forward * width));
        }
    }
    for (rim, back) in domes {
        dome(mesh, &rim, back * DEPTH);
    }
    let members: Vec<u32> = (first..mesh.vertex_count() as u32).collect();
    mesh.groups.insert(GROUP.to_string(), members);
    Some(EyeCut {
        found,
        first,
        triangles: mesh.triangles.len() - before,
        copies,
    })
}

/// One eye: its margins, then the band between them.
fn find_one(mesh: &Mesh, landmarks: &[u32], upper_ids: &[usize], lower_ids: &[usize]) -> Lids {
    let Some(eye) = Eye::of(mesh, landmarks, upper_ids, lower_ids) else {
        return Lids::NotFound;
    };
    let graph = Graph::new(mesh, eye.centre, REACH * eye.width);
    let lowness =
        |p: Vec3| distance_to_polyline(p, &eye.upper) - distance_to_polyline(p, &eye.lower);
    let contours = [(upper_ids, &eye.upper[..]), (lower_ids, &eye.lower[..])];
    let Some((upper, lower)) =
        graph.two_lines(mesh, GUIDE * eye.width, landmarks, contours, lowness)
    else {
        return Lids::NotFound;
    };
    if upper == lower {
        return Lids::OneRow;
    }
    // the triangles just inside the upper margin (not on the lower one too), the lower lid's
    // side of it
    let lower_edges: HashSet<[u32; 2]> = lower.windows(2).map(|p| key(p[0], p[1])).collect();
    let seeds = graph.below(mesh, (&upper, &lower_edges), lowness, DECISIVE);
    if seeds.is_empty() {
        return Lids::Open;
    }
    match grown_from_each(&seeds, |seed| {
        band(mesh, &graph, &eye, seed, &upper, &lower)
    }) {
        Some(band) => Lids::Covered(Cover { upper, lower, band }),
        None => Lids::Apart,
    }
}

/// The eye as its lid landmarks place it.
struct Eye {
    /// The upper lid polyline (corner to corner) and the lower.
    upper: Vec<Vec3>,
    lower: Vec<Vec3>,
    centre: Vec3,
    /// Corner to corner.
    width: f32,
    /// The widest gap between facing lid landmarks.
    gap: f32,
}

impl Eye {
    fn of(mesh: &Mesh, landmarks: &[u32], upper_ids: &[usize], lower_ids: &[usize]) -> Option<Eye> {
        if landmarks.len() != COUNT || landmarks.iter().any(|&v| v as usize >= mesh.vertex_count())
        {
            return None;
        }
        let at = |i: usize| mesh.positions[landmarks[i] as usize];
        let upper: Vec<Vec3> = upper_ids.iter().map(|&i| at(i)).collect();
        let lower: Vec<Vec3> = lower_ids.iter().map(|&i| at(i)).collect();
        let centre = upper.iter().chain(&lower).copied().sum::<Vec3>() / (2 * upper.len()) as f32;
        let width = upper[0].distance(upper[upper.len() - 1]);
        let gap = upper
            .iter()
            .zip(&lower)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f32::max);
        (width > 0.0).then_some(Eye {
            upper,
            lower,
            centre,
            width,
            gap,
        })
    }

    /// Whether a point lies in the slit between the lid polylines.
    fn in_slit(&self, p: Vec3) -> bool {
        let d = distance_to_polyline(p, &self.upper) + distance_to_polyline(p, &self.lower);
        d <= 1.5 * self.gap + SLIT_SLACK * self.width
    }
}

/// The band grown from `seed` (a triangle just inside the upper margin) without crossing
/// either margin, sorted; `None` when it leaves the slit between the lid landmarks or reaches
/// an edge of the mesh (a hole: the skin is a lid's own fold, not a cover).
fn band(
    mesh: &Mesh,
    graph: &Graph,
    eye: &Eye,
    seed: usize,
    upper: &[u32],
    lower: &[u32],
) -> Option<Vec<usize>> {
    let walls: HashSet<[u32; 2]> = upper
        .windows(2)
        .chain(lower.windows(2))
        .map(|p| key(p[0], p[1]))
        .collect();
    let on_margin: HashSet<u32> = upper.iter().chain(lower).copied().collect();
    let mut seen: HashSet<usize> = HashSet::from([seed]);
    let mut stack = vec![seed];
    while let Some(t) = stack.pop() {
        let tri = mesh.triangles[t];
        let in_slit = tri
            .iter()
            .all(|&v| on_margin.contains(&v) || eye.in_slit(mesh.positions[v as usize]));
        if !in_slit {
            return None;
        }
        for k in 0..3 {
            let edge = key(tri[k], tri[(k + 1) % 3]);
            if walls.contains(&edge) {
                continue;
            }
            let across = graph.across(&edge);
            if across.len() != 2 {
                return None;
            }
            for &u in across {
                if seen.insert(u) {
                    stack.push(u);
                }
            }
        }
    }
    let mut band: Vec<usize> = seen.into_iter().collect();
    band.sort_unstable();
    Some(band)
}

/// Moves the band's triangles onto copies of their vertices set back by `inset` against
/// `forward`, appending the copies (their originals to `copies`); returns the copies along
/// the band's rim in order. A band that bulges out of the opening (a scan's cornea fused with
/// its lids) is first flattened to the margins' front-most depth, so the closing lids pass in
/// front of all of it.
fn set_back(
    mesh: &mut Mesh,
    cover: &Cover,
    forward: Vec3,
    inset: f32,
    copies: &mut Vec<u32>,
) -> Vec<u32> {
    let front = cover
        .upper
        .iter()
        .chain(&cover.lower)
        .map(|&v| mesh.positions[v as usize].dot(forward))
        .fold(f32::NEG_INFINITY, f32::max);
    let mut copy_of: BTreeMap<u32, u32> = BTreeMap::new();
    for &t in &cover.band {
        for corner in 0..3 {
            let v = mesh.triangles[t][corner];
            let copy = *copy_of.entry(v).or_insert_with(|| {
                let p = mesh.positions[v as usize];
                let bulge = (p.dot(forward) - front).max(0.0);
                mesh.positions.push(p - forward * (inset + bulge));
                copies.push(v);
                mesh.positions.len() as u32 - 1
            });
            mesh.triangles[t][corner] = copy;
        }
    }
    rim(mesh, &cover.band)
}

/// The boundary of a disk of triangles as one loop of vertices, following the triangles'
/// winding; empty when the boundary is not one loop.
fn rim(mesh: &Mesh, band: &[usize]) -> Vec<u32> {
    let mut count: HashMap<[u32; 2], usize> = HashMap::new();
    for &t in band {
        let tri = mesh.triangles[t];
        for k in 0..3 {
            *count.entry(key(tri[k], tri[(k + 1) % 3])).or_default() += 1;
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &t in band {
        let tri = mesh.triangles[t];
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if count[&key(a, b)] == 1 && next.insert(a, b).is_some() {
                return Vec::new();
            }
        }
    }
    let Some(&start) = next.keys().min() else {
        return Vec::new();
    };
    let mut ring = vec![start];
    while let Some(&v) = next.get(ring.last().unwrap_or(&start)) {
        if v == start {
            break;
        }
        if ring.len() > next.len() {
            return Vec::new();
        }
        ring.push(v);
    }
    if ring.len() == next.len() {
        ring
    } else {
        Vec::new()
    }
}

/// Closes the set-back band into a dark eye: rings shrinking from the band's `rim` to a point
/// `depth` behind its centre, like the back of an eyeball, wound outward. The rim follows the
/// band's winding, so the dome's triangles run the other way round it.
fn dome(mesh: &mut Mesh, rim: &[u32], depth: Vec3) {
    if rim.len() < 3 {
        return;
    }
    let at = |mesh: &Mesh, v: u32| mesh.positions[v as usize];
    let centre = rim.iter().map(|&v| at(mesh, v)).sum::<Vec3>() / rim.len() as f32;
    let mut rows: Vec<Vec<u32>> = vec![rim.to_vec()];
    for row in 1..ROWS {
        let angle = FRAC_PI_2 * row as f32 / ROWS as f32;
        let ring: Vec<u32> = rim
            .iter()
            .map(|&v| {
                let p = centre + (at(mesh, v) - centre) * angle.cos() - depth * angle.sin();
                mesh.positions.push(p);
                mesh.positions.len() as u32 - 1
            })
            .collect();
        rows.push(ring);
    }
    mesh.positions.push(centre - depth);
    let apex = mesh.positions.len() as u32 - 1;
    let m = rim.len();
    for pair in rows.windows(2) {
        let (near, far) = (&pair[0], &pair[1]);
        for i in 0..m {
            let j = (i + 1) % m;
            // the band runs near[i] -> near[j]; the dome shares that edge the other way
            mesh.triangles.push([near[j], near[i], far[i]]);
            mesh.triangles.push([near[j], far[i], far[j]]);
        }
    }
    let last = &rows[rows.len() - 1];
    for i in 0..m {
        mesh.triangles.push([last[(i + 1) % m], last[i], apex]);
    }
}

/// The lid vertices of each covered eye of `found`: its two margins.
pub fn margins(found: &[Lids; 2]) -> Vec<u32> {
    found
        .iter()
        .filter_map(|l| match l {
            Lids::Covered(c) => Some(c.upper.iter().chain(&c.lower).copied()),
            _ => None,
        })
        .flatten()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rim_of_two_triangles_follows_their_winding() {
        let p = Vec3::ZERO;
        let mesh = Mesh::new(vec![p; 4], vec![[0, 1, 2], [0, 2, 3]]).unwrap();
        assert_eq!(rim(&mesh, &[0, 1]), vec![0, 1, 2, 3]);
    }
}
