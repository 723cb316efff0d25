//! How well a deformed face holds together: the numbers `grimace check` prints.
//!
//! Everything is measured against the rest mesh, on the skin: the connected pieces of the
//! mesh that carry a landmark (eyeballs, teeth and helper geometry carry none). Lengths are in
//! millimetres, from the mesh's units when they are known, else from the outer canthal
//! distance (landmarks 36-45) taken as [`CANTHAL_MM`](crate::landmarks::CANTHAL_MM), a typical adult's.
//!
//! - **Turned triangles**: skin triangles whose deformed normal points against the rest
//!   normal (a fold or a tear in the rendered surface).
//! - **Stretch**: the largest ratio of a skin edge's deformed length to its rest length.
//! - **Lid gap** (AU43 and AU45): the opening left between the upper and lower lid
//!   landmarks (37/41, 38/40 on the subject's right eye, 43/47, 44/46 on the left), across
//!   the eye as seen from the front (the part of their separation off the line through the
//!   eye's corners and off the face's forward axis, so lids that meet with their landmarks
//!   a little apart along the lid, or one lid a little in front of the other, count as
//!   closed), as a fraction of the rest opening; the largest pair counts. Where the lids' free edges seen
//!   from the front lie away from those landmarks (landmarks on the lid's back,
//!   `super::lidedge`), the gap is what still shows between the lids in the landmarks'
//!   columns instead: the share of the rest opening between the free edges where, looking
//!   along the face, the eyeball (or a hole) is seen rather than skin.
//! - **Jaw drop** (AU26 and AU27): how far the chin (landmark 8) and the lower lip
//!   (landmark 57) travel down the face, the smaller of the two.
//! - **Most moved**: the vertex that travelled furthest, and the face region nearest it.

use glam::Vec3;

use super::lidedge::{Sight, EYE_MARKS};
use super::parts::{components, find_parts, PartOverrides};
use crate::landmarks::{mm_per_unit as estimate_mm_per_unit, CANTHAL_MM};
use crate::model::Mesh;

/// A skin edge stretched beyond this many times its rest length is a tear.
pub const MAX_STRETCH: f32 = 2.5;
/// A closing lid leaving this fraction of its rest opening or more does not close.
pub const MAX_LID_GAP: f32 = 0.10;
/// An opening jaw whose chin and lower lip drop less than this (mm) does not open: the
/// lower incisors of an adult drop at least 15 mm when the jaw drops (AU26).
pub const MIN_JAW_DROP_MM: f32 = 15.0;

/// Upper and lower lid landmark pairs: the subject's right eye, then the left.
pub const LID_PAIRS: [[(usize, usize); 2]; 2] = [[(37, 41), (38, 40)], [(43, 47), (44, 46)]];

/// The corners of each eye of [`LID_PAIRS`]: the subject's right eye, then the left.
const EYE_CORNERS: [(usize, usize); 2] = [(36, 39), (42, 45)];

/// Which eyes a lid measure looks at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Eyes {
    /// Both eyes.
    Both,
    /// The subject's right eye only.
    Right,
    /// The subject's left eye only.
    Left,
}

/// What a measure of one state asks for beyond the always-measured numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Expect {
    /// The lids of these eyes should close (AU43, AU45).
    pub lids_close: Option<Eyes>,
    /// The jaw should open (AU26, AU27).
    pub jaw_opens: bool,
}

/// A face region, named from the nearest landmarks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Region {
    /// Eyebrows and forehead (landmarks 17-26).
    Brow,
    /// The eyes and lids (36-47).
    Eye,
    /// The nose (27-35).
    Nose,
    /// Between the eyes, the nose, the mouth and the jaw line.
    Cheek,
    /// The lips (48-67).
    Mouth,
    /// The chin (jaw line 6-10).
    Chin,
    /// The jaw line (0-5, 11-16).
    Jaw,
    /// Away from every landmark.
    Other,
}

