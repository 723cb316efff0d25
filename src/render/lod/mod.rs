//! Levels of detail: simplified copies of a big mesh, drawn at terminal sizes.
//!
//! A terminal shows a few hundred thousand dots at most; a scan or an artist's head has up
//! to half a million vertices. Drawing every triangle costs what the mesh costs, not what
//! the screen costs. [`Lod::build`] makes, once at load, a few simplified meshes by edge
//! collapse with edges up to `extent / 2^k` long (the extent of what a view fits), and
//! [`Lod::choose`] picks for a frame the coarsest whose edges span at most [`CELL_DOTS`]
//! dots: triangles about the size of a few terminal dots, so the picture is the full mesh's
//! within a cell while the work is bounded by the screen.
//!
//! Every vertex of a level is a vertex of the full mesh at its rest position (its
//! [`Level::source`]), so a level is kept in step with the full mesh by the same
//! deformation evaluated at those vertices (`BoundRig::deform_at`), never by a deformation
//! of its own. What a level keeps (the rules are in `collapse`):
//!
//! * a clean surface: no edge with three triangles, no hole, no triangle turned over, so
//!   silhouettes and creases appear only where the surface has them;
//! * feature lines: mesh borders (eye openings, mouth slit, rim) stay chains of border
//!   edges, and the two lips across the slit or the two lids across an eye are never joined;
//! * parts: a vertex collapses only onto a vertex of the same named groups (teeth, tongue,
//!   eyes, the landmark groups) and the same part label given by the caller (what turns
//!   with the jaw and what does not, the masks' regions), so part boundaries are kept.
//!
//! Meshes under [`LOD_MIN_VERTICES`] have no levels and are always drawn whole; `export`,
//! glTF, PNG and SVG always use the full mesh.

mod collapse;

use std::collections::{BTreeMap, HashMap};

use glam::Vec3;
use rayon::prelude::*;

use super::camera::{Camera, Projection};
use super::framing::Framing;
use crate::model::{Mesh, Rig};
use collapse::Collapser;

/// Meshes with fewer vertices than this have no levels of detail: they are drawn whole
/// (the built-in face, 3 463 vertices, costs well under a millisecond per frame).
pub const LOD_MIN_VERTICES: usize = 16_384;

/// The largest cell, in dots, of the level a frame draws (levels are a factor of two apart,
/// so the level drawn has cells of 2 to 4 dots): a braille cell is 2 by 4 dots, and at this
/// size the feature lines stay within a cell of the full mesh's while a frame costs about
/// what the built-in face's does.
pub const CELL_DOTS: f32 = 4.0;

/// Finest and coarsest levels: edges up to `extent / 2^k` long.
const FINEST: i32 = 10;
const COARSEST: i32 = 5;

/// A level is kept only when it has at most this fraction of the vertices of the next finer
/// one drawn (a level that barely simplifies is not worth its memory).
const KEEP_FRACTION: f32 = 0.6;

/// One simplified mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// The simplified mesh at rest: its vertices are full-mesh vertices at their rest
    /// positions, with the named groups carried over.
    pub mesh: Mesh,
    /// Per level vertex: the full-mesh vertex it is.
    pub source: Vec<u32>,
    /// The longest edge a collapse could make, in mesh units, where the surface curves
    /// (flat regions may have edges up to three times as long, see `collapse`).
    pub cell: f32,
    /// The points views of this level fit (the framed points, one per grid cell): few, so
    /// fitting the camera costs little.
    pub frame: Vec<Vec3>,
}

impl Level {
    /// The level's pose picked out of a pose of the full mesh (`full`).
    pub fn gather(&self, full: &[Vec3], out: &mut Vec<Vec3>) {
        out.clear();
        out.extend(self.source.iter().map(|&v| full[v as usize]));
    }
}

/// The levels of detail of one mesh, finest first (empty for small meshes).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Lod {
    levels: Vec<Level>,
}

