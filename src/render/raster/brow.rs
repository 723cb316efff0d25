//! Eyebrows drawn per dot: the brow's tone decided at every dot from where the surface point
//! lies in the brow's band, so that the brow's edge is sharp whatever the triangles' size.
//!
//! A head's brow hair is a vertex group (`left_brow_hair`, `right_brow_hair`: the built-in
//! face's own, or marked from the landmarks when a head is loaded, `fit::brow_hair`). A tone
//! per vertex, interpolated across the triangles, draws a dense mesh's brow well, but on a
//! coarse one (MediaPipe's 468-vertex mask, whose brow group is the five vertices along the
//! brow's upper edge) it smears the brow over triangles a centimetre wide, onto the forehead
//! and the upper lids, and the face tracker no longer finds brows and eyes where they are.
//!
//! Here each brow becomes a band fitted to its group at rest, in the face's plane (across the
//! face from the right brow to the left, up as forward cross across, forward the brows' outward
//! normal):
//!
//! * `x`, along the brow from its head (0) to its tail (1): the group's extent across the face;
//! * the band's centre, a quadratic in `x` fitted to the members' height;
//! * its upper and lower edges: the members' highest and lowest offsets from that centre, in
//!   the head's half and the tail's, blended along `x` and moved out until every member lies
//!   inside; a group that is a single row of vertices (covering no triangle of its own:
//!   landmarks run along the brow's upper edge, so a coarse head's group can be one) has its
//!   band lowered at its lower edge to [`HEIGHT_AT_HEAD`] of the brow's length at the head
//!   and [`HEIGHT_AT_TAIL`] at the tail; a denser group is drawn to its own members' extent.
//!
//! A group whose members leave a gap along the brow ([`GAP_SPACINGS`] times their spacing)
//! is a brow in pieces: each run of members gets its own band, so no band bridges the gap,
//! and a triangle near several takes the one covering most of it.
//!
//! Every corner of a triangle near a brow gets its coordinates in that band at rest: `x` and
//! `v`, 0 at the upper edge and 1 at the lower. The rasterizer interpolates them per dot like
//! any attribute, so the band is carried by the skin when muscles move it, and tones the dots
//! inside (`0 <= x, v <= 1`). Every member vertex lies inside its band (tested). A triangle
//! wholly inside a band is toned per vertex (the band is convex in these coordinates, so that
//! is the same at every dot); only the triangles a band's edge crosses are stepped over again
//! after the fill ([`Renderer::tone_brows`]), which leaves the fill's inner loops as they were.

use glam::{Vec2, Vec3};

use super::depth::{corner_weights, triangle_box};
use super::fill::{float_box, inside, plane, plane_at, BROW_TONE};
use super::pieces::{affine, clip_convex, fan, UNIT_SQUARE};
use super::{LitTriangle, Renderer};
use crate::model::Mesh;

/// The brow's height at its head and at its tail, as fractions of its length: on an adult
/// face a brow about 50 mm long is drawn 5 mm tall at its head and 2 mm at its tail (the
/// heights `fit::brow_hair` marks below the landmarks, measured against the brow's length
/// instead of the eye's width, since the renderer knows the brow and not the eye).
const HEIGHT_AT_HEAD: f32 = 0.1;
const HEIGHT_AT_TAIL: f32 = 0.04;
/// How far in front of or behind the brow's fitted surface a corner may lie and still be
/// drawn as brow, as a fraction of the brow's length (the eye's lining and the back of the
/// head are not brow).
const DEPTH_REACH: f32 = 0.25;

/// A triangle near a brow, drawn with the brow's tone where the band covers it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BrowTriangle {
    /// Index into the renderer's triangles.
    pub triangle: u32,
    /// Per corner, the position along the brow (0 head, 1 tail) and across it (0 upper
    /// edge, 1 lower).
    pub along: [f32; 3],
    /// See `along`.
    pub across: [f32; 3],
}

