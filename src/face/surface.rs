//! The shape of the default face: outline, head cross-section and the relief of its features.
//!
//! Every function here works in millimetres on one half (x >= 0, the subject's left) and is
//! mirrored by the generator, so the face is exactly symmetric. The skin is an elliptic
//! cylinder (angle `theta` around the vertical axis, height `y`) whose depth is shaped by
//! smooth, local anatomical features added along z.

use std::f64::consts::PI;

use super::anthropometry::*;
/// Hermite smoothstep (the one fitting uses too).
pub use crate::fit::regions::smoothstep;

/// Angle (radians) of the outermost column: the mesh reaches round to the side of the head,
/// where the ears begin.
pub const THETA_MAX: f64 = 0.5 * PI;

/// Height of the mesh's lower edge (the jaw line, mm) for a column at angle `theta`: the
/// gnathion on the midline, rising past the gonion to the ear lobe at the side.
pub fn bottom_y(theta: f64) -> f64 {
    let side_y = -75.0;
    let t = (1.0 - theta.abs().cos()).max(0.0).powf(0.85);
    GNATHION_Y + (side_y - GNATHION_Y) * t
}

/// Height of the mesh's upper edge (mm): above the hairline on the midline, lower over the
/// temples.
pub fn top_y(theta: f64) -> f64 {
    TOP_Y - 14.0 * theta.sin().powi(2)
}

/// Half-width (mm) of the head's cross-section at height `y`: narrow at the chin, widest at
/// the cheekbones (zygion), narrowing again over the temples and forehead.
pub fn half_width(y: f64) -> f64 {
    const KNOTS: [(f64, f64); 11] = [
        (-125.0, 32.0),
        (-120.0, 40.0),
        (-105.0, 48.0),
        (GONION_Y, GONION_X + 4.0),
        (-70.0, 59.0),
        (-40.0, 65.0),
        (-20.0, ZYGION_X),
        (0.0, 65.0),
        (20.0, 62.0),
        (45.0, FRONTOTEMPORALE_X + 3.0),
        (70.0, FRONTOTEMPORALE_X + 1.0),
    ];
    catmull_rom(&KNOTS, y)
}

/// Depth (mm) from the front of the face back to the side of the head at height `y`.
pub fn depth_radius(y: f64) -> f64 {
    const KNOTS: [(f64, f64); 4] = [
        (-125.0, HEAD_DEPTH - 12.0),
        (-90.0, HEAD_DEPTH - 5.0),
        (-60.0, HEAD_DEPTH),
        (70.0, HEAD_DEPTH + 5.0),
    ];
    catmull_rom(&KNOTS, y)
}

/// The midline profile (z in mm) of the face without nose, lips and chin: a forehead that
/// slopes back above the brows, a flat mid-face and a lower face that recedes slightly.
pub fn midline_z(y: f64) -> f64 {
    const KNOTS: [(f64, f64); 10] = [
        (-128.0, -22.0),
        (-120.0, -13.0),
        (-105.0, -6.0),
        (-85.0, -5.0),
        (-60.0, -3.0),
        (-20.0, -3.0),
        (5.0, -1.0),
        (20.0, 0.0),
        (45.0, -5.0),
        (70.0, -17.0),
    ];
    catmull_rom(&KNOTS, y)
}

/// The relief of the facial features (mm along z) at `(x, y)`, x >= 0.
pub fn relief(x: f64, y: f64) -> f64 {
    let x = x.abs();
    brow(x, y)
        + eyebrow(x, y)
        + orbit(x, y)
        + nose(x, y)
        + cheek(x, y)
        + nasolabial_fold(x, y)
        + lips(x, y)
        + chin(x, y)
        + forehead(x, y)
}

/// Brow ridge and glabella: a horizontal roll above the eyes.
fn brow(x: f64, y: f64) -> f64 {
    let arch_y = BROW_Y - 3.0 + 3.0 * gauss((x - 30.0) / 16.0);
    let band = gauss((y - arch_y) / 6.5);
    let arch = window(x, 8.0, 46.0, 12.0);
    let glabella = 2.5 * gauss2(x / 10.0, (y - 6.0) / 8.0);
    5.0 * band * arch + glabella
}

