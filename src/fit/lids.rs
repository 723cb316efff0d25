//! The closing lids of a fitted head, shaped from the mesh's own lids.
//!
//! The template's closing eye ring (`Orbicularis_Oculi` in the default rig) carries a mask
//! made for the template's lids (`face::lids`): each lid margin closes to near where the lids
//! meet, and the skin beyond it follows less and less, to nothing at the brow. Carried to a
//! head whose lids are shaped otherwise (MakeHuman's several close rows folding into the
//! socket, MediaPipe's coarse lids), that mask no longer matches the lids: neighbouring rows
//! take different shares of the pull and turn over, and the margins stop short (a tenth of the
//! opening and more is left at AU45, where the skin rules' area bound holds back the rows
//! that would collapse). The closing ring's per-vertex mask and gain are therefore rebuilt
//! from the mesh's lid landmarks, the same way the default rig builds them from its lids:
//!
//! - In the ring's frame (`x` across the eye, `y` up, centred on its axis, where the lids
//!   meet), the upper margin is the polyline through the eye's corners and upper lid
//!   landmarks (37, 38 or 43, 44), the lower one through the lower lid landmarks.
//! - At 2.0 each margin travels to within [`STOP_SHORT`] of where the lids meet (the axis, or
//!   the lower margin where it lies above the axis) in its own column; skin beyond the upper
//!   margin follows linearly less, to nothing at the brow's height (the brow landmarks of that
//!   side), and below the lower margin over a band as tall. Skin inside the opening (a lid's
//!   inner fold, rows folding back into the socket) moves with the margin nearer to it, so
//!   the rows of a lid's edge move together and do not turn over. Nothing beyond the corners
//!   moves.
//! - Where that travel would turn a triangle over (the close rows of a canthus's fold), the
//!   triangle's corners close up over their least travel only as far as keeps a fifth of
//!   its normal ([`keep_triangles_facing`]).
//! - The lower lid's own ring (AU7) is not a closing ring; its carried mask is replaced by
//!   one faded along the skin to the canthi (`super::lowerlid`).
//! - The ring's gain is the smallest that lets its own pull (`2 g f t` at 2.0) reach that
//!   travel at every lid landmark; each vertex's weight is the share of that pull it needs.
//!
//! Where the mesh's skin inside the ring is the template's own (the template fitted to
//! itself) the carried mask is exact and is kept, so the identity fit is unchanged.

use glam::{DMat3, DVec3, Vec3};

use super::lidedge::EyeMarks;
use super::lowerlid::{lower_lid_mask, replace_carried, EyeVertices};
use super::parts::{Part, Parts};
use super::warp::Warp;
use super::Template;
use crate::model::{Convergence, Mask, Mesh, MuscleKind, Rig, Sphincter};

/// How far short of where the lids meet each margin stops at 2.0, as a share of its travel.
pub const STOP_SHORT: f64 = 0.015;

/// A lid's triangle keeps at least this share of its normal (along the rest normal) at 2.0
/// ([`keep_triangles_facing`]).
const KEEP_NORMAL: f64 = 0.2;

/// Rounds of [`keep_triangles_facing`] at most.
const MAX_ROUNDS: usize = 100;

/// How much further short the lids stop at the corners, as a share of their travel there.
const CORNER_SLACK: f64 = 0.3;

/// The most a lid vertex's travel at 2.0 may exceed a neighbour's, per unit of the length
/// between them (`limit_travel_slope`): an edge then stretches or shrinks by about its own
/// length at most as the lid closes.
const TRAVEL_SLOPE: f64 = 1.0;

/// The activation a profile is made for (the default table's AU43/45 use 2.0).
const FULL: f64 = 2.0;

/// The landmarks of each eye: outer and inner corners' order as in the iBUG scheme, the
/// upper lid (corner, two lid points, corner), the lower lid (corner, two lid points,
/// corner), and the brow above it.
struct EyeLandmarks {
    upper: [usize; 4],
    lower: [usize; 4],
    brow: [usize; 5],
}

