//! The closing lids' travel in the default rig (`face::rigs`, `docs/face.md`): how far each
//! point of a closing eye moves at 2.0, and the mask weights and gain that make the closing
//! ring move it so.

use glam::Vec3;

use crate::model::Sphincter;

/// A lid margin from corner to corner: `(x, y)` points sorted by x (the left eye's side).
#[derive(Debug, Clone)]
pub(super) struct Margin(Vec<(f32, f32)>);

impl Margin {
    pub(super) fn new(points: impl Iterator<Item = Vec3>) -> Margin {
        let mut m: Vec<(f32, f32)> = points.map(|p| (p.x, p.y)).collect();
        m.sort_by(|a, b| a.0.total_cmp(&b.0));
        Margin(m)
    }

    /// The margin's height in the column at `x`; `None` beyond the corners.
    fn at(&self, x: f32) -> Option<f32> {
        self.0
            .windows(2)
            .find(|w| w[0].0 <= x && x <= w[1].0)
            .map(|w| {
                let s = (x - w[0].0) / (w[1].0 - w[0].0).max(f32::EPSILON);
                w[0].1 + s * (w[1].1 - w[0].1)
            })
    }
}

/// How far each point of a closing eye travels at 2.0, column by column: the lids meet on
/// the ring's axis (toward which the ring pulls), or where the lower margin lies above it
/// (by the outer corner, with the eye's canthal tilt) on the lower margin, which stays; each
/// margin stops 3 % short of there, and beyond each margin
/// the travel falls linearly to 0 at `lid` from the axis (the skin of the lid unfolds evenly).
/// The corners, where the lids already meet, stay.
#[derive(Debug, Clone)]
pub(super) struct LidProfile {
    pub(super) upper: Margin,
    pub(super) lower: Margin,
    pub(super) axis: f32,
    /// How far beyond the axis the pull reaches: above it, below it.
    pub(super) lid: [f32; 2],
}

impl LidProfile {
    /// The travel at 2.0 toward the axis of the skin point `(x, y)`.
    fn travel(&self, x: f32, y: f32) -> f32 {
        let (Some(up), Some(low)) = (self.upper.at(x), self.lower.at(x)) else {
            return 0.0;
        };
        let ramp = |margin_travel: f32, from_margin: f32, margin_to_rim: f32| {
            if margin_travel <= 0.0 || from_margin >= margin_to_rim {
                0.0
            } else {
                margin_travel * (1.0 - from_margin.max(0.0) / margin_to_rim)
            }
        };
        if y >= up && up > self.axis {
            let to = low.max(self.axis);
            let rim = self.axis + self.lid[0];
            ramp(0.97 * (up - to), y - up, rim - up)
        } else if y <= low && low < self.axis {
            let rim = self.axis - self.lid[1];
            ramp(0.97 * (self.axis - low), low - y, low - rim)
        } else {
            0.0
        }
    }

    /// The mask weight at `p` (on the left eye's side, in the ring's frame) that makes the
    /// ring, with `gain`,
    /// move `p` by the profile's travel at 2.0, at most 1 (where the ring's own pull is the
    /// smaller); `None` outside the ring.
    pub(super) fn weight(&self, ring: &Sphincter, gain: f32, p: Vec3) -> Option<f32> {
        let px = (p.x - ring.centre.x) / ring.semi_major;
        let t = (p.y - ring.centre.y).abs() / ring.semi_minor;
        let f = 1.0 - (px * px + t * t).sqrt();
        if f <= 0.0 {
            return None;
        }
        let own = 2.0 * gain * f * t;
        let want = self.travel(p.x, p.y);
        Some(if own > want { want / own } else { 1.0 })
    }
}

/// The gain the closing ring needs so that at 2.0 every upper margin vertex can travel as
/// far as `profile` asks: the ring's own pull there is `2 g f t` units. At least 1. `None`
/// when no margin vertex lies inside the ring.
pub(super) fn closing_gain(ring: &Sphincter, margin: &[Vec3], profile: &LidProfile) -> Option<f32> {
    margin
        .iter()
        .filter_map(|p| {
            let px = (p.x - ring.centre.x) / ring.semi_major;
            let t = (p.y - ring.centre.y).abs() / ring.semi_minor;
            let f = 1.0 - (px * px + t * t).sqrt();
            (f > 0.0 && t > 0.0).then(|| profile.travel(p.x, p.y) / (2.0 * f * t))
        })
        .reduce(f32::max)
        .map(|g| g.max(1.0))
}
