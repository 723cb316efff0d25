//! The inside of the default face's mouth: teeth, gums, a tongue and a dark back wall.
//!
//! Each part is a closed piece of its own, appended after the eyeballs so every skin and
//! eyeball vertex keeps its number. All lie behind the lips and inside the head; sizes are
//! adult means in millimetres (like the skin):
//!
//! - the dental arches follow a parabola from the incisors back to the second molars (arch
//!   depth 38 mm, half-width 25 mm at the back), each a band swept along it: the crowns 9 mm
//!   tall (from the occlusal plane, the upper incisors 2 mm over the lower ones) and 7 mm
//!   thick at the incisors to 10 mm at the molars, the gums above (upper) and below (lower);
//! - the tongue is a flattened ellipsoid lying inside the lower arch, its top just under the
//!   occlusal plane;
//! - the mouth's back wall is a thin elliptic slab behind the arches, drawn dark, so an open
//!   mouth shows teeth and a dark mouth rather than the background.
//!
//! The lower teeth, the lower gum and the tongue turn with the jaw (weight 1); the upper
//! ones and the back wall stay. No muscle moves any of them (`face::groups::hold_still`).

use glam::Vec3;

use super::anthropometry::*;

/// One closed part of the mouth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MouthPart {
    /// The upper teeth's crowns.
    UpperTeeth,
    /// The upper gum, above the upper teeth.
    UpperGum,
    /// The lower teeth's crowns.
    LowerTeeth,
    /// The lower gum, below the lower teeth.
    LowerGum,
    /// The tongue.
    Tongue,
    /// The dark back wall of the mouth.
    Interior,
}

impl MouthPart {
    /// Every part, in the order they are appended to the mesh.
    pub const ALL: [MouthPart; 6] = [
        MouthPart::UpperTeeth,
        MouthPart::UpperGum,
        MouthPart::LowerTeeth,
        MouthPart::LowerGum,
        MouthPart::Tongue,
        MouthPart::Interior,
    ];

    /// The part's vertex group name (these names are what `fit-rig` reads as teeth, gums,
    /// tongue and mouth interior).
    pub fn group(self) -> &'static str {
        match self {
            MouthPart::UpperTeeth => "upper_teeth",
            MouthPart::UpperGum => "upper_gum",
            MouthPart::LowerTeeth => "lower_teeth",
            MouthPart::LowerGum => "lower_gum",
            MouthPart::Tongue => "tongue",
            MouthPart::Interior => "mouth_interior",
        }
    }

    /// True for the parts the mandible carries.
    pub fn turns_with_jaw(self) -> bool {
        matches!(
            self,
            MouthPart::LowerTeeth | MouthPart::LowerGum | MouthPart::Tongue
        )
    }

    /// The part's vertices (mm) and triangles (counter-clockwise seen from outside, on
    /// vertices numbered from 0).
    pub fn shape(self) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let upper = |bottom: f64, top: f64| Band {
            front_z: UPPER_FRONT_Z,
            bottom,
            top,
        };
        let lower = |bottom: f64, top: f64| Band {
            front_z: UPPER_FRONT_Z - OVERJET - INCISOR_THICKNESS,
            bottom,
            top,
        };
        match self {
            MouthPart::UpperTeeth => upper(OCCLUSAL_Y - OVERBITE, OCCLUSAL_Y + CROWN).shape(),
            MouthPart::UpperGum => upper(OCCLUSAL_Y + CROWN, OCCLUSAL_Y + CROWN + GUM).shape(),
            MouthPart::LowerTeeth => lower(OCCLUSAL_Y - CROWN, OCCLUSAL_Y).shape(),
            MouthPart::LowerGum => lower(OCCLUSAL_Y - CROWN - GUM, OCCLUSAL_Y - CROWN).shape(),
            MouthPart::Tongue => ellipsoid(TONGUE_CENTRE, TONGUE_SEMI_AXES),
            MouthPart::Interior => slab(),
        }
    }

    /// The centre of the part's vertices (mm), to tell the parts apart in a mesh read back
    /// from a file.
    pub fn centroid(self) -> [f64; 3] {
        let (points, _) = self.shape();
        let n = points.len() as f64;
        let sum = points
            .iter()
            .fold([0.0; 3], |s, p| [s[0] + p[0], s[1] + p[1], s[2] + p[2]]);
        sum.map(|c| c / n)
    }
}

