//! The 68 facial landmarks of the iBUG 300-W scheme (the one dlib and OpenFace 2.0 use), as
//! vertex numbers or points, and what fitting needs from them: the face's own frame, checks
//! that a set is usable, and the correspondence for MediaPipe face meshes.
//!
//! Numbering (0-based): 0-16 jaw line from the subject's right to left; 17-21 right brow
//! (outer to inner); 22-26 left brow (inner to outer); 27-30 nose bridge down to the tip;
//! 31-35 nostrils right to left (33 below the tip); 36-41 right eye (36 outer corner, 37-38
//! upper lid, 39 inner corner, 40-41 lower lid); 42-47 left eye (42 inner corner, 43-44 upper
//! lid, 45 outer corner, 46-47 lower lid); 48-59 outer lip line (48 right corner, 51 top, 54
//! left corner, 57 bottom); 60-67 inner lip line (60 right corner, 62 upper middle, 64 left
//! corner, 66 lower middle).

use glam::{DVec3, Vec3};
use thiserror::Error;

use crate::model::Mesh;

/// Number of landmarks in the scheme.
pub const COUNT: usize = 68;

/// Outer lip corners (subject's right, left).
pub const MOUTH_CORNERS: [usize; 2] = [48, 54];
/// The inner lip line's upper half, right corner to left corner.
pub const INNER_UPPER: [usize; 5] = [60, 61, 62, 63, 64];
/// The inner lip line's lower half, right corner to left corner.
pub const INNER_LOWER: [usize; 5] = [60, 67, 66, 65, 64];
/// Right eye: upper lid from the outer corner to the inner corner.
pub const RIGHT_EYE_UPPER: [usize; 4] = [36, 37, 38, 39];
/// Right eye: lower lid from the outer corner to the inner corner.
pub const RIGHT_EYE_LOWER: [usize; 4] = [36, 41, 40, 39];
/// Left eye: upper lid from the inner corner to the outer corner.
pub const LEFT_EYE_UPPER: [usize; 4] = [42, 43, 44, 45];
/// Left eye: lower lid from the inner corner to the outer corner.
pub const LEFT_EYE_LOWER: [usize; 4] = [42, 47, 46, 45];

/// The six landmarks round each eye's opening: the subject's right eye, then the left.
pub const EYES: [[usize; 6]; 2] = [[36, 37, 38, 39, 40, 41], [42, 43, 44, 45, 46, 47]];

/// The centre of an eye's opening (one of [`EYES`]): the mean of its six landmarks.
pub fn eye_centre(points: &[Vec3], eye: [usize; 6]) -> DVec3 {
    eye.iter().map(|&i| points[i].as_dvec3()).sum::<DVec3>() / 6.0
}

/// The chin's lowest point.
pub const CHIN: usize = 8;
/// The nose tip.
pub const NOSE_TIP: usize = 30;

/// The mirror partner of each landmark (itself on the midline).
pub fn mirror(i: usize) -> usize {
    match i {
        0..=16 => 16 - i,
        17..=26 => 43 - i,
        27..=30 => i,
        31..=35 => 66 - i,
        36..=39 => 81 - i,
        40 | 41 => 87 - i,
        42..=45 => 81 - i,
        46 | 47 => 87 - i,
        48..=54 => 102 - i,
        55..=59 => 114 - i,
        60..=64 => 124 - i,
        _ => 132 - i,
    }
}

