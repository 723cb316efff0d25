//! Joined lips cut open: many meshes (MediaPipe's canonical face, scans) close the mouth with
//! skin, either one row of vertices shared by both lips or a thin band of triangles between
//! the upper and lower inner lip rows. Such a mouth cannot open without stretching that skin
//! into a sheet. [`find`] finds the joined inner lip line from the landmarks and the mesh, and
//! cuts it: every vertex inside the line (not the corners) is duplicated, and the triangles
//! below the line take the copies, so the lips are separate surfaces that meet at the corners.
//!
//! The line is the upper lip's inner edge: the shortest chain of mesh edges from the right
//! inner corner (landmark 60) through the upper inner lip landmarks (61-63) to the left
//! corner (64), each step's length weighed up by its distance from the landmarks' polyline,
//! so the chain follows the lip and not a diagonal across it. The same chain along the lower
//! inner lip (60, 67-65, 64) bounds the band below it. The lips are joined when skin lies
//! below the line and that skin is either the lower lip itself (the two chains are one row)
//! or a band that closes on the lower chain without leaving the slit between the inner lip
//! landmarks. A mouth whose line is a boundary is open already; lips that are separate
//! surfaces joined only deep inside the mouth (a mouth bag) are left alone too.
//!
//! The cut keeps every original vertex at its number; the copies are appended in the order of
//! the line, and [`LipCut::copies`] says which vertex each copies. Nothing here reads files.

use std::collections::{BTreeMap, HashMap, HashSet};

use glam::Vec3;

use super::eyecut::{EyeCut, Lids};
use super::pocket::Pocket;
use super::seam::{distance_to_polyline, grown_from_each, key, Graph};
use crate::landmarks::{COUNT, INNER_LOWER, INNER_UPPER};
use crate::model::{Mesh, Rig};

/// Landmarks on the lower lip: on a cut vertex they move to its copy.
const LOWER_LIP: [usize; 8] = [55, 56, 57, 58, 59, 65, 66, 67];
/// How far from the mouth's centre the line is looked for, in outer mouth widths (the
/// corners lie at a half).
const REACH: f32 = 0.8;
/// The distance from the landmarks' polyline at which a step of the line costs twice its
/// length, in outer mouth widths.
const GUIDE: f32 = 0.04;
/// Slack of the slit test, in outer mouth widths: a band vertex's distances to the upper and
/// lower inner lip polylines add up to at most 1.5 times the widest inner lip gap plus this.
const SLIT_SLACK: f32 = 0.02;

/// What [`find`] found at the inner lip line.
#[derive(Debug, Clone, PartialEq)]
pub enum Lips {
    /// The line is a boundary of the mesh: the mouth opens already.
    Open,
    /// Skin lies below the line, but it is not a band closing the slit between the lips (the
    /// lips are separate surfaces joined deep inside the mouth): nothing to cut.
    Separate,
    /// No chain of edges joins the inner lip landmarks (they lie on pieces that do not touch).
    NotFound,
    /// The lips are joined; the cut that opens them.
    Joined(LipCut),
}

/// Joined lips cut open.
#[derive(Debug, Clone, PartialEq)]
pub struct LipCut {
    /// The opened mesh: the original vertices at their numbers, then the copies; triangles in
    /// the original order, those below the line using the copies; each copy in its
    /// original's groups.
    pub mesh: Mesh,
    /// The original vertex of each appended copy: vertex `n + i` of the opened mesh (`n` the
    /// original count) copies `copies[i]`.
    pub copies: Vec<u32>,
    /// The cut line from the right inner corner to the left, as original vertex numbers.
    pub line: Vec<u32>,
    /// Triangles of the band between the lips that now belong to the lower lip (0 when the
    /// lips shared one row of vertices).
    pub band: usize,
    /// The 68 landmarks as vertices of the opened mesh: lower lip landmarks on a cut vertex
    /// name its copy.
    pub landmarks: Vec<u32>,
    /// The mouth pocket appended after the copies (its vertices last, its triangles last):
    /// the inside of the opened mouth ([`Pocket`]).
    pub pocket: Option<Pocket>,
    /// The eyes' insides appended after the pocket, where covered eye openings were cut
    /// ([`super::eyecut`]).
    pub eyes: Option<Box<EyeCut>>,
}