impl Region {
    /// The region's name as printed.
    pub fn name(self) -> &'static str {
        match self {
            Region::Brow => "brow",
            Region::Eye => "eye",
            Region::Nose => "nose",
            Region::Cheek => "cheek",
            Region::Mouth => "mouth",
            Region::Chin => "chin",
            Region::Jaw => "jaw",
            Region::Other => "other",
        }
    }

    /// The region of one landmark (0-67).
    fn of_landmark(index: usize) -> Region {
        match index {
            6..=10 => Region::Chin,
            0..=16 => Region::Jaw,
            17..=26 => Region::Brow,
            27..=35 => Region::Nose,
            36..=47 => Region::Eye,
            48..=67 => Region::Mouth,
            _ => Region::Other,
        }
    }
}

/// The numbers of one deformed state.
#[derive(Debug, Clone, PartialEq)]
pub struct Quality {
    /// Skin triangles turned against their rest normal.
    pub turned: usize,
    /// Largest skin edge length over its rest length.
    pub stretch: f32,
    /// Lid opening left, as a fraction of the rest opening (when the lids should close).
    pub lid_gap: Option<f32>,
    /// Chin and lower lip drop in mm, the smaller (when the jaw should open).
    pub jaw_drop_mm: Option<f32>,
    /// How far the most-moved vertex went, in mm.
    pub moved_mm: f32,
    /// Where that vertex is.
    pub moved_region: Region,
}

impl Quality {
    /// What is wrong with the state, in words; empty when nothing is.
    pub fn failures(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.turned > 0 {
            out.push(format!("{} triangles turned over", self.turned));
        }
        if self.stretch > MAX_STRETCH {
            out.push(format!(
                "an edge stretched {:.2}x (over {MAX_STRETCH}x)",
                self.stretch
            ));
        }
        if let Some(gap) = self.lid_gap.filter(|&g| g >= MAX_LID_GAP) {
            out.push(format!(
                "the lids leave {:.0}% of the opening (closed is under {:.0}%)",
                gap * 100.0,
                MAX_LID_GAP * 100.0
            ));
        }
        if let Some(drop) = self.jaw_drop_mm.filter(|&d| d < MIN_JAW_DROP_MM) {
            out.push(format!(
                "the jaw drops {drop:.1} mm (an open jaw drops {MIN_JAW_DROP_MM} mm or more)"
            ));
        }
        out
    }
}

/// Measures deformed states of one mesh with its 68 landmark vertices.
#[derive(Debug, Clone)]
pub struct Gauge {
    rest: Vec<Vec3>,
    skin_triangles: Vec<[u32; 3]>,
    skin_edges: Vec<[u32; 2]>,
    rest_normals: Vec<Vec3>,
    landmarks: Vec<u32>,
    /// Per eye, its visible opening where the landmarks are not on the lids' free edges.
    sights: [Option<Sight>; 2],
    mm_per_unit: f32,
    /// The face's down direction (from the nose bridge toward the chin), unit.
    down: Vec3,
    /// The face's forward axis (across the eyes and down, crossed), unit: lids are looked at
    /// along it.
    forward: Vec3,
}

/// Why a mesh cannot be measured.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GaugeError {
    /// Not 68 landmark vertices, or one out of range.
    #[error("{0}")]
    Landmarks(String),
    /// The outer eye corners coincide, so there is no scale.
    #[error("the outer eye corners (landmarks 36 and 45) coincide: the face has no scale")]
    NoScale,
}