impl BrowTriangle {
    /// Per corner, whether it lies inside the band.
    pub fn corners_in_band(&self) -> [bool; 3] {
        [0, 1, 2].map(|k| in_band(self.along[k], self.across[k]))
    }
}

/// Whether a dot at band coordinates `(along, across)` lies inside the band.
#[inline]
pub(super) fn in_band(along: f32, across: f32) -> bool {
    (0.0..=1.0).contains(&along) && (0.0..=1.0).contains(&across)
}

impl Renderer {
    /// Tones the shaded dots of the triangles a brow band's edge crosses: each such triangle
    /// facing the viewer is stepped over again, and every dot it drew (the depth there is
    /// its own, to the bit: the same plane evaluated the same way) gets its shade again,
    /// times the brow's tone when its interpolated band coordinates lie inside the band.
    /// (A triangle wholly inside a band has its three corners toned per vertex, which is
    /// the same at every dot.) A dot two such triangles both claim, on their shared edge,
    /// is set, not scaled, so it is toned once.
    #[inline(never)]
    pub(super) fn tone_brows(&mut self, w: usize, h: usize, depth: &[f32]) {
        for k in 0..self.brows.len() {
            let b = self.brows[k];
            let tri = self.triangles[b.triangle as usize];
            // The corners' shades before the brow's tone (corners inside the band carry it
            // per vertex).
            let untoned = b
                .corners_in_band()
                .map(|inside| if inside { BROW_TONE } else { 1.0 });
            let shade = [0, 1, 2].map(|k| self.vertex_shade[tri[k] as usize] / untoned[k]);
            self.retone_dots(
                b.triangle as usize,
                shade,
                [b.along, b.across],
                (w, h, depth),
                |shade, [along, across]| {
                    shade
                        * if in_band(along, across) {
                            BROW_TONE
                        } else {
                            1.0
                        }
                },
            );
        }
    }

    /// Steps again over the dots triangle `t` drew (if it faces the viewer): every dot whose
    /// depth is the triangle's own (to the bit: the same plane evaluated the same way) gets
    /// the shade `dot` gives from the corners' `shade` and the corner attributes `attrs`
    /// interpolated there. A dot two such triangles both claim, on their shared edge, is set,
    /// not scaled, so it is toned once.
    pub(super) fn retone_dots<const K: usize>(
        &mut self,
        t: usize,
        shade: [f32; 3],
        attrs: [[f32; 3]; K],
        (w, h, depth): (usize, usize, &[f32]),
        dot: impl Fn(f32, [f32; K]) -> f32,
    ) {
        if !self.facing[t] {
            return;
        }
        let tri = self.triangles[t];
        let p = tri.map(|i| self.projected[i as usize]);
        let [x0, x1, y0, y1] = if w.max(h) < 1 << 24 {
            triangle_box(tri.map(|i| self.dot_spans[i as usize]))
        } else {
            float_box(p, w, h)
        };
        let [a, b, c] = p;
        let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if x0 >= x1 || y0 >= y1 || !area.is_finite() || area.abs() < 1e-9 {
            return;
        }
        let [wa, wb] = corner_weights(p, area);
        let z = plane(wa, wb, [a.z, b.z, c.z]);
        let attrs = attrs.map(|v| plane(wa, wb, v));
        let shade = plane(wa, wb, shade);
        for y in y0..y1 {
            let py = y as f32 + 0.5;
            for x in x0..x1 {
                let px = x as f32 + 0.5;
                let i = y * w + x;
                let drawn = inside(plane_at(wa, px, py), plane_at(wb, px, py))
                    && depth.get(i) == Some(&plane_at(z, px, py));
                if drawn {
                    let at = attrs.map(|a| plane_at(a, px, py));
                    self.dot_shade[i] = dot(plane_at(shade, px, py), at);
                }
            }
        }
    }
}

