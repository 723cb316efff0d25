//! The paper's extra muscles on the classic Waters face: the two frontalis sheets, the mouth
//! and eye sphincters and the jaw, placed from the imported mesh's own geometry.
//!
//! The classic files describe only 18 linear muscles. The paper adds sheet and sphincter
//! muscles and a jaw; this module places them for that mesh by finding landmarks in it, never
//! from typed-in coordinates or vertex numbers:
//!
//! - the mouth, as the hole crossing the midline (the classic mouth is a slit of
//!   close-but-distinct vertices), split at its leftmost and rightmost vertices into the upper
//!   and lower lip;
//! - the eyes, as the widest hole on each side above the mouth, split the same way into the
//!   upper and lower lid;
//! - the brows, at a fixed fraction of the eye opening's height above the upper lid;
//! - the chin, as the lowest midline vertex; the top of the forehead, as the highest vertex;
//! - the depth of the head, as the deepest vertex.
//!
//! The skin height under a front-view point comes from [`rigs::skin_under`]. Every muscle is
//! placed on the subject's left (x > 0: the import converts the classic data to glTF's
//! convention, see [`crate::io::waters`]) and mirrored exactly, so the rig is
//! mirror-symmetric.
//! `docs/model.md` ("The paper's rig on the classic face") describes the placement.

use std::collections::{BTreeMap, BTreeSet};

use glam::Vec3;
use thiserror::Error;

use super::rigs;
use super::topology;
use super::{round3, rounded};
use crate::fit::propose::carry;
use crate::fit::regions::smoothstep;
use crate::model::{Convergence, Frame, Jaw, Mesh, Muscle, MuscleKind, Sheet, Side, Sphincter};

/// Jaw rotation in degrees per unit of jaw activation on the classic face. The paper's 1
/// degree per unit (K in 0..4 degrees) opens the classic mouth by about 0.6 units (6 mm at the
/// face's scale of about 1 unit per centimetre) at K = 4, which barely shows in a terminal
/// wireframe; 2.5 degrees per unit turns the jaw 10 degrees at K = 4 and opens the lips about
/// 1.5 units, a clear but natural jaw drop.
pub const CLASSIC_JAW_DEGREES_PER_UNIT: f32 = 2.5;

/// Height of the brow line above the top of the upper lid, as a fraction of the eye
/// opening's height (the classic brows sit a little more than half an opening above the lid).
const BROW_ABOVE_LID: f32 = 0.6;

/// Height of the jaw pivot between the mouth line (0) and the eye line (1): the
/// temporomandibular joint sits at about the height of the nose's base.
const PIVOT_HEIGHT: f32 = 0.45;

/// The middle of the lower lip that turns fully with the jaw, as a fraction of the mouth's
/// half-width; from there the weight falls smoothly to 0 at the corner.
const LIP_MIDDLE: f64 = 0.3;

/// Why the extra muscles cannot be placed on a mesh.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ClassicError {
    /// A feature the placement needs was not found.
    #[error("cannot place the paper's extra muscles: {0} (is this the classic Waters face?)")]
    Missing(&'static str),
    /// No skin lies under a point where a muscle must go.
    #[error("cannot place `{muscle}`: no skin under x = {x:.3}, y = {y:.3}")]
    NoSkin {
        /// The muscle being placed.
        muscle: String,
        /// Front-view x.
        x: f32,
        /// Front-view y.
        y: f32,
    },
    /// The template's landmarks cannot be warped onto the found ones.
    #[error(
        "cannot carry the template's landmarks onto this face: the points found do not span it"
    )]
    Warp,
}

/// A slit-shaped hole of the mesh (the mouth or an eye), split into its two margins.
#[derive(Debug, Clone, PartialEq)]
pub struct Opening {
    /// The vertices of the upper margin (upper lip or lid), corners excluded.
    pub upper: Vec<u32>,
    /// The vertices of the lower margin, corners excluded.
    pub lower: Vec<u32>,
    /// The leftmost (smallest x) and rightmost vertex of the hole.
    pub corners: [u32; 2],
}