impl Gauge {
    /// Prepares the measures for `mesh` with its 68 iBUG landmark vertices; `mm_per_unit`
    /// is the mesh's scale when known (else from the canthal distance).
    pub fn new(
        mesh: &Mesh,
        landmarks: &[u32],
        mm_per_unit: Option<f32>,
    ) -> Result<Gauge, GaugeError> {
        let n = mesh.vertex_count();
        if landmarks.len() != 68 {
            return Err(GaugeError::Landmarks(format!(
                "{} landmarks given; the iBUG scheme has 68",
                landmarks.len()
            )));
        }
        if let Some(v) = landmarks.iter().find(|&&v| v as usize >= n) {
            return Err(GaugeError::Landmarks(format!(
                "landmark vertex {v} is beyond the mesh's {n} vertices"
            )));
        }
        let rest = mesh.positions.clone();
        let at = |i: usize| rest[landmarks[i] as usize];
        let landmark_points: Vec<Vec3> = landmarks.iter().map(|&v| rest[v as usize]).collect();
        let mm_per_unit = match mm_per_unit.filter(|m| m.is_finite() && *m > 0.0) {
            Some(mm) => mm,
            None => estimate_mm_per_unit(&landmark_points).ok_or(GaugeError::NoScale)?,
        };
        let across = (at(45) - at(36)).normalize();
        let down = at(8) - at(27);
        let down = (down - across * down.dot(across)).normalize_or_zero();
        let component = components(mesh);
        let mut skin_piece = vec![false; n];
        for &v in landmarks {
            skin_piece[component[v as usize] as usize] = true;
        }
        let skin_triangles: Vec<[u32; 3]> = mesh
            .triangles
            .iter()
            .filter(|t| skin_piece[component[t[0] as usize] as usize])
            .copied()
            .collect();
        let skin_edges: Vec<[u32; 2]> = mesh
            .edges()
            .into_iter()
            .filter(|e| skin_piece[component[e[0] as usize] as usize])
            .collect();
        let rest_normals = skin_triangles.iter().map(|t| normal(&rest, t)).collect();
        let parts = find_parts(mesh, landmarks, &landmark_points, &PartOverrides::default());
        let sights = EYE_MARKS.map(|eye| Sight::new(mesh, &parts, landmarks, &eye));
        Ok(Gauge {
            rest,
            skin_triangles,
            skin_edges,
            rest_normals,
            landmarks: landmarks.to_vec(),
            sights,
            mm_per_unit,
            down,
            forward: across.cross(down).normalize_or_zero(),
        })
    }

    /// Millimetres per mesh unit used.
    pub fn mm_per_unit(&self) -> f32 {
        self.mm_per_unit
    }

    /// Measures one deformed state (positions of the same mesh).
    pub fn measure(&self, positions: &[Vec3], expect: Expect) -> Quality {
        let turned = self
            .skin_triangles
            .iter()
            .zip(&self.rest_normals)
            .filter(|(t, rest)| **rest != Vec3::ZERO && normal(positions, t).dot(**rest) < 0.0)
            .count();
        let stretch = self
            .skin_edges
            .iter()
            .filter_map(|&[a, b]| {
                let rest = self.rest[a as usize].distance(self.rest[b as usize]);
                (rest > 0.0).then(|| positions[a as usize].distance(positions[b as usize]) / rest)
            })
            .fold(1.0f32, f32::max);
        let (moved, vertex) = positions
            .iter()
            .zip(&self.rest)
            .enumerate()
            .map(|(v, (p, r))| (p.distance(*r), v))
            .fold(
                (0.0f32, 0usize),
                |best, x| if x.0 > best.0 { x } else { best },
            );
        Quality {
            turned,
            stretch,
            lid_gap: expect.lids_close.map(|eyes| self.lid_gap(positions, eyes)),
            jaw_drop_mm: expect.jaw_opens.then(|| self.jaw_drop(positions)),
            moved_mm: moved * self.mm_per_unit,
            moved_region: self.region(self.rest[vertex]),
        }
    }

    fn landmark(&self, positions: &[Vec3], i: usize) -> Vec3 {
        positions[self.landmarks[i] as usize]
    }

    /// The largest lid opening left, as a fraction of its rest opening.
    fn lid_gap(&self, positions: &[Vec3], eyes: Eyes) -> f32 {
        let eyes: &[usize] = match eyes {
            Eyes::Both => &[0, 1],
            Eyes::Right => &[0],
            Eyes::Left => &[1],
        };
        let mut worst = 0.0f32;
        for &eye in eyes {
            let (inner, outer) = EYE_CORNERS[eye];
            // Across the eye: the separation off the corners' line, in each pose's own
            // corners (the eye may move as a whole).
            if let Some(sight) = &self.sights[eye] {
                worst = worst.max(sight.left_open(positions) as f32);
                continue;
            }
            // Seen from the front: lids that meet with one a little in front of the other
            // (an uneven mesh's lid landmarks lie up to a millimetre apart in depth) are
            // closed to a viewer, as the free edges' sight measures them.
            let across = |p: &[Vec3], upper: usize, lower: usize| {
                let along = (self.landmark(p, outer) - self.landmark(p, inner)).normalize_or_zero();
                let forward = (self.forward - along * self.forward.dot(along)).normalize_or_zero();
                let d = self.landmark(p, upper) - self.landmark(p, lower);
                (d - along * d.dot(along) - forward * d.dot(forward)).length()
            };
            for &(upper, lower) in &LID_PAIRS[eye] {
                let rest = across(&self.rest, upper, lower);
                if rest > 0.0 {
                    worst = worst.max(across(positions, upper, lower) / rest);
                }
            }
        }
        worst
    }

