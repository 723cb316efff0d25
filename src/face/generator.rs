//! The default face's mesh: a grid over the head's cylinder, split open along the lid lines
//! and the mouth line.
//!
//! Columns run round the head (angle `theta`, the subject's right at negative x and left at
//! positive x, glTF's convention: right-handed, y up, the face toward +z), rows run up
//! the face. The rows below the mouth bend down to follow the jaw line; the row through the
//! eye corners and the row through the mouth corners are split: between the corners each
//! vertex has an upper copy (used by the triangles above) and a lower copy (used below), so
//! the lids and lips are separate skin that muscles and the jaw can part. The corners
//! themselves are shared, so nothing tears there.
//!
//! Only one half (x >= 0, the subject's left) is computed; the other half is its exact mirror
//! and the midline column has x = 0 exactly.
//!
//! Winding: every triangle is counter-clockwise seen from outside the face, so its
//! right-hand normal points out of the skin (toward the viewer on the front of the face).
//!
//! After the skin come the two eyeballs ([`EYEBALL`]), closed and separate pieces: the
//! subject's left eye, then its mirror; then the inside of the mouth ([`super::mouth`]).
//! Appending them keeps every skin vertex's number.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use glam::Vec3;

use super::anthropometry::*;
use super::surface::{self, THETA_MAX};
use crate::model::Mesh;

/// Columns on each side of the midline column.
const HALF_COLUMNS: usize = 30;
/// Rows strictly between the mouth line and the jaw line (plus the jaw line itself).
const JAW_ROWS: usize = 13;
/// Rows strictly between the mouth line and the eye line.
const MID_ROWS: usize = 20;
/// Rows above the eye line (the last one is the top edge).
const UPPER_ROWS: usize = 21;
/// Half the gap between the lips at the middle of the mouth line (mm): close, not touching.
const LIP_GAP: f64 = 0.3;

/// How a row's height is found.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Row {
    /// Below the mouth: this fraction of the way from the mouth line down to the jaw line.
    Jaw(f64),
    /// The mouth line (split between the mouth corners).
    Mouth,
    /// Between the mouth and eye lines, at this height (mm).
    Level(f64),
    /// The eye line (split between each eye's corners).
    Eye,
    /// Above the eye line: this fraction of the way up to the top edge.
    Upper(f64),
}

/// Which copy of a split vertex is meant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Margin {
    /// The only vertex (not split), or the upper copy of a split one.
    Upper,
    /// The lower copy of a split vertex.
    Lower,
}

/// The grid's layout: column angles, rows, and where the slits are.
struct Layout {
    /// Column angles for columns 0..=2*HALF_COLUMNS (negative x, the subject's right, first).
    thetas: Vec<f64>,
    rows: Vec<Row>,
    mouth_row: usize,
    eye_row: usize,
    /// Column offsets from the midline of the inner and outer eye corners (either eye).
    eye_corners: (usize, usize),
    /// Column offset of the mouth corner.
    mouth_corner: usize,
    /// x (mm) of the inner and outer eye corners and of the mouth corner (at positive x).
    en_x: f64,
    ex_x: f64,
    ch_x: f64,
}

/// Builds the default face mesh, without its vertex groups, and the vertices along its
/// openings that name them ([`super::generate`] adds the groups).
pub fn build() -> (Mesh, Slits) {
    let layout = Layout::new();
    let mut builder = Builder::new(&layout);
    builder.place_vertices();
    builder.build_triangles();
    builder.add_eyeballs();
    super::mouth::append(&mut builder.positions, &mut builder.triangles);
    let mesh = Mesh {
        positions: builder.positions,
        triangles: builder.triangles,
        groups: BTreeMap::new(),
    };
    (mesh, builder.slits)
}

