//! The lines along which a face opens (the inner lip line, each eye's lid line) and which
//! side of them each vertex and each muscle lies on.
//!
//! A closed mouth is one surface across the lips; a jaw weight or a muscle mask that changes
//! sharply at the inner lip line still lets it open, and keeps a muscle of one lip from
//! dragging the other across the mouth. The same holds for the lids.

use glam::{DVec3, Vec3};

use crate::landmarks::{
    FaceFrame, INNER_LOWER, INNER_UPPER, LEFT_EYE_LOWER, LEFT_EYE_UPPER, RIGHT_EYE_LOWER,
    RIGHT_EYE_UPPER,
};

/// Which side of an opening a muscle works on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Above the line (upper lip, upper lid).
    Upper,
    /// Below the line (lower lip, lower lid).
    Lower,
}

/// An opening of the face: the line halfway between its upper and lower margins, in the
/// face's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Opening {
    /// A short name for reports: `mouth`, `right eye`, `left eye`.
    pub name: &'static str,
    frame: FaceFrame,
    origin: DVec3,
    /// The line's points as (across, up) in the frame, sorted by `across`.
    line: Vec<(f64, f64)>,
    /// Half the opening's width (corner to corner).
    half_width: f64,
    /// How far above and below the line the opening's zone reaches.
    reach_up: f64,
    reach_down: f64,
    /// How far behind the line (into the head) the zone reaches.
    depth: f64,
    /// Across the line the two sides blend over this far each way (0: a step).
    soft: f64,
}

/// An eye's two sides blend across its line over this share of its half-width each way. A
/// lid's rows at the canthus (MakeHuman's fold, rows 0.6 mm apart) lie on both sides of the
/// line: with a step, a lower lid muscle (AU7) moved one row 1.1 mm and left the next,
/// turning the rows between over.
const EYE_LINE_BLEND: f64 = 0.15;

impl Opening {
    /// The mouth and both eyes of a landmark set; empty when the set has no frame.
    pub fn all(points: &[Vec3]) -> Vec<Opening> {
        let Some(frame) = FaceFrame::of(points) else {
            return Vec::new();
        };
        let p = |i: usize| points[i].as_dvec3();
        let mouth_height = p(33).distance(p(8));
        let eye_height = frame.eyes_to_mouth;
        vec![
            Opening::new(
                "mouth",
                frame,
                points,
                (&INNER_UPPER, &INNER_LOWER),
                (0.5 * mouth_height, mouth_height),
            ),
            Opening::new(
                "right eye",
                frame,
                points,
                (&RIGHT_EYE_UPPER, &RIGHT_EYE_LOWER),
                (0.5 * eye_height, 0.5 * eye_height),
            )
            .softened(EYE_LINE_BLEND),
            Opening::new(
                "left eye",
                frame,
                points,
                (&LEFT_EYE_UPPER, &LEFT_EYE_LOWER),
                (0.5 * eye_height, 0.5 * eye_height),
            )
            .softened(EYE_LINE_BLEND),
        ]
    }

    fn new(
        name: &'static str,
        frame: FaceFrame,
        points: &[Vec3],
        (upper, lower): (&[usize], &[usize]),
        (reach_up, reach_down): (f64, f64),
    ) -> Opening {
        let mid: Vec<DVec3> = upper
            .iter()
            .zip(lower)
            .map(|(&u, &l)| 0.5 * (points[u].as_dvec3() + points[l].as_dvec3()))
            .collect();
        let origin = mid.iter().copied().sum::<DVec3>() / mid.len() as f64;
        let mut line: Vec<(f64, f64)> = mid
            .iter()
            .map(|&m| {
                let l = frame.local(origin, m);
                (l.x, l.y)
            })
            .collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        let half_width = 0.5 * (line[line.len() - 1].0 - line[0].0).abs();
        Opening {
            name,
            frame,
            origin,
            line,
            half_width,
            reach_up,
            reach_down,
            depth: 2.0 * half_width,
            soft: 0.0,
        }
    }

    /// The opening with its sides blended across its line over `share` of its half-width.
    fn softened(mut self, share: f64) -> Opening {
        self.soft = share * self.half_width;
        self
    }

    /// The line's height (frame `up`) at `across`, held level beyond the corners.
    fn line_height(&self, across: f64) -> f64 {
        let line = &self.line;
        if across <= line[0].0 {
            return line[0].1;
        }
        for w in line.windows(2) {
            if across <= w[1].0 {
                let span = w[1].0 - w[0].0;
                let t = if span > 0.0 {
                    (across - w[0].0) / span
                } else {
                    0.0
                };
                return w[0].1 + t * (w[1].1 - w[0].1);
            }
        }
        line[line.len() - 1].1
    }

    /// 1 between the corners, falling smoothly to 0 at them.
    fn across_weight(&self, across: f64) -> f64 {
        let centre = 0.5 * (self.line[0].0 + self.line[self.line.len() - 1].0);
        let t = (across - centre).abs() / self.half_width.max(1e-300);
        1.0 - smoothstep(0.7, 1.0, t)
    }