    /// How far the chin and the lower lip dropped down the face (mm), the smaller.
    fn jaw_drop(&self, positions: &[Vec3]) -> f32 {
        [8, 57]
            .iter()
            .map(|&i| (self.landmark(positions, i) - self.landmark(&self.rest, i)).dot(self.down))
            .fold(f32::INFINITY, f32::min)
            * self.mm_per_unit
    }

    /// The region of a rest point: that of the nearest landmark, the cheek between the
    /// features, or other when far from every landmark.
    fn region(&self, p: Vec3) -> Region {
        let (index, distance) = (0..68)
            .map(|i| (i, self.landmark(&self.rest, i).distance(p)))
            .fold(
                (0, f32::INFINITY),
                |best, x| if x.1 < best.1 { x } else { best },
            );
        let mm = distance * self.mm_per_unit;
        // beyond half the canthal distance of every landmark: off the face
        if mm > 0.5 * CANTHAL_MM {
            return Region::Other;
        }
        let nearest = Region::of_landmark(index);
        let height = |q: Vec3| (q - self.landmark(&self.rest, 27)).dot(self.down);
        let upper_lids = [37, 38, 43, 44]
            .iter()
            .map(|&i| height(self.landmark(&self.rest, i)))
            .fold(f32::INFINITY, f32::min);
        // the glabella, above the lids between the brows, is nearest the nose's root
        if nearest == Region::Nose && height(p) < upper_lids {
            return Region::Brow;
        }
        let below_eyes = height(p) > height(self.landmark(&self.rest, 41));
        let above_mouth = height(p) < height(self.landmark(&self.rest, 48));
        // well away from the feature it is nearest to, between the eyes and the mouth
        if mm > 0.15 * CANTHAL_MM && below_eyes && above_mouth {
            return Region::Cheek;
        }
        nearest
    }
}