impl Layout {
    fn new() -> Layout {
        let thetas = column_angles();
        let rows = row_layout();
        let mouth_row = rows.iter().position(|r| *r == Row::Mouth).unwrap_or(0);
        let eye_row = rows.iter().position(|r| *r == Row::Eye).unwrap_or(0);
        let eye_width = surface::half_width(EYE_LINE_Y);
        let mouth_width = surface::half_width(STOMION_Y);
        let en = nearest_column(&thetas, eye_width, ENDOCANTHION_X);
        let ex = nearest_column(&thetas, eye_width, EXOCANTHION_X);
        let ch = nearest_column(&thetas, mouth_width, CHEILION_X);
        let column_x = |width: f64, offset: usize| width * thetas[HALF_COLUMNS + offset].sin();
        Layout {
            en_x: column_x(eye_width, en),
            ex_x: column_x(eye_width, ex),
            ch_x: column_x(mouth_width, ch),
            thetas,
            rows,
            mouth_row,
            eye_row,
            eye_corners: (en, ex),
            mouth_corner: ch,
        }
    }

    /// Column offset from the midline (`0..=HALF_COLUMNS`) of column `i`.
    fn offset(&self, i: usize) -> usize {
        i.abs_diff(HALF_COLUMNS)
    }

    /// True when vertex `(i, j)` is split into an upper and a lower copy.
    fn is_split(&self, i: usize, j: usize) -> bool {
        let k = self.offset(i);
        (j == self.eye_row && k > self.eye_corners.0 && k < self.eye_corners.1)
            || (j == self.mouth_row && k < self.mouth_corner)
    }

    /// Which slit (if any) vertex `(i, j)` borders, for the vertex groups.
    fn slit_of(&self, i: usize, j: usize) -> Option<Slit> {
        if !self.is_split(i, j) {
            return None;
        }
        if j == self.mouth_row {
            return Some(Slit::Mouth);
        }
        Some(if i < HALF_COLUMNS {
            Slit::RightEye
        } else {
            Slit::LeftEye
        })
    }
}

/// The three openings of the face.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slit {
    /// The subject's left eye (x > 0).
    LeftEye,
    /// The subject's right eye (x < 0).
    RightEye,
    /// The mouth.
    Mouth,
}

/// The vertices along each slit, for naming groups: `(slit, upper copy, lower copy)`
/// in order of increasing x, and the corners `(slit, corner at lower x, corner at higher x)`.
#[derive(Debug, Default, Clone)]
pub struct Slits {
    /// Upper and lower copies of each split vertex.
    pub pairs: Vec<(Slit, u32, u32)>,
    /// The two corner vertices of each slit (lower x, higher x).
    pub corners: Vec<(Slit, u32, u32)>,
}

/// Column angles: denser on the front of the face, sparser round the sides.
fn column_angles() -> Vec<f64> {
    const ALPHA: f64 = 0.6;
    let n = HALF_COLUMNS as f64;
    (0..=2 * HALF_COLUMNS)
        .map(|i| {
            let s = (i as f64 - n) / n;
            let sa = s.abs();
            let theta = THETA_MAX * (sa + ALPHA * sa * sa * sa) / (1.0 + ALPHA);
            if i < HALF_COLUMNS {
                -theta
            } else {
                theta
            }
        })
        .collect()
}

/// The column offset (from the midline) whose x at this half-width is nearest `x`.
fn nearest_column(thetas: &[f64], half_width: f64, x: f64) -> usize {
    (0..=HALF_COLUMNS)
        .min_by(|&a, &b| {
            let da = (half_width * thetas[HALF_COLUMNS + a].sin() - x).abs();
            let db = (half_width * thetas[HALF_COLUMNS + b].sin() - x).abs();
            da.total_cmp(&db)
        })
        .unwrap_or(0)
}

