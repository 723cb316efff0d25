//! Jaw weights beyond the template's face, found along the mesh.
//!
//! The template is a face mask: it ends at the jaw line and has no mouth lining. Carried by
//! nearest point, a vertex under the chin or inside the mouth took the weight of the nearest
//! template vertex faded by its straight-line distance from it, so two neighbours 5 and 11 mm
//! from the template's jaw line took weights 1 and 0: at AU26 the skin under MakeHuman's chin
//! and the floor of its mouth folded over (42 triangles). Beyond the template's skin the
//! weights are instead a harmonic map on the mesh's skin: held at the carried weight where the
//! template's skin is near, held at 0 beyond [`FADE_ALONG`] of the face along the mesh (the
//! submental skin follows the mandible down to about the hyoid; the neck below stays), every
//! other skin vertex the mean of its neighbours (edges weighted by `1 / length^2`). So the
//! weight falls evenly from the jaw line down the neck, and a mouth's lining goes over evenly
//! from its lower lip (the jaw's) to its upper lip (still) round the back of the mouth.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::parts::{Part, Parts};
use crate::model::mesh::Distance;
use crate::model::Mesh;

/// How far along the mesh from the template's skin the jaw's weights die out, as a fraction
/// of the landmarks' spread (about 43 mm on an adult head, the chin-to-hyoid distance).
pub const FADE_ALONG: f64 = 0.75;
/// Gauss-Seidel rounds at most; the rounds stop once no weight changes by [`TOLERANCE`].
const ROUNDS: usize = 4000;
/// Over-relaxation factor of the rounds.
const OMEGA: f64 = 1.8;
/// Largest change of a weight in a round at which the map counts as found.
const TOLERANCE: f64 = 1e-6;

/// The skin's edges as neighbour lists with their lengths (skin to skin only).
fn skin_neighbours(mesh: &Mesh, parts: &Parts) -> Vec<Vec<(usize, f64)>> {
    let mut neighbours = vec![Vec::new(); mesh.vertex_count()];
    for [a, b] in mesh.edges() {
        let (a, b) = (a as usize, b as usize);
        if parts.of_vertex[a] != Part::Skin || parts.of_vertex[b] != Part::Skin {
            continue;
        }
        let len = f64::from(mesh.positions[a].distance(mesh.positions[b]));
        if len > 0.0 {
            neighbours[a].push((b, len));
            neighbours[b].push((a, len));
        }
    }
    neighbours
}

/// Distance along the skin's edges from the nearest `held` vertex (infinite where none is
/// reached within `limit`).
fn distance_from(neighbours: &[Vec<(usize, f64)>], held: &[bool], limit: f64) -> Vec<f64> {
    let mut dist = vec![f64::INFINITY; neighbours.len()];
    let mut heap = BinaryHeap::new();
    for (v, _) in held.iter().enumerate().filter(|(_, &h)| h) {
        dist[v] = 0.0;
        heap.push(Reverse((Distance(0.0), v)));
    }
    while let Some(Reverse((Distance(d), v))) = heap.pop() {
        if d > dist[v] {
            continue;
        }
        for &(n, len) in &neighbours[v] {
            let next = d + len;
            if next < dist[n] && next < limit {
                dist[n] = next;
                heap.push(Reverse((Distance(next), n)));
            }
        }
    }
    dist
}

/// Replaces the jaw weights `w` of skin vertices that are not `held` by the harmonic map
/// described in the module: held weights kept, 0 at `length` (mesh units) along the skin
/// from every held vertex and beyond. A fit whose every skin vertex is held (the template
/// fitted to itself) changes nothing.
pub fn relax_beyond(mesh: &Mesh, parts: &Parts, w: &mut [f32], held: &[bool], length: f64) {
    let neighbours = skin_neighbours(mesh, parts);
    let dist = distance_from(&neighbours, held, length);
    let mut free: Vec<usize> = (0..w.len())
        .filter(|&v| parts.of_vertex[v] == Part::Skin && !held[v])
        .collect();
    for &v in &free {
        if dist[v].is_infinite() {
            w[v] = 0.0;
        }
    }
    free.retain(|&v| dist[v].is_finite() && !neighbours[v].is_empty());
    // nearest the held skin first, so each round carries the weights outward
    free.sort_by(|&a, &b| dist[a].total_cmp(&dist[b]));
    let mut x: Vec<f64> = w.iter().map(|&v| f64::from(v)).collect();
    for _ in 0..ROUNDS {
        let mut largest: f64 = 0.0;
        for &v in &free {
            let (sum, total) = neighbours[v].iter().fold((0.0, 0.0), |(s, t), &(n, len)| {
                let k = 1.0 / (len * len);
                (s + k * x[n], t + k)
            });
            let mean = sum / total;
            let next = (x[v] + OMEGA * (mean - x[v])).clamp(0.0, 1.0);
            largest = largest.max((next - x[v]).abs());
            x[v] = next;
        }
        if largest < TOLERANCE {
            break;
        }
    }
    for &v in &free {
        w[v] = x[v] as f32;
    }
}