/// A triangle's unit normal (zero when degenerate).
fn normal(positions: &[Vec3], t: &[u32; 3]) -> Vec3 {
    let [a, b, c] = t.map(|v| positions[v as usize]);
    (b - a).cross(c - a).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat grid of `k` x `k` vertices in the x-y plane, y up; landmarks spread over it.
    fn grid(k: u32) -> (Mesh, Vec<u32>) {
        let mut positions = Vec::new();
        for j in 0..k {
            for i in 0..k {
                positions.push(Vec3::new(i as f32, -(j as f32), 0.0));
            }
        }
        let mut triangles = Vec::new();
        for j in 0..k - 1 {
            for i in 0..k - 1 {
                let v = j * k + i;
                triangles.push([v, v + k, v + 1]);
                triangles.push([v + 1, v + k, v + k + 1]);
            }
        }
        let mesh = Mesh::new(positions, triangles).unwrap();
        let mut landmarks: Vec<u32> = (0..68).map(|i| (i * 7) % (k * k)).collect();
        landmarks[36] = 2 * k + 1;
        landmarks[45] = 2 * k + 7;
        landmarks[27] = 2 * k + 4;
        landmarks[8] = 9 * k + 4;
        (mesh, landmarks)
    }

    /// The lid gap of `positions` measured by `gauge` with both eyes asked to close.
    fn closing_gap(gauge: &Gauge, positions: &[Vec3]) -> f32 {
        let expect = Expect {
            lids_close: Some(Eyes::Both),
            jaw_opens: false,
        };
        gauge.measure(positions, expect).lid_gap.unwrap()
    }

    #[test]
    fn rest_is_whole_and_a_fold_and_a_stretch_are_seen() {
        let (mesh, landmarks) = grid(10);
        let gauge = Gauge::new(&mesh, &landmarks, None).unwrap();
        assert!(
            (gauge.mm_per_unit() - 15.0).abs() < 1e-4,
            "90 mm over 6 units"
        );
        let rest = gauge.measure(&mesh.positions, Expect::default());
        assert_eq!((rest.turned, rest.stretch, rest.moved_mm), (0, 1.0, 0.0));
        assert!(rest.failures().is_empty());
        let mut folded = mesh.positions.clone();
        folded[55].x += 3.0;
        let bad = gauge.measure(&folded, Expect::default());
        assert!(bad.turned > 0 && bad.stretch > MAX_STRETCH, "{bad:?}");
        assert!((bad.moved_mm - 45.0).abs() < 1e-3);
        assert_eq!(bad.failures().len(), 2);
    }

    #[test]
    fn a_jaw_that_stays_and_lids_that_stay_open_fail() {
        let (mesh, landmarks) = grid(10);
        let gauge = Gauge::new(&mesh, &landmarks, Some(10.0)).unwrap();
        let expect = Expect {
            lids_close: Some(Eyes::Both),
            jaw_opens: true,
        };
        let still = gauge.measure(&mesh.positions, expect);
        assert_eq!(still.lid_gap, Some(1.0));
        assert_eq!(still.jaw_drop_mm, Some(0.0));
        assert_eq!(still.failures().len(), 2, "{:?}", still.failures());
        // everything below the middle row drops 2 units (20 mm): the jaw opens
        let dropped: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| if p.y < -4.5 { *p - Vec3::Y * 2.0 } else { *p })
            .collect();
        let open = gauge.measure(
            &dropped,
            Expect {
                lids_close: None,
                jaw_opens: true,
            },
        );
        assert!((open.jaw_drop_mm.unwrap() - 20.0).abs() < 1e-3, "{open:?}");
    }

    /// Lids looked at from the front: an upper lid landmark that comes down onto the lower
    /// one's height but stays in front of it (an uneven mesh's lids lie up to a millimetre
    /// apart in depth) is closed; one that stops halfway down leaves half the opening,
    /// wherever it lies in depth.
    #[test]
    fn lids_that_meet_one_in_front_of_the_other_count_as_closed() {
        let (mesh, landmarks) = grid(10);
        let gauge = Gauge::new(&mesh, &landmarks, Some(10.0)).unwrap();
        let at = |i: usize| mesh.positions[landmarks[i] as usize];
        let moved = |share: f32| {
            let mut p = mesh.positions.clone();
            for pairs in &LID_PAIRS {
                for &(upper, lower) in pairs {
                    let down = at(lower) - at(upper);
                    // a unit in front of the face (the grid lies in z = 0)
                    p[landmarks[upper] as usize] = at(upper) + down * share + Vec3::Z;
                }
            }
            p
        };
        let closed = closing_gap(&gauge, &moved(1.0));
        assert!(closed < 1e-5, "{closed}");
        let half = closing_gap(&gauge, &moved(0.5));
        assert!((half - 0.5).abs() < 1e-5, "{half}");
    }

    #[test]
    fn lids_that_meet_a_little_apart_along_the_lid_count_as_closed() {
        let (mesh, landmarks) = grid(10);
        let gauge = Gauge::new(&mesh, &landmarks, Some(10.0)).unwrap();
        let mut closed = mesh.positions.clone();
        for (eye, pairs) in LID_PAIRS.iter().enumerate() {
            let (inner, outer) = EYE_CORNERS[eye];
            let at = |i: usize| mesh.positions[landmarks[i] as usize];
            let along = (at(outer) - at(inner)).normalize_or_zero();
            for &(upper, lower) in pairs {
                // On the lower lid's line across the eye, half a unit along it.
                closed[landmarks[upper] as usize] = at(lower) + along * 0.5;
            }
        }
        let gap = closing_gap(&gauge, &closed);
        assert!(gap < 1e-5, "{gap}");
    }
}