impl Renderer {
    /// For vector output: the brow triangle `k` (one a band's edge crosses), projected to
    /// the dots `screen`, as flat pieces at its `depth`: the triangle with its corners'
    /// shades before the brow's tone, then the part of it inside the band in the brow's tone.
    pub(super) fn brow_pieces(&self, k: usize, screen: [Vec2; 3], depth: f32) -> Vec<LitTriangle> {
        let b = self.brows[k];
        let tri = self.triangles[b.triangle as usize];
        let untoned = b
            .corners_in_band()
            .map(|inside| if inside { BROW_TONE } else { 1.0 });
        let shade = [0, 1, 2]
            .map(|k| self.vertex_shade[tri[k] as usize] / untoned[k])
            .iter()
            .sum::<f32>()
            / 3.0;
        let mut out = vec![LitTriangle {
            corners: screen,
            depth,
            shade,
        }];
        let place = [0, 1, 2].map(|j| Vec2::new(b.along[j], b.across[j]));
        let Some(to_screen) = affine(place, screen) else {
            return out;
        };
        let band: Vec<Vec2> = clip_convex(&place, &UNIT_SQUARE)
            .into_iter()
            .map(to_screen)
            .collect();
        out.extend(fan(&band).map(|corners| LitTriangle {
            corners,
            depth,
            shade: shade * BROW_TONE,
        }));
        out
    }
}

/// Gives the corners of `brows` that lie inside their band the brow's tone per vertex, of
/// `n` vertices' `tones` (empty: all 1.0 so far), for the triangles wholly inside a band.
pub(super) fn tone_corners(
    brows: &[BrowTriangle],
    triangles: &[[u32; 3]],
    n: usize,
    tones: &mut Vec<f32>,
) {
    if tones.is_empty() && !brows.is_empty() {
        tones.resize(n, 1.0);
    }
    for b in brows {
        let tri = triangles[b.triangle as usize];
        for (k, inside) in b.corners_in_band().into_iter().enumerate() {
            let v = tri[k] as usize;
            if let (true, Some(t)) = (inside, tones.get_mut(v)) {
                *t = BROW_TONE;
            }
        }
    }
}

/// The face's frame at the brows: where the brows' midline is, and the unit vectors across
/// the face (to the subject's left), up and forward (out of the face).
#[derive(Debug, Clone, Copy)]
struct Frame {
    mid: Vec3,
    lateral: Vec3,
    up: Vec3,
    forward: Vec3,
}

impl Frame {
    /// `p` in this frame on `side` (+1 left, -1 right): along the brow from the midline,
    /// up, forward.
    fn local(&self, p: Vec3, side: f32) -> Vec3 {
        let d = p - self.mid;
        Vec3::new(
            side * d.dot(self.lateral),
            d.dot(self.up),
            d.dot(self.forward),
        )
    }
}

/// One brow's band at rest.
#[derive(Debug, Clone, Copy)]
struct Band {
    /// +1 for the subject's left brow, -1 for the right: along the brow is `side` times
    /// across the face.
    side: f32,
    /// The head's and the tail's distance across the face from the midline, signed by side.
    head: f32,
    length: f32,
    /// The centre's height above `mid` as `c0 + c1 x + c2 x^2`.
    centre: [f32; 3],
    /// Offsets of the upper and lower edges from the centre at the head and at the tail.
    upper: [f32; 2],
    lower: [f32; 2],
    /// The brow's surface depth along forward, as a quadratic in `x` like the centre.
    depth: [f32; 3],
    /// How far from that surface a point may lie and still be drawn as brow: a fraction
    /// ([`DEPTH_REACH`]) of the whole brow's length, whichever piece of it this band is.
    reach: f32,
}

impl Band {
    /// Band coordinates `(along, across)` of a point, and its distance from the brow's
    /// surface along forward.
    fn coordinates(&self, frame: &Frame, p: Vec3) -> (f32, f32, f32) {
        let d = p - frame.mid;
        let x = (self.side * d.dot(frame.lateral) - self.head) / self.length;
        let centre = quadratic(self.centre, x);
        let upper = centre + lerp(self.upper, x);
        let lower = centre + lerp(self.lower, x);
        let across = (upper - d.dot(frame.up)) / (upper - lower).max(f32::EPSILON);
        let depth = d.dot(frame.forward) - quadratic(self.depth, x);
        (x, across, depth)
    }
}