/// The subject's right eye, then the left.
const EYES: [EyeLandmarks; 2] = [
    EyeLandmarks {
        upper: [36, 37, 38, 39],
        lower: [39, 40, 41, 36],
        brow: [17, 18, 19, 20, 21],
    },
    EyeLandmarks {
        upper: [42, 43, 44, 45],
        lower: [45, 46, 47, 42],
        brow: [22, 23, 24, 25, 26],
    },
];

/// The facing lid landmarks (upper, lower) of an eye.
fn pairs(eye: &EyeLandmarks) -> [(usize, usize); 2] {
    [(eye.upper[1], eye.lower[2]), (eye.upper[2], eye.lower[1])]
}

/// The direction from the lower lid landmarks' middle to the upper ones' (the eye's middle
/// column): the way a closing upper lid travels to meet the lower one.
fn lid_up(target: &[Vec3], eye: &EyeLandmarks) -> Vec3 {
    let mean = |ids: &[usize]| ids.iter().map(|&i| target[i]).sum::<Vec3>() / ids.len() as f32;
    mean(&eye.upper[1..3]) - mean(&eye.lower[1..3])
}

/// A ring's frame about its centre: local `(x, y, z)` of mesh points.
struct RingFrame {
    centre: DVec3,
    rotation: DMat3,
}

impl RingFrame {
    fn of(s: &Sphincter) -> RingFrame {
        RingFrame {
            centre: s.centre.as_dvec3(),
            rotation: s.frame.rotation().unwrap_or(DMat3::IDENTITY),
        }
    }

    fn local(&self, p: Vec3) -> DVec3 {
        self.rotation.transpose() * (p.as_dvec3() - self.centre)
    }
}

/// A margin in the ring's frame: `(x, y, z)` points sorted by x.
struct Margin(Vec<DVec3>);

impl Margin {
    fn new(mut points: Vec<DVec3>) -> Margin {
        points.sort_by(|a, b| a.x.total_cmp(&b.x));
        Margin(points)
    }

    /// The margin's point in the column at `x`; `None` beyond the corners.
    fn at(&self, x: f64) -> Option<DVec3> {
        super::lidedge::polyline_at(&self.0, x)
    }
}

/// How far each point of a closing eye travels at 2.0 toward the ring's axis (`y = 0`).
struct Profile {
    /// The lid landmarks' polylines: the top and bottom of the bands that move as one.
    upper: Margin,
    lower: Margin,
    /// The lids' free edges as seen from the front (`super::lidedge`), or the landmarks'
    /// polylines where none were found: where the lids meet.
    upper_edge: Margin,
    lower_edge: Margin,
    /// The opening in the middle column: skin more than 0.4 of it behind its margin's
    /// depth (the socket's lining behind the globe) fades out by 0.9 of it.
    opening: f64,
    /// The opening between the free edges in the middle column.
    seen: f64,
    /// The height of the upper lid's skin's end (the brow) above the axis.
    reach: f64,
}

impl Column {
    /// The travel that brings a point at height `y` to the meeting line (short by `keep`),
    /// from its own side of the axis; 0 for a point already past it.
    fn to_meet(&self, y: f64) -> f64 {
        if y > 0.0 {
            self.keep * (y - self.meet.max(0.0)).max(0.0)
        } else {
            self.keep * (self.meet.min(0.0) - y).max(0.0)
        }
    }

    /// The top and bottom of the lids' bands: each lid from its free edge to its landmarks
    /// (its front, edge and back where the landmarks sit on the lid's back) moves as one.
    fn band(&self) -> (f64, f64) {
        (self.up.y.max(self.eu.y), self.low.y.min(self.el.y))
    }

    /// The depths of the upper and lower lids' fronts: the deeper of the landmark and the
    /// edge's front.
    fn fronts(&self) -> (f64, f64) {
        (self.up.z.min(self.eu.z), self.low.z.min(self.el.z))
    }
}

/// One column of a closing eye ([`Profile::column`]).
struct Column {
    /// The landmarks' margins.
    up: DVec3,
    low: DVec3,
    /// The free edges.
    eu: DVec3,
    el: DVec3,
    /// The share of the way to the meeting line the lids travel.
    keep: f64,
    /// The meeting line's height.
    meet: f64,
}