/// The rows from the jaw line (row 0) to the top edge, denser at the lips, the nose base,
/// the eyes and the brows.
fn row_layout() -> Vec<Row> {
    let mut rows = Vec::new();
    let jaw = distribute(JAW_ROWS, |f| 1.0 + 1.5 * surface::gauss((f - 0.12) / 0.15));
    rows.extend(jaw.iter().rev().map(|&f| Row::Jaw(f)));
    rows.push(Row::Mouth);
    let mid = distribute(MID_ROWS + 1, |t| {
        let y = STOMION_Y + t * (EYE_LINE_Y - STOMION_Y);
        1.0 + 1.2 * surface::gauss((y - STOMION_Y) / 9.0)
            + 1.2 * surface::gauss((y - (SUBNASALE_Y + 5.0)) / 8.0)
            + 1.0 * surface::gauss((y - EYE_LINE_Y) / 10.0)
    });
    rows.extend(
        mid.iter()
            .take(MID_ROWS)
            .map(|&t| Row::Level(STOMION_Y + t * (EYE_LINE_Y - STOMION_Y))),
    );
    rows.push(Row::Eye);
    let upper = distribute(UPPER_ROWS, |t| {
        1.0 + 1.5 * surface::gauss(t / 0.25) + 1.2 * surface::gauss((t - 0.3) / 0.12)
    });
    rows.extend(upper.iter().map(|&t| Row::Upper(t)));
    rows
}

/// `n` fractions in (0, 1], the last exactly 1, spaced inversely to `density` on [0, 1].
fn distribute(n: usize, density: impl Fn(f64) -> f64) -> Vec<f64> {
    const STEPS: usize = 2000;
    let mut cumulative = Vec::with_capacity(STEPS + 1);
    let mut total = 0.0;
    cumulative.push(0.0);
    for k in 0..STEPS {
        let t = (k as f64 + 0.5) / STEPS as f64;
        total += density(t) / STEPS as f64;
        cumulative.push(total);
    }
    (1..=n)
        .map(|m| {
            let target = total * m as f64 / n as f64;
            let k = cumulative.partition_point(|&c| c < target).clamp(1, STEPS);
            let (c0, c1) = (cumulative[k - 1], cumulative[k]);
            let frac = if c1 > c0 {
                (target - c0) / (c1 - c0)
            } else {
                0.0
            };
            if m == n {
                1.0
            } else {
                ((k - 1) as f64 + frac) / STEPS as f64
            }
        })
        .collect()
}

struct Builder<'a> {
    layout: &'a Layout,
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    /// Vertex index per (row, column) for the triangles above the row (upper copy).
    above: Vec<Vec<u32>>,
    /// Vertex index per (row, column) for the triangles below the row (lower copy).
    below: Vec<Vec<u32>>,
    slits: Slits,
}