/// The brow triangles of `mesh` drawn as `triangles` (right-hand normals outward when `sign`
/// is +1), in triangle order, or nothing when the mesh has no pair of brow groups (left and
/// right, three vertices or more each) a band can be fitted to.
pub(super) fn brow_triangles(
    mesh: &Mesh,
    triangles: &[[u32; 3]],
    sign: f32,
) -> Option<Vec<BrowTriangle>> {
    let members = |side: &str| {
        mesh.groups
            .iter()
            .filter(|(name, _)| {
                let lower = name.to_ascii_lowercase();
                lower.contains("brow_hair") && lower.starts_with(side)
            })
            .flat_map(|(_, m)| m.iter().copied())
            .filter(|&v| (v as usize) < mesh.positions.len())
            .collect::<Vec<u32>>()
    };
    let (left, right) = (members("left"), members("right"));
    let frame = frame(mesh, triangles, sign, &left, &right)?;
    let bands = [
        side_bands(mesh, &frame, triangles, &left, 1.0)?,
        side_bands(mesh, &frame, triangles, &right, -1.0)?,
    ];
    let mut out = Vec::new();
    for (t, tri) in triangles.iter().enumerate() {
        let p = tri.map(|i| mesh.positions.get(i as usize).copied().unwrap_or(Vec3::NAN));
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let side = usize::from((centroid - frame.mid).dot(frame.lateral) < 0.0);
        // The band of this side covering most of the triangle (the pieces of a split brow
        // are apart, so a triangle is rarely near two).
        let best = bands[side]
            .iter()
            .filter_map(|band| corner_coordinates(band, &frame, p))
            .map(|(along, across)| (coverage(along, across), along, across))
            .filter(|c| c.0 > 0.0)
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, along, across)) = best {
            out.push(BrowTriangle {
                triangle: t as u32,
                along,
                across,
            });
        }
    }
    Some(out)
}

/// The band coordinates of a triangle's corners `p` in `band`, or `None` when a corner lies
/// off the band's reach in depth (the eye's lining, the back of the head).
fn corner_coordinates(band: &Band, frame: &Frame, p: [Vec3; 3]) -> Option<([f32; 3], [f32; 3])> {
    let c = p.map(|q| band.coordinates(frame, q));
    c.iter()
        .all(|&(x, v, d)| x.is_finite() && v.is_finite() && d.abs() <= band.reach)
        .then(|| (c.map(|(x, _, _)| x), c.map(|(_, v, _)| v)))
}

/// The bands of one brow group on `side` (+1 left, -1 right): one per run of its members
/// along the brow ([`runs`]), so a brow marked in pieces is drawn as its pieces (a run too
/// short for a band, one vertex or one column, is left undrawn); `None` when the group
/// gives no band at all.
fn side_bands(
    mesh: &Mesh,
    frame: &Frame,
    triangles: &[[u32; 3]],
    members: &[u32],
    side: f32,
) -> Option<Vec<Band>> {
    let (head, tail) = along_span(mesh, frame, members, side)?;
    let span = (head, tail - head);
    let bands: Vec<Band> = runs(mesh, frame, triangles, members, side)
        .iter()
        .filter_map(|run| fit_band(mesh, frame, run, side, one_row(triangles, run), span))
        .collect();
    (!bands.is_empty()).then_some(bands)
}

/// Where a group of brow members starts and ends across the face (its head and its tail,
/// signed by side); `None` when it has no length.
fn along_span(mesh: &Mesh, frame: &Frame, members: &[u32], side: f32) -> Option<(f32, f32)> {
    let xs = members
        .iter()
        .map(|&v| frame.local(mesh.positions[v as usize], side).x);
    let (head, tail) = xs.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    });
    let length = tail - head;
    (length.is_finite() && length > 0.0).then_some((head, tail))
}