impl LipCut {
    /// `mesh` with nothing cut (landmarks `landmarks`): a mesh written beside the rig for
    /// another reason (its seams joined, [`super::weld`]).
    pub fn uncut(mesh: Mesh, landmarks: Vec<u32>) -> LipCut {
        LipCut {
            mesh,
            copies: Vec::new(),
            line: Vec::new(),
            band: 0,
            landmarks,
            pocket: None,
            eyes: None,
        }
    }

    /// The original vertex count.
    pub fn original_count(&self) -> usize {
        let appended = self.pocket.as_ref().map(|p| p.first);
        appended
            .or(self.eyes.as_ref().map(|e| e.first))
            .map_or(self.mesh.vertex_count(), |first| first as usize)
            - self.copies.len()
    }

    /// The lower lip's inner edge after the cut, from the right corner to the left: the
    /// line's copies where it was cut, its own vertices elsewhere.
    pub fn lower_edge(&self) -> Vec<u32> {
        let n = self.original_count() as u32;
        self.line
            .iter()
            .map(|&v| match self.copies.iter().position(|&o| o == v) {
                Some(k) => n + k as u32,
                None => v,
            })
            .collect()
    }
}

/// Finds the inner lip line of `mesh` from its 68 landmark vertices and cuts it when the lips
/// are joined.
pub fn find(mesh: &Mesh, landmarks: &[u32]) -> Lips {
    let Some(mouth) = Mouth::of(mesh, landmarks) else {
        return Lips::NotFound;
    };
    let graph = Graph::new(mesh, mouth.centre, REACH * mouth.width);
    let Some((upper, lower)) = mouth.lines(&graph, mesh, landmarks) else {
        return Lips::NotFound;
    };
    let lowness = |p: Vec3| mouth.lowness(p);
    // every edge with a lower side takes part: the cut splits each line vertex's triangles
    // by them, and leaving a steep edge out left vertices of MediaPipe's lip line joined
    let below = graph.below(mesh, (&upper, &HashSet::new()), lowness, 0.0);
    if below.is_empty() {
        return Lips::Open;
    }
    let (band, below) = if upper == lower {
        (0, below)
    } else {
        let grown = grown_from_each(&below, |seed| {
            graph.band(mesh, &mouth, seed, &upper, &lower)
        });
        let Some(band) = grown else {
            return Lips::Separate;
        };
        (band.len(), graph.below_in_band(&upper, &band, &below))
    };
    let cut = graph.cut(mesh, &upper, &below);
    if cut.copies.is_empty() {
        return Lips::Open;
    }
    let mut landmarks = landmarks.to_vec();
    for &i in &LOWER_LIP {
        if let Some(k) = cut.copies.iter().position(|&o| o == landmarks[i]) {
            landmarks[i] = (mesh.vertex_count() + k) as u32;
        }
    }
    let mut cut = LipCut {
        mesh: cut.mesh,
        copies: cut.copies,
        line: upper,
        band,
        landmarks,
        pocket: None,
        eyes: None,
    };
    let points: Vec<Vec3> = cut
        .landmarks
        .iter()
        .map(|&v| cut.mesh.positions[v as usize])
        .collect();
    let lower = cut.lower_edge();
    cut.pocket = Pocket::append(&mut cut.mesh, &cut.line, &lower, &points);
    Lips::Joined(cut)
}

/// A mouth pocket for lips that are apart already (`fit-rig` asks for one when [`find`] finds
/// them [`Lips::Separate`]: joined only deep inside the mouth, as in MakeHuman's base mesh,
/// whose mouth bag is skin and draws as lit as the cheek). The same
/// closed `mouth_interior` bag as behind cut lips ([`Pocket`]), its rim behind the upper and
/// lower inner lip edges (the chains [`find`] looks for), appended to a copy of the mesh: a
/// [`LipCut`] with no copies, its `line` the upper edge. `None` when the mesh has a
/// `mouth_interior` of its own, the lips are one row (joined: [`find`] cuts those) or the
/// edges are not found. The mesh's own teeth and tongue stay where they are, in the bag.
pub fn pocket_behind_apart_lips(mesh: &Mesh, landmarks: &[u32]) -> Option<LipCut> {
    if mesh.groups.contains_key(super::pocket::GROUP) {
        return None;
    }
    let mouth = Mouth::of(mesh, landmarks)?;
    let graph = Graph::new(mesh, mouth.centre, REACH * mouth.width);
    let (upper, lower) = mouth.lines(&graph, mesh, landmarks)?;
    if upper == lower {
        return None;
    }
    let (rim_upper, rim_lower) = paired(mesh, &upper, &lower);
    let points: Vec<Vec3> = landmarks
        .iter()
        .map(|&v| mesh.positions[v as usize])
        .collect();
    let mut opened = mesh.clone();
    let pocket = Pocket::append(&mut opened, &rim_upper, &rim_lower, &points)?;
    Some(LipCut {
        mesh: opened,
        copies: Vec::new(),
        line: upper,
        band: 0,
        landmarks: landmarks.to_vec(),
        pocket: Some(pocket),
        eyes: None,
    })
}