impl<'a> Builder<'a> {
    fn new(layout: &'a Layout) -> Builder<'a> {
        Builder {
            layout,
            positions: Vec::new(),
            triangles: Vec::new(),
            above: Vec::new(),
            below: Vec::new(),
            slits: Slits::default(),
        }
    }

    fn place_vertices(&mut self) {
        let columns = self.layout.thetas.len();
        for j in 0..self.layout.rows.len() {
            let mut above = Vec::with_capacity(columns);
            let mut below = Vec::with_capacity(columns);
            for i in 0..columns {
                let upper = self.push(i, j, Margin::Upper);
                let lower = if self.layout.is_split(i, j) {
                    let lower = self.push(i, j, Margin::Lower);
                    if let Some(slit) = self.layout.slit_of(i, j) {
                        self.slits.pairs.push((slit, upper, lower));
                    }
                    lower
                } else {
                    upper
                };
                above.push(upper);
                below.push(lower);
            }
            self.above.push(above);
            self.below.push(below);
        }
        self.record_corners();
    }

    fn record_corners(&mut self) {
        let l = self.layout;
        let (en, ex) = l.eye_corners;
        let row = &self.above[l.eye_row];
        let eye = |k: usize, negative_x: bool| {
            if negative_x {
                row[HALF_COLUMNS - k]
            } else {
                row[HALF_COLUMNS + k]
            }
        };
        self.slits
            .corners
            .push((Slit::RightEye, eye(ex, true), eye(en, true)));
        self.slits
            .corners
            .push((Slit::LeftEye, eye(en, false), eye(ex, false)));
        let mouth = &self.above[l.mouth_row];
        self.slits.corners.push((
            Slit::Mouth,
            mouth[HALF_COLUMNS - l.mouth_corner],
            mouth[HALF_COLUMNS + l.mouth_corner],
        ));
    }

    fn push(&mut self, i: usize, j: usize, margin: Margin) -> u32 {
        let k = self.layout.offset(i);
        let p = point(self.layout, HALF_COLUMNS + k, j, margin);
        let x = if i < HALF_COLUMNS { -p[0] } else { p[0] };
        let index = self.positions.len() as u32;
        self.positions.push(Vec3::new(
            units(x) as f32,
            y_units(p[1]) as f32,
            units(p[2]) as f32,
        ));
        index
    }

    /// Appends both eyeballs after the skin: the subject's left, then its exact mirror (x
    /// negated, triangles turned round so they still face out).
    fn add_eyeballs(&mut self) {
        let points = EYEBALL.points();
        for sign in [1.0, -1.0] {
            let first = self.positions.len() as u32;
            for ([x, y, z], _) in &points {
                self.positions.push(Vec3::new(
                    (sign * units(*x)) as f32,
                    y_units(*y) as f32,
                    units(*z) as f32,
                ));
            }
            for [a, b, c] in EYEBALL.triangles(first) {
                self.triangles
                    .push(if sign > 0.0 { [a, b, c] } else { [a, c, b] });
            }
        }
    }

    fn build_triangles(&mut self) {
        let columns = self.layout.thetas.len();
        for j in 0..self.layout.rows.len() - 1 {
            for i in 0..columns - 1 {
                let a = self.above[j][i];
                let b = self.above[j][i + 1];
                let c = self.below[j + 1][i + 1];
                let d = self.below[j + 1][i];
                // diagonals mirror across the midline so the triangulation is symmetric too
                if i < HALF_COLUMNS {
                    self.triangles.push([a, b, c]);
                    self.triangles.push([a, c, d]);
                } else {
                    self.triangles.push([a, b, d]);
                    self.triangles.push([b, c, d]);
                }
            }
        }
    }
}

/// The eyeballs (millimetres, like the skin; the subject's left eye, the right one is its
/// mirror). Each is a closed surface of revolution about an axis straight out of the face:
/// the sclera a sphere, the iris a disc a little sunk behind the limbus, the pupil a shallow
/// cup in the iris. The steps at the limbus and at the pupil's rim are creases, so the line
/// styles draw the iris and the pupil as circles; [`Tissue`] names the parts for shading.
///
/// Sizes are adult means: the globe about 24 mm across, the visible iris (the cornea's
/// diameter) 11.5 mm, a pupil of 4 mm in room light. The centre lies 31 mm from the midline
/// (an interpupillary distance of 62 mm) and 2.5 mm above the corner line, so the upper lid
/// covers the top 1.5 mm of the iris and the lower lid its bottom 1 mm. It sits as far
/// forward as the lids allow: the outer half of the lower lid margin, where the skin turns
/// back toward the temple, lies about 1 mm in front of it (0.4 mm when AU5 draws the upper
/// lid back), so no lid, open, closing or raised, lets the globe through.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eyeball {
    /// Centre of the subject's left eyeball: x from the midline, y above the nasion, z (mm).
    pub centre: [f64; 3],
    /// Radius of the sclera's sphere.
    pub radius: f64,
    /// Radius of the iris (where the sclera meets it, the limbus).
    pub iris_radius: f64,
    /// Radius of the pupil.
    pub pupil_radius: f64,
    /// How far the iris lies behind the limbus.
    pub iris_recess: f64,
    /// How far the pupil's floor lies behind the iris.
    pub pupil_depth: f64,
    /// Vertices round each ring.
    pub segments: usize,
}