/// What each landmark marks, in words (the subject's left and right).
pub const NAMES: [&str; COUNT] = [
    "jaw line, right, at the ear",
    "jaw line, right, below the ear",
    "jaw line, right, upper",
    "jaw line, right, above the corner",
    "jaw corner, right",
    "jaw line, right, below the corner",
    "jaw line, right, lower",
    "jaw line, right, beside the chin",
    "chin, lowest point",
    "jaw line, left, beside the chin",
    "jaw line, left, lower",
    "jaw line, left, below the corner",
    "jaw corner, left",
    "jaw line, left, above the corner",
    "jaw line, left, upper",
    "jaw line, left, below the ear",
    "jaw line, left, at the ear",
    "right brow, outer end",
    "right brow, outer middle",
    "right brow, middle",
    "right brow, inner middle",
    "right brow, inner end",
    "left brow, inner end",
    "left brow, inner middle",
    "left brow, middle",
    "left brow, outer middle",
    "left brow, outer end",
    "nose bridge, top (between the eyes)",
    "nose bridge, upper middle",
    "nose bridge, lower middle",
    "nose tip",
    "right nostril, outer edge",
    "right nostril, inner",
    "below the nose tip (columella)",
    "left nostril, inner",
    "left nostril, outer edge",
    "right eye, outer corner",
    "right eye, upper lid, outer",
    "right eye, upper lid, inner",
    "right eye, inner corner",
    "right eye, lower lid, inner",
    "right eye, lower lid, outer",
    "left eye, inner corner",
    "left eye, upper lid, inner",
    "left eye, upper lid, outer",
    "left eye, outer corner",
    "left eye, lower lid, outer",
    "left eye, lower lid, inner",
    "mouth corner, right (outer lip line)",
    "upper lip, right, outer line",
    "upper lip, right of the middle, outer line",
    "upper lip, middle, outer line",
    "upper lip, left of the middle, outer line",
    "upper lip, left, outer line",
    "mouth corner, left (outer lip line)",
    "lower lip, left, outer line",
    "lower lip, left of the middle, outer line",
    "lower lip, middle, outer line",
    "lower lip, right of the middle, outer line",
    "lower lip, right, outer line",
    "mouth corner, right (inner lip line)",
    "upper lip, right, inner line",
    "upper lip, middle, inner line",
    "upper lip, left, inner line",
    "mouth corner, left (inner lip line)",
    "lower lip, left, inner line",
    "lower lip, middle, inner line",
    "lower lip, right, inner line",
];

/// MediaPipe face-mesh vertex for each of the 68 landmarks: vertex `i` of a MediaPipe mesh
/// is face-mesh landmark `i`, so such meshes need no landmark file.
pub const MEDIAPIPE: [u32; COUNT] = [
    127, 234, 93, 132, 58, 136, 150, 176, 152, 400, 379, 365, 288, 361, 323, 454, 356, // jaw
    70, 63, 105, 66, 107, 336, 296, 334, 293, 300, // brows
    168, 197, 5, 4, 75, 97, 2, 326, 305, // nose
    33, 160, 158, 133, 153, 144, 362, 385, 387, 263, 373, 380, // eyes
    61, 39, 37, 0, 267, 269, 291, 405, 314, 17, 84, 181, // outer lips
    78, 82, 13, 312, 308, 317, 14, 87, // inner lips
];

/// Number of vertices of a MediaPipe face mesh (468, or 478 with the irises).
pub const MEDIAPIPE_VERTICES: [usize; 2] = [468, 478];

/// Landmarks as given: vertex numbers of the mesh, or points in its coordinates.
#[derive(Debug, Clone, PartialEq)]
pub enum Landmarks {
    /// Vertex numbers (0-based), one per landmark.
    Vertices(Vec<u32>),
    /// Points in the mesh's coordinates, one per landmark.
    Points(Vec<Vec3>),
}