impl Profile {
    fn new(
        (upper, lower): (Margin, Margin),
        (upper_edge, lower_edge): (Margin, Margin),
        reach: f64,
    ) -> Option<Profile> {
        let (up, low) = (upper.at(0.0)?, lower.at(0.0)?);
        let (eu, el) = (upper_edge.at(0.0)?, lower_edge.at(0.0)?);
        let opening = up.y - low.y;
        let seen = eu.y - el.y;
        (opening > 0.0 && seen > 0.0).then_some(Profile {
            opening,
            seen,
            upper,
            lower,
            upper_edge,
            lower_edge,
            reach,
        })
    }

    /// The column at `x`: the landmarks' margins, the free edges, the share of the way to
    /// the meeting line the lids travel ([`STOP_SHORT`], more toward the corners) and the
    /// meeting line's height; `None` beyond the corners.
    fn column(&self, x: f64) -> Option<Column> {
        let (up, low) = (self.upper.at(x)?, self.lower.at(x)?);
        let eu = self.upper_edge.at(x).unwrap_or(up);
        let el = self.lower_edge.at(x).unwrap_or(low);
        // toward the corners, where the opening narrows to a fold of the canthus whose rows
        // lie closer together than the lids travel, the lids stop further short (up to
        // [`CORNER_SLACK`] of the way at the corner): collapsing those rows fully turned
        // them over; the opening in the middle columns still closes to [`STOP_SHORT`]
        let narrow = 1.0 - super::regions::smoothstep(0.0, 0.5, (eu.y - el.y) / self.seen);
        let keep = (1.0 - STOP_SHORT) * (1.0 - CORNER_SLACK * narrow);
        // the ring pulls each point toward its axis and no further, so the lids meet on the
        // axis; where the axis runs outside the opening (toward a corner that lies above or
        // below it) the far lid comes to the near one's edge. Meeting anywhere else leaves
        // the gap between there and the axis open: one lid stops at the axis, the other at
        // the meeting line (a scanned head whose corners' line is turned 6 degrees from
        // the axis kept 31% of its opening at AU45)
        let meet = 0.0f64.clamp(el.y.min(eu.y), eu.y.max(el.y));
        Some(Column {
            up,
            low,
            eu,
            el,
            keep,
            meet,
        })
    }

    /// The share of a point's travel it keeps at `depth` (its lid's front there) given its
    /// own `z`: the socket's lining far behind the margin stays (the globe lies between).
    fn before_the_socket(&self, depth: f64, z: f64) -> f64 {
        let behind = (depth - z) / self.opening;
        1.0 - super::regions::smoothstep(0.4, 0.9, behind)
    }

    /// How far a vertex on the opening's own border (a lid's margin row on the mesh) travels
    /// at 2.0: to the meeting line in its column, whatever the found edges say. The edges
    /// are sampled in columns and smoothed, so on a coarse lid a margin vertex, a corner of
    /// the margin's polyline, lies up to a millimetre beyond them; taken as skin beyond the
    /// band, it stopped that far short. Never less than [`Profile::travel`].
    fn margin_travel(&self, p: DVec3) -> f64 {
        let travel = self.travel(p);
        let Some(c) = self.column(p.x) else {
            return travel;
        };
        // only the lids' own margins: within a quarter of the opening of the bands (as the
        // edges were looked for), not the face's outer border or the socket's lining
        let pad = 0.25 * self.opening;
        let (top, bottom) = c.band();
        if p.y > top + pad || p.y < bottom - pad {
            return travel;
        }
        let (up_z, low_z) = c.fronts();
        let depth = if p.y >= 0.0 { up_z } else { low_z };
        travel.max(c.to_meet(p.y) * self.before_the_socket(depth, p.z))
    }

