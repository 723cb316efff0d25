//! The lids' free edges as a viewer sees them: where, looking at the eye from the front, the
//! lid's skin ends and the eyeball shows.
//!
//! The lid landmarks are not always on that edge. A mesh that models the lids' thickness
//! (MakeHuman's base mesh: the lid's front, its rounded edge, its back against the globe and
//! the socket's lining behind it) has its lid landmarks picked on the skin nearest the
//! eyeball, the lid's back, a few millimetres above the upper edge and below the lower one:
//! there the landmarks' opening is twice the visible one. A lid closed by its landmarks then
//! overshoots the other lid by the difference, and its rows shear against the still corners.
//!
//! So each eye is looked at along the face's forward direction, column by column between its
//! corners: the front-most drawn surface under each sample point is the face's skin (a lid),
//! a rigid part (the eyeball) or nothing (a hole). The opening of a column is the run of
//! samples that are not skin around the middle between the lid landmarks; its ends are the
//! lids' free edges. Skin that is not on the face's pieces (lashes) and helper geometry that is
//! never drawn are looked through. Skin far behind the lids (more than [`SOCKET_DEPTH`] of the
//! eye's width behind its lid landmarks) is the socket seen through an eye that has no
//! eyeball: it counts as the opening. An eye covered by skin (no opening in most columns) has no
//! free edges found, and its landmarks stand for them.

use glam::{DVec3, Vec3};

use super::parts::{components, drawn_triangles, Part, Parts};
use crate::model::Mesh;

/// Columns looked at between an eye's corners.
const COLUMNS: usize = 24;
/// Samples per column, over the landmarks' opening and a quarter of it beyond each lid.
const ROWS: usize = 160;
/// Skin this far behind the lid landmarks, as a share of the eye's width (corner to corner),
/// is the back of the socket seen through the opening, not a lid: a lid is a few millimetres
/// thick and an eyeball's front sits at the lids, while an empty socket is as deep as the
/// eye is wide.
const SOCKET_DEPTH: f64 = 0.25;

/// Whether a sample whose front-most surface is `hit` shows the opening: nothing, something
/// other than the face's skin (the eyeball), or skin deeper than `socket` (an empty socket's
/// back).
fn shows_opening(hit: Option<(f64, Seen)>, socket: f64) -> bool {
    !matches!(hit, Some((z, Seen::Skin)) if z > socket)
}

/// An eye's landmarks: the upper lid (outer or inner corner, two lid points, the other corner)
/// and the lower lid (from the second corner back), as in the iBUG scheme.
#[derive(Debug, Clone, Copy)]
pub struct EyeMarks {
    /// Corner, two upper lid points, corner.
    pub upper: [usize; 4],
    /// Corner, two lower lid points, corner (the same corners, in reverse).
    pub lower: [usize; 4],
}

/// The subject's right eye, then the left.
pub const EYE_MARKS: [EyeMarks; 2] = [
    EyeMarks {
        upper: [36, 37, 38, 39],
        lower: [39, 40, 41, 36],
    },
    EyeMarks {
        upper: [42, 43, 44, 45],
        lower: [45, 46, 47, 42],
    },
];

/// An eye's free lid edges in mesh space, each from corner to corner (the corners are the
/// landmarks'), sorted across the eye.
#[derive(Debug, Clone, PartialEq)]
pub struct LidEdges {
    /// The upper lid's edge.
    pub upper: Vec<Vec3>,
    /// The lower lid's edge.
    pub lower: Vec<Vec3>,
}

/// The eye's view frame: across (toward the subject's left), up (from the lower lid
/// landmarks to the upper ones) and forward (toward the nose tip's side), about the lid
/// landmarks' middle.
#[derive(Debug, Clone)]
struct View {
    origin: DVec3,
    axes: [DVec3; 3],
}

impl View {
    fn of(points: &[Vec3], eye: &EyeMarks) -> Option<View> {
        let p = |i: usize| points[i].as_dvec3();
        let across = (p(eye.upper[3]) - p(eye.upper[0])).normalize_or_zero();
        let mean = |ids: &[usize]| ids.iter().map(|&i| p(i)).sum::<DVec3>() / ids.len() as f64;
        let up = mean(&eye.upper[1..3]) - mean(&eye.lower[1..3]);
        let up = (up - across * up.dot(across)).normalize_or_zero();
        let origin = (mean(&eye.upper) + mean(&eye.lower)) / 2.0;
        let mut forward = across.cross(up);
        // the nose tip (landmark 30) lies in front of the eyes
        if forward.dot(p(30) - origin) < 0.0 {
            forward = -forward;
        }
        (across != DVec3::ZERO && up != DVec3::ZERO).then_some(View {
            origin,
            axes: [across, up, forward],
        })
    }

