//! Flat pieces of triangles for vector output: what the raster styles tone per dot (an
//! iris's disc, a brow's band) is cut out of each triangle as convex polygons, drawn over
//! it at its depth.

use glam::Vec2;

/// The unit square, counter-clockwise: a brow's band in its own coordinates.
pub(super) const UNIT_SQUARE: [Vec2; 4] = [
    Vec2::new(0.0, 0.0),
    Vec2::new(1.0, 0.0),
    Vec2::new(1.0, 1.0),
    Vec2::new(0.0, 1.0),
];

/// Sides of the polygon a disc is drawn as in vector output.
const CIRCLE_SIDES: usize = 32;

/// A disc of `radius` about the origin as a counter-clockwise polygon.
pub(super) fn circle(radius: f32) -> Vec<Vec2> {
    (0..CIRCLE_SIDES)
        .map(|k| {
            let a = std::f32::consts::TAU * k as f32 / CIRCLE_SIDES as f32;
            Vec2::new(a.cos(), a.sin()) * radius
        })
        .collect()
}

/// The part of the convex polygon `subject` inside the convex, counter-clockwise polygon
/// `clip` (Sutherland and Hodgman's clipping, one edge of `clip` at a time).
pub(super) fn clip_convex(subject: &[Vec2], clip: &[Vec2]) -> Vec<Vec2> {
    let mut out: Vec<Vec2> = subject.to_vec();
    for (k, &a) in clip.iter().enumerate() {
        let b = clip[(k + 1) % clip.len()];
        let side = |p: Vec2| (b - a).perp_dot(p - a);
        let input = std::mem::take(&mut out);
        for (j, &p) in input.iter().enumerate() {
            let q = input[(j + 1) % input.len()];
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                out.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The affine map taking the triangle `from` onto `to`, corner to corner; `None` for a
/// degenerate `from`.
pub(super) fn affine(from: [Vec2; 3], to: [Vec2; 3]) -> Option<impl Fn(Vec2) -> Vec2> {
    let (e1, e2) = (from[1] - from[0], from[2] - from[0]);
    let det = e1.perp_dot(e2);
    if !det.is_finite() || det.abs() < 1e-12 {
        return None;
    }
    let (f1, f2) = (to[1] - to[0], to[2] - to[0]);
    Some(move |q: Vec2| {
        let d = q - from[0];
        let s = d.perp_dot(e2) / det;
        let t = e1.perp_dot(d) / det;
        to[0] + f1 * s + f2 * t
    })
}

/// The triangles of a convex polygon, as a fan from its first corner, leaving out those of
/// no area (a polygon clipped at a corner repeats points).
pub(super) fn fan(corners: &[Vec2]) -> impl Iterator<Item = [Vec2; 3]> + '_ {
    (1..corners.len().saturating_sub(1))
        .map(move |w| [corners[0], corners[w], corners[w + 1]])
        .filter(|[a, b, c]| (*b - *a).perp_dot(*c - *a).abs() > 1e-6)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_keeps_the_part_inside() {
        let square = [
            Vec2::new(-1.0, -1.0),
            Vec2::new(1.0, -1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(-1.0, 1.0),
        ];
        let triangle = [
            Vec2::new(0.0, 0.0),
            Vec2::new(4.0, 0.0),
            Vec2::new(0.0, 4.0),
        ];
        let area = |p: &[Vec2]| {
            (0..p.len())
                .map(|k| p[k].perp_dot(p[(k + 1) % p.len()]))
                .sum::<f32>()
                / 2.0
        };
        // The triangle covers the square's upper right quarter.
        assert!((area(&clip_convex(&triangle, &square)) - 1.0).abs() < 1e-6);
        // The iris's polygon inside a big triangle is the whole disc's polygon.
        let big = [
            Vec2::new(-9.0, -9.0),
            Vec2::new(9.0, -9.0),
            Vec2::new(0.0, 9.0),
        ];
        let disc = clip_convex(&big, &circle(1.0));
        assert!((area(&disc) - area(&circle(1.0))).abs() < 1e-5);
        assert!(clip_convex(
            &triangle,
            &circle(1.0)
                .iter()
                .map(|p| *p - Vec2::new(9.0, 0.0))
                .collect::<Vec<_>>()
        )
        .is_empty());
    }

    #[test]
    fn the_affine_map_takes_corners_to_corners() {
        let from = [Vec2::ZERO, Vec2::X, Vec2::Y];
        let to = [
            Vec2::new(5.0, 5.0),
            Vec2::new(7.0, 5.0),
            Vec2::new(5.0, 8.0),
        ];
        let map = affine(from, to).unwrap();
        for k in 0..3 {
            assert!((map(from[k]) - to[k]).length() < 1e-6);
        }
        assert!((map(Vec2::new(0.5, 0.5)) - Vec2::new(6.0, 6.5)).length() < 1e-6);
        assert!(affine([Vec2::ZERO, Vec2::X, Vec2::X * 2.0], to).is_none());
    }
}