/// The default face's eyeballs.
pub const EYEBALL: Eyeball = Eyeball {
    centre: [31.0, EYE_LINE_Y + 2.5, -32.0],
    radius: 12.0,
    iris_radius: 5.75,
    pupil_radius: 2.0,
    iris_recess: 0.6,
    pupil_depth: 1.0,
    segments: 24,
};

/// What part of the eye a ring of an eyeball's profile belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tissue {
    /// The white of the eye, up to and including the limbus.
    Sclera,
    /// The iris, from the foot of the limbus to the pupil's rim.
    Iris,
    /// The pupil's floor.
    Pupil,
}

impl Eyeball {
    /// The rings of the profile from the back pole to the front centre, as `(distance from the
    /// axis, height along the axis from the centre, tissue)` in millimetres. The first and
    /// last have distance 0 (the poles, one vertex each).
    pub fn profile(&self) -> Vec<(f64, f64, Tissue)> {
        let r = self.radius;
        let limbus = (self.iris_radius / r).asin();
        let mut rings = vec![(0.0, -r, Tissue::Sclera)];
        // the back is never seen (it lies inside the head): few rings there
        for degrees in [135.0f64, 100.0, 80.0, 64.0, 50.0, 39.0] {
            let a = degrees.to_radians();
            rings.push((r * a.sin(), r * a.cos(), Tissue::Sclera));
        }
        let front = r * limbus.cos();
        rings.push((self.iris_radius, front, Tissue::Sclera));
        let iris = front - self.iris_recess;
        rings.push((self.iris_radius - 0.3, iris, Tissue::Iris));
        rings.push((
            0.5 * (self.iris_radius + self.pupil_radius),
            iris + 0.05,
            Tissue::Iris,
        ));
        rings.push((self.pupil_radius, iris + 0.1, Tissue::Iris));
        let floor = iris + 0.1 - self.pupil_depth;
        rings.push((self.pupil_radius - 0.25, floor, Tissue::Pupil));
        rings.push((0.0, floor, Tissue::Pupil));
        rings
    }

    /// Vertices of one eyeball.
    pub fn vertex_count(&self) -> usize {
        let rings = self.profile().len();
        2 + (rings - 2) * self.segments
    }

    /// The left eyeball's vertices (mm) in order: the back pole, each ring round from +x
    /// counter-clockwise seen from the front, the front centre; with the tissue of each.
    pub fn points(&self) -> Vec<([f64; 3], Tissue)> {
        let [cx, cy, cz] = self.centre;
        let mut out = Vec::with_capacity(self.vertex_count());
        for (rho, z, tissue) in self.profile() {
            if rho == 0.0 {
                out.push(([cx, cy, cz + z], tissue));
                continue;
            }
            for k in 0..self.segments {
                let a = 2.0 * PI * k as f64 / self.segments as f64;
                out.push(([cx + rho * a.cos(), cy + rho * a.sin(), cz + z], tissue));
            }
        }
        out
    }

    /// The triangles of one eyeball on vertices numbered from `first` as [`Eyeball::points`]
    /// lists them, counter-clockwise seen from outside.
    pub fn triangles(&self, first: u32) -> Vec<[u32; 3]> {
        let n = self.segments as u32;
        let rings = self.profile().len() as u32 - 2;
        let back = first;
        let ring = |r: u32, k: u32| first + 1 + r * n + k % n;
        let front = first + 1 + rings * n;
        let mut out = Vec::with_capacity(2 * (rings as usize) * self.segments);
        for k in 0..n {
            out.push([back, ring(0, k + 1), ring(0, k)]);
        }
        for r in 0..rings - 1 {
            for k in 0..n {
                let (a, b) = (ring(r, k), ring(r, k + 1));
                let (c, d) = (ring(r + 1, k + 1), ring(r + 1, k));
                out.push([a, b, c]);
                out.push([a, c, d]);
            }
        }
        for k in 0..n {
            out.push([front, ring(rings - 1, k), ring(rings - 1, k + 1)]);
        }
        out
    }
}