/// Two chains from one corner to the other, as long as each other: the longer as it is, the
/// shorter resampled (each column takes the vertex at the nearest share of its length), so
/// the pocket's columns pair the lips' edges by their place along the mouth.
fn paired(mesh: &Mesh, a: &[u32], b: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let shares = |chain: &[u32]| -> Vec<f32> {
        let mut run = vec![0.0f32];
        for pair in chain.windows(2) {
            let step = mesh.positions[pair[0] as usize].distance(mesh.positions[pair[1] as usize]);
            run.push(run.last().copied().unwrap_or(0.0) + step);
        }
        let total = run.last().copied().unwrap_or(0.0).max(f32::MIN_POSITIVE);
        run.iter().map(|r| r / total).collect()
    };
    let resample = |long: &[u32], short: &[u32]| -> Vec<u32> {
        let (along, on) = (shares(long), shares(short));
        along
            .iter()
            .map(|&t| {
                let k = (0..short.len())
                    .min_by(|&i, &j| (on[i] - t).abs().total_cmp(&(on[j] - t).abs()))
                    .unwrap_or(0);
                short[k]
            })
            .collect()
    };
    if a.len() >= b.len() {
        (a.to_vec(), resample(a, b))
    } else {
        (resample(b, a), b.to_vec())
    }
}

/// Gives the vertices on each side of the cut line the jaw and mask weights of the skin next
/// to them on their own side, and the mouth pocket the jaw weights of the lips it lies
/// behind ([`Pocket::jaw_weights`]): fitting splits weights by position at the line halfway between
/// the inner lip landmarks, where a cut line's vertices and their copies lie on top of each
/// other (or the copies lie above it, on a band's upper row), so the line itself is set from
/// its neighbours. `rig` must be fitted to `cut.mesh`.
pub fn weights_by_side(rig: &mut Rig, cut: &LipCut) {
    let sources = side_neighbours(cut);
    if let Some(jaw) = &mut rig.jaw {
        set_from_neighbours(&mut jaw.weights, &sources, 0.0, &cut.mesh.positions);
        if let Some(pocket) = &cut.pocket {
            // the pocket follows the lips it lies behind
            let mut map: BTreeMap<u32, f32> = jaw.weights.iter().copied().collect();
            let lips = map.clone();
            let weight = |v: u32| lips.get(&v).copied().unwrap_or(0.0);
            for (v, w) in pocket.jaw_weights(weight) {
                if w > 0.0 {
                    map.insert(v, w);
                } else {
                    map.remove(&v);
                }
            }
            jaw.weights = map.into_iter().collect();
        }
    }
    for mask in &mut rig.masks {
        set_from_neighbours(&mut mask.weights, &sources, 1.0, &cut.mesh.positions);
    }
}

/// For each vertex on the cut (originals and copies), its neighbours on its own side that are
/// not on the line.
fn side_neighbours(cut: &LipCut) -> Vec<(u32, Vec<u32>)> {
    let n = cut.original_count() as u32;
    let on_line: HashSet<u32> = cut
        .line
        .iter()
        .copied()
        .chain(n..n + cut.copies.len() as u32)
        .collect();
    let cut_vertices: Vec<u32> = cut
        .copies
        .iter()
        .copied()
        .chain((0..cut.copies.len() as u32).map(|k| n + k))
        .collect();
    let wanted: HashSet<u32> = cut_vertices.iter().copied().collect();
    let mut neighbours: HashMap<u32, Vec<u32>> = HashMap::new();
    for tri in &cut.mesh.triangles {
        for (k, &v) in tri.iter().enumerate() {
            if !wanted.contains(&v) {
                continue;
            }
            for &w in [tri[(k + 1) % 3], tri[(k + 2) % 3]].iter() {
                let list = neighbours.entry(v).or_default();
                if !on_line.contains(&w) && !list.contains(&w) {
                    list.push(w);
                }
            }
        }
    }
    cut_vertices
        .into_iter()
        .map(|v| (v, neighbours.remove(&v).unwrap_or_default()))
        .collect()
}