impl Opening {
    /// The margin vertex nearest in x to `x` (the middle of a lid or lip).
    fn nearest(margin: &[u32], positions: &[Vec3], x: f32) -> Option<u32> {
        margin.iter().copied().min_by(|&a, &b| {
            (positions[a as usize].x - x)
                .abs()
                .total_cmp(&(positions[b as usize].x - x).abs())
        })
    }

    /// The middle of the upper and of the lower margin: the vertices nearest the centre's x.
    pub fn centres(&self, positions: &[Vec3]) -> Option<(Vec3, Vec3)> {
        let [a, b] = self.corners.map(|v| positions[v as usize]);
        let x = 0.5 * (a.x + b.x);
        let upper = Self::nearest(&self.upper, positions, x)?;
        let lower = Self::nearest(&self.lower, positions, x)?;
        Some((positions[upper as usize], positions[lower as usize]))
    }
}

/// The features of the classic face the placement uses, found by geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct Landmarks {
    /// The mouth slit.
    pub mouth: Opening,
    /// The subject's right eye opening (x < 0).
    pub right_eye: Opening,
    /// The subject's left eye opening (x > 0).
    pub left_eye: Opening,
    /// The lowest vertex on the midline.
    pub chin: Vec3,
    /// The highest vertex.
    pub top: Vec3,
    /// The smallest z of any vertex (the back of the mask).
    pub deepest_z: f32,
}

/// The hook for [`crate::io::waters::ImportOptions::extras`]: the paper's 2 sheet muscles, 3
/// sphincters and jaw placed on the classic face. A mesh where the landmarks cannot be found
/// gets none; call [`place_extras`] for the reason.
pub fn extra_muscles(mesh: &Mesh) -> (Vec<Muscle>, Option<Jaw>) {
    match place_extras(mesh) {
        Ok((muscles, jaw)) => (muscles, Some(jaw)),
        Err(_) => (Vec::new(), None),
    }
}

/// Places the paper's extra muscles on the classic face: `L_` and `R_Frontalis_Sheet`,
/// `Orbicularis_Oris`, `L_` and `R_Orbicularis_Oculi` (the names of `presets/paper.rig.ron`),
/// and the jaw.
pub fn place_extras(mesh: &Mesh) -> Result<(Vec<Muscle>, Jaw), ClassicError> {
    let marks = find_landmarks(mesh)?;
    let skin = SkinSampler::new(mesh);
    let mut muscles = Vec::with_capacity(5);
    muscles.extend(frontalis_sheets(&marks, &skin, &mesh.positions)?);
    muscles.push(orbicularis_oris(&marks, mesh)?);
    muscles.extend(orbicularis_oculi(&marks, &mesh.positions)?);
    let jaw = jaw(&marks, &mesh.positions)?;
    Ok((muscles, jaw))
}

