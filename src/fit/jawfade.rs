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

use super::parts::{Part, Parts, SkinGraph};
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

/// Replaces the jaw weights `w` of skin vertices that are not `held` by the harmonic map
/// described in the module: held weights kept, 0 at `length` (mesh units) along the skin
/// from every held vertex and beyond. A fit whose every skin vertex is held (the template
/// fitted to itself) changes nothing.
pub fn relax_beyond(mesh: &Mesh, parts: &Parts, w: &mut [f32], held: &[bool], length: f64) {
    let graph = SkinGraph::new(mesh, parts);
    let seeds: Vec<u32> = (0..held.len() as u32)
        .filter(|&v| held[v as usize])
        .collect();
    let dist = graph.distances(&seeds, length);
    let neighbours = &graph.next;
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
                (s + k * x[n as usize], t + k)
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