/// The eyebrow: a low pad of brow hair along the brow ridge, thick at its head beside the
/// nose and tapering to its tail, arching highest over the outer third of the eye. It gives
/// the brows an outline, so their movement shows.
fn eyebrow(x: f64, y: f64) -> f64 {
    let (head, tail) = (ENDOCANTHION_X - 3.0, EXOCANTHION_X + 6.0);
    let along = ((x - head) / (tail - head)).clamp(0.0, 1.0);
    let centre = eyebrow_y(x);
    let half_height = 3.2 - 1.6 * along;
    let across = ((y - centre) / half_height).abs();
    let profile = (1.0 - across * across).max(0.0).powf(0.7);
    2.0 * profile * window(x, head, tail, 3.0)
}

/// Height (mm above the nasion) of the middle of the eyebrow at `x`.
pub fn eyebrow_y(x: f64) -> f64 {
    BROW_Y + 1.0 + 3.5 * gauss((x - 33.0) / 13.0)
}

/// The orbit: a socket under the brow with the lids rounded over the eyeball.
fn orbit(x: f64, y: f64) -> f64 {
    let cx = 0.5 * (ENDOCANTHION_X + EXOCANTHION_X);
    let cy = EYE_LINE_Y + 1.0;
    let socket = -12.0 * gauss2((x - cx) / 17.0, (y - cy) / 12.0);
    let r2 = ((x - cx) / 16.5).powi(2) + ((y - cy) / 11.0).powi(2);
    let eyeball = 7.0 * (1.0 - r2).max(0.0).powf(0.8);
    socket + eyeball
}

/// The nose: a ridge from the nasion to the tip, alae on both sides of the tip and
/// nostrils under it.
fn nose(x: f64, y: f64) -> f64 {
    const HEIGHT: [(f64, f64); 9] = [
        (-54.0, 0.0),
        (SUBNASALE_Y, 4.0),
        (-47.0, 20.0),
        (PRONASALE_Y, 26.0),
        (-38.0, 21.5),
        (-28.0, 13.5),
        (-12.0, 8.0),
        (0.0, 3.5),
        (6.0, 0.0),
    ];
    const HALF_WIDTH: [(f64, f64); 6] = [
        (-54.0, 14.0),
        (-48.0, 14.0),
        (PRONASALE_Y, 12.0),
        (-30.0, 10.0),
        (-10.0, 8.5),
        (6.0, 8.5),
    ];
    let ridge = if (-54.0..=6.0).contains(&y) {
        let h = catmull_rom(&HEIGHT, y).max(0.0);
        let t = x / catmull_rom(&HALF_WIDTH, y);
        h * (1.0 - t * t).max(0.0).powi(2) * (1.0 - 0.35 * t * t)
    } else {
        0.0
    };
    let alae = 10.0 * gauss2((x - (ALARE_X - 4.0)) / 5.5, (y - (SUBNASALE_Y + 5.0)) / 5.0);
    let nostril = -3.0 * gauss2((x - 5.5) / 3.0, (y - (SUBNASALE_Y + 2.5)) / 2.0);
    ridge + alae + nostril
}

/// Cheekbone prominence and the temple hollow above it.
fn cheek(x: f64, y: f64) -> f64 {
    let zygoma = 5.0 * gauss2((x - 46.0) / 17.0, (y + 30.0) / 13.0);
    let temple = -4.0 * gauss2((x - 56.0) / 11.0, (y - 15.0) / 16.0);
    zygoma + temple
}

/// The nasolabial fold: the cheek stands proud of the upper lip along a line from the ala
/// to beyond the mouth corner, with a shallow crease on the line.
fn nasolabial_fold(x: f64, y: f64) -> f64 {
    let (ax, ay) = (ALARE_X + 1.0, SUBNASALE_Y + 3.0);
    let (bx, by) = (CHEILION_X + 8.0, STOMION_Y - 12.0);
    let (dx, dy) = (bx - ax, by - ay);
    let len = (dx * dx + dy * dy).sqrt();
    let along = ((x - ax) * dx + (y - ay) * dy) / (len * len);
    // signed distance, positive on the cheek side (away from the mouth)
    let across = ((y - ay) * dx - (x - ax) * dy) / len;
    let fade = window(along, 0.0, 1.0, 0.25);
    let step = 2.5 * smoothstep(-4.0, 6.0, across);
    let crease = -1.2 * gauss(across / 1.8);
    (step + crease) * fade
}

/// Upper vermilion border height above the mouth line at `x` (a Cupid's bow, falling to 0
/// at the corners).
pub fn upper_vermilion_height(x: f64) -> f64 {
    let t = (x / CHEILION_X).min(1.0);
    let bow = 1.0 + 0.18 * gauss((x - 5.0) / 3.0) - 0.08 * gauss(x / 2.0);
    (LABIALE_SUPERIUS_Y - STOMION_Y) * (1.0 - t * t).max(0.0).powf(0.9) * bow
}