/// The occlusal plane's height (mm above the nasion): where the upper and lower teeth meet,
/// 1 mm under the mouth line.
pub const OCCLUSAL_Y: f64 = STOMION_Y - 1.0;
/// How far the upper incisors reach down over the lower ones.
const OVERBITE: f64 = 2.0;
/// How far the lower incisors' front lies behind the upper ones' back.
const OVERJET: f64 = 0.5;
/// Crown height.
const CROWN: f64 = 9.0;
/// Visible gum height beyond the crowns.
const GUM: f64 = 5.0;
/// Front (labial) face of the upper incisors: 8 mm behind the lips' front.
const UPPER_FRONT_Z: f64 = -8.0;
/// Thickness of the incisors (lips to tongue side) and of the molars.
const INCISOR_THICKNESS: f64 = 7.0;
const MOLAR_THICKNESS: f64 = 10.0;
/// The arch: half-width at the back molars and depth from the incisors to them.
const ARCH_HALF_WIDTH: f64 = 25.0;
const ARCH_DEPTH: f64 = 38.0;
/// Samples along the arch on each side of the midline.
const ARCH_STEPS: i32 = 10;
/// The tongue: centre and semi-axes (mm).
const TONGUE_CENTRE: [f64; 3] = [0.0, OCCLUSAL_Y - 6.0, -36.0];
const TONGUE_SEMI_AXES: [f64; 3] = [14.0, 5.0, 17.0];
/// The back wall: an elliptic slab facing the lips, reaching from under the nose to below
/// the lower incisors at the widest opening. Its centre lies above the occlusal plane: the
/// wall belongs to the skull, and fitting tells still pieces from the jaw's by that side.
const WALL_CENTRE: [f64; 3] = [0.0, OCCLUSAL_Y + 8.0, -52.0];
const WALL_SEMI_AXES: [f64; 2] = [27.0, 36.0];
const WALL_THICKNESS: f64 = 4.0;
/// Segments round the tongue and the wall, and rings from pole to pole of the tongue.
const SEGMENTS: usize = 16;
const RINGS: usize = 8;

/// A band swept along the dental arch: crowns or gum between two heights.
struct Band {
    /// z (mm) of the front on the midline.
    front_z: f64,
    bottom: f64,
    top: f64,
}

impl Band {
    /// Four vertices per step (front-bottom, front-top, back-top, back-bottom), steps from
    /// the subject's right to left, the ends closed by two triangles each.
    fn shape(&self) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut points = Vec::new();
        for k in -ARCH_STEPS..=ARCH_STEPS {
            let s = f64::from(k.abs()) / f64::from(ARCH_STEPS);
            let sign = if k < 0 { -1.0 } else { 1.0 };
            // the arch x = W s, z = front - D s^2, and its inward normal
            let (x, z) = (ARCH_HALF_WIDTH * s, self.front_z - ARCH_DEPTH * s * s);
            let (nx, nz) = (-2.0 * ARCH_DEPTH * s, -ARCH_HALF_WIDTH);
            let len = nx.hypot(nz);
            let t = INCISOR_THICKNESS + (MOLAR_THICKNESS - INCISOR_THICKNESS) * s;
            let (bx, bz) = (x + t * nx / len, z + t * nz / len);
            for (px, py, pz) in [
                (x, self.bottom, z),
                (x, self.top, z),
                (bx, self.top, bz),
                (bx, self.bottom, bz),
            ] {
                points.push([sign * px, py, pz]);
            }
        }
        let steps = points.len() as u32 / 4;
        let mut triangles = Vec::new();
        for step in 0..steps - 1 {
            let (a, b) = (4 * step, 4 * (step + 1));
            for side in 0..4 {
                let next = (side + 1) % 4;
                triangles.push([a + side, b + side, b + next]);
                triangles.push([a + side, b + next, a + next]);
            }
        }
        let last = 4 * (steps - 1);
        triangles.push([0, 1, 2]);
        triangles.push([0, 2, 3]);
        triangles.push([last, last + 2, last + 1]);
        triangles.push([last, last + 3, last + 2]);
        (points, triangles)
    }
}

/// A closed ellipsoid: a pole at the back (-z), rings, a pole at the front.
fn ellipsoid(centre: [f64; 3], semi: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut rings = Vec::new();
    for r in 1..RINGS {
        let a = std::f64::consts::PI * r as f64 / RINGS as f64;
        rings.push((a.sin(), -a.cos()));
    }
    revolve(centre, [semi[0], semi[1]], semi[2], &rings)
}

/// The back wall: a thin slab whose outline is an ellipse in the face's plane.
fn slab() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let half = 0.5 * WALL_THICKNESS;
    // from the back face's centre round the back rim, the front rim, to the front centre
    let rings = [(1.0, -1.0), (1.0, 1.0)];
    revolve(WALL_CENTRE, WALL_SEMI_AXES, half, &rings)
}