    fn travel(&self, p: DVec3) -> f64 {
        let Some(c) = self.column(p.x) else {
            return 0.0;
        };
        let (eu, el) = (c.eu, c.el);
        let upper_travel = c.keep * (eu.y - c.meet.max(0.0)).max(0.0);
        let lower_travel = c.keep * (c.meet.min(0.0) - el.y).max(0.0);
        // each lid's band moves as one; beyond, the skin follows less
        let (top, bottom) = c.band();
        let ramp = |travel: f64, from_band: f64, to_rim: f64| {
            if from_band <= 0.0 {
                travel
            } else if to_rim <= 0.0 || from_band >= to_rim {
                0.0
            } else {
                travel * (1.0 - from_band / to_rim)
            }
        };
        let (up_z, low_z) = c.fronts();
        let (depth, travel) = if p.y >= eu.y {
            (up_z, ramp(upper_travel, p.y - top, self.reach - top))
        } else if p.y <= el.y {
            (low_z, ramp(lower_travel, bottom - p.y, bottom + self.reach))
        } else {
            // inside the opening: a lid's inner fold goes with its edge, blended between the
            // lids by the point's height between the edges in its column, whatever its depth
            // (the fold's rows at one height move as one band); linear in height, so the
            // rows close up without passing each other (the opening closes to 1.5% of its
            // height, the rows' order kept). The ring cannot pull a point across the axis
            // from the other side, so a point goes no further than the meeting line (a
            // fade toward the axis instead held back a lid's margin vertices lying just
            // inside the found edge, which then stopped short of the lids' meeting)
            let s = ((p.y - el.y) / (eu.y - el.y).max(f64::EPSILON)).clamp(0.0, 1.0);
            let travel = if p.y > 0.0 {
                (s * upper_travel).min(c.to_meet(p.y))
            } else {
                ((1.0 - s) * lower_travel).min(c.to_meet(p.y))
            };
            (s * up_z + (1.0 - s) * low_z, travel)
        };
        travel * self.before_the_socket(depth, p.z)
    }
}

/// The ring's own pull toward its axis at 2.0 per unit weight (`2 f t`); 0 outside.
fn own_pull(s: &Sphincter, local: DVec3) -> f64 {
    let px = local.x / f64::from(s.semi_major);
    let t = local.y.abs() / f64::from(s.semi_minor);
    let f = 1.0 - px.hypot(t);
    if f <= 0.0 {
        0.0
    } else {
        FULL * f * t
    }
}

/// The vertex of `mesh` nearest `p`.
fn nearest_vertex(mesh: &Mesh, p: Vec3) -> usize {
    mesh.positions
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.distance_squared(p).total_cmp(&b.1.distance_squared(p)))
        .map_or(0, |(i, _)| i)
}

/// The share of an eye's opening (summed over its facing lid landmarks) by which the ring
/// `name` of `rig` brings the upper lid down at 2.0.
fn upper_closure(
    rig: &Rig,
    name: &str,
    mesh: &Mesh,
    landmarks: &[Vec3],
    eye: &EyeLandmarks,
) -> Option<f64> {
    let s = sphincter(rig, name)?;
    let up = RingFrame::of(s).rotation.col(1);
    let pull = |i: usize| {
        let p = landmarks[i];
        let v = nearest_vertex(mesh, p);
        let d = crate::model::field::sphincter_displacement(s, mesh.positions[v], FULL as f32);
        rig.mask_weight(name, v as u32) * d.as_dvec3().dot(up)
    };
    let (mut open, mut upper) = (0.0, 0.0);
    for (u, l) in pairs(eye) {
        open += (landmarks[u] - landmarks[l]).as_dvec3().dot(up);
        upper -= pull(u);
    }
    (open > 0.0).then(|| upper / open)
}

fn sphincter<'a>(rig: &'a Rig, name: &str) -> Option<&'a Sphincter> {
    match &rig.muscles.iter().find(|m| m.name == name)?.kind {
        MuscleKind::Sphincter(s) => Some(s),
        _ => None,
    }
}

/// Whether ring `name` acts on the lower lid alone: its weight at each upper lid landmark is
/// under a tenth of its least weight at the lower lid's, which is above 0.
fn is_lower_ring(rig: &Rig, name: &str, eye: &EyeVertices) -> bool {
    let at = |vs: &[u32]| {
        vs.iter()
            .map(|&v| rig.mask_weight(name, v))
            .collect::<Vec<f64>>()
    };
    let lower = at(&eye.lower).into_iter().fold(f64::INFINITY, f64::min);
    let upper = at(&eye.upper).into_iter().fold(0.0, f64::max);
    lower > 0.0 && upper < 0.1 * lower
}

