//! Nearest-point queries over a fixed point set, on a uniform grid.

use std::collections::HashMap;

use glam::Vec3;

/// A point set bucketed on a uniform grid for nearest-point queries.
#[derive(Debug, Clone)]
pub struct Nearest {
    points: Vec<Vec3>,
    /// The original index of each point.
    ids: Vec<u32>,
    cell: f32,
    cells: HashMap<[i32; 3], Vec<u32>>,
    /// The smallest and largest cell keys holding points.
    lo: [i32; 3],
    hi: [i32; 3],
}

impl Nearest {
    /// Buckets `points` (with their ids) on a grid of about two points per cell.
    pub fn new(points: Vec<Vec3>, ids: Vec<u32>) -> Nearest {
        let (lo, hi) = crate::model::mesh::bounds_of(&points);
        let extent = (hi - lo).max_element().max(f32::MIN_POSITIVE);
        let per_axis = ((points.len() as f32 / 2.0).cbrt()).max(1.0);
        let cell = extent / per_axis;
        let mut cells: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
        let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
        for (i, p) in points.iter().enumerate() {
            let k = key(*p, cell);
            for a in 0..3 {
                lo[a] = lo[a].min(k[a]);
                hi[a] = hi[a].max(k[a]);
            }
            cells.entry(k).or_default().push(i as u32);
        }
        Nearest {
            points,
            ids,
            cell,
            cells,
            lo,
            hi,
        }
    }

    /// The id of the point nearest `p` and its distance; `None` for an empty set.
    pub fn nearest(&self, p: Vec3) -> Option<(u32, f32)> {
        self.nearest_within(p, f32::INFINITY)
    }

    /// The id of the point nearest `p` and its distance, if one lies within `limit`.
    pub fn nearest_within(&self, p: Vec3, limit: f32) -> Option<(u32, f32)> {
        let rings = limit
            .is_finite()
            .then(|| (limit / self.cell).ceil() as i64 + 1);
        let mut best: Option<(u32, f32)> = None;
        self.walk(p, rings, |step| match step {
            Step::Point(i, d) => {
                if best.is_none_or(|(_, b)| d < b) {
                    best = Some((i, d));
                }
                false
            }
            Step::Beyond(reach) => best.is_some_and(|(_, d)| d <= reach),
        });
        best.filter(|&(_, d)| d <= limit)
            .map(|(i, d)| (self.ids[i as usize], d))
    }

    /// The ids of the `k` points nearest `p` with their distances, nearest first (fewer when
    /// the set holds fewer).
    pub fn k_nearest(&self, p: Vec3, k: usize) -> Vec<(u32, f32)> {
        let mut best: Vec<(u32, f32)> = Vec::with_capacity(k + 1);
        if k == 0 {
            return best;
        }
        self.walk(p, None, |step| match step {
            Step::Point(i, d) => {
                if best.len() < k || d < best[k - 1].1 {
                    let at = best.partition_point(|&(j, e)| (e, j) < (d, i));
                    best.insert(at, (i, d));
                    best.truncate(k);
                }
                false
            }
            Step::Beyond(reach) => best.len() == k && best[k - 1].1 <= reach,
        });
        best.into_iter()
            .map(|(i, d)| (self.ids[i as usize], d))
            .collect()
    }

    /// Visits the points by rings of grid cells round `p`'s cell (ring `r`: the cells `r`
    /// cells away along the farthest axis), at most `rings` of them (all with `None`):
    /// `visit(Step::Point(index, distance))` for each point, then `visit(Step::Beyond(d))`
    /// after each ring, every point not yet seen lying at least `d` away; `visit` returning
    /// true stops the walk.
    fn walk(&self, p: Vec3, rings: Option<i64>, mut visit: impl FnMut(Step) -> bool) {
        if self.points.is_empty() {
            return;
        }
        let centre = key(p, self.cell);
        // Beyond this ring every cell of the grid has been visited.
        let last = (0..3)
            .map(|a| {
                (centre[a] - self.lo[a])
                    .abs()
                    .max((self.hi[a] - centre[a]).abs())
            })
            .max()
            .unwrap_or(0);
        let last = rings.map_or(last, |r| r.min(i64::from(last)) as i32);
        for ring in 0..=last {
            // Only the cells of this ring's shell that lie inside the grid's box.
            let range =
                |a: usize| (centre[a] - ring).max(self.lo[a])..=(centre[a] + ring).min(self.hi[a]);
            for x in range(0) {
                for y in range(1) {
                    for z in range(2) {
                        let c = [x, y, z];
                        let shell = (0..3).map(|a| (c[a] - centre[a]).abs()).max();
                        if shell != Some(ring) {
                            continue;
                        }
                        for &i in self.cells.get(&c).map(Vec::as_slice).unwrap_or(&[]) {
                            if visit(Step::Point(i, self.points[i as usize].distance(p))) {
                                return;
                            }
                        }
                    }
                }
            }
            if visit(Step::Beyond(ring as f32 * self.cell)) {
                return;
            }
        }
    }