/// How many times the members' typical spacing along the brow a gap between two of them
/// must be to cut the group there: within a row of landmarks or a band of hair, neighbours
/// along the brow are about one spacing apart, and a single member missed by the marking
/// leaves a gap of about two (fitted MakeHuman's brows: 1.97); a wider gap is skin the
/// group leaves out, a brow in pieces.
const GAP_SPACINGS: f32 = 3.0;

/// The members split into runs along the brow: sorted by their position along it and cut
/// wherever two neighbours in that order lie farther apart than [`GAP_SPACINGS`] times the
/// members' typical spacing along the brow: the median length along the brow of the mesh's
/// edges that join two members and run more along the brow than across it (an edge between
/// two rows of the same column says nothing of the spacing along the brow). A group with no
/// such edge is one run.
fn runs(
    mesh: &Mesh,
    frame: &Frame,
    triangles: &[[u32; 3]],
    members: &[u32],
    side: f32,
) -> Vec<Vec<u32>> {
    let local = |v: u32| frame.local(mesh.positions[v as usize], side);
    let along = |v: u32| local(v).x;
    let mut is_member = vec![false; mesh.positions.len()];
    for &v in members {
        is_member[v as usize] = true;
    }
    let member = |v: &u32| is_member.get(*v as usize) == Some(&true);
    let mut spans: Vec<f32> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .filter(|(a, b)| member(a) && member(b))
        .map(|(a, b)| (local(a) - local(b)).abs())
        .map(|d| (d.x, d.y))
        .filter(|&(x, y)| x >= y)
        .map(|(x, _)| x)
        .collect();
    spans.sort_by(f32::total_cmp);
    let spacing = spans.get(spans.len() / 2).copied().unwrap_or(f32::INFINITY);
    let mut points: Vec<(f32, u32)> = members.iter().map(|&v| (along(v), v)).collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<Vec<u32>> = Vec::new();
    for (i, &(x, v)) in points.iter().enumerate() {
        if i == 0 || x - points[i - 1].0 > GAP_SPACINGS * spacing {
            out.push(Vec::new());
        }
        if let Some(run) = out.last_mut() {
            run.push(v);
        }
    }
    out
}

/// The face's frame from the two brows' members: across from the right brow's centroid to the
/// left's, forward the outward normal of the triangles they touch, up forward cross across.
fn frame(
    mesh: &Mesh,
    triangles: &[[u32; 3]],
    sign: f32,
    left: &[u32],
    right: &[u32],
) -> Option<Frame> {
    if left.len() < 3 || right.len() < 3 {
        return None;
    }
    let centroid =
        |m: &[u32]| m.iter().map(|&v| mesh.positions[v as usize]).sum::<Vec3>() / m.len() as f32;
    let (l, r) = (centroid(left), centroid(right));
    let mut member = vec![false; mesh.positions.len()];
    for &v in left.iter().chain(right) {
        member[v as usize] = true;
    }
    let mut normal = Vec3::ZERO;
    for tri in triangles {
        if tri.iter().any(|&i| member.get(i as usize) == Some(&true)) {
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            normal += (b - a).cross(c - a);
        }
    }
    let forward = (normal * sign).normalize_or_zero();
    let lateral = (l - r).reject_from_normalized(forward).normalize_or_zero();
    let up = forward.cross(lateral);
    let frame = Frame {
        mid: (l + r) * 0.5,
        lateral,
        up,
        forward,
    };
    (forward != Vec3::ZERO && lateral != Vec3::ZERO && frame.mid.is_finite()).then_some(frame)
}

/// Whether a brow group is a single row of vertices: no drawn triangle has all three corners
/// in it, so the group marks a line (a coarse head's landmarks along the brow's upper edge)
/// rather than the hair's area.
fn one_row(triangles: &[[u32; 3]], members: &[u32]) -> bool {
    let mut sorted = members.to_vec();
    sorted.sort_unstable();
    !triangles
        .iter()
        .any(|tri| tri.iter().all(|v| sorted.binary_search(v).is_ok()))
}