/// The position (mm, x >= 0) of the vertex at column `i` (right half) and row `j`.
fn point(layout: &Layout, i: usize, j: usize, margin: Margin) -> [f64; 3] {
    let theta = layout.thetas[i];
    let y0 = row_height(layout.rows[j], theta);
    let x = surface::half_width(y0) * theta.sin();
    let y = y0 + slit_shift(layout, x, y0, j, margin);
    let fade = 1.0 - surface::smoothstep(0.28 * PI, 0.45 * PI, theta.abs());
    let z = surface::midline_z(y)
        + surface::depth_radius(y) * (theta.cos() - 1.0)
        + surface::relief(x, y) * fade;
    [x, y, z]
}

/// The height (mm) of a row before the lids and lips are opened.
fn row_height(row: Row, theta: f64) -> f64 {
    match row {
        Row::Jaw(f) => STOMION_Y + f * (surface::bottom_y(theta) - STOMION_Y),
        Row::Mouth => STOMION_Y,
        Row::Level(y) => y,
        Row::Eye => EYE_LINE_Y,
        Row::Upper(t) => EYE_LINE_Y + t * (surface::top_y(theta) - EYE_LINE_Y),
    }
}

/// How far a vertex moves up to open the eye into an almond and part the lips: the lid
/// margins move apart by the lid opening, the rows around follow with a smooth falloff so
/// no row crosses another, and the outer eye corner rises by the canthal tilt.
fn slit_shift(layout: &Layout, x: f64, y: f64, j: usize, margin: Margin) -> f64 {
    if j == layout.mouth_row {
        let t = (x / layout.ch_x).min(1.0);
        let gap = LIP_GAP * (1.0 - t * t).max(0.0).sqrt();
        return match margin {
            Margin::Upper => gap,
            Margin::Lower => -gap,
        };
    }
    let s = (x - layout.en_x) / (layout.ex_x - layout.en_x);
    let upper = UPPER_LID_OPENING * almond(s, 0.42);
    let lower = LOWER_LID_OPENING * almond(s, 0.6);
    let tilt = CANTHAL_TILT
        * surface::smoothstep(0.0, 1.0, s)
        * (1.0 - surface::smoothstep(layout.ex_x, layout.ex_x + 20.0, x));
    let d = y - EYE_LINE_Y;
    if j == layout.eye_row {
        let lid = match margin {
            Margin::Upper => upper,
            Margin::Lower => -lower,
        };
        // corners (not split) have s = 0 or 1 where both lid openings vanish
        return lid + tilt;
    }
    let lid = if d > 0.0 {
        upper * bump(d / 16.0)
    } else {
        -lower * bump(-d / 12.0)
    };
    lid + tilt * bump(d.abs() / 22.0)
}

/// The lid margin's shape across the eye: 0 at the corners, 1 at `peak` (a fraction of the
/// way from the inner to the outer corner), blunt like an almond.
fn almond(s: f64, peak: f64) -> f64 {
    if s <= 0.0 || s >= 1.0 {
        return 0.0;
    }
    let p = 0.5f64.ln() / peak.ln();
    (PI * s.powf(p)).sin().powf(0.8)
}

/// A raised-cosine falloff: 1 at 0, 0 from 1 on.
fn bump(t: f64) -> f64 {
    if t >= 1.0 {
        0.0
    } else {
        0.5 * (1.0 + (PI * t).cos())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distribute_ends_at_one_and_increases() {
        let f = distribute(10, |t| 1.0 + t);
        assert_eq!(f.len(), 10);
        assert_eq!(f[9], 1.0);
        assert!(f.windows(2).all(|w| w[0] < w[1]));
        assert!(f[0] > 0.0);
    }

    #[test]
    fn almond_vanishes_at_the_corners_and_peaks_where_asked() {
        assert_eq!(almond(0.0, 0.42), 0.0);
        assert_eq!(almond(1.0, 0.42), 0.0);
        assert!((almond(0.42, 0.42) - 1.0).abs() < 1e-9);
    }
}