/// A closed surface about the z axis through `centre`: the back pole, one ring per
/// `(radius fraction, z fraction)` (radii `semi` in x and y, z along `depth`), the front
/// pole. Rings run from +x counter-clockwise seen from the front; the ring vertices at
/// opposite angles are exact mirrors in x.
fn revolve(
    centre: [f64; 3],
    semi: [f64; 2],
    depth: f64,
    rings: &[(f64, f64)],
) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let [cx, cy, cz] = centre;
    let mut points = vec![[cx, cy, cz - depth]];
    for &(rho, h) in rings {
        for k in 0..SEGMENTS {
            let (sin, cos) = angle(k);
            points.push([
                cx + semi[0] * rho * cos,
                cy + semi[1] * rho * sin,
                cz + depth * h,
            ]);
        }
    }
    points.push([cx, cy, cz + depth]);
    let n = SEGMENTS as u32;
    let ring = |r: u32, k: u32| 1 + r * n + k % n;
    let count = rings.len() as u32;
    let front = 1 + count * n;
    let mut triangles = Vec::new();
    for k in 0..n {
        triangles.push([0, ring(0, k + 1), ring(0, k)]);
    }
    for r in 0..count - 1 {
        for k in 0..n {
            let (a, b) = (ring(r, k), ring(r, k + 1));
            let (c, d) = (ring(r + 1, k + 1), ring(r + 1, k));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    for k in 0..n {
        triangles.push([front, ring(count - 1, k), ring(count - 1, k + 1)]);
    }
    (points, triangles)
}

/// `(sin, cos)` of segment `k`'s angle, with the segments at `pi - a` given the exact
/// mirror of those at `a` (so the parts are exactly symmetric across the midline).
fn angle(k: usize) -> (f64, f64) {
    let half = SEGMENTS / 2;
    let a = |k: usize| 2.0 * std::f64::consts::PI * k as f64 / SEGMENTS as f64;
    // k and half - k mirror each other (angles a and pi - a); compute from the smaller
    let k = k % SEGMENTS;
    let (m, upper) = if k <= half {
        (k, false)
    } else {
        (SEGMENTS - k, true)
    };
    // m in 0..=half; m and half - m are mirrors
    let (base, mirrored) = if m <= half / 2 {
        (m, false)
    } else {
        (half - m, true)
    };
    let (sin, cos) = a(base).sin_cos();
    // a quarter turn is its own mirror: its cosine must be exactly 0
    let cos = if 2 * base == half {
        0.0
    } else if mirrored {
        -cos
    } else {
        cos
    };
    let sin = if upper { -sin } else { sin };
    (sin, cos)
}

/// Appends every mouth part to `positions` and `triangles` (mm turned into mesh units).
pub fn append(positions: &mut Vec<Vec3>, triangles: &mut Vec<[u32; 3]>) {
    for part in MouthPart::ALL {
        let first = positions.len() as u32;
        let (points, tris) = part.shape();
        positions.extend(
            points
                .iter()
                .map(|&[x, y, z]| Vec3::new(units(x) as f32, y_units(y) as f32, units(z) as f32)),
        );
        triangles.extend(tris.iter().map(|t| t.map(|v| v + first)));
    }
}

/// The part whose centroid lies nearest `p` (mm).
pub fn nearest_part(p: [f64; 3]) -> MouthPart {
    let distance = |part: MouthPart| {
        let c = part.centroid();
        (c[0] - p[0]).hypot(c[1] - p[1]).hypot(c[2] - p[2])
    };
    MouthPart::ALL
        .into_iter()
        .min_by(|a, b| distance(*a).total_cmp(&distance(*b)))
        .unwrap_or(MouthPart::Interior)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_mirror_exactly() {
        for k in 0..SEGMENTS {
            let (s, c) = angle(k);
            let mirror = (SEGMENTS / 2 + SEGMENTS - k) % SEGMENTS;
            let (ms, mc) = angle(mirror);
            assert_eq!((s, c), (ms, -mc), "segment {k} and {mirror}");
            let a = 2.0 * std::f64::consts::PI * k as f64 / SEGMENTS as f64;
            assert!((s - a.sin()).abs() < 1e-12 && (c - a.cos()).abs() < 1e-12);
        }
    }

    #[test]
    fn parts_are_told_apart_by_their_centroids() {
        for part in MouthPart::ALL {
            assert_eq!(nearest_part(part.centroid()), part);
        }
    }
}