/// Why a landmark set cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LandmarkError {
    /// Not 68 landmarks.
    #[error("{found} landmarks given; the iBUG scheme has exactly {COUNT}")]
    Count {
        /// How many were given.
        found: usize,
    },
    /// A vertex number the mesh does not have.
    #[error("landmark {landmark} is vertex {vertex}, but the mesh has only {count} vertices")]
    VertexOutOfRange {
        /// The landmark (0-based).
        landmark: usize,
        /// The vertex given.
        vertex: u32,
        /// Vertices in the mesh.
        count: usize,
    },
    /// A point that is not finite.
    #[error("landmark {landmark} is not a finite point")]
    NonFinite {
        /// The landmark (0-based).
        landmark: usize,
    },
    /// The landmarks do not span a face (all on one point, or on a line).
    #[error("the landmarks do not span a face: they lie on one point or on a line")]
    Degenerate,
    /// The landmarks lie in one plane: the nose tip does not stand out of the face.
    #[error(
        "the landmarks lie in one plane (the nose tip, 30, is not in front of the eyes and \
         mouth): grimace needs their 3D positions on the mesh, not a 2D image's"
    )]
    Planar,
    /// The points are so far from the origin, for their spread, that single precision
    /// cannot tell them apart.
    #[error(
        "the landmarks lie about {offset:.3e} units from the origin but only {spread:.3e} \
         apart: single-precision numbers cannot tell them apart there; move the mesh nearer \
         the origin"
    )]
    FarFromOrigin {
        /// Distance of the landmarks' centre from the origin.
        offset: f64,
        /// Their spread.
        spread: f64,
    },
    /// One landmark lies far from all the others.
    #[error(
        "landmark {landmark} lies {times:.0} times farther from the face's centre than the \
         others do: it is not on this face"
    )]
    Outlier {
        /// The landmark (0-based).
        landmark: usize,
        /// Its distance from the median centre over the other landmarks' median distance.
        times: f64,
    },
    /// The landmarks are not in the iBUG scheme's order.
    #[error("the landmarks are not in the iBUG order: {problems}")]
    OutOfOrder {
        /// What is out of order (the first few problems).
        problems: String,
    },
    /// The landmarks are the template's mirror image.
    #[error(
        "the landmarks are mirrored: the subject's left and right are swapped relative to the \
         template (check the order of the points: 0 is on the subject's right, 16 on the left)"
    )]
    Mirrored,
    /// `--landmarks mediapipe` on a mesh that is not a MediaPipe face mesh.
    #[error(
        "the mesh has {count} vertices; a MediaPipe face mesh has 468 (or 478 with the \
         irises), so `--landmarks mediapipe` does not apply"
    )]
    NotMediapipe {
        /// Vertices in the mesh.
        count: usize,
    },
}

impl Landmarks {
    /// The MediaPipe correspondence, for a mesh with a MediaPipe face mesh's vertex count.
    pub fn mediapipe(mesh: &Mesh) -> Result<Landmarks, LandmarkError> {
        let count = mesh.vertex_count();
        if !MEDIAPIPE_VERTICES.contains(&count) {
            return Err(LandmarkError::NotMediapipe { count });
        }
        Ok(Landmarks::Vertices(MEDIAPIPE.to_vec()))
    }

    /// Number of landmarks given.
    pub fn len(&self) -> usize {
        match self {
            Landmarks::Vertices(v) => v.len(),
            Landmarks::Points(p) => p.len(),
        }
    }

    /// True when no landmark is given.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Checks what can be checked without a mesh: the count and finite points.
    pub fn check(&self) -> Result<(), LandmarkError> {
        if self.len() != COUNT {
            return Err(LandmarkError::Count { found: self.len() });
        }
        if let Landmarks::Points(points) = self {
            if let Some(landmark) = points.iter().position(|p| !p.is_finite()) {
                return Err(LandmarkError::NonFinite { landmark });
            }
        }
        Ok(())
    }

    /// The landmark positions on `mesh`, checked: 68 of them, every vertex in range, not
    /// degenerate.
    pub fn positions(&self, mesh: &Mesh) -> Result<Vec<Vec3>, LandmarkError> {
        self.check()?;
        let points = match self {
            Landmarks::Vertices(vertices) => {
                let count = mesh.vertex_count();
                vertices
                    .iter()
                    .enumerate()
                    .map(|(landmark, &vertex)| {
                        mesh.positions.get(vertex as usize).copied().ok_or(
                            LandmarkError::VertexOutOfRange {
                                landmark,
                                vertex,
                                count,
                            },
                        )
                    })
                    .collect::<Result<Vec<_>, _>>()?
            }
            Landmarks::Points(points) => points.clone(),
        };
        check_shape(&points)?;
        Ok(points)
    }

    /// The vertex of each landmark: as given, or the mesh vertex nearest each point.
    pub fn vertices(&self, mesh: &Mesh) -> Vec<u32> {
        match self {
            Landmarks::Vertices(v) => v.clone(),
            Landmarks::Points(points) => points
                .iter()
                .map(|p| nearest_vertex(&mesh.positions, *p))
                .collect(),
        }
    }
}