/// Finds the mouth, the eyes, the chin, the top and the depth of the classic face.
pub fn find_landmarks(mesh: &Mesh) -> Result<Landmarks, ClassicError> {
    let p = &mesh.positions;
    // The classic face repeats 6 triangles; they would hide boundary edges.
    let unique = without_duplicate_triangles(mesh)?;
    let mut loops = topology::boundary_loops(&unique);
    // The longest loop is the outer rim of the mask.
    loops.sort_by_key(|l| std::cmp::Reverse(l.len()));
    let holes = loops.get(1..).unwrap_or_default();
    let extent = |l: &Vec<u32>| {
        let (lo, hi) =
            crate::model::mesh::bounds_of(&l.iter().map(|&v| p[v as usize]).collect::<Vec<_>>());
        (lo, hi)
    };
    let mouth_loop = holes
        .iter()
        .filter(|l| {
            let (lo, hi) = extent(l);
            lo.x < 0.0 && hi.x > 0.0
        })
        .max_by(|a, b| width(extent(a)).total_cmp(&width(extent(b))))
        .ok_or(ClassicError::Missing(
            "no mouth opening crosses the midline",
        ))?;
    let mouth = split_opening(&unique, mouth_loop)
        .ok_or(ClassicError::Missing("the mouth opening has no two lips"))?;
    let mouth_y = p[mouth.corners[0] as usize].y;
    let eye = |positive_x: bool| {
        holes
            .iter()
            .filter(|l| {
                let (lo, hi) = extent(l);
                let side = if positive_x { lo.x > 0.0 } else { hi.x < 0.0 };
                side && lo.y > mouth_y
            })
            .max_by(|a, b| area(extent(a)).total_cmp(&area(extent(b))))
            .and_then(|l| split_opening(&unique, l))
    };
    let left_eye = eye(true).ok_or(ClassicError::Missing("no left eye opening"))?;
    let right_eye = eye(false).ok_or(ClassicError::Missing("no right eye opening"))?;
    let chin = p
        .iter()
        .filter(|v| v.x == 0.0)
        .copied()
        .min_by(|a, b| a.y.total_cmp(&b.y))
        .ok_or(ClassicError::Missing("no vertex on the midline"))?;
    let top = p
        .iter()
        .copied()
        .max_by(|a, b| a.y.total_cmp(&b.y))
        .ok_or(ClassicError::Missing("no vertices"))?;
    let deepest_z = p.iter().map(|v| v.z).fold(f32::INFINITY, f32::min);
    Ok(Landmarks {
        mouth,
        right_eye,
        left_eye,
        chin,
        top,
        deepest_z,
    })
}

/// The iBUG numbers of the points [`find_landmarks`] gives, in the order of [`found_ibug`]:
/// the eye corners, the mouth corners, the middles of the inner lips and the chin.
pub const FOUND_IBUG: [usize; 9] = [36, 39, 42, 45, 48, 54, 62, 66, 8];

/// The vertices of the classic face at the iBUG points of [`FOUND_IBUG`]. iBUG's subject's
/// right (36 to 41, 48) is at x < 0 in the glTF convention the import uses.
pub fn found_ibug(mesh: &Mesh) -> Result<[u32; 9], ClassicError> {
    let marks = find_landmarks(mesh)?;
    let p = &mesh.positions;
    let [r_out, r_in] = marks.right_eye.corners;
    let [l_in, l_out] = marks.left_eye.corners;
    let mouth = &marks.mouth;
    let middle_x = 0.5 * (p[mouth.corners[0] as usize].x + p[mouth.corners[1] as usize].x);
    let upper = Opening::nearest(&mouth.upper, p, middle_x)
        .ok_or(ClassicError::Missing("the mouth has no upper lip"))?;
    let lower = Opening::nearest(&mouth.lower, p, middle_x)
        .ok_or(ClassicError::Missing("the mouth has no lower lip"))?;
    // find_landmarks gives the chin as a point; it is the first vertex there.
    let chin = p
        .iter()
        .position(|v| *v == marks.chin)
        .ok_or(ClassicError::Missing("no vertex on the midline"))? as u32;
    Ok([
        r_out,
        r_in,
        l_in,
        l_out,
        mouth.corners[0],
        mouth.corners[1],
        upper,
        lower,
        chin,
    ])
}