impl Lod {
    /// No levels: the mesh is drawn whole.
    pub const fn none() -> Lod {
        Lod { levels: Vec::new() }
    }

    /// Builds the levels of `mesh`. `frame` is what views fit (the face region, or the whole
    /// rest pose) and sets the edges' scale; `parts` labels vertices that must not merge
    /// together (for example 1 for what the jaw turns, 0 for the rest; empty: no labels).
    pub fn build(mesh: &Mesh, parts: &[u32], frame: &[Vec3]) -> Lod {
        let n = mesh.positions.len();
        if n < LOD_MIN_VERTICES || frame.is_empty() {
            return Lod::default();
        }
        let (lo, hi) = crate::model::mesh::bounds_of(frame);
        let size = (hi - lo).max_element();
        if !(size.is_finite() && size > 0.0) {
            return Lod::default();
        }
        let signature = signatures(mesh, parts);
        // Start at the first length longer than the mesh's own edges: shorter ones would
        // keep nearly every vertex.
        let edge = mean_edge(mesh);
        let mut k = FINEST;
        while k > COARSEST && size / 2f32.powi(k) < 1.5 * edge {
            k -= 1;
        }
        let mut levels: Vec<Level> = Vec::new();
        let mut drawn = n;
        let mut thinned = frame.to_vec();
        // The level just made (kept or not) and its vertices' signatures: the next, coarser
        // one is made from it.
        let mut prev: Option<(Level, Vec<u64>)> = None;
        while k >= COARSEST {
            let cell = size / 2f32.powi(k);
            k -= 1;
            let (input, source, sig) = match &prev {
                None => (mesh, None, &signature[..]),
                Some((level, sig)) => (&level.mesh, Some(&level.source[..]), &sig[..]),
            };
            thinned = frame_points(&thinned, lo, cell);
            let (level, next) = simplify(input, source, sig, cell, &thinned);
            let count = level.source.len();
            if count > 0 && (count as f32) <= KEEP_FRACTION * drawn as f32 {
                drawn = count;
                levels.push(level.clone());
            }
            prev = Some((level, next));
            if count < 64 {
                break;
            }
        }
        Lod { levels }
    }

    /// The levels of a rigged mesh as every front end builds them: edge lengths scaled to
    /// `framing`'s region, and vertices kept apart where the rig moves them apart (what the
    /// jaw turns and what it does not, the masks' regions such as the two lips).
    pub fn of_rig(rig: &Rig, mesh: &Mesh, framing: &Framing) -> Lod {
        if mesh.positions.len() < LOD_MIN_VERTICES {
            return Lod::default();
        }
        let parts = Lod::rig_parts(rig, mesh.positions.len());
        let frame = framing.frame(mesh);
        Lod::build(mesh, &parts, frame)
    }

    /// The part labels [`Lod::of_rig`] builds with, per vertex of an `n`-vertex mesh: a
    /// front end that builds the levels on a thread of its own passes them, the mesh and
    /// the framed points to [`Lod::build`] without a copy of the rig.
    pub fn rig_parts(rig: &Rig, n: usize) -> Vec<u32> {
        let mut parts = vec![0u32; n];
        let mut label = |v: u32, salt: u64| {
            if let Some(p) = parts.get_mut(v as usize) {
                *p = mix(u64::from(*p) ^ salt) as u32;
            }
        };
        if let Some(jaw) = &rig.jaw {
            for &(v, w) in &jaw.weights {
                if w > 0.0 {
                    label(v, 1);
                }
            }
        }
        for (m, mask) in rig.masks.iter().enumerate() {
            for &(v, w) in &mask.weights {
                // four bands of weight: a mask's soft edge may merge, its sides not
                let band = (w.clamp(0.0, 1.0) * 3.0).round() as u64;
                label(v, mix(m as u64 + 2) ^ band);
            }
        }
        parts
    }

    /// The levels, finest first.
    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// True when the mesh is always drawn whole.
    pub fn is_empty(&self) -> bool {
        self.levels.is_empty()
    }