    /// A value known at the set's points, read at `p` between them: the [`BLEND`] nearest
    /// points' values blended with weights `((r - d) / (r d))^2`, `r` the distance of the
    /// farthest of them (Franke and Nielson's local form of Shepard's method). Continuous in
    /// `p` (a point entering the nearest enters with weight zero) and exact at a point of the
    /// set, so a mesh finer than the set sees the values change smoothly between the set's
    /// points where the nearest point alone made steps. `None` for an empty set.
    pub fn blend(&self, p: Vec3, value: impl Fn(u32) -> f64) -> Option<f64> {
        let shares = self.blend_shares(p);
        (!shares.is_empty()).then(|| weighted(&shares, value))
    }

    /// The ids and shares (adding up to 1) that [`Nearest::blend`] reads at `p`; empty for
    /// an empty set.
    pub fn blend_shares(&self, p: Vec3) -> Vec<(u32, f64)> {
        let near = self.k_nearest(p, BLEND);
        let Some(&(first, d0)) = near.first() else {
            return Vec::new();
        };
        let r = f64::from(near[near.len() - 1].1);
        let mut shares: Vec<(u32, f64)> = near
            .iter()
            .map(|&(id, d)| {
                let d = f64::from(d);
                (id, ((r - d) / (r * d)).max(0.0).powi(2))
            })
            .filter(|&(_, w)| w > 0.0)
            .collect();
        let total: f64 = shares.iter().map(|&(_, w)| w).sum();
        // on a point of the set (d0 = 0), or with every point at one distance, the nearest
        if d0 == 0.0 || total <= 0.0 || !total.is_finite() {
            return vec![(first, 1.0)];
        }
        for (_, w) in &mut shares {
            *w /= total;
        }
        shares
    }
}

/// A value read from `shares` of points ([`Nearest::blend_shares`]): the sum of each point's
/// `value` times its share.
pub fn weighted(shares: &[(u32, f64)], value: impl Fn(u32) -> f64) -> f64 {
    shares.iter().map(|&(id, w)| w * value(id)).sum()
}

/// Template vertices (points of the set) a value is blended from ([`Nearest::blend`]): the
/// nearest alone gave a mesh finer than the set steps of value between neighbouring vertices
/// (MediaPipe's face cut in sixteen, 1.7 mm edges at the mouth against the template's 3.9:
/// AU27 turned 24 triangles over in the paper's model and stretched an edge 7.4x).
pub const BLEND: usize = 6;

/// One step of [`Nearest::walk`].
enum Step {
    /// A point (its index in the set) and its distance.
    Point(u32, f32),
    /// A ring done: every point not yet seen lies at least this far away.
    Beyond(f32),
}

fn key(p: Vec3, cell: f32) -> [i32; 3] {
    let k = (p / cell).floor();
    [k.x as i32, k.y as i32, k.z as i32]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_brute_force() {
        let points: Vec<Vec3> = (0..500)
            .map(|i| {
                let t = i as f32;
                Vec3::new(
                    (t * 1.3).sin() * 5.0,
                    (t * 0.7).cos() * 2.0,
                    (t * 0.11).sin() * 9.0,
                )
            })
            .collect();
        let index = Nearest::new(points.clone(), (0..500).collect());
        for q in 0..200 {
            let t = q as f32 * 0.37;
            let p = Vec3::new(t.cos() * 7.0, t.sin() * 3.0, (t * 0.5).cos() * 12.0);
            let (i, d) = index.nearest(p).unwrap();
            let brute = points
                .iter()
                .map(|x| x.distance(p))
                .fold(f32::INFINITY, f32::min);
            assert_eq!(d, brute);
            assert_eq!(points[i as usize].distance(p), brute);
            let within = index.nearest_within(p, 0.5 * brute);
            assert!(within.is_none(), "{within:?}");
            assert_eq!(index.nearest_within(p, brute * 1.01).unwrap().1, brute);
            let mut sorted: Vec<f32> = points.iter().map(|x| x.distance(p)).collect();
            sorted.sort_by(f32::total_cmp);
            let k = index.k_nearest(p, 7);
            let found: Vec<f32> = k.iter().map(|&(_, d)| d).collect();
            assert_eq!(found, sorted[..7]);
            for (i, d) in k {
                assert_eq!(points[i as usize].distance(p), d);
            }
        }
    }

    #[test]
    fn blend_is_exact_at_the_points_and_between_their_values() {
        let points: Vec<Vec3> = (0..64)
            .map(|i| Vec3::new((i % 8) as f32, (i / 8) as f32, 0.0))
            .collect();
        let index = Nearest::new(points.clone(), (0..64).collect());
        let value = |id: u32| f64::from(points[id as usize].x * 2.0 + points[id as usize].y);
        for (i, p) in points.iter().enumerate() {
            assert_eq!(index.blend(*p, value), Some(value(i as u32)));
        }
        // along a line the blend moves without steps and stays within the values around it
        let mut last = index.blend(Vec3::new(2.0, 3.0, 0.0), value).unwrap();
        for step in 1..=400 {
            let p = Vec3::new(2.0 + step as f32 * 0.005, 3.0, 0.0);
            let now = index.blend(p, value).unwrap();
            assert!((now - last).abs() < 0.05, "a step of {} at {p}", now - last);
            assert!((4.0..=12.0).contains(&now), "{now}");
            last = now;
        }
        assert!(index.blend(Vec3::ZERO, value).is_some());
        assert!(Nearest::new(vec![], vec![])
            .blend(Vec3::ZERO, value)
            .is_none());
    }
}