/// All 68 iBUG landmarks of the classic face as its vertex numbers, carried over from a
/// template face (`template` with its 68 landmark vertices `template_marks`): the template is
/// aligned and warped onto the classic face by the points of [`found_ibug`] (a similarity
/// and a thin-plate spline, [`carry`]), every template landmark is carried through the warp
/// and snapped to the nearest classic vertex. The found points are kept exactly; the lids
/// and inner lips snap to their own margin, so a point never lands on the wrong side of the
/// closed mouth slit or an eye.
pub fn ibug_landmarks(
    mesh: &Mesh,
    template: &Mesh,
    template_marks: &[u32],
) -> Result<Vec<u32>, ClassicError> {
    let marks = find_landmarks(mesh)?;
    let found = found_ibug(mesh)?;
    let p = &mesh.positions;
    let t: Vec<Vec3> = template_marks
        .iter()
        .map(|&v| template.positions[v as usize])
        .collect();
    let known: Vec<(usize, Vec3)> = FOUND_IBUG
        .iter()
        .zip(&found)
        .map(|(&i, &v)| (i, p[v as usize]))
        .collect();
    let carried = carry(&t, &known).ok_or(ClassicError::Warp)?;
    let all: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
    let with_corners = |o: &Opening, margin: &[u32]| {
        let mut v = margin.to_vec();
        v.extend(o.corners);
        v
    };
    let margin = |i: usize| -> Vec<u32> {
        match i {
            37 | 38 => with_corners(&marks.right_eye, &marks.right_eye.upper),
            40 | 41 => with_corners(&marks.right_eye, &marks.right_eye.lower),
            43 | 44 => with_corners(&marks.left_eye, &marks.left_eye.upper),
            46 | 47 => with_corners(&marks.left_eye, &marks.left_eye.lower),
            61 | 63 => with_corners(&marks.mouth, &marks.mouth.upper),
            65 | 67 => with_corners(&marks.mouth, &marks.mouth.lower),
            // The classic mouth is a slit: its inner corners are its corners.
            60 => vec![marks.mouth.corners[0]],
            64 => vec![marks.mouth.corners[1]],
            _ => all.clone(),
        }
    };
    let landmarks = (0..template_marks.len())
        .map(|i| match FOUND_IBUG.iter().position(|&f| f == i) {
            Some(k) => found[k],
            None => {
                let q = carried[i];
                let candidates = margin(i);
                candidates
                    .iter()
                    .copied()
                    .min_by(|&a, &b| {
                        p[a as usize]
                            .distance_squared(q)
                            .total_cmp(&p[b as usize].distance_squared(q))
                    })
                    .unwrap_or(0)
            }
        })
        .collect();
    Ok(landmarks)
}

fn width((lo, hi): (Vec3, Vec3)) -> f32 {
    hi.x - lo.x
}

fn area((lo, hi): (Vec3, Vec3)) -> f32 {
    (hi.x - lo.x) * (hi.y - lo.y)
}

fn without_duplicate_triangles(mesh: &Mesh) -> Result<Mesh, ClassicError> {
    let mut seen = BTreeSet::new();
    let triangles = mesh
        .triangles
        .iter()
        .filter(|t| {
            let mut key = **t;
            key.sort_unstable();
            seen.insert(key)
        })
        .copied()
        .collect();
    Mesh::new(mesh.positions.clone(), triangles).map_err(|_| ClassicError::Missing("a valid mesh"))
}