/// The band of one run of a brow's members, `members`, on `side` (+1 left, -1 right); a
/// run that is `one_row` is given a brow's height below its row, that of the place it has
/// along the whole brow (`brow`: the group's head and length, [`along_span`]).
fn fit_band(
    mesh: &Mesh,
    frame: &Frame,
    members: &[u32],
    side: f32,
    one_row: bool,
    brow: (f32, f32),
) -> Option<Band> {
    let points: Vec<(f32, f32, f32)> = members
        .iter()
        .map(|&v| frame.local(mesh.positions[v as usize], side).into())
        .collect();
    let (head, tail) = along_span(mesh, frame, members, side)?;
    let length = tail - head;
    let xs: Vec<f32> = points.iter().map(|p| (p.0 - head) / length).collect();
    let centre = fit_quadratic(&xs, &points.iter().map(|p| p.1).collect::<Vec<_>>())?;
    let depth = fit_quadratic(&xs, &points.iter().map(|p| p.2).collect::<Vec<_>>())?;
    // The members' extreme offsets from the centre in the head's half and in the tail's.
    let mut upper = [f32::NEG_INFINITY; 2];
    let mut lower = [f32::INFINITY; 2];
    for (&x, p) in xs.iter().zip(&points) {
        let r = p.1 - quadratic(centre, x);
        let half = usize::from(x >= 0.5);
        upper[half] = upper[half].max(r);
        lower[half] = lower[half].min(r);
    }
    for k in 0..2 {
        if !upper[k].is_finite() {
            upper[k] = upper[1 - k];
            lower[k] = lower[1 - k];
        }
    }
    // A line from the head's half's extreme to the tail's, moved out until every member lies
    // inside it.
    let fit_edge = |ends: [f32; 2], sign: f32| {
        let gap = xs
            .iter()
            .zip(&points)
            .map(|(&x, p)| sign * (p.1 - quadratic(centre, x) - lerp(ends, x)))
            .fold(0.0f32, f32::max);
        ends.map(|e| e + sign * gap)
    };
    let upper = fit_edge(upper, 1.0);
    let mut lower = fit_edge(lower, -1.0);
    // A row marks the brow's upper edge: the hair reaches a brow's height below it. A group
    // covering triangles of its own is the hair's own extent.
    if one_row {
        let height = |x: f32| {
            let t = ((x - brow.0) / brow.1).clamp(0.0, 1.0);
            (HEIGHT_AT_HEAD + (HEIGHT_AT_TAIL - HEIGHT_AT_HEAD) * t) * brow.1
        };
        lower[0] = lower[0].min(upper[0] - height(head));
        lower[1] = lower[1].min(upper[1] - height(tail));
    }
    Some(Band {
        side,
        head,
        length,
        centre,
        upper,
        lower,
        depth,
        reach: DEPTH_REACH * brow.1,
    })
}

/// `v[0]` at 0 to `v[1]` at 1.
fn lerp(v: [f32; 2], x: f32) -> f32 {
    v[0] + (v[1] - v[0]) * x
}

/// `c0 + c1 x + c2 x^2`.
fn quadratic(c: [f32; 3], x: f32) -> f32 {
    c[0] + x * (c[1] + x * c[2])
}

/// The least-squares quadratic through `(x, y)` (a line through two distinct x, a constant
/// through one).
fn fit_quadratic(x: &[f32], y: &[f32]) -> Option<[f32; 3]> {
    let mut m = [[0.0f64; 3]; 3];
    let mut b = [0.0f64; 3];
    for (&x, &y) in x.iter().zip(y) {
        let p = [1.0, x as f64, (x as f64).powi(2)];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += p[i] * p[j];
            }
            b[i] += p[i] * y as f64;
        }
    }
    for degree in (0..3).rev() {
        if let Some(c) = solve(&m, &b, degree + 1) {
            return Some([c[0] as f32, c[1] as f32, c[2] as f32]);
        }
    }
    None
}