/// The vertex nearest a point (0 for an empty list).
pub fn nearest_vertex(positions: &[Vec3], p: Vec3) -> u32 {
    let mut best = (f32::INFINITY, 0u32);
    for (i, q) in positions.iter().enumerate() {
        let d = q.distance_squared(p);
        if d < best.0 {
            best = (d, i as u32);
        }
    }
    best.1
}

/// Refuses landmark sets that do not span a face, saying why: one far outlier, points past
/// single precision, a plane, or every point nearly on one point or line.
pub fn check_shape(points: &[Vec3]) -> Result<(), LandmarkError> {
    if points.len() != COUNT {
        return Err(LandmarkError::Count {
            found: points.len(),
        });
    }
    // A point far beyond all the others is never part of the face, whatever the frame says.
    if let outlier @ LandmarkError::Outlier { .. } = why_not_a_face(points) {
        return Err(outlier);
    }
    let Some(frame) = FaceFrame::of(points) else {
        return Err(why_not_a_face(points));
    };
    let spread = rms_spread(&points.iter().map(|p| p.as_dvec3()).collect::<Vec<_>>());
    // The eye line and the eyes-to-mouth line must both be a fair part of the face.
    if !(frame.eye_distance > 0.2 * spread && frame.eyes_to_mouth > 0.2 * spread) {
        return Err(why_not_a_face(points));
    }
    Ok(())
}

/// Why a set does not span a face, most specific first.
fn why_not_a_face(points: &[Vec3]) -> LandmarkError {
    let p: Vec<DVec3> = points.iter().map(|p| p.as_dvec3()).collect();
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let centre = DVec3::new(
        median(p.iter().map(|q| q.x).collect()),
        median(p.iter().map(|q| q.y).collect()),
        median(p.iter().map(|q| q.z).collect()),
    );
    let distances: Vec<f64> = p.iter().map(|q| q.distance(centre)).collect();
    let typical = median(distances.clone());
    if let Some((landmark, far)) = distances
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
    {
        if typical > 0.0 && far > 20.0 * typical {
            return LandmarkError::Outlier {
                landmark,
                times: far / typical,
            };
        }
    }
    // Points a few float steps apart: their spread is lost against their offset.
    let offset = centre.length();
    let step = offset * f64::from(f32::EPSILON);
    // (Points given as one, near the origin, are one point, not a precision loss.)
    if (typical > 0.0 && typical < 64.0 * step) || (typical == 0.0 && offset >= 1e6) {
        return LandmarkError::FarFromOrigin {
            offset,
            spread: typical,
        };
    }
    let mean = p.iter().copied().sum::<DVec3>() / p.len() as f64;
    let mut covariance = glam::DMat3::ZERO;
    for q in &p {
        let d = *q - mean;
        covariance += glam::DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    // The smallest principal spread against the middle one: a plane has none across it.
    let trace = covariance.x_axis.x + covariance.y_axis.y + covariance.z_axis.z;
    let det = covariance.determinant();
    let spread2 = trace / 3.0;
    if spread2 > 0.0 && det.abs() < 1e-9 * spread2.powi(3) && covariance_rank2(&covariance, spread2)
    {
        return LandmarkError::Planar;
    }
    LandmarkError::Degenerate
}

/// Whether a covariance matrix with determinant near zero still spans two directions (a
/// plane, not a line): some 2x2 principal minor stays large.
fn covariance_rank2(c: &glam::DMat3, spread2: f64) -> bool {
    let minors = [
        c.x_axis.x * c.y_axis.y - c.y_axis.x * c.x_axis.y,
        c.x_axis.x * c.z_axis.z - c.z_axis.x * c.x_axis.z,
        c.y_axis.y * c.z_axis.z - c.z_axis.y * c.y_axis.z,
    ];
    minors.iter().any(|m| *m > 1e-3 * spread2 * spread2)
}

/// Which side of the face landmark `i` marks: -1 the subject's right, +1 the subject's left,
/// 0 the midline. The subject's left is `+lateral` in [`FaceFrame`].
pub fn side(i: usize) -> i8 {
    match i {
        0..=7 | 17..=21 | 31 | 32 | 36..=41 | 48..=50 | 58..=61 | 67 => -1,
        9..=16 | 22..=26 | 34 | 35 | 42..=47 | 52..=56 | 63..=65 => 1,
        _ => 0,
    }
}

/// How the points of one contour of the scheme follow each other, seen from the front with
/// the subject's left to the right of the picture (the face frame's `lateral`, `up`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Order {
    /// Going round the nose from the subject's right ear down past the chin to the left
    /// (the jaw line): counter-clockwise about the nose.
    RoundTheChin,
    /// From the subject's right to the left (brows, nostrils).
    RightToLeft,
    /// From the top down (the nose bridge).
    Downward,
    /// A closed loop, clockwise: along the top from the subject's right corner to the left,
    /// back along the bottom, each top point above its bottom partner (eyes, lips).
    Clockwise,
}