    fn local(&self, p: Vec3) -> DVec3 {
        let d = p.as_dvec3() - self.origin;
        DVec3::new(
            d.dot(self.axes[0]),
            d.dot(self.axes[1]),
            d.dot(self.axes[2]),
        )
    }

    fn world(&self, q: DVec3) -> Vec3 {
        (self.origin + self.axes[0] * q.x + self.axes[1] * q.y + self.axes[2] * q.z).as_vec3()
    }
}

/// What a drawn triangle is to a viewer of the eye.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Seen {
    /// The face's skin: a lid.
    Skin,
    /// Anything else drawn (the eyeball): the opening.
    Other,
}

/// The triangles a viewer of the eye sees, each with what it is: drawn triangles, less
/// those on skin that is not the face's (lashes, looked through).
fn seen_triangles(mesh: &Mesh, parts: &Parts, marks: &[u32]) -> Vec<([u32; 3], Seen)> {
    let piece = components(mesh);
    let mut face = vec![false; mesh.vertex_count()];
    for &v in marks {
        if let Some(&c) = piece.get(v as usize) {
            face[c as usize] = true;
        }
    }
    let on_face = |v: u32| face[piece[v as usize] as usize];
    let loose_skin = |v: u32| parts.of_vertex[v as usize] == Part::Skin && !on_face(v);
    drawn_triangles(mesh)
        .unwrap_or_else(|| mesh.triangles.clone())
        .into_iter()
        .filter(|t| !t.iter().any(|&v| loose_skin(v)))
        .map(|t| {
            let skin = t
                .iter()
                .all(|&v| on_face(v) && parts.of_vertex[v as usize] == Part::Skin);
            (t, if skin { Seen::Skin } else { Seen::Other })
        })
        .collect()
}

/// The front-most surface at `(x, y)` among `tris` (view coordinates): its depth and kind.
fn front_at(tris: &[([DVec3; 3], Seen)], x: f64, y: f64) -> Option<(f64, Seen)> {
    let mut best: Option<(f64, Seen)> = None;
    for (t, seen) in tris {
        let [a, b, c] = *t;
        let det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if det.abs() < 1e-18 {
            continue;
        }
        let u = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
        let v = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
        if u < 0.0 || v < 0.0 || u + v > 1.0 {
            continue;
        }
        let z = a.z + u * (b.z - a.z) + v * (c.z - a.z);
        if best.is_none_or(|(d, _)| z > d) {
            best = Some((z, *seen));
        }
    }
    best
}

/// Linear interpolation along a polyline of view points sorted by x; `None` beyond its ends.
pub(super) fn polyline_at(points: &[DVec3], x: f64) -> Option<DVec3> {
    points
        .windows(2)
        .find(|w| w[0].x <= x && x <= w[1].x)
        .map(|w| w[0].lerp(w[1], (x - w[0].x) / (w[1].x - w[0].x).max(f64::EPSILON)))
}

/// One column's opening: the upper and lower edge points (view coordinates, at the depth of
/// the lid's front there), or `None` where the column shows no opening between the lids.
fn column_opening(
    tris: &[([DVec3; 3], Seen)],
    x: f64,
    (low, high): (f64, f64),
    middle: f64,
    socket: f64,
) -> Option<(DVec3, DVec3)> {
    let step = (high - low) / ROWS as f64;
    let samples: Vec<(f64, Option<(f64, Seen)>)> = (0..=ROWS)
        .map(|k| {
            let y = low + step * k as f64;
            (y, front_at(tris, x, y))
        })
        .collect();
    let open = |k: usize| shows_opening(samples[k].1, socket);
    let start = ((middle - low) / step).round().clamp(0.0, ROWS as f64) as usize;
    if !open(start) {
        return None;
    }
    let top = (start..=ROWS).find(|&k| !open(k))?;
    let bottom = (0..=start).rev().find(|&k| !open(k))?;
    let depth = |k: usize| samples[k].1.map_or(0.0, |(z, _)| z);
    let edge = |k: usize, inward: usize| {
        let y = (samples[k].0 + samples[inward].0) / 2.0;
        DVec3::new(x, y, depth(k))
    };
    Some((edge(top, top - 1), edge(bottom, bottom + 1)))
}