/// Sets each vertex's weight in sorted `(vertex, weight)` pairs (absent meaning `default`)
/// to its sources' weights averaged by the inverse square of their distance from it, where
/// it has sources. The plain mean gave a lower lip's line vertex on a coarse scan the
/// weight of a neighbour 7.5 mm along the lip (jaw weight 0.83 where its neighbour 1.4 mm
/// away had 0.74, falling toward the corner); the jaw then moved it 2 mm further than that
/// neighbour 0.9 mm below it, and AU26 and AU27 turned the triangle between them over.
fn set_from_neighbours(
    weights: &mut Vec<(u32, f32)>,
    sources: &[(u32, Vec<u32>)],
    default: f32,
    positions: &[Vec3],
) {
    let mut map: BTreeMap<u32, f32> = weights.iter().copied().collect();
    let value = |map: &BTreeMap<u32, f32>, v: u32| map.get(&v).copied().unwrap_or(default);
    let new: Vec<(u32, f32)> = sources
        .iter()
        .filter(|(_, from)| !from.is_empty())
        .map(|(v, from)| {
            let p = positions[*v as usize];
            let (mut sum, mut total) = (0.0f32, 0.0f32);
            for &w in from {
                let d2 = positions[w as usize]
                    .distance_squared(p)
                    .max(f32::MIN_POSITIVE);
                sum += value(&map, w) / d2;
                total += 1.0 / d2;
            }
            (*v, sum / total)
        })
        .collect();
    for (v, w) in new {
        if w == default {
            map.remove(&v);
        } else {
            map.insert(v, w);
        }
    }
    *weights = map.into_iter().collect();
}

/// The mouth as the landmarks place it.
struct Mouth {
    /// The upper inner lip polyline (60-64) and the lower (60, 67-65, 64).
    upper: Vec<Vec3>,
    lower: Vec<Vec3>,
    /// The upper outer lip polyline (48-54) and the lower (54-59, 48).
    outer_upper: Vec<Vec3>,
    outer_lower: Vec<Vec3>,
    centre: Vec3,
    /// The outer mouth width (48-54).
    width: f32,
    /// The widest gap between the upper and lower inner lip landmarks.
    gap: f32,
}

impl Mouth {
    fn of(mesh: &Mesh, landmarks: &[u32]) -> Option<Mouth> {
        if landmarks.len() != COUNT || landmarks.iter().any(|&v| v as usize >= mesh.vertex_count())
        {
            return None;
        }
        let points: Vec<Vec3> = landmarks
            .iter()
            .map(|&v| mesh.positions[v as usize])
            .collect();
        let polyline = |ids: &[usize]| ids.iter().map(|&i| points[i]).collect::<Vec<_>>();
        let upper = polyline(&INNER_UPPER);
        let lower = polyline(&INNER_LOWER);
        let outer_upper = polyline(&[48, 49, 50, 51, 52, 53, 54]);
        let outer_lower = polyline(&[54, 55, 56, 57, 58, 59, 48]);
        let centre = upper.iter().chain(&lower).copied().sum::<Vec3>() / 10.0;
        let width = points[48].distance(points[54]);
        let gap = [(61, 67), (62, 66), (63, 65)]
            .iter()
            .map(|&(a, b)| points[a].distance(points[b]))
            .fold(0.0, f32::max);
        (width > 0.0).then_some(Mouth {
            upper,
            lower,
            outer_upper,
            outer_lower,
            centre,
            width,
            gap,
        })
    }

    /// How far `p` lies on the lower lip's side: nearer the lower outer lip line and further
    /// from the upper one (the lips' own curl makes "down the face" an unreliable guide this
    /// close).
    fn lowness(&self, p: Vec3) -> f32 {
        distance_to_polyline(p, &self.outer_upper) - distance_to_polyline(p, &self.outer_lower)
    }

    /// The upper and lower inner lip chains of edges, kept apart ([`Graph::two_lines`]).
    fn lines(&self, graph: &Graph, mesh: &Mesh, landmarks: &[u32]) -> Option<(Vec<u32>, Vec<u32>)> {
        let contours = [
            (&INNER_UPPER[..], &self.upper[..]),
            (&INNER_LOWER[..], &self.lower[..]),
        ];
        graph.two_lines(mesh, GUIDE * self.width, landmarks, contours, |p| {
            self.lowness(p)
        })
    }