/// Splits a hole's boundary loop at its leftmost and rightmost vertices into two margins,
/// and tells which is the upper one by the triangles along each: a margin's triangles lie on
/// its own side of the slit (the two lips of the classic mouth are only 0.004 apart, so the
/// margins' own heights cannot tell them apart).
fn split_opening(mesh: &Mesh, hole: &[u32]) -> Option<Opening> {
    let p = &mesh.positions;
    let n = hole.len();
    if n < 4 {
        return None;
    }
    let by_x = |a: &usize, b: &usize| p[hole[*a] as usize].x.total_cmp(&p[hole[*b] as usize].x);
    let left = (0..n).min_by(by_x)?;
    let right = (0..n).max_by(by_x)?;
    let chain = |from: usize, to: usize| -> Vec<usize> {
        let mut out = Vec::new();
        let mut i = (from + 1) % n;
        while i != to {
            out.push(i);
            i = (i + 1) % n;
        }
        out
    };
    // the third corner of the triangle on each directed boundary edge
    let mut third: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            third.insert((t[k], t[(k + 1) % 3]), t[(k + 2) % 3]);
        }
    }
    // positive when the triangles along the loop from `from` to `to` lie above it
    let side = |from: usize, to: usize| -> f32 {
        let mut vote = 0.0;
        let mut i = from;
        while i != to {
            let j = (i + 1) % n;
            let (a, b) = (hole[i], hole[j]);
            if let Some(&c) = third.get(&(a, b)) {
                vote += p[c as usize].y - 0.5 * (p[a as usize].y + p[b as usize].y);
            }
            i = j;
        }
        vote
    };
    let one: Vec<u32> = chain(left, right).into_iter().map(|i| hole[i]).collect();
    let other: Vec<u32> = chain(right, left).into_iter().map(|i| hole[i]).collect();
    if one.is_empty() || other.is_empty() {
        return None;
    }
    let (upper, lower) = if side(left, right) > side(right, left) {
        (one, other)
    } else {
        (other, one)
    };
    Some(Opening {
        upper,
        lower,
        corners: [hole[left], hole[right]],
    })
}

/// Skin heights under front-view points, on a copy of the mesh wound to face the viewer
/// (the classic face's triangles face into the head).
struct SkinSampler {
    front: Mesh,
}

impl SkinSampler {
    fn new(mesh: &Mesh) -> SkinSampler {
        let facing: f32 = mesh.face_normals(&mesh.positions).iter().map(|n| n.z).sum();
        let mut front = mesh.clone();
        if facing < 0.0 {
            for t in &mut front.triangles {
                t.swap(1, 2);
            }
        }
        SkinSampler { front }
    }

    fn at(&self, muscle: &str, x: f32, y: f32) -> Result<Vec3, ClassicError> {
        rigs::skin_under(&self.front, x, y).ok_or_else(|| ClassicError::NoSkin {
            muscle: muscle.to_string(),
            x,
            y,
        })
    }
}

/// The frontalis as two sheets: from the top of the forehead (the highest vertex's height
/// and depth, where the galea begins) down to a brow line above each eye, as wide as from
/// the midline to as far beyond the eye's centre; the pull fades out at the upper lid, which
/// the eye sphincter owns.
fn frontalis_sheets(
    marks: &Landmarks,
    skin: &SkinSampler,
    p: &[Vec3],
) -> Result<[Muscle; 2], ClassicError> {
    let name = "L_Frontalis_Sheet";
    let eye = &marks.left_eye;
    let [inner, outer] = eye.corners.map(|v| p[v as usize]);
    let lid_top = eye
        .upper
        .iter()
        .map(|&v| p[v as usize].y)
        .fold(f32::NEG_INFINITY, f32::max);
    let lid_bottom = eye
        .lower
        .iter()
        .map(|&v| p[v as usize].y)
        .fold(f32::INFINITY, f32::min);
    let brow_y = lid_top + BROW_ABOVE_LID * (lid_top - lid_bottom);
    let l1 = rounded(skin.at(name, inner.x, brow_y)?);
    let l2 = rounded(skin.at(name, outer.x, brow_y)?);
    let a1 = rounded(Vec3::new(inner.x, marks.top.y, marks.top.z));
    let a2 = rounded(Vec3::new(outer.x, marks.top.y, marks.top.z));
    let (ac, lc) = (0.5 * (a1 + a2), 0.5 * (l1 + l2));
    let span = ac.distance(lc);
    // The pull fades out at the upper lid: the sheet ends where its axis reaches the lid
    // margin's nearest vertex (the lid is recessed under the brow, so this is measured
    // along the axis, not in height).
    let axis = (lc - ac).normalize_or_zero();
    let lid_reach = eye
        .upper
        .iter()
        .map(|&v| (p[v as usize] - ac).dot(axis))
        .fold(f32::INFINITY, f32::min);
    let length = if lid_reach > span * 1.01 {
        lid_reach
    } else {
        span * 1.05
    };
    Ok(rigs::frontalis_pair(
        "Frontalis_Sheet",
        Sheet {
            attachment: [a1, a2],
            insertion: [l1, l2],
            length: round3(length),
            width: round3(inner.x + outer.x),
        },
    ))
}