/// The free lid edges of `eye` on `mesh` (module docs); `None` when fewer than half the
/// columns between the corners show an opening (an eye covered by skin, or no eyeball and no
/// hole to see).
pub fn lid_edges(mesh: &Mesh, parts: &Parts, marks: &[u32], eye: &EyeMarks) -> Option<LidEdges> {
    let points: Vec<Vec3> = marks
        .iter()
        .map(|&v| mesh.positions.get(v as usize).copied())
        .collect::<Option<_>>()?;
    let view = View::of(&points, eye)?;
    let sorted = |ids: &[usize; 4]| {
        let mut q: Vec<DVec3> = ids.iter().map(|&i| view.local(points[i])).collect();
        q.sort_by(|a, b| a.x.total_cmp(&b.x));
        q
    };
    let (upper, lower) = (sorted(&eye.upper), sorted(&eye.lower));
    let (x0, x1) = (upper[0].x, upper[3].x);
    let top = upper.iter().map(|q| q.y).fold(f64::MIN, f64::max);
    let bottom = lower.iter().map(|q| q.y).fold(f64::MAX, f64::min);
    let pad = 0.25 * (top - bottom);
    if !(x1 > x0 && pad > 0.0) {
        return None;
    }
    let span = (bottom - pad, top + pad);
    let tris: Vec<([DVec3; 3], Seen)> = seen_triangles(mesh, parts, marks)
        .into_iter()
        .map(|(t, seen)| (t.map(|v| view.local(mesh.positions[v as usize])), seen))
        .filter(|(t, _)| {
            let (lo, hi) = t.iter().fold((f64::MAX, f64::MIN), |(lo, hi), q| {
                (lo.min(q.y), hi.max(q.y))
            });
            t.iter().any(|q| q.x >= x0)
                && t.iter().any(|q| q.x <= x1)
                && hi >= span.0
                && lo <= span.1
        })
        .collect();
    let (mut up_edge, mut low_edge) = (vec![upper[0]], vec![lower[0]]);
    for k in 1..COLUMNS {
        let x = x0 + (x1 - x0) * k as f64 / COLUMNS as f64;
        let (Some(u), Some(l)) = (polyline_at(&upper, x), polyline_at(&lower, x)) else {
            continue;
        };
        let column: Vec<([DVec3; 3], Seen)> = tris
            .iter()
            .filter(|(t, _)| t.iter().any(|q| q.x >= x) && t.iter().any(|q| q.x <= x))
            .copied()
            .collect();
        let socket = (u.z + l.z) / 2.0 - SOCKET_DEPTH * (x1 - x0);
        if let Some((a, b)) = column_opening(&column, x, span, (u.y + l.y) / 2.0, socket) {
            up_edge.push(a);
            low_edge.push(b);
        }
    }
    if up_edge.len() <= COLUMNS / 2 {
        return None;
    }
    up_edge.push(upper[3]);
    low_edge.push(lower[3]);
    let (up_edge, low_edge) = (smoothed(&up_edge), smoothed(&low_edge));
    let world = |q: Vec<DVec3>| q.into_iter().map(|p| view.world(p)).collect();
    Some(LidEdges {
        upper: world(up_edge),
        lower: world(low_edge),
    })
}