/// The eye a ring centred at `c` closes: the eye whose lid landmarks' middle is within the
/// eye's half-width of it.
fn eye_of(landmarks: &[Vec3], c: Vec3) -> Option<&'static EyeLandmarks> {
    EYES.iter().find(|eye| {
        let (a, b) = (landmarks[eye.upper[0]], landmarks[eye.upper[3]]);
        c.distance(0.5 * (a + b)) < 0.5 * a.distance(b)
    })
}

/// The eye rings [`shape_lids`] rebuilt.
pub type Reshaped = Vec<String>;

/// Rebuilds the closing eye rings' masks from the mesh's lids, unless the mesh there is the
/// template's own (module docs); returns the rings rebuilt.
/// `rig` is the fitted rig with all its masks; `target` the mesh's landmarks, `marks` their
/// vertices.
pub(super) fn shape_lids(
    rig: &mut Rig,
    template: Template<'_>,
    mesh: &Mesh,
    warp: &Warp,
    parts: &Parts,
    target: &[Vec3],
    marks: &[u32],
) -> Reshaped {
    let mut reshaped = Vec::new();
    let mut lower = Vec::new();
    let names: Vec<String> = rig.muscles.iter().map(|m| m.name.clone()).collect();
    for name in names {
        let Some(s) = sphincter(rig, &name).cloned() else {
            continue;
        };
        if s.convergence != Convergence::MajorAxis {
            continue;
        }
        let Some(eye) = eye_of(target, s.centre) else {
            continue;
        };
        let Some(upper) = upper_closure(rig, &name, mesh, target, eye) else {
            continue;
        };
        if is_template_here(&s, template, warp, mesh, parts) {
            continue;
        }
        // a ring that does not bring the upper lid down is not the closing ring; one that
        // acts on the lower lid alone is the lower lid's own (AU7), faded along the skin
        if upper < 0.25 {
            let at = |ids: &[usize]| [marks[ids[0]], marks[ids[1]]];
            let vertices = EyeVertices {
                corners: at(&[eye.upper[0], eye.upper[3]]),
                upper: at(&eye.upper[1..3]),
                lower: at(&eye.lower[1..3]),
            };
            if is_lower_ring(rig, &name, &vertices) {
                if let Some(mask) = lower_lid_mask(&name, &s, mesh, parts, vertices) {
                    lower.push((name, mask));
                }
            }
            continue;
        }
        // the ring closes along the lids' own slope, so the upper margin comes down onto the
        // lower one rather than stopping in front of or behind it
        let mut ring = s.clone();
        ring.frame.y = lid_up(target, eye);
        if ring.frame.rotation().is_none() {
            continue;
        }
        if let Some(mask) = lid_mask(&ring, &name, mesh, parts, target, marks, eye) {
            if let Some(m) = rig.muscles.iter_mut().find(|m| m.name == name) {
                m.kind = MuscleKind::Sphincter(ring);
            }
            release(rig, &name);
            rig.masks.push(mask);
            reshaped.push(name);
        }
    }
    let (names, masks): (Vec<String>, Vec<Mask>) = lower.into_iter().unzip();
    replace_carried(rig, parts, &names, masks);
    reshaped.extend(names);
    reshaped
}

/// Whether the mesh's skin inside ring `s` is the template's own, carried by the warp (each
/// vertex within a ten-thousandth of the landmarks' spread of a warped template vertex): the
/// template fitted to itself, whose carried mask is exact.
fn is_template_here(
    s: &Sphincter,
    template: Template<'_>,
    warp: &Warp,
    mesh: &Mesh,
    parts: &Parts,
) -> bool {
    let frame = RingFrame::of(s);
    let near = (1e-4 * warp.spread) as f32;
    let warped: Vec<Vec3> = template
        .mesh
        .positions
        .iter()
        .map(|&p| warp.apply_f32(p))
        .collect();
    mesh.positions
        .iter()
        .enumerate()
        .filter(|&(v, p)| parts.of_vertex[v] == Part::Skin && own_pull(s, frame.local(*p)) > 0.0)
        .all(|(_, p)| warped.iter().any(|w| w.distance(*p) <= near))
}