    /// The level to draw on a canvas of `width` by `height` dots seen by `camera`: the
    /// coarsest whose cell spans at most [`CELL_DOTS`] dots, or `None` (draw the full mesh)
    /// when even the finest is coarser, as when zoomed in close.
    pub fn choose(
        &self,
        camera: &Camera,
        width: usize,
        height: usize,
        dot_aspect: f32,
    ) -> Option<&Level> {
        let coarsest = self.levels.last()?;
        let proj = camera.fit_points(&coarsest.frame, width, height, dot_aspect);
        self.choose_for(&proj)
    }

    /// [`Lod::choose`] for a projection already fitted.
    pub fn choose_for(&self, proj: &Projection) -> Option<&Level> {
        let dots_per_unit = proj.scale_x.abs().max(proj.scale_y.abs());
        if !dots_per_unit.is_finite() {
            return None;
        }
        self.levels
            .iter()
            .rev()
            .find(|level| level.cell * dots_per_unit <= CELL_DOTS)
    }
}

/// Per vertex, a hash of its named groups and its part label: vertices with different
/// signatures never merge.
fn signatures(mesh: &Mesh, parts: &[u32]) -> Vec<u64> {
    let mut sig: Vec<u64> = (0..mesh.positions.len())
        .map(|v| mix(u64::from(parts.get(v).copied().unwrap_or(0))))
        .collect();
    for (g, members) in mesh.groups.values().enumerate() {
        let salt = mix(g as u64 + 1);
        for &v in members {
            if let Some(s) = sig.get_mut(v as usize) {
                *s = mix(*s ^ salt);
            }
        }
    }
    sig
}

/// A 64-bit mixing function (splitmix64's finalizer).
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// The mean length of some triangles' edges (a sample is enough to pick the first level).
fn mean_edge(mesh: &Mesh) -> f32 {
    let step = (mesh.triangles.len() / 4096).max(1);
    let (mut sum, mut count) = (0.0f64, 0usize);
    for t in mesh.triangles.iter().step_by(step) {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        for len in [(b - a).length(), (c - b).length(), (a - c).length()] {
            if len.is_finite() {
                sum += f64::from(len);
                count += 1;
            }
        }
    }
    if count == 0 {
        0.0
    } else {
        (sum / count as f64) as f32
    }
}

/// The renderer's default crease: edges whose faces meet at more than this many degrees
/// are drawn, so a level keeps them as chains of edges.
const CREASE_DEGREES: f32 = 40.0;