/// The mouth sphincter, centred between the lips at the midline. Its semi-minor axis is
/// twice the larger height of the lips' most prominent midline points above and below the
/// mouth line (so the ellipse covers both vermilions), its semi-major axis reaches that far
/// beyond the mouth corners.
fn orbicularis_oris(marks: &Landmarks, mesh: &Mesh) -> Result<Muscle, ClassicError> {
    let p = &mesh.positions;
    let (upper, lower) = marks
        .mouth
        .centres(p)
        .ok_or(ClassicError::Missing("the middle of the lips"))?;
    let centre = 0.5 * (upper + lower);
    let corner_x = marks.mouth.corners.map(|v| p[v as usize].x.abs());
    let corner_x = corner_x[0].max(corner_x[1]);
    // the most prominent midline points of each lip, within a mouth's width of the line
    let prominent = |above: bool| {
        p.iter()
            .filter(|v| {
                let dy = v.y - centre.y;
                v.x == 0.0 && dy.abs() < corner_x && (dy > 0.0) == above && dy.abs() > 1e-3
            })
            .max_by(|a, b| a.z.total_cmp(&b.z))
            .map(|v| (v.y - centre.y).abs())
    };
    let (up, down) = (
        prominent(true).ok_or(ClassicError::Missing("the upper lip's midline"))?,
        prominent(false).ok_or(ClassicError::Missing("the lower lip's midline"))?,
    );
    let semi_minor = 2.0 * up.max(down);
    Ok(Muscle {
        name: "Orbicularis_Oris".into(),
        side: Side::Centre,
        mirror: None,
        kind: MuscleKind::Sphincter(Sphincter {
            centre: rounded(Vec3::new(0.0, centre.y, centre.z)),
            semi_major: round3(corner_x + semi_minor),
            semi_minor: round3(semi_minor),
            convergence: Convergence::Centre,
            bulge: 10.0,
            frame: Frame::IDENTITY,
        }),
    })
}

/// The eye sphincters on the lid line (see [`rigs::eye_sphincters`]), wider than the eye so
/// the lids close along most of their length.
fn orbicularis_oculi(marks: &Landmarks, p: &[Vec3]) -> Result<[Muscle; 2], ClassicError> {
    let eye = &marks.left_eye;
    let lids = eye
        .centres(p)
        .ok_or(ClassicError::Missing("the middle of the left eyelids"))?;
    let corners = eye.corners.map(|v| p[v as usize]);
    rigs::eye_sphincters(corners, lids.into(), |half_width, semi_minor| {
        (1.6 * half_width).max(1.05 * semi_minor)
    })
    .ok_or(ClassicError::Missing("an open left eye"))
}