/// Takes muscle `name` out of every mask that is not all zeros (the still parts and the
/// depth cut stay): its carried weights and gains, replaced by the lid mask.
fn release(rig: &mut Rig, name: &str) {
    for mask in &mut rig.masks {
        if mask.weights.is_empty() || mask.weights.iter().any(|&(_, w)| w != 0.0) {
            mask.muscles.retain(|n| n != name);
        }
    }
    rig.masks.retain(|m| !m.muscles.is_empty());
}

/// Per vertex, for the skin inside ring `s`: its place in the ring's frame and how far the
/// ring should move it at 2.0 (the profile's travel). Skin on a piece of its own, holding no
/// landmark (lashes, whether their group says so or not), takes the travel of the nearest
/// skin vertex of the face's pieces inside the ring: the lid edge it grows from. Travel
/// that would turn a triangle over is lowered ([`keep_triangles_facing`]), the face's before
/// the lashes take theirs.
fn wanted_travel(
    s: &Sphincter,
    frame: &RingFrame,
    profile: &Profile,
    mesh: &Mesh,
    parts: &Parts,
    marks: &[u32],
) -> Vec<Option<(DVec3, f64)>> {
    let piece = super::parts::components(mesh);
    let face: Vec<u32> = marks.iter().map(|&v| piece[v as usize]).collect();
    let inside: Vec<Option<DVec3>> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(v, p)| {
            let q = frame.local(*p);
            (parts.of_vertex[v] == Part::Skin && own_pull(s, q) > 0.0).then_some(q)
        })
        .collect();
    let on_face = |v: usize| face.contains(&piece[v]);
    let margin = opening_border(mesh, parts);
    let mut travel: Vec<Option<f64>> = inside
        .iter()
        .enumerate()
        .map(|(v, q)| {
            let q = (*q)?;
            on_face(v).then(|| match margin[v] {
                true => profile.margin_travel(q),
                false => profile.travel(q),
            })
        })
        .collect();
    keep_triangles_facing(mesh, &inside, &mut travel);
    limit_travel_slope(mesh, &mut travel, TRAVEL_SLOPE);
    let lid: Vec<(Vec3, f64)> = travel
        .iter()
        .enumerate()
        .filter_map(|(v, t)| Some((mesh.positions[v], (*t)?)))
        .collect();
    for (v, q) in inside.iter().enumerate() {
        if q.is_none() || travel[v].is_some() {
            continue;
        }
        let p = mesh.positions[v];
        travel[v] = lid
            .iter()
            .min_by(|a, b| a.0.distance_squared(p).total_cmp(&b.0.distance_squared(p)))
            .map(|nearest| nearest.1);
    }
    // the lashes' own triangles, from lid vertices a little apart, keep facing too
    keep_triangles_facing(mesh, &inside, &mut travel);
    inside
        .iter()
        .zip(&travel)
        .map(|(q, t)| Some(((*q)?, (*t)?)))
        .collect()
}

/// Per vertex: whether it lies on the border of the face's skin, on an edge with skin on one
/// side only (a lid's margin where the eye's opening begins: a hole, the eyeball, or the
/// dark eye a covered eye was cut open into).
fn opening_border(mesh: &Mesh, parts: &Parts) -> Vec<bool> {
    let skin = |v: u32| parts.of_vertex[v as usize] == Part::Skin;
    let skin_triangles = mesh.triangles.iter().filter(|t| t.iter().all(|&v| skin(v)));
    let mut border = vec![false; mesh.vertex_count()];
    for (a, b) in Mesh::boundary_edges_of(skin_triangles) {
        border[a as usize] = true;
        border[b as usize] = true;
    }
    border
}