/// Per vertex: whether it lies on a mesh border (an edge with one triangle), and whether it
/// lies on a crease (an edge whose two faces meet at more than [`CREASE_DEGREES`]).
fn feature_vertices(mesh: &Mesh) -> (Vec<bool>, Vec<bool>) {
    let mut edges: Vec<(u64, u32)> = mesh
        .triangles
        .par_iter()
        .enumerate()
        .flat_map_iter(|(k, t)| {
            [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]
                .into_iter()
                .filter(|(a, b)| a != b)
                .map(move |(a, b)| ((u64::from(a.min(b)) << 32) | u64::from(a.max(b)), k as u32))
        })
        .collect();
    edges.par_sort_unstable();
    let normal = |k: u32| {
        let [a, b, c] = mesh.triangles[k as usize].map(|v| mesh.positions[v as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    };
    let cos = CREASE_DEGREES.to_radians().cos();
    let (mut border, mut crease) = (
        vec![false; mesh.positions.len()],
        vec![false; mesh.positions.len()],
    );
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 {
            j += 1;
        }
        let ends = [
            (edges[i].0 >> 32) as usize,
            (edges[i].0 & 0xffff_ffff) as usize,
        ];
        let mark = match j - i {
            1 => Some(&mut border),
            2 if normal(edges[i].1).dot(normal(edges[i + 1].1)) < cos => Some(&mut crease),
            _ => None,
        };
        if let Some(flags) = mark {
            ends.iter().for_each(|&v| flags[v] = true);
        }
        i = j;
    }
    (border, crease)
}

/// The grid cell of `p` (cells of `cell` from `lo`), packed in 63 bits.
fn grid_key(p: Vec3, lo: Vec3, cell: f32) -> u64 {
    let q = ((p - lo) / cell).floor();
    let pack = |x: f32| (x as i64 as u64) & 0x1f_ffff;
    (pack(q.x) << 42) | (pack(q.y) << 21) | pack(q.z)
}

/// One level made from `mesh` (the full mesh, or a finer level whose vertices are the full
/// mesh's `source`): edges collapsed up to `cell` long. Returns the level and its vertices'
/// signatures.
fn simplify(
    mesh: &Mesh,
    source: Option<&[u32]>,
    signature: &[u64],
    cell: f32,
    frame: &[Vec3],
) -> (Level, Vec<u64>) {
    let mut collapser = Collapser::new(
        &mesh.positions,
        &mesh.triangles,
        signature,
        feature_vertices(mesh),
    );
    collapser.run(cell);
    let (kept, number, triangles) = collapser.finish();
    let mut groups = BTreeMap::new();
    for (name, members) in &mesh.groups {
        let mapped: Vec<u32> = members
            .iter()
            .map(|&v| number[v as usize])
            .filter(|&v| v != u32::MAX)
            .collect();
        groups.insert(name.clone(), mapped);
    }
    let level = Level {
        mesh: Mesh {
            positions: kept.iter().map(|&v| mesh.positions[v as usize]).collect(),
            triangles,
            groups,
        },
        source: match source {
            Some(s) => kept.iter().map(|&v| s[v as usize]).collect(),
            None => kept.clone(),
        },
        cell,
        frame: frame.to_vec(),
    };
    let signature = kept.iter().map(|&v| signature[v as usize]).collect();
    (level, signature)
}

/// The framed points thinned to one per grid cell (the one farthest from their centre, so
/// the extent a view fits shrinks by less than a cell).
fn frame_points(frame: &[Vec3], lo: Vec3, cell: f32) -> Vec<Vec3> {
    let finite = frame.iter().filter(|p| p.is_finite());
    let count = finite.clone().count().max(1) as f32;
    let centre = finite.clone().fold(Vec3::ZERO, |a, p| a + *p) / count;
    let mut cells: HashMap<u64, Vec3> = HashMap::new();
    for &p in finite {
        let slot = cells.entry(grid_key(p, lo, cell)).or_insert(p);
        if p.distance_squared(centre) > slot.distance_squared(centre) {
            *slot = p;
        }
    }
    let mut points: Vec<(u64, Vec3)> = cells.into_iter().collect();
    points.sort_unstable_by_key(|&(k, _)| k);
    points.into_iter().map(|(_, p)| p).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat grid of `side` x `side` vertices split into triangles.
    fn sheet(side: u32) -> Mesh {
        let mut positions = Vec::new();
        for y in 0..side {
            for x in 0..side {
                positions.push(Vec3::new(x as f32, y as f32, 0.0));
            }
        }
        let mut triangles = Vec::new();
        for y in 0..side - 1 {
            for x in 0..side - 1 {
                let v = y * side + x;
                triangles.push([v, v + 1, v + side]);
                triangles.push([v + 1, v + side + 1, v + side]);
            }
        }
        Mesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn small_meshes_have_no_levels() {
        let mesh = sheet(20);
        assert!(Lod::build(&mesh, &[], &mesh.positions).is_empty());
    }

    #[test]
    fn levels_are_full_mesh_vertices_and_get_coarser() {
        let mesh = sheet(200);
        let lod = Lod::build(&mesh, &[], &mesh.positions);
        assert!(lod.levels().len() >= 2, "{}", lod.levels().len());
        let mut last = mesh.positions.len();
        for level in lod.levels() {
            assert!(level.source.len() < last);
            last = level.source.len();
            level.mesh.validate().unwrap();
            for (p, &v) in level.mesh.positions.iter().zip(&level.source) {
                assert_eq!(*p, mesh.positions[v as usize]);
            }
            // the sheet's border stays where it was: corners are kept exactly
            for corner in [Vec3::ZERO, Vec3::new(199.0, 199.0, 0.0)] {
                let near = level
                    .mesh
                    .positions
                    .iter()
                    .map(|p| p.distance(corner))
                    .fold(f32::INFINITY, f32::min);
                assert!(near <= level.cell * 1.5, "{near} {}", level.cell);
            }
        }
    }

    #[test]
    fn flat_regions_get_longer_edges_than_curved_ones() {
        // A sheet flat on one half and rippled (a few cells a wave) on the other.
        let mut mesh = sheet(200);
        for p in &mut mesh.positions {
            if p.x > 100.0 {
                p.z = 4.0 * ((p.x - 100.0) / 5.0).sin() * (p.y / 5.0).sin();
            }
        }
        let lod = Lod::build(&mesh, &[], &mesh.positions);
        let level = &lod.levels()[0];
        let (mut flat, mut rippled) = ((0.0f32, 0.0f32, 0usize), (0.0f32, 0.0f32, 0usize));
        for t in &level.mesh.triangles {
            let p = t.map(|v| level.mesh.positions[v as usize]);
            let side = if p.iter().all(|q| q.x < 95.0) {
                &mut flat
            } else if p.iter().all(|q| q.x > 105.0) {
                &mut rippled
            } else {
                continue;
            };
            for (a, b) in [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])] {
                let len = a.distance(b);
                *side = (side.0.max(len), side.1 + len, side.2 + 1);
            }
        }
        let cell = level.cell;
        // flat: past the level's length, never past the stretch
        assert!(flat.0 > 1.5 * cell, "{} {cell}", flat.0);
        let most = collapse::FLAT_STRETCH * cell * 1.001;
        assert!(flat.0 <= most && rippled.0 <= most);
        // rippled: shorter edges on the whole
        let mean = |s: (f32, f32, usize)| s.1 / s.2 as f32;
        assert!(
            mean(rippled) < 0.8 * mean(flat),
            "{} {}",
            mean(rippled),
            mean(flat)
        );
    }

    #[test]
    fn unconnected_sides_never_merge() {
        // Two sheets a hair apart (lips across a slit): connected nowhere, never merged.
        let a = sheet(130);
        let mut positions = a.positions.clone();
        positions.extend(a.positions.iter().map(|p| *p + Vec3::new(0.0, 0.0, 1e-3)));
        let offset = a.positions.len() as u32;
        let mut triangles = a.triangles.clone();
        triangles.extend(a.triangles.iter().map(|t| t.map(|v| v + offset)));
        let mesh = Mesh::new(positions, triangles).unwrap();
        let lod = Lod::build(&mesh, &[], &mesh.positions);
        assert!(!lod.is_empty());
        for level in lod.levels() {
            for t in &level.mesh.triangles {
                let sides = t.map(|v| level.source[v as usize] >= offset);
                assert!(sides[0] == sides[1] && sides[1] == sides[2]);
            }
        }
    }

    #[test]
    fn the_level_follows_zoom() {
        let mesh = sheet(300);
        let lod = Lod::build(&mesh, &[], &mesh.positions);
        let mut camera = Camera::front();
        let far = lod.choose(&camera, 160, 96, 1.0).map(|l| l.cell);
        camera.zoom = 4.0;
        let near = lod.choose(&camera, 160, 96, 1.0).map(|l| l.cell);
        camera.zoom = 1000.0;
        assert!(lod.choose(&camera, 160, 96, 1.0).is_none());
        assert!(far.is_some());
        assert!(near.is_none_or(|n| n < far.unwrap()), "{near:?} {far:?}");
    }
}