/// The contours of the scheme: name, first and last landmark, and their order.
pub const CONTOURS: [(&str, usize, usize, Order); 9] = [
    ("jaw line", 0, 16, Order::RoundTheChin),
    ("right brow", 17, 21, Order::RightToLeft),
    ("left brow", 22, 26, Order::RightToLeft),
    ("nose bridge", 27, 30, Order::Downward),
    ("nostrils", 31, 35, Order::RightToLeft),
    ("right eye", 36, 41, Order::Clockwise),
    ("left eye", 42, 47, Order::Clockwise),
    ("outer lip line", 48, 59, Order::Clockwise),
    ("inner lip line", 60, 67, Order::Clockwise),
];

/// What is out of order in a set of 68 landmark points against the iBUG scheme: each point
/// of one side on that side of the midline (the face's own frame: the subject's left is the
/// side of the left eye, 42-47), and each contour ([`CONTOURS`]) in its order. Empty when
/// the set follows the scheme. A set swapped as a whole (an image's left taken for the
/// subject's) passes: its frame swaps with it, and [`FaceFrame::right_handed`] tells.
pub fn order_problems(points: &[Vec3]) -> Vec<String> {
    let Some(frame) = FaceFrame::of(points) else {
        return vec!["the landmarks do not span a face".into()];
    };
    let midline: Vec<DVec3> = (0..COUNT)
        .filter(|&i| side(i) == 0)
        .map(|i| points[i].as_dvec3())
        .collect();
    let origin = midline.iter().copied().sum::<DVec3>() / midline.len() as f64;
    let flat: Vec<(f64, f64)> = points
        .iter()
        .map(|p| {
            let l = frame.local(origin, p.as_dvec3());
            (l.x, l.y)
        })
        .collect();
    let mut problems = Vec::new();
    for (i, &(x, _)) in flat.iter().enumerate() {
        let s = f64::from(side(i));
        if s != 0.0 && x * s <= 0.0 {
            let wrong = if s > 0.0 { "right" } else { "left" };
            problems.push(format!(
                "landmark {i} ({}) lies on the subject's {wrong} side",
                NAMES[i]
            ));
        }
    }
    for &(name, first, last, order) in &CONTOURS {
        if !in_order(&flat, first, last, order) {
            problems.push(format!(
                "the {name} ({first}-{last}) is not in the scheme's order ({})",
                match order {
                    Order::RoundTheChin => "from the subject's right ear round the chin to the left",
                    Order::RightToLeft => "from the subject's right to the left",
                    Order::Downward => "from the top down",
                    Order::Clockwise =>
                        "from the subject's right corner along the top to the left, back along the bottom",
                }
            ));
        }
    }
    problems
}