/// The first `n` unknowns of `m c = b` (the others zero), by Cramer's rule; `None` when
/// that system is (nearly) singular.
fn solve(m: &[[f64; 3]; 3], b: &[f64; 3], n: usize) -> Option<[f64; 3]> {
    let det = |a: [[f64; 3]; 3]| -> f64 {
        match n {
            1 => a[0][0],
            2 => a[0][0] * a[1][1] - a[0][1] * a[1][0],
            _ => {
                a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
                    - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
                    + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
            }
        }
    };
    let d = det(*m);
    let scale = m[0][0].powi(n as i32);
    // NaN fails too.
    if d.abs().is_nan() || d.abs() <= 1e-9 * scale {
        return None;
    }
    let mut c = [0.0; 3];
    for (k, ck) in c.iter_mut().enumerate().take(n) {
        let mut a = *m;
        for (row, bi) in a.iter_mut().zip(b) {
            row[k] = *bi;
        }
        *ck = det(a) / d;
    }
    Some(c)
}

/// The share of a triangle inside the band, from its corners' band coordinates: the band
/// test on a grid of barycentric samples.
fn coverage(along: [f32; 3], across: [f32; 3]) -> f32 {
    const STEPS: usize = 12;
    let (mut inside, mut total) = (0usize, 0usize);
    for i in 0..=STEPS {
        for j in 0..=STEPS - i {
            let (a, b) = (i as f32 / STEPS as f32, j as f32 / STEPS as f32);
            let c = 1.0 - a - b;
            let x = a * along[0] + b * along[1] + c * along[2];
            let v = a * across[0] + b * across[1] + c * across[2];
            inside += usize::from(in_band(x, v));
            total += 1;
        }
    }
    inside as f32 / total as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row of vertices along a brow covers no triangle of its own and is given a brow's
    /// height; the built-in face's brow groups cover the hair's area and are not.
    #[test]
    fn a_row_of_landmarks_is_one_row_and_the_builtin_hair_is_not() {
        let row = [0, 1, 2];
        assert!(one_row(&[[0, 1, 3], [1, 2, 4], [1, 4, 3]], &row));
        assert!(!one_row(&[[0, 1, 3], [0, 1, 2]], &row));
        let mesh = crate::io::builtin::default_mesh();
        for g in ["left_brow_hair", "right_brow_hair"] {
            assert!(!one_row(&mesh.triangles, &mesh.groups[g]), "{g}");
        }
    }

    /// On the built-in face, every brow member lies inside its fitted band, the bands are
    /// mirror images, and the skin of the glabella and the upper lids stays outside.
    #[test]
    fn the_builtin_brows_lie_inside_their_bands() {
        let mesh = crate::io::builtin::default_mesh();
        let tris = brow_triangles(&mesh, &mesh.triangles, 1.0).expect("bands");
        let mut drawn = vec![false; mesh.positions.len()];
        for g in ["left_brow_hair", "right_brow_hair"] {
            for &v in &mesh.groups[g] {
                drawn[v as usize] = true;
            }
        }
        // Every member's triangles carry it inside the band at its corner.
        for t in &tris {
            for k in 0..3 {
                let v = mesh.triangles[t.triangle as usize][k];
                if drawn[v as usize] {
                    assert!(
                        in_band(t.along[k], t.across[k]) || {
                            let (x, a) = (t.along[k], t.across[k]);
                            (-1e-4..=1.0001).contains(&x) && (-1e-4..=1.0001).contains(&a)
                        },
                        "member {v} at {} {}",
                        t.along[k],
                        t.across[k]
                    );
                }
            }
        }
        for side in ["left", "right"] {
            for &v in &mesh.groups[&format!("{side}_upper_lid")] {
                for t in tris
                    .iter()
                    .filter(|t| mesh.triangles[t.triangle as usize].contains(&v))
                {
                    let k = mesh.triangles[t.triangle as usize]
                        .iter()
                        .position(|&i| i == v)
                        .unwrap();
                    assert!(
                        !in_band(t.along[k], t.across[k]),
                        "{side} lid vertex {v} in the brow"
                    );
                }
            }
        }
    }
}