    /// Whether a point lies in the slit between the inner lip polylines.
    fn in_slit(&self, p: Vec3) -> bool {
        let d = distance_to_polyline(p, &self.upper) + distance_to_polyline(p, &self.lower);
        d <= 1.5 * self.gap + SLIT_SLACK * self.width
    }
}

impl Graph {
    /// On each edge of `line`, its triangle in `band` (sorted), the one of `below` where both
    /// are: what the cut splits the line's vertices by. An edge tilted so that its
    /// lower-looking triangle (in `below`) lies on the upper lip would otherwise cut that lip.
    fn below_in_band(&self, line: &[u32], band: &[usize], below: &[usize]) -> Vec<usize> {
        line.windows(2)
            .filter_map(|p| {
                let mut tris = self
                    .across(&key(p[0], p[1]))
                    .iter()
                    .filter(|t| band.binary_search(t).is_ok());
                match (tris.next(), tris.next()) {
                    (Some(&t), None) => Some(t),
                    (Some(&t), Some(&u)) => Some(if below.contains(&u) { u } else { t }),
                    _ => None,
                }
            })
            .collect()
    }

    /// The band of triangles between the upper and lower chains, grown from `seed` (a
    /// triangle just below the upper one) without crossing either chain, sorted; `None` when
    /// it leaves the slit between the inner lip landmarks (the skin below is not a band
    /// across the lips).
    fn band(
        &self,
        mesh: &Mesh,
        mouth: &Mouth,
        seed: usize,
        upper: &[u32],
        lower: &[u32],
    ) -> Option<Vec<usize>> {
        let walls: HashSet<[u32; 2]> = upper
            .windows(2)
            .chain(lower.windows(2))
            .map(|p| key(p[0], p[1]))
            .collect();
        let on_chain: HashSet<u32> = upper.iter().chain(lower).copied().collect();
        let mut seen: HashSet<usize> = HashSet::from([seed]);
        let mut stack = vec![seed];
        while let Some(t) = stack.pop() {
            let tri = mesh.triangles[t];
            let inside = tri.iter().all(|&v| {
                self.near[v as usize]
                    && (on_chain.contains(&v) || mouth.in_slit(mesh.positions[v as usize]))
            });
            if !inside {
                return None;
            }
            for k in 0..3 {
                let edge = key(tri[k], tri[(k + 1) % 3]);
                if walls.contains(&edge) {
                    continue;
                }
                for &u in self.across(&edge) {
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

    /// Duplicates each inner vertex of the line whose triangles split into a part above the
    /// line and a part below it (holding a triangle of `below`); the part below takes the copy.
    fn cut(&self, mesh: &Mesh, line: &[u32], below: &[usize]) -> Cut {
        let below: HashSet<usize> = below.iter().copied().collect();
        let mut opened = mesh.clone();
        let mut copies = vec![];
        for k in 1..line.len() - 1 {
            let (prev, v, next) = (line[k - 1], line[k], line[k + 1]);
            let fan = self.vertex_triangles.get(&v).map_or(&[][..], Vec::as_slice);
            let part = fan_parts(mesh, fan, v, [prev, next]);
            let lower: HashSet<usize> = fan
                .iter()
                .zip(&part)
                .filter(|(t, _)| below.contains(t))
                .map(|(_, &p)| p)
                .collect();
            // The other side of each line edge at v: the fan must not wrap round to it.
            let line_tris = [key(prev, v), key(v, next)]
                .iter()
                .flat_map(|e| self.across(e).iter().copied())
                .collect::<Vec<_>>();
            let wraps = fan
                .iter()
                .zip(&part)
                .any(|(t, p)| lower.contains(p) && line_tris.contains(t) && !below.contains(t));
            if lower.is_empty() || wraps {
                continue;
            }
            let copy = opened.positions.len() as u32;
            opened.positions.push(mesh.positions[v as usize]);
            copies.push(v);
            for (&t, p) in fan.iter().zip(&part) {
                if lower.contains(p) {
                    for corner in &mut opened.triangles[t] {
                        if *corner == v {
                            *corner = copy;
                        }
                    }
                }
            }
            for members in opened.groups.values_mut() {
                if members.binary_search(&v).is_ok() {
                    members.push(copy);
                }
            }
        }
        Cut {
            mesh: opened,
            copies,
        }
    }
}

/// The cut: the opened mesh and the original of each copy.
struct Cut {
    mesh: Mesh,
    copies: Vec<u32>,
}

/// Splits the triangles round `v` into parts joined across their edges from `v`, except the
/// edges to `walls`; returns each triangle's part number.
fn fan_parts(mesh: &Mesh, fan: &[usize], v: u32, walls: [u32; 2]) -> Vec<usize> {
    let mut part: Vec<usize> = (0..fan.len()).collect();
    fn root(part: &mut [usize], mut i: usize) -> usize {
        while part[i] != i {
            part[i] = part[part[i]];
            i = part[i];
        }
        i
    }
    let others = |t: usize| -> Vec<u32> {
        mesh.triangles[t]
            .iter()
            .copied()
            .filter(|&w| w != v && !walls.contains(&w))
            .collect()
    };
    for i in 0..fan.len() {
        for j in i + 1..fan.len() {
            let (a, b) = (others(fan[i]), others(fan[j]));
            if a.iter().any(|w| b.contains(w)) {
                let (ri, rj) = (root(&mut part, i), root(&mut part, j));
                part[ri] = rj;
            }
        }
    }
    (0..fan.len()).map(|i| root(&mut part, i)).collect()
}

/// The opened mesh with the covered eyes of `found` cut open ([`super::eyecut::open`]): `cut` (the lips cut
/// or a mouth pocket added, [`find`]) or else `source` as it is, whose 68 landmark
/// vertices are `landmarks`. `None` when neither the lips nor the eyes were opened.
pub fn open_eyes(
    cut: Option<LipCut>,
    source: &Mesh,
    landmarks: &[u32],
    found: [Lids; 2],
) -> Option<LipCut> {
    let had_cut = cut.is_some();
    let mut cut = cut.unwrap_or_else(|| LipCut {
        mesh: source.clone(),
        copies: Vec::new(),
        line: Vec::new(),
        band: 0,
        landmarks: landmarks.to_vec(),
        pocket: None,
        eyes: None,
    });
    cut.eyes = super::eyecut::open(&mut cut.mesh, &cut.landmarks, found).map(Box::new);
    (had_cut || cut.eyes.is_some()).then_some(cut)
}

/// The distance between the middles of the inner lips (landmarks 62 and 66) at `positions`.
pub fn mouth_gap(positions: &[Vec3], landmarks: &[u32]) -> f32 {
    let p = |i: usize| positions[landmarks[i] as usize];
    p(62).distance(p(66))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polyline_distance() {
        let line = [Vec3::ZERO, Vec3::X];
        assert!((distance_to_polyline(Vec3::new(0.5, 1.0, 0.0), &line) - 1.0).abs() < 1e-6);
        assert!((distance_to_polyline(Vec3::new(2.0, 0.0, 0.0), &line) - 1.0).abs() < 1e-6);
    }

    /// A line vertex between a near neighbour (1 away, weight 0.7) and a far one (7 away,
    /// 0.9) takes nearly the near one's weight (the mean, 0.8, turned triangles over at a
    /// scan's mouth corner); absent weights are the default, and a vertex with no sources
    /// keeps its own.
    #[test]
    fn a_line_vertex_takes_its_nearest_neighbours_weights() {
        let positions = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 7.0, 0.0),
            Vec3::new(5.0, 5.0, 5.0),
        ];
        let mut weights = vec![(1, 0.7), (2, 0.9), (3, 0.4)];
        let sources = vec![(0, vec![1, 2]), (3, vec![])];
        set_from_neighbours(&mut weights, &sources, 0.0, &positions);
        let w0 = weights.iter().find(|(v, _)| *v == 0).unwrap().1;
        let expected = (0.7 + 0.9 / 49.0) / (1.0 + 1.0 / 49.0);
        assert!((w0 - expected).abs() < 1e-6, "{w0}");
        assert!(weights.contains(&(3, 0.4)));
        let mut masks = vec![(2, 0.5)];
        set_from_neighbours(&mut masks, &[(0, vec![1, 2])], 1.0, &positions);
        let m0 = masks.iter().find(|(v, _)| *v == 0).unwrap().1;
        assert!(
            (m0 - (1.0 + 0.5 / 49.0) / (1.0 + 1.0 / 49.0)).abs() < 1e-6,
            "{m0}"
        );
    }
}