/// A found edge with its sampled points between the corners smoothed along the edge (a
/// binomial window over five columns; the corners kept). Each column's edge is where its
/// samples change from lid to opening, a step of the sampling grid, and an uneven lid moves
/// it further; the closing lid's rows are placed between the edges, the rows of a jagged
/// edge's neighbouring columns folded, and keeping them facing held the whole lid back
/// (MakeHuman's base mesh made uneven by 0.2 mm: the lids left 20% of the opening;
/// `tests/fit/lids.rs`). A window that keeps a quadratic's height (Savitzky-Golay, five
/// or seven columns) let that fold through.
fn smoothed(edge: &[DVec3]) -> Vec<DVec3> {
    const WINDOW: [f64; 5] = [1.0, 4.0, 6.0, 4.0, 1.0];
    let last = edge.len() - 1;
    (0..=last)
        .map(|i| {
            if i == 0 || i == last {
                return edge[i];
            }
            // the window's part that lies on the edge, its weights renormalised
            let (mut sum, mut total) = (DVec3::ZERO, 0.0);
            for (k, w) in WINDOW.iter().enumerate() {
                if let Some(q) = (i + k).checked_sub(2).and_then(|j| edge.get(j)) {
                    sum += *q * *w;
                    total += w;
                }
            }
            let mean = sum / total;
            DVec3::new(edge[i].x, mean.y, mean.z)
        })
        .collect()
}

/// An eye's visible opening, for measuring how far its lids close: the lids' free edges in
/// the columns of the facing lid landmarks (37 over 41, 38 over 40 on the right eye) and
/// the drawn triangles to look at them through.
#[derive(Debug, Clone)]
pub struct Sight {
    view: View,
    triangles: Vec<([u32; 3], Seen)>,
    /// Per landmark column: its place across the eye, the rest edges' heights (lower,
    /// upper) and the depth behind which skin is the socket ([`SOCKET_DEPTH`]).
    columns: Vec<(f64, f64, f64, f64)>,
    /// The free edges found.
    edges: LidEdges,
}

impl Sight {
    /// The sight of `eye` when its free edges were found and lie away from its lid
    /// landmarks (more than a tenth of the landmarks' opening, in either landmark column):
    /// landmarks on the lid's back. `None` where the landmarks are the edges (or none were
    /// found): then the landmarks measure the lids.
    pub fn new(mesh: &Mesh, parts: &Parts, marks: &[u32], eye: &EyeMarks) -> Option<Sight> {
        let edges = lid_edges(mesh, parts, marks, eye)?;
        let points: Vec<Vec3> = marks.iter().map(|&v| mesh.positions[v as usize]).collect();
        let view = View::of(&points, eye)?;
        let local = |ps: &[Vec3]| ps.iter().map(|&p| view.local(p)).collect::<Vec<_>>();
        let (upper, lower) = (local(&edges.upper), local(&edges.lower));
        let pairs = [(eye.upper[1], eye.lower[2]), (eye.upper[2], eye.lower[1])];
        let width = (view.local(points[eye.upper[3]]).x - view.local(points[eye.upper[0]]).x).abs();
        let mut away = false;
        let mut columns = Vec::new();
        for (u, l) in pairs {
            let (qu, ql) = (view.local(points[u]), view.local(points[l]));
            let x = (qu.x + ql.x) / 2.0;
            let (eu, el) = (polyline_at(&upper, x)?, polyline_at(&lower, x)?);
            let opening = qu.y - ql.y;
            away |= (eu.y - qu.y).abs() > 0.1 * opening || (el.y - ql.y).abs() > 0.1 * opening;
            let socket = (qu.z + ql.z) / 2.0 - SOCKET_DEPTH * width;
            columns.push((x, el.y, eu.y, socket));
        }
        away.then(|| Sight {
            view,
            triangles: seen_triangles(mesh, parts, marks),
            columns,
            edges,
        })
    }

    /// The free edges found (away from the landmarks, or there would be no sight).
    pub fn edges(&self) -> &LidEdges {
        &self.edges
    }

    /// The largest share of a landmark column's rest opening (between the rest edges) that
    /// still shows something other than the face's skin at `positions`.
    pub fn left_open(&self, positions: &[Vec3]) -> f64 {
        self.columns
            .iter()
            .map(|&(x, low, high, socket)| {
                let column: Vec<([DVec3; 3], Seen)> = self
                    .triangles
                    .iter()
                    .map(|&(t, seen)| (t.map(|v| self.view.local(positions[v as usize])), seen))
                    .filter(|(t, _)| t.iter().any(|q| q.x >= x) && t.iter().any(|q| q.x <= x))
                    .collect();
                let open = (0..ROWS)
                    .filter(|&k| {
                        let y = low + (high - low) * (k as f64 + 0.5) / ROWS as f64;
                        shows_opening(front_at(&column, x, y), socket)
                    })
                    .count();
                open as f64 / ROWS as f64
            })
            .fold(0.0, f64::max)
    }
}