/// The jaw: a pivot deep in the head at about the height of the nose's base, and weights 0
/// on the upper lip and everything above the mouth line; 1 in the middle of the lower lip
/// and chin, falling smoothly to 0 at the lip corners; lower down the band that moves widens
/// to the whole mandible, so the lower lip turns with the chin while the corners and
/// cheeks stay put.
fn jaw(marks: &Landmarks, p: &[Vec3]) -> Result<Jaw, ClassicError> {
    let mouth = &marks.mouth;
    let line = MouthLine::new(mouth, p);
    let mouth_y = line.y_at(0.0);
    let eye_y = {
        let (u, l) = marks
            .left_eye
            .centres(p)
            .ok_or(ClassicError::Missing("the middle of the left eyelids"))?;
        0.5 * (u.y + l.y)
    };
    // the lower lip reaches its corner at the outermost vertex of its own margin
    let corner_x = mouth
        .lower
        .iter()
        .map(|&v| p[v as usize].x.abs())
        .fold(0.0, f32::max);
    let depth_scale = mouth_y - marks.chin.y;
    if corner_x <= 0.0 || depth_scale.is_nan() || depth_scale <= 0.0 {
        return Err(ClassicError::Missing("a chin below the mouth"));
    }
    // the half-width of the face below the mouth line: the mandible's reach
    let jaw_half = p
        .iter()
        .filter(|v| v.y < mouth_y)
        .map(|v| v.x.abs())
        .fold(0.0, f32::max);
    let upper: BTreeSet<u32> = mouth.upper.iter().copied().chain(mouth.corners).collect();
    let lower: BTreeSet<u32> = mouth.lower.iter().copied().collect();
    let mut weights = Vec::new();
    for (i, v) in p.iter().enumerate() {
        let i = i as u32;
        if upper.contains(&i) {
            continue;
        }
        let ax = v.x.abs();
        let below = (line.y_at(ax) - v.y).max(0.0);
        if below <= 0.0 && !lower.contains(&i) {
            continue;
        }
        let depth = f64::from((below / depth_scale).clamp(0.0, 1.0));
        let ease = smoothstep(0.0, 0.6, depth);
        let jaw_half = f64::from(jaw_half);
        // the middle third of the lower lip moves fully, so the mouth opens round, not in a V
        let inner = LIP_MIDDLE * f64::from(corner_x) * (1.0 - ease) + ease * 0.75 * jaw_half;
        let outer = f64::from(corner_x) + ease * (1.25 * jaw_half - f64::from(corner_x));
        let w = round3((1.0 - smoothstep(inner, outer, f64::from(ax))) as f32);
        if w > 0.0 {
            weights.push((i, w));
        }
    }
    let pivot_y = mouth_y + PIVOT_HEIGHT * (eye_y - mouth_y);
    Ok(Jaw {
        axis: glam::Vec3::X,
        slide: glam::Vec3::ZERO,
        pivot: rounded(Vec3::new(0.0, pivot_y, marks.deepest_z)),
        degrees_per_unit: CLASSIC_JAW_DEGREES_PER_UNIT,
        weights,
    })
}

/// The mouth line's height as a function of |x|: piecewise linear through the slit's
/// vertices (both lips, which lie within a few thousandths of each other; knots at the same
/// |x| are averaged), flat beyond the corners. Built from |x| so it is the same on both sides.
struct MouthLine {
    knots: Vec<(f32, f32)>,
}

impl MouthLine {
    fn new(mouth: &Opening, p: &[Vec3]) -> MouthLine {
        let mut knots: Vec<(f32, f32)> = mouth
            .upper
            .iter()
            .chain(&mouth.lower)
            .chain(&mouth.corners)
            .map(|&v| (p[v as usize].x.abs(), p[v as usize].y))
            .collect();
        knots.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        // knots at the same |x| (the two lips, the two sides) become their mean height
        let mut merged: Vec<(f32, f32, u32)> = Vec::with_capacity(knots.len());
        for (x, y) in knots {
            match merged.last_mut() {
                Some(last) if last.0 == x => {
                    last.1 += y;
                    last.2 += 1;
                }
                _ => merged.push((x, y, 1)),
            }
        }
        MouthLine {
            knots: merged
                .into_iter()
                .map(|(x, y, n)| (x, y / n as f32))
                .collect(),
        }
    }