/// Lowers the travel toward the axis (`travel`, for the points `inside` at their place in
/// the ring's frame) where a triangle would turn over: a canthus's fold
/// (MakeHuman's rows 0.8 mm apart, one travelling 1.2 mm further than the row below it)
/// turned over under the profile's own travel. The ring moves each point across the axis's
/// line (frame `y`), so a triangle's normal moves linearly with how much of its points'
/// differences in travel it takes: each triangle on one side of the axis that would keep
/// less than [`KEEP_NORMAL`] of its normal takes only the share that keeps it, over its
/// least travel (the rows then close up without passing), until no triangle needs it. Only
/// travels are lowered, and only in triangles that would turn: the lids' middle keeps its
/// profile.
fn keep_triangles_facing(mesh: &Mesh, inside: &[Option<DVec3>], travel: &mut [Option<f64>]) {
    let triangles: Vec<[usize; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.map(|v| v as usize))
        .filter(|t| t.iter().all(|&v| travel[v].is_some()))
        .collect();
    for _ in 0..MAX_ROUNDS {
        let mut changed = false;
        for t in &triangles {
            let (Some(q), Some(d)) = (
                t.iter().map(|&v| inside[v]).collect::<Option<Vec<DVec3>>>(),
                t.iter().map(|&v| travel[v]).collect::<Option<Vec<f64>>>(),
            ) else {
                continue;
            };
            // one side of the axis: every point moves the same way along y
            let side = q[0].y.signum();
            if q.iter().any(|p| p.y.signum() != side || p.y == 0.0) {
                continue;
            }
            let least = d.iter().copied().fold(f64::INFINITY, f64::min);
            let excess: Vec<f64> = d.iter().map(|x| x - least).collect();
            let (u, w) = (q[1] - q[0], q[2] - q[0]);
            let n = u.cross(w);
            // the normal with a share `l` of the excess: n - l k (the y-moves are linear)
            let (a, b) = (
                -side * (excess[1] - excess[0]),
                -side * (excess[2] - excess[0]),
            );
            let k = -n.dot(b * u.cross(DVec3::Y) + a * DVec3::Y.cross(w));
            let room = (1.0 - KEEP_NORMAL) * n.length_squared();
            if k > room {
                let share = room / k;
                for (&v, e) in t.iter().zip(&excess) {
                    travel[v] = Some(least + share * e);
                }
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
}

/// The mask that makes ring `s` close the eye's lids on `mesh` as the profile asks.
fn lid_mask(
    s: &Sphincter,
    name: &str,
    mesh: &Mesh,
    parts: &Parts,
    target: &[Vec3],
    marks: &[u32],
    eye: &EyeLandmarks,
) -> Option<Mask> {
    let frame = RingFrame::of(s);
    let local = |i: usize| frame.local(target[i]);
    let brow = eye.brow.iter().map(|&i| local(i).y).sum::<f64>() / eye.brow.len() as f64;
    let margins = || {
        (
            Margin::new(eye.upper.iter().map(|&i| local(i)).collect()),
            Margin::new(eye.lower.iter().map(|&i| local(i)).collect()),
        )
    };
    let marks_of = EyeMarks {
        upper: eye.upper,
        lower: eye.lower,
    };
    // the free edges lead only where they lie away from the landmarks (landmarks on the
    // lid's back); where the landmarks are the edges (a covered eye cut along them) the
    // landmarks' own polylines are the surer line: the sampled edges step between rows
    let edges = match super::lidedge::Sight::new(mesh, parts, marks, &marks_of) {
        Some(sight) => {
            let to_local = |ps: &[Vec3]| Margin::new(ps.iter().map(|&p| frame.local(p)).collect());
            (
                to_local(&sight.edges().upper),
                to_local(&sight.edges().lower),
            )
        }
        None => margins(),
    };
    let profile = Profile::new(margins(), edges, brow.min(f64::from(s.semi_minor)))?;
    let wanted = wanted_travel(s, &frame, &profile, mesh, parts, marks);
    // the share of the ring's own pull each point needs
    let need = |(p, want): (DVec3, f64)| {
        let own = own_pull(s, p);
        (own > 0.0).then(|| want / own)
    };
    // the gain lets the lid landmarks and every point with a tenth of the ring's pull or
    // more (the lid's inner fold near the axis has little) reach their travel
    let lid_points = eye.upper[1..3].iter().chain(&eye.lower[1..3]);
    let at_lids = lid_points
        .filter_map(|&i| need((local(i), profile.travel(local(i)))))
        .fold(0.0, f64::max);
    let gain = wanted
        .iter()
        .flatten()
        .filter(|(q, _)| own_pull(s, *q) >= 0.1)
        .filter_map(|&w| need(w))
        .fold(at_lids, f64::max);
    if !(gain.is_finite() && gain > 0.0) {
        return None;
    }
    let weights: Vec<(u32, f32)> = wanted
        .iter()
        .enumerate()
        .filter_map(|(v, w)| {
            let w = (need((*w)?)? / gain).min(1.0);
            (w < 1.0).then_some((v as u32, w as f32))
        })
        .collect();
    Some(Mask {
        muscles: vec![name.to_string()],
        gain: gain as f32,
        weights,
    })
}

/// Lowers travels until no two neighbouring lid vertices differ by more than `slope` per unit
/// of the length between them ([`TRAVEL_SLOPE`]): the lowering that keeps a triangle facing
/// ([`keep_triangles_facing`]) is the triangle's own, and its neighbours kept their travel;
/// on a mesh finer than the lid's rounded margin needs (MakeHuman cut in four: rows 0.4 mm
/// apart) one edge then stretched 4.7x as the lid closed.
fn limit_travel_slope(mesh: &Mesh, travel: &mut [Option<f64>], slope: f64) {
    let n = mesh.vertex_count();
    let mut neighbours: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for [a, b] in mesh.edges() {
        let (a, b) = (a as usize, b as usize);
        if travel[a].is_some() && travel[b].is_some() {
            let len = f64::from(mesh.positions[a].distance(mesh.positions[b]));
            neighbours[a].push((b, len));
            neighbours[b].push((a, len));
        }
    }
    let mut values: Vec<f64> = travel.iter().map(|t| t.unwrap_or(f64::INFINITY)).collect();
    let sources: Vec<usize> = (0..n).filter(|&v| travel[v].is_some()).collect();
    crate::model::envelope::lower_envelope(
        &mut values,
        sources,
        |v| neighbours[v].iter().copied(),
        |value, len| value + slope * len,
    );
    for (t, v) in travel.iter_mut().zip(values) {
        if t.is_some() {
            *t = Some(v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two rows of a fold 0.8 apart above the axis, the upper one travelling 1.2 further
    /// than the lower: the triangle between them would turn over. It keeps facing, the lower
    /// row keeps its travel, and a triangle that would not turn (one travel) is untouched.
    #[test]
    fn a_fold_row_that_would_pass_the_row_below_stops_short() {
        let positions = vec![
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.8, 0.0),
            Vec3::new(5.0, 1.0, 0.0),
            Vec3::new(6.0, 1.0, 0.0),
            Vec3::new(5.0, 1.8, 0.0),
        ];
        let mesh = Mesh::new(positions, vec![[0, 1, 2], [3, 4, 5]]).unwrap();
        let inside: Vec<Option<DVec3>> =
            mesh.positions.iter().map(|p| Some(p.as_dvec3())).collect();
        let mut travel = vec![
            Some(1.7),
            Some(1.7),
            Some(2.9),
            Some(2.0),
            Some(2.0),
            Some(2.0),
        ];
        keep_triangles_facing(&mesh, &inside, &mut travel);
        let t: Vec<f64> = travel.iter().map(|t| t.unwrap()).collect();
        assert_eq!(&t[..2], &[1.7, 1.7]);
        assert!(t[2] < 2.9 && t[2] > 1.7, "{}", t[2]);
        assert_eq!(&t[3..], &[2.0, 2.0, 2.0]);
        // the upper row still lies above the lower one after the move: a fifth of the normal
        let moved = |v: usize| mesh.positions[v].y as f64 - t[v];
        assert!(
            (moved(2) - moved(0) - 0.2 * 0.8).abs() < 1e-6,
            "{}",
            moved(2) - moved(0)
        );
    }
}