/// Lower vermilion border depth below the mouth line at `x`.
pub fn lower_vermilion_height(x: f64) -> f64 {
    let t = (x / CHEILION_X).min(1.0);
    (STOMION_Y - LABIALE_INFERIUS_Y) * (1.0 - t * t).max(0.0).powf(0.9)
}

/// The lips: the mouth region stands forward on the teeth, the vermilion of each lip rolls
/// forward from the mouth line.
fn lips(x: f64, y: f64) -> f64 {
    let mound_x = window(x, 0.0, CHEILION_X + 6.0, 10.0);
    let mound_y = window(y, SUBLABIALE_Y + 2.0, SUBNASALE_Y - 2.0, 10.0);
    let mound = 3.0 * mound_x * mound_y;
    let upper_h = upper_vermilion_height(x);
    let lower_h = lower_vermilion_height(x);
    let vermilion = if y >= STOMION_Y {
        let v = (y - STOMION_Y) / (upper_h + 0.8);
        lip_roll(v) * 3.0 * smoothstep(0.0, 4.0, upper_h)
    } else {
        let v = (STOMION_Y - y) / (lower_h + 0.8);
        lip_roll(v) * 3.5 * smoothstep(0.0, 4.0, lower_h)
    };
    let philtrum =
        -0.8 * gauss(x / 3.0) * window(y, LABIALE_SUPERIUS_Y + 1.0, SUBNASALE_Y - 1.0, 2.0);
    mound + vermilion + philtrum
}

/// Profile across one lip's vermilion: 0 on the mouth line, full near the border, falling
/// to 0 just beyond it (v = 1 is the border).
fn lip_roll(v: f64) -> f64 {
    if v <= 0.0 || v >= 1.6 {
        return 0.0;
    }
    let rise = (v / 0.7).min(1.0);
    let rise = (rise * PI * 0.5).sin().powf(0.7);
    let fall = 1.0 - smoothstep(1.0, 1.6, v);
    rise * fall
}

/// The mentolabial sulcus and the chin (pogonion).
fn chin(x: f64, y: f64) -> f64 {
    let sulcus = -2.5 * gauss2(x / 22.0, (y - SUBLABIALE_Y) / 5.0);
    let pogonion = 5.0 * gauss2(x / 17.0, (y - POGONION_Y) / 9.0);
    sulcus + pogonion
}

/// Frontal eminences: two faint bosses on the forehead.
fn forehead(x: f64, y: f64) -> f64 {
    2.0 * gauss2((x - 24.0) / 16.0, (y - 40.0) / 14.0)
}

/// A Gaussian bump of unit height, `exp(-t^2)`.
pub fn gauss(t: f64) -> f64 {
    (-t * t).exp()
}

/// A two-dimensional Gaussian bump of unit height.
pub fn gauss2(a: f64, b: f64) -> f64 {
    (-(a * a + b * b)).exp()
}

/// 1 inside `[lo, hi]`, falling smoothly to 0 over `soft` outside it.
pub fn window(t: f64, lo: f64, hi: f64, soft: f64) -> f64 {
    smoothstep(lo - soft, lo, t) * (1.0 - smoothstep(hi, hi + soft, t))
}

/// Catmull-Rom interpolation through knots sorted by their first coordinate, held constant
/// beyond the ends.
pub fn catmull_rom(knots: &[(f64, f64)], t: f64) -> f64 {
    let n = knots.len();
    if t <= knots[0].0 {
        return knots[0].1;
    }
    if t >= knots[n - 1].0 {
        return knots[n - 1].1;
    }
    let k = knots.windows(2).position(|w| t < w[1].0).unwrap_or(n - 2);
    let (t0, p0) = knots[k];
    let (t1, p1) = knots[k + 1];
    let slope = |i: usize| -> f64 {
        let (a, b) = (knots[i.saturating_sub(1)], knots[(i + 1).min(n - 1)]);
        (b.1 - a.1) / (b.0 - a.0)
    };
    let h = t1 - t0;
    let (m0, m1) = (slope(k) * h, slope(k + 1) * h);
    let s = (t - t0) / h;
    let (s2, s3) = (s * s, s * s * s);
    (2.0 * s3 - 3.0 * s2 + 1.0) * p0
        + (s3 - 2.0 * s2 + s) * m0
        + (-2.0 * s3 + 3.0 * s2) * p1
        + (s3 - s2) * m1
}