    fn y_at(&self, x: f32) -> f32 {
        let k = &self.knots;
        let Some(first) = k.first() else { return 0.0 };
        if x <= first.0 {
            return first.1;
        }
        for w in k.windows(2) {
            let ((x0, y0), (x1, y1)) = (w[0], w[1]);
            if x <= x1 {
                return if x1 > x0 {
                    y0 + (x - x0) / (x1 - x0) * (y1 - y0)
                } else {
                    y1
                };
            }
        }
        k[k.len() - 1].1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat patch with a slit across its middle: corners at x = -2 and 2, the upper margin
    /// at y = 0 and the lower margin 0.002 ABOVE it (as the classic lower lip rises above
    /// its neighbours), so only the triangles can tell the margins apart.
    fn slit_patch() -> (Mesh, Vec<u32>, Vec<u32>) {
        let mut positions = Vec::new();
        let mut row = |y: f32, xs: &[f32]| -> Vec<u32> {
            xs.iter()
                .map(|&x| {
                    positions.push(Vec3::new(x, y, 0.0));
                    (positions.len() - 1) as u32
                })
                .collect()
        };
        let xs = [-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0];
        let top = row(1.0, &xs);
        let bottom = row(-1.0, &xs);
        // the patch's sides at the slit's height, and the slit's corners
        let sides = row(0.0, &[-3.0, 3.0]);
        let corners = row(0.0, &[-2.0, 2.0]);
        let upper = row(0.0, &[-1.0, 0.0, 1.0]);
        let lower = row(0.002, &[-1.0, 0.0, 1.0]);
        let line = |margin: &[u32]| {
            let mut l = vec![sides[0], corners[0]];
            l.extend_from_slice(margin);
            l.extend([corners[1], sides[1]]);
            l
        };
        let (u, l) = (line(&upper), line(&lower));
        let mut triangles = Vec::new();
        for i in 0..6 {
            // counter-clockwise seen from +z
            triangles.push([u[i], u[i + 1], top[i + 1]]);
            triangles.push([u[i], top[i + 1], top[i]]);
            triangles.push([bottom[i], bottom[i + 1], l[i + 1]]);
            triangles.push([bottom[i], l[i + 1], l[i]]);
        }
        (Mesh::new(positions, triangles).unwrap(), upper, lower)
    }

    #[test]
    fn a_slit_is_split_by_its_triangles_not_by_height() {
        let (mesh, upper, lower) = slit_patch();
        let mut loops = topology::boundary_loops(&mesh);
        loops.sort_by_key(|l| std::cmp::Reverse(l.len()));
        assert_eq!(loops.len(), 2);
        let slit = split_opening(&mesh, &loops[1]).unwrap();
        let sorted = |mut v: Vec<u32>| {
            v.sort_unstable();
            v
        };
        assert_eq!(sorted(slit.upper.clone()), upper);
        assert_eq!(sorted(slit.lower.clone()), lower);
        let p = &mesh.positions;
        assert_eq!(slit.corners.map(|v| p[v as usize].x), [-2.0, 2.0]);
        let (u, l) = slit.centres(p).unwrap();
        assert_eq!((u.x, u.y, l.x, l.y), (0.0, 0.0, 0.0, 0.002));
    }

    #[test]
    fn the_mouth_line_interpolates_by_distance_from_the_midline() {
        let (mesh, _, _) = slit_patch();
        let mut loops = topology::boundary_loops(&mesh);
        loops.sort_by_key(|l| std::cmp::Reverse(l.len()));
        let slit = split_opening(&mesh, &loops[1]).unwrap();
        let line = MouthLine::new(&slit, &mesh.positions);
        // the lips at |x| <= 1 average to 0.001; the corners at |x| = 2 are at 0, and the
        // line stays flat beyond them
        for (x, y) in [
            (0.0, 0.001),
            (-1.0, 0.001),
            (1.5, 0.0005),
            (2.0, 0.0),
            (5.0, 0.0),
        ] {
            assert!(
                (line.y_at(f32::abs(x)) - y).abs() < 1e-7,
                "{x}: {}",
                line.y_at(x)
            );
        }
    }

    #[test]
    fn a_face_without_eyes_gets_no_extras_and_a_reason() {
        let (mesh, _, _) = slit_patch();
        assert_eq!(extra_muscles(&mesh), (Vec::new(), None));
        assert_eq!(
            place_extras(&mesh).unwrap_err(),
            ClassicError::Missing("no left eye opening")
        );
    }
}