/// Whether landmarks `first..=last` of `flat` (front-view coordinates) follow `order`.
/// Neighbours may coincide (a coarse mesh snaps two points to one vertex, a closed mouth puts
/// its inner lips on one line), but no step goes back and the ends differ.
fn in_order(flat: &[(f64, f64)], first: usize, last: usize, order: Order) -> bool {
    let x = |i: usize| flat[i].0;
    let y = |i: usize| flat[i].1;
    // Along `ids` the key never falls and ends higher than it starts.
    let rising = |ids: &[usize], key: &dyn Fn(usize) -> f64| {
        ids.windows(2).all(|w| key(w[1]) >= key(w[0])) && key(ids[ids.len() - 1]) > key(ids[0])
    };
    let run: Vec<usize> = (first..=last).collect();
    match order {
        Order::RightToLeft => rising(&run, &x),
        Order::Downward => rising(&run, &|i| -y(i)),
        Order::RoundTheChin => {
            // Counter-clockwise about the nose, less than a full turn.
            let (cx, cy) = mean_of(&flat[27..=35]);
            let angle = |i: usize| (y(i) - cy).atan2(x(i) - cx);
            let turns: Vec<f64> = run
                .windows(2)
                .map(|w| {
                    let t = angle(w[1]) - angle(w[0]);
                    t - std::f64::consts::TAU * (t / std::f64::consts::TAU).round()
                })
                .collect();
            turns.iter().all(|&t| t >= 0.0)
                && (0.0..std::f64::consts::TAU).contains(&turns.iter().sum::<f64>())
        }
        Order::Clockwise => {
            // The top runs right to left corner, the bottom back; each top point lies above
            // its bottom partner (the one as far from the corners), or level with it within
            // 1% of the corners' distance: a closed mouth's lips meet.
            let corner = first + (last + 1 - first) / 2;
            let bottom: Vec<usize> = (corner..=last).chain([first]).collect();
            let level = 0.01 * (x(corner) - x(first)).abs();
            rising(&run[..=corner - first], &x)
                && rising(&bottom, &|i| -x(i))
                && (first + 1..corner).all(|i| y(i) >= y(first + last + 1 - i) - level)
        }
    }
}

/// The mean of some front-view points.
fn mean_of(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len().max(1) as f64;
    let (x, y) = points
        .iter()
        .fold((0.0, 0.0), |(x, y), p| (x + p.0, y + p.1));
    (x / n, y / n)
}

/// A face's own frame from its landmarks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceFrame {
    /// Unit vector from the subject's right toward the left (between the eye centres).
    pub lateral: DVec3,
    /// Unit vector from the mouth toward the eyes, made orthogonal to `lateral`.
    pub up: DVec3,
    /// Unit vector out of the face (toward the nose tip's side).
    pub forward: DVec3,
    /// Whether `lateral x up` points out of the face (a right-handed face) or into it.
    pub right_handed: bool,
    /// Distance between the eye centres.
    pub eye_distance: f64,
    /// Distance from the eye centres' midpoint to the mouth's centre.
    pub eyes_to_mouth: f64,
}

impl FaceFrame {
    /// The frame of a set of 68 landmarks; `None` when the eyes or mouth coincide.
    pub fn of(points: &[Vec3]) -> Option<FaceFrame> {
        if points.len() != COUNT {
            return None;
        }
        let mean = |ids: &[usize]| {
            ids.iter().map(|&i| points[i].as_dvec3()).sum::<DVec3>() / ids.len() as f64
        };
        let right_eye = eye_centre(points, EYES[0]);
        let left_eye = eye_centre(points, EYES[1]);
        let mouth = mean(&[48, 51, 54, 57, 60, 62, 64, 66]);
        let eyes = 0.5 * (right_eye + left_eye);
        let across = left_eye - right_eye;
        let eye_distance = across.length();
        let lateral = across.normalize_or_zero();
        let rise = eyes - mouth;
        let eyes_to_mouth = rise.length();
        let up = (rise - lateral * rise.dot(lateral)).normalize_or_zero();
        if lateral == DVec3::ZERO || up == DVec3::ZERO {
            return None;
        }
        let normal = lateral.cross(up);
        // The nose tip stands out of the face: in front of the eyes-mouth plane.
        let nose = points[NOSE_TIP].as_dvec3() - 0.5 * (eyes + mouth);
        let out = nose.dot(normal);
        if out == 0.0 || !out.is_finite() {
            return None;
        }
        Some(FaceFrame {
            lateral,
            up,
            forward: normal * out.signum(),
            right_handed: out > 0.0,
            eye_distance,
            eyes_to_mouth,
        })
    }

    /// Coordinates of `p` in this frame about `origin`: (across, up, out of the face).
    pub fn local(&self, origin: DVec3, p: DVec3) -> DVec3 {
        let d = p - origin;
        DVec3::new(d.dot(self.lateral), d.dot(self.up), d.dot(self.forward))
    }
}

