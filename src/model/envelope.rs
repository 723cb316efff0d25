//! The slope-limited lower envelope of values on a graph: the largest values under the given
//! ones that rise by at most a slope per unit of length along the graph's edges (a distance
//! transform, a Lipschitz envelope from below).
//!
//! Fitting caps the brow lowerer's pull with it (`fit::brow_ramp`), and the skin's slide its
//! neighbours' lift caps (`model::deform::slide`).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::mesh::Distance;

/// Lowers `values` to their slope-limited lower envelope: each value becomes the least of
/// its own and, over its neighbours, `rise(the neighbour's value, the edge's length)`, so
/// no value exceeds a neighbour's by more than the rise allows. Found nearest first
/// (Dijkstra's order) from `sources`, the items whose own values may lower others (an item
/// not among them passes a value on only once it has been lowered; give every item when
/// any may). `neighbours(i)` lists item `i`'s
/// neighbours and the lengths to them; `rise(value, length)` must be at least `value` and
/// grow with it, and may round (a caller that keeps single-precision values rounds there,
/// so the values compared are the ones it keeps).
pub fn lower_envelope<I>(
    values: &mut [f64],
    sources: impl IntoIterator<Item = usize>,
    neighbours: impl Fn(usize) -> I,
    rise: impl Fn(f64, f64) -> f64,
) where
    I: IntoIterator<Item = (usize, f64)>,
{
    let mut queue: BinaryHeap<Reverse<(Distance, usize)>> = sources
        .into_iter()
        .map(|i| Reverse((Distance(values[i]), i)))
        .collect();
    while let Some(Reverse((Distance(value), i))) = queue.pop() {
        if value > values[i] {
            continue;
        }
        for (j, length) in neighbours(i) {
            let reached = rise(value, length);
            if reached < values[j] {
                values[j] = reached;
                queue.push(Reverse((Distance(reached), j)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The neighbours of a path of `n` items one unit apart.
    fn path(n: usize) -> impl Fn(usize) -> Vec<(usize, f64)> {
        move |i| {
            [i.checked_sub(1), (i + 1 < n).then_some(i + 1)]
                .into_iter()
                .flatten()
                .map(|j| (j, 1.0))
                .collect()
        }
    }

    fn ramp(values: &[f64], slope: f64) -> Vec<f64> {
        let (mut envelope, n) = (values.to_vec(), values.len());
        lower_envelope(&mut envelope, 0..n, path(n), |v, l| v + l * slope);
        envelope
    }

    /// A step from nothing to the full value becomes a ramp of the given slope, from either
    /// side; a gentle rise is left as it is.
    #[test]
    fn a_steep_rise_becomes_a_ramp() {
        assert_eq!(ramp(&[0.0, 1.0, 1.0, 1.0], 0.4), [0.0, 0.4, 0.8, 1.0]);
        assert_eq!(ramp(&[1.0, 1.0, 1.0, 0.0], 0.4), [1.0, 0.8, 0.4, 0.0]);
        assert_eq!(ramp(&[1.0, 0.5, 1.0, 1.0], 0.25), [0.75, 0.5, 0.75, 1.0]);
        let gentle = [0.0, 0.2, 0.4, 0.6];
        assert_eq!(ramp(&gentle, 0.4), gentle);
    }

    /// An item left out of the sources passes its value on only once it has been lowered;
    /// where two sources reach an item the lower reach wins.
    #[test]
    fn only_sources_lower_their_neighbours() {
        let mut values = vec![f64::MAX, 0.0, f64::MAX, f64::MAX, 1.0];
        lower_envelope(&mut values, [1, 4], path(5), |v, l| v + l);
        assert_eq!(values, [1.0, 0.0, 1.0, 2.0, 1.0]);
        let mut values = vec![5.0, 0.0, 5.0];
        lower_envelope(&mut values, [0], path(3), |v, l| v + l);
        assert_eq!(values, [5.0, 0.0, 5.0], "item 1 is no source");
    }

    /// A rise that rounds to single precision gives values single precision keeps.
    #[test]
    fn a_rounding_rise_keeps_its_precision() {
        let mut values = vec![f64::from(0.1f32), f64::from(f32::MAX), f64::from(f32::MAX)];
        let rise = |v: f64, l: f64| (v + l / 3.0) as f32 as f64;
        lower_envelope(&mut values, [0], path(3), rise);
        for v in &values {
            assert_eq!(f64::from(*v as f32), *v);
        }
        assert!(values[2] > values[1] && values[1] > values[0]);
    }
}