    /// How much `p` belongs to the given side of the opening: 0 outside the zone, up to 1
    /// between the corners, on that side of the line.
    pub fn side_weight(&self, p: Vec3, side: Side) -> f64 {
        let local = self.frame.local(self.origin, p.as_dvec3());
        if local.z < -self.depth {
            return 0.0;
        }
        let dy = local.y - self.line_height(local.x);
        let above = if self.soft > 0.0 {
            smoothstep(-self.soft, self.soft, dy)
        } else if dy > 0.0 {
            1.0
        } else {
            0.0
        };
        let share = match side {
            Side::Upper if dy < self.reach_up => above,
            Side::Lower if -dy < self.reach_down => 1.0 - above,
            _ => 0.0,
        };
        share * self.across_weight(local.x)
    }

    /// The side of the opening a muscle acting at `p` works on: `None` when it acts at the
    /// corners, outside the opening's width, or far away.
    pub fn side_of(&self, p: Vec3) -> Option<Side> {
        let local = self.frame.local(self.origin, p.as_dvec3());
        let centre = 0.5 * (self.line[0].0 + self.line[self.line.len() - 1].0);
        if (local.x - centre).abs() >= self.half_width {
            return None;
        }
        let dy = local.y - self.line_height(local.x);
        let margin = 0.2 * self.half_width;
        if dy > margin {
            Some(Side::Upper)
        } else if dy < -margin {
            Some(Side::Lower)
        } else {
            None
        }
    }
}

/// Hermite smoothstep from 0 at `a` to 1 at `b` (the one the face generator uses too).
pub fn smoothstep(a: f64, b: f64, t: f64) -> f64 {
    let s = ((t - a) / (b - a)).clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// A closed landmark contour around an opening: the outer lip line and each eye's lids,
/// by their corners and their landmarks (first to last).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Contour {
    /// The subject's right and left corners.
    pub corners: [usize; 2],
    /// The contour's landmarks, `first..=last`.
    pub first: usize,
    /// See `first`.
    pub last: usize,
    /// Whether the ring around it is an eye's: sized across by the contour's width and up by
    /// the geometric mean of its width and height ratios, turned with the face, and capped
    /// by the template ring's reach (`fit::reach`). The orbicularis oculi spans the orbit,
    /// which scales with the eye's width, not with how far apart the lids happen to be (a
    /// head modelled wide-eyed would otherwise get a ring reaching the nose and the brow);
    /// the lids still have to sit inside it much as on the template for it to close them.
    /// The lips' contour is the oris itself: its ring follows the contour both ways.
    pub round: bool,
}

/// The contours the rings of the face sit in: the outer lip line, the right eye, the left eye.
pub const CONTOURS: [Contour; 3] = [
    Contour {
        corners: [48, 54],
        first: 48,
        last: 59,
        round: false,
    },
    Contour {
        corners: [36, 39],
        first: 36,
        last: 41,
        round: true,
    },
    Contour {
        corners: [42, 45],
        first: 42,
        last: 47,
        round: true,
    },
];

/// How far a contour of landmarks reaches, in its own frame: `across` from the right corner
/// to the left, `out` the face's forward direction made perpendicular to it, `up` completing
/// them (`out x across`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    /// The mean of the contour's landmarks.
    pub centre: DVec3,
    /// Unit vectors: across (corner to corner), up, out of the face.
    pub axes: [DVec3; 3],
    /// Half the corners' distance along `across`.
    pub half_width: f64,
    /// Half the contour's height along `up`.
    pub half_height: f64,
}

impl Extent {
    /// The extent of `contour` among 68 landmark `points`, in a face whose forward direction
    /// is `forward`; `None` when the corners coincide or the contour has no height.
    pub fn of(points: &[Vec3], contour: &Contour, forward: DVec3) -> Option<Extent> {
        let at = |i: usize| points[i].as_dvec3();
        let ids = contour.first..=contour.last;
        let d = at(contour.corners[1]) - at(contour.corners[0]);
        let across = (d - forward * d.dot(forward)).normalize_or_zero();
        let out = (forward - across * forward.dot(across)).normalize_or_zero();
        let up = out.cross(across);
        let heights = ids.clone().map(|i| at(i).dot(up));
        let (lo, hi) = heights.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| {
            (lo.min(h), hi.max(h))
        });
        let half_width = 0.5 * d.dot(across);
        let half_height = 0.5 * (hi - lo);
        let centre = ids.clone().map(at).sum::<DVec3>() / ids.count() as f64;
        (across != DVec3::ZERO && half_width > 0.0 && half_height > 0.0)
            .then_some(Extent {
                centre,
                axes: [across, up, out],
                half_width,
                half_height,
            })
            .filter(|e| e.centre.is_finite() && e.half_height.is_finite())
    }
}