/// The outer canthal distance of an adult face, in mm: the scale when units are unknown.
pub const CANTHAL_MM: f32 = 90.0;

/// Millimetres per mesh unit estimated from the 68 landmark points: the outer canthal
/// distance (landmarks 36 and 45) taken as [`CANTHAL_MM`], a typical adult's. `None` when the
/// set is not 68 points or the two corners coincide. The one estimate every command uses when
/// a mesh's units are not known (`check`, `export`'s hint).
pub fn mm_per_unit(points: &[Vec3]) -> Option<f32> {
    let canthal = (points.len() == COUNT).then(|| points[36].distance(points[45]))?;
    (canthal.is_finite() && canthal > 0.0).then(|| CANTHAL_MM / canthal)
}

/// The root-mean-square distance of points from their centroid.
pub fn rms_spread(points: &[DVec3]) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let mean = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    (points.iter().map(|p| p.distance_squared(mean)).sum::<f64>() / points.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn builtin_points() -> Vec<Vec3> {
        let mesh = crate::io::builtin::default_mesh();
        crate::io::builtin::landmarks("default")
            .unwrap()
            .positions(&mesh)
            .unwrap()
    }

    #[test]
    fn a_set_that_is_no_face_is_refused_for_its_own_reason() {
        let good = builtin_points();
        assert_eq!(check_shape(&good), Ok(()));
        let mut flat = good.clone();
        for p in &mut flat {
            p.z = 0.0;
        }
        assert_eq!(check_shape(&flat), Err(LandmarkError::Planar));
        let mut outlier = good.clone();
        outlier[40] = Vec3::new(1e4, 0.0, 0.0);
        assert!(matches!(
            check_shape(&outlier),
            Err(LandmarkError::Outlier { landmark: 40, .. })
        ));
        let far: Vec<Vec3> = good.iter().map(|p| *p * 1e-3 + Vec3::splat(1e6)).collect();
        assert!(matches!(
            check_shape(&far),
            Err(LandmarkError::FarFromOrigin { .. })
        ));
        let line: Vec<Vec3> = (0..COUNT).map(|i| Vec3::X * i as f32).collect();
        assert_eq!(check_shape(&line), Err(LandmarkError::Degenerate));
        assert_eq!(check_shape(&[]), Err(LandmarkError::Count { found: 0 }));
    }

    #[test]
    fn mirror_is_an_involution_that_keeps_the_midline() {
        for i in 0..COUNT {
            assert_eq!(mirror(mirror(i)), i, "landmark {i}");
        }
        for i in [8, 27, 28, 29, 30, 33, 51, 57, 62, 66] {
            assert_eq!(mirror(i), i);
        }
        assert_eq!(mirror(36), 45);
        assert_eq!(mirror(37), 44);
        assert_eq!(mirror(41), 46);
        assert_eq!(mirror(48), 54);
        assert_eq!(mirror(55), 59);
        assert_eq!(mirror(61), 63);
        assert_eq!(mirror(67), 65);
    }

    #[test]
    fn names_follow_the_mirror() {
        for i in 0..COUNT {
            let (a, b) = (NAMES[i], NAMES[mirror(i)]);
            if mirror(i) == i {
                assert!(!a.contains("left") && !a.contains("right"), "{i}: {a}");
            } else {
                assert_eq!(
                    a.replace("left", "right"),
                    b.replace("left", "right"),
                    "{i}"
                );
                assert_ne!(a, b, "{i}");
            }
        }
    }

    #[test]
    fn sides_follow_the_mirror_and_the_names() {
        for (i, name) in NAMES.iter().enumerate() {
            assert_eq!(side(mirror(i)), -side(i), "landmark {i}");
            let want = if name.contains("right") {
                -1
            } else if name.contains("left") {
                1
            } else {
                0
            };
            assert_eq!(side(i), want, "{i}: {name}");
        }
    }

    #[test]
    fn mediapipe_table_has_distinct_vertices() {
        let mut v = MEDIAPIPE.to_vec();
        v.sort_unstable();
        v.dedup();
        assert_eq!(v.len(), COUNT);
        assert!(v.iter().all(|&i| i < 468));
    }
}
