//! Framing: which way a face looks and which part of the mesh a view fits.
//!
//! A mesh may stand any way up (y up as glTF, z up as Blender and many scanners) and may be a
//! face, a head, a bust or a whole body. Views are defined in the face's own axes: across
//! (the subject's left), up, and out of the face. [`Framing::of_face`] takes them, best
//! first, from the axes the user gives (`--up`, `--front`), the face's 68 landmarks (the eye
//! line across, the mouth to the eyes up, out toward the nose tip), the rig's sphincters
//! (their frames lie in the face's plane, major axis across, minor axis up), else the mesh's
//! shape ([`Framing::of_mesh`]: the longer of its y and z extents is taken for up). The face
//! region comes from the landmarks, with margins in the face's own proportions, else from
//! the rig's muscle points: a fitted bust is shown upright with its face filling the view,
//! and the view does not move when fitting moves a muscle. A bust or a body known by its
//! shape alone (the landmark picker's first view) is fitted at its head: what lies above the
//! neck, found where the shoulders widen the mesh. [`Framing::of_loaded`] looks the
//! landmarks up for a loaded rig; every front end frames through it.
//!
//! Axes within 20 degrees of the mesh's own are snapped to them exactly, so a face modelled
//! square to its axes is drawn square (the built-in face's front view is the mesh's xy plane
//! bit for bit), while a scan lying at an angle is turned upright.

use glam::{Mat3, Vec2, Vec3};

use crate::io::load::LoadedRig;
use crate::landmarks::{eye_centre, FaceFrame, CHIN, COUNT, EYES};
use crate::model::mesh::bounds_of as bounds;
use crate::model::{Mesh, MuscleKind, Rig};

/// Up to this angle between the face's axes and an axis-aligned frame, the aligned frame is
/// used.
const SNAP_DEGREES: f32 = 20.0;

/// A mesh whose face region spans at least this share of its extent, across and up, is
/// framed whole: it is a face, not a head or body around one.
const MOSTLY_FACE: f32 = 0.9;

/// How far beyond the rig's muscle points the face region reaches, as a fraction of their
/// extent on each side (the chin below the lowest muscle, the forehead above the frontalis).
const FACE_MARGIN: f32 = 0.12;

/// The forehead above the brows, in the face's middle third (brows to the nose's base): the
/// canon of facial thirds makes hairline to brows, brows to the nose's base and the nose's
/// base to the chin about equal.
const FOREHEAD_THIRDS: f32 = 1.0;

/// Room below the chin, in the face's lower third (the nose's base to the chin): the chin
/// drops as the jaw opens (at AU26 about 15 mm of a lower third of about 65 mm).
const BELOW_CHIN_THIRDS: f32 = 0.25;

/// Room beside the jaw line's ends (landmarks 0 and 16, in front of the ears), in the
/// contour's width, each side: a head is about 1.1-1.2 times as broad as its face, the
/// ears a little more.
const BESIDE_JAW: f32 = 0.1;

/// How a mesh is shown: its face's axes and the points a view is fitted to.
#[derive(Debug, Clone, PartialEq)]
pub struct Framing {
    /// Mesh to face coordinates (rows: across toward the subject's left, up, out of the
    /// face): the camera's [`super::Camera::basis`].
    pub basis: Mat3,
    /// The rest vertices of the face region, when the face is a small part of the mesh;
    /// `None` fits the whole mesh.
    pub focus: Option<Vec<Vec3>>,
    /// The extent of what a view fits, in face coordinates (measured once, so views that
    /// scale steps and pans with the face pay nothing per frame).
    extent: Vec3,
    /// Where the irises are, from the landmarks (empty without them): `shaded` paints them on
    /// eyes the mesh does not model to the iris ([`Iris`]).
    pub irises: Vec<Iris>,
}

/// An iris looking straight out of the face, at rest: a disc in the face's plane. Drawn on
/// the eye's surface where a mesh's eyes are blank (an eyeball without an iris of its own, or
/// the inside of an eye opened by `fit-rig`): a face tracker, like a person, reads an eye
/// with no iris as a closed or a blind one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Iris {
    /// The iris's centre, in mesh coordinates (only its place in the face's plane counts).
    pub centre: Vec3,
    /// Unit vectors across the face (to the subject's left) and up it, in mesh coordinates.
    pub across: Vec3,
    /// See `across`.
    pub up: Vec3,
    /// The iris's radius, in mesh units.
    pub radius: f32,
}

/// The iris's diameter over the eye's width (corner to corner): about 11.8 mm of a
/// palpebral fissure about 29 mm long in adults.
const IRIS_OF_EYE_WIDTH: f32 = 0.2;

impl Iris {
    /// The two irises of a face with these 68 landmarks (iBUG scheme), in the face's axes
    /// `basis` (rows across, up, out): each centred on its eye's opening (the mean of its six
    /// landmarks, so straight ahead), its radius a fifth of the eye's width ([`IRIS_OF_EYE_WIDTH`]).
    /// None when the landmarks are not 68 or an eye has no width.
    pub fn of_landmarks(points: &[Vec3], basis: Mat3) -> Vec<Iris> {
        if points.len() != COUNT {
            return Vec::new();
        }
        let (across, up) = (basis.row(0), basis.row(1));
        let irises = EYES.map(|eye| {
            // The ring runs from one corner (first) to the other (fourth).
            let width = points[eye[0]].distance(points[eye[3]]);
            Iris {
                centre: eye_centre(points, eye).as_vec3(),
                across,
                up,
                radius: IRIS_OF_EYE_WIDTH * width,
            }
        });
        if irises
            .iter()
            .all(|i| i.radius.is_finite() && i.radius > 0.0 && i.centre.is_finite())
        {
            irises.to_vec()
        } else {
            Vec::new()
        }
    }
}

/// The face region: a box across and up in face coordinates (depth is not bounded).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Region {
    lo: Vec2,
    hi: Vec2,
}

impl Framing {
    /// The framing of a loaded rig: [`Framing::of_face`] with the landmarks of its mesh
    /// ([`LoadedRig::landmark_points`]) and the axes given (`--up`, `--front`; see
    /// [`facing`]), if any. Never fails: a landmark file that is there but cannot be used
    /// leaves the rig to frame the face, and the second value says why (for the front end to
    /// show as a warning).
    pub fn of_loaded(loaded: &LoadedRig, given: Option<Mat3>) -> (Framing, Option<String>) {
        let (points, warning) = match loaded.landmark_points() {
            Ok(points) => (points, None),
            Err(e) => (
                None,
                Some(format!("{e}; the view is framed without the landmarks")),
            ),
        };
        let framing = Framing::of_face(Some(&loaded.rig), &loaded.mesh, points.as_deref(), given);
        (framing, warning)
    }

    /// The framing of a rigged mesh without landmarks: axes from the sphincters' frames (the
    /// mouth's first), the face region from the muscles' points.
    pub fn of_rig(rig: &Rig, mesh: &Mesh) -> Framing {
        Framing::of_face(Some(rig), mesh, None, None)
    }

    /// The framing of a face from what is known of it. Axes: `given`, else the landmarks'
    /// (68 points on the mesh, in the iBUG scheme), else the rig's sphincters, else the
    /// mesh's shape ([`Framing::of_mesh`]); all but `given` snapped to the mesh's axes within
    /// 20 degrees. Face region: from the landmarks, else from the rig's muscle points, else
    /// the head found from the mesh's shape, else the whole mesh; a region that is most of
    /// the mesh fits the whole mesh.
    pub fn of_face(
        rig: Option<&Rig>,
        mesh: &Mesh,
        landmarks: Option<&[Vec3]>,
        given: Option<Mat3>,
    ) -> Framing {
        let marks = landmarks.and_then(|points| Some((points, landmark_axes(points)?)));
        let basis = given
            .or_else(|| marks.map(|(_, axes)| snap(axes)))
            .or_else(|| rig.and_then(face_axes).map(snap));
        let Some(basis) = basis else {
            return Framing::of_mesh(mesh);
        };
        let region = match (marks, rig) {
            (Some((points, _)), _) => landmark_region(points, basis),
            (None, Some(rig)) => muscle_region(rig, basis),
            (None, None) => return Framing::of_shape(mesh, Some(basis)),
        };
        let focus = region.and_then(|region| vertices_inside(region, mesh, basis));
        let mut framing = Framing::new(basis, focus, mesh);
        if let Some((points, _)) = marks {
            framing.irises = Iris::of_landmarks(points, basis);
        }
        framing
    }

    /// The framing of a mesh alone: up is the longer of its y and z extents (y when equal),
    /// the face toward +z for y up and toward -y for z up (Blender's front view).
    /// On a bust or a body the view fits its head ([`head_of`]).
    pub fn of_mesh(mesh: &Mesh) -> Framing {
        Framing::of_shape(mesh, None)
    }

    /// [`Framing::of_mesh`] with the face's axes `given` (`--up`, `--front`), if any.
    pub fn of_shape(mesh: &Mesh, given: Option<Mat3>) -> Framing {
        let (lo, hi) = mesh.bounds();
        let size = hi - lo;
        let basis = given.unwrap_or(if size.is_finite() && size.z > size.y * 1.05 {
            Mat3::from_cols(Vec3::X, Vec3::Z, -Vec3::Y).transpose()
        } else {
            Mat3::IDENTITY
        });
        Framing::new(basis, head_of(mesh, basis), mesh)
    }

    /// The rest points a view fits: the face region, else the whole mesh.
    pub fn frame<'a>(&'a self, mesh: &'a Mesh) -> &'a [Vec3] {
        self.focus.as_deref().unwrap_or(&mesh.positions)
    }

    fn new(basis: Mat3, focus: Option<Vec<Vec3>>, mesh: &Mesh) -> Framing {
        let points = focus.as_deref().unwrap_or(&mesh.positions);
        let face: Vec<Vec3> = points.iter().map(|p| basis * *p).collect();
        let (lo, hi) = bounds(&face);
        let extent = hi - lo;
        Framing {
            basis,
            focus,
            extent: if extent.is_finite() {
                extent
            } else {
                Vec3::ONE
            },
            irises: Vec::new(),
        }
    }

    /// The size of what a view fits, for steps and pans that scale with the face: the larger
    /// of its extents across and up, in mesh units.
    pub fn size(&self) -> f32 {
        self.extent.truncate().max_element().max(f32::EPSILON)
    }

    /// The face's height (its extent along the face's up), for rig mode's steps.
    pub fn height(&self) -> f32 {
        if self.extent.y > 0.0 {
            self.extent.y
        } else {
            1.0
        }
    }
}

/// The face's axes for a face whose up and front (out of the face) are the given mesh
/// directions; either may be left out, and is then taken as the usual partner of the other
/// (y up faces +z, z up faces -y, as glTF and Blender have it). `None` when the two are not
/// at right angles or not unit axes.
pub fn facing(up: Option<Vec3>, front: Option<Vec3>) -> Option<Mat3> {
    let first_across = |given: Vec3, choices: [Vec3; 3]| {
        choices
            .into_iter()
            .find(|c| c.dot(given).abs() < 1e-6)
            .unwrap_or(Vec3::ZERO)
    };
    let (up, front) = match (up, front) {
        (None, None) => return None,
        (Some(up), Some(front)) => (up, front),
        (Some(up), None) => (up, first_across(up, [Vec3::Z, -Vec3::Y, Vec3::X])),
        (None, Some(front)) => (first_across(front, [Vec3::Y, Vec3::Z, Vec3::X]), front),
    };
    let across = up.cross(front);
    (up.is_normalized() && front.is_normalized() && up.dot(front).abs() < 1e-6)
        .then(|| Mat3::from_cols(across, up, front).transpose())
}

/// The face's axes (rows across, up, out) from the rig's sphincters, the mouth's first;
/// `None` without a sphincter.
fn face_axes(rig: &Rig) -> Option<Mat3> {
    let mut frames = rig.muscles.iter().filter_map(|m| match &m.kind {
        MuscleKind::Sphincter(s) => Some((s.convergence, s.frame)),
        _ => None,
    });
    let first = frames
        .clone()
        .find(|(c, _)| *c == crate::model::Convergence::Centre);
    let (_, frame) = first.or_else(|| frames.next())?;
    let across = frame.x.normalize_or_zero();
    let out = across.cross(frame.y).normalize_or_zero();
    let up = out.cross(across);
    (across != Vec3::ZERO && out != Vec3::ZERO)
        .then(|| Mat3::from_cols(across, up, out).transpose())
}

/// `basis` replaced by the axis-aligned rotation nearest to it when that is within
/// [`SNAP_DEGREES`] of it.
fn snap(basis: Mat3) -> Mat3 {
    let aligned = |v: Vec3| {
        let a = v.abs();
        let axis = if a.x >= a.y && a.x >= a.z {
            Vec3::X * v.x.signum()
        } else if a.y >= a.z {
            Vec3::Y * v.y.signum()
        } else {
            Vec3::Z * v.z.signum()
        };
        (axis, v.dot(axis).clamp(-1.0, 1.0).acos().to_degrees())
    };
    let (across, a) = aligned(basis.row(0));
    let (up, b) = aligned(basis.row(1));
    let out = across.cross(up);
    let c = basis.row(2).dot(out).clamp(-1.0, 1.0).acos().to_degrees();
    if a.max(b).max(c) <= SNAP_DEGREES && out != Vec3::ZERO {
        Mat3::from_cols(across, up, out).transpose()
    } else {
        basis
    }
}

/// The muscles' points: where the face is.
fn muscle_points(rig: &Rig) -> Vec<Vec3> {
    let mut points = Vec::new();
    for muscle in &rig.muscles {
        match &muscle.kind {
            MuscleKind::Linear(l) => points.extend([l.attachment, l.insertion]),
            MuscleKind::Sphincter(s) => {
                let (x, y) = (s.frame.x.normalize_or_zero(), s.frame.y.normalize_or_zero());
                points.extend([
                    s.centre + x * s.semi_major,
                    s.centre - x * s.semi_major,
                    s.centre + y * s.semi_minor,
                    s.centre - y * s.semi_minor,
                ]);
            }
            MuscleKind::Sheet(s) => points.extend(s.attachment.iter().chain(&s.insertion)),
        }
    }
    if let Some(jaw) = &rig.jaw {
        points.push(jaw.pivot);
    }
    points.retain(|p| p.is_finite());
    points
}

/// The face's axes (rows across, up, out) from its 68 landmarks: across along the eye line
/// (toward the subject's left), up from the mouth to the eyes, out of the face on the nose
/// tip's side ([`FaceFrame`]). A mirrored set (the subject's left on the wrong side) still
/// gives a rotation: across is then taken from up and out. `None` for points that are no
/// face.
fn landmark_axes(points: &[Vec3]) -> Option<Mat3> {
    let frame = FaceFrame::of(points)?;
    let (up, out) = (frame.up.as_vec3(), frame.forward.as_vec3());
    let across = up.cross(out).normalize_or_zero();
    (across != Vec3::ZERO && up.is_finite() && out.is_finite())
        .then(|| Mat3::from_cols(across, up, out).transpose())
}

/// The face region the landmarks mark, in face coordinates: their extent, with the forehead
/// above the brows, room below the chin and beside the jaw line, each measured in the face's
/// own thirds and width (`FOREHEAD_THIRDS`, `BELOW_CHIN_THIRDS`, `BESIDE_JAW`).
fn landmark_region(points: &[Vec3], basis: Mat3) -> Option<Region> {
    if points.len() != COUNT {
        return None;
    }
    let face: Vec<Vec3> = points.iter().map(|p| basis * *p).collect();
    let (lo, hi) = bounds(&face);
    let brows = face[17..=26].iter().map(|p| p.y).sum::<f32>() / 10.0;
    let nose_base = face[NOSE_BASE].y;
    let middle_third = (brows - nose_base).max(0.0);
    let lower_third = (nose_base - face[CHIN].y).max(0.0);
    let beside = (hi.x - lo.x) * BESIDE_JAW;
    let region = Region {
        lo: Vec2::new(lo.x - beside, lo.y - lower_third * BELOW_CHIN_THIRDS),
        hi: Vec2::new(hi.x + beside, hi.y + middle_third * FOREHEAD_THIRDS),
    };
    region.is_finite().then_some(region)
}

/// The landmark below the nose tip (the columella, at the nose's base).
const NOSE_BASE: usize = 33;

/// The face region the rig's muscle points span, with `FACE_MARGIN` on each side; `None`
/// with fewer than three points.
fn muscle_region(rig: &Rig, basis: Mat3) -> Option<Region> {
    let points: Vec<Vec3> = muscle_points(rig).iter().map(|p| basis * *p).collect();
    if points.len() < 3 {
        return None;
    }
    let (lo, hi) = bounds(&points);
    let margin = (hi - lo) * FACE_MARGIN;
    Some(Region {
        lo: (lo - margin).truncate(),
        hi: (hi + margin).truncate(),
    })
}

impl Region {
    fn is_finite(&self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }

    fn contains(&self, f: Vec3) -> bool {
        f.x >= self.lo.x && f.x <= self.hi.x && f.y >= self.lo.y && f.y <= self.hi.y
    }
}

/// The rest vertices inside the face region, or `None` when that is most of the mesh (or
/// almost none of it).
fn vertices_inside(region: Region, mesh: &Mesh, basis: Mat3) -> Option<Vec<Vec3>> {
    let face: Vec<Vec3> = mesh.positions.iter().map(|p| basis * *p).collect();
    let (mlo, mhi) = bounds(&face);
    let (mlo, mhi) = (mlo.truncate(), mhi.truncate());
    // The share of the mesh's extent, across and up, that the face region covers.
    let covered =
        (region.hi.min(mhi) - region.lo.max(mlo)) / (mhi - mlo).max(Vec2::splat(f32::EPSILON));
    if covered.x >= MOSTLY_FACE && covered.y >= MOSTLY_FACE {
        return None;
    }
    let inside: Vec<Vec3> = mesh
        .positions
        .iter()
        .zip(&face)
        .filter(|(_, f)| region.contains(**f))
        .map(|(p, _)| *p)
        .collect();
    (inside.len() >= 3).then_some(inside)
}

/// Slices of a mesh's height in which [`head_of`] measures its width.
const SLICES: usize = 64;
/// A slice at least this many times as wide as the widest one above it is the shoulders (or
/// the arms from them): a head is about 0.4 of the shoulders' breadth.
const SHOULDERS: f32 = 1.8;
/// Between the head's widest slice and the shoulders a slice this narrow (of the head's
/// width) is a neck; the crown's slices, each wider than the one above, never are.
const NECK: f32 = 0.9;

/// The head of a bust or a body known by its shape alone (no landmarks, no rig): the drawn
/// vertices above its neck. Measured slice by slice from the top down in the face's axes:
/// the shoulders are a sudden step to much wider than the head above them, and the neck is
/// the narrowest slice before that step. `None` when there is no such step (a face or a head
/// alone, hair down to the shoulders, arms raised above the head): the whole mesh is fitted.
fn head_of(mesh: &Mesh, basis: Mat3) -> Option<Vec<Vec3>> {
    let drawn = crate::fit::parts::drawn_triangles(mesh);
    let mut used = vec![false; mesh.vertex_count()];
    for &v in drawn.as_deref().unwrap_or(&mesh.triangles).iter().flatten() {
        used[v as usize] = true;
    }
    let face: Vec<Vec3> = mesh
        .positions
        .iter()
        .zip(&used)
        .filter(|(_, &u)| u)
        .map(|(p, _)| basis * *p)
        .collect();
    let (lo, hi) = bounds(&face);
    let height = hi.y - lo.y;
    if !(height.is_finite() && height > 0.0) {
        return None;
    }
    let slice_of = |y: f32| ((((hi.y - y) / height) * SLICES as f32) as usize).min(SLICES - 1);
    let mut across = [(f32::INFINITY, f32::NEG_INFINITY); SLICES];
    for p in &face {
        let slice = &mut across[slice_of(p.y)];
        *slice = (slice.0.min(p.x), slice.1.max(p.x));
    }
    // Empty slices (a sparse mesh) have no width and are passed over.
    let width: Vec<f32> = across.iter().map(|(a, b)| (b - a).max(0.0)).collect();
    let mut widest = (0.0f32, 0usize);
    for (k, &w) in width.iter().enumerate() {
        if w <= 0.0 {
            continue;
        }
        let neck = (widest.1..k)
            .filter(|&j| width[j] > 0.0)
            .min_by(|&a, &b| width[a].total_cmp(&width[b]));
        if let Some(neck) = neck.filter(|&j| w > SHOULDERS * widest.0 && width[j] < NECK * widest.0)
        {
            let cut = hi.y - (neck + 1) as f32 / SLICES as f32 * height;
            let head: Vec<Vec3> = mesh
                .positions
                .iter()
                .zip(&used)
                .filter(|(p, &u)| u && (basis * **p).y >= cut)
                .map(|(p, _)| *p)
                .collect();
            return (head.len() >= 3).then_some(head);
        }
        if w > widest.0 {
            widest = (w, k);
        }
    }
    None
}

/// For tests: a column of rings, `(height, radius)` from the top down, as a mesh, each ring
/// a band of triangles to the next.
#[cfg(test)]
pub(crate) fn column(rings: &[(f32, f32)]) -> Mesh {
    const AROUND: usize = 16;
    let mut positions = Vec::new();
    for &(y, r) in rings {
        for k in 0..AROUND {
            let a = k as f32 / AROUND as f32 * std::f32::consts::TAU;
            positions.push(Vec3::new(r * a.cos(), y, r * a.sin()));
        }
    }
    let mut triangles = Vec::new();
    for ring in 0..rings.len() - 1 {
        for k in 0..AROUND {
            let (a, b) = (ring * AROUND + k, ring * AROUND + (k + 1) % AROUND);
            let (c, d) = (a + AROUND, b + AROUND);
            triangles.push([a as u32, c as u32, b as u32]);
            triangles.push([b as u32, c as u32, d as u32]);
        }
    }
    Mesh::new(positions, triangles).unwrap()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::builtin;

    #[test]
    fn the_built_in_face_is_framed_as_it_is() {
        let mesh = builtin::default_mesh();
        let framing = Framing::of_rig(&builtin::default_rig(), &mesh);
        assert_eq!((framing.basis, &framing.focus), (Mat3::IDENTITY, &None));
        let (lo, hi) = mesh.bounds();
        assert_eq!(framing.height(), (hi - lo).y);
    }

    #[test]
    fn a_bust_known_by_its_shape_is_framed_at_its_head() {
        // Crown, head, neck, shoulders, chest: the view fits what is above the neck.
        let bust = super::column(&[
            (10.0, 0.3),
            (9.5, 0.8),
            (9.0, 1.0),
            (8.0, 1.0),
            (7.0, 0.9),
            (6.5, 0.5),
            (6.0, 0.5),
            (5.5, 2.5),
            (0.0, 2.5),
        ]);
        let framing = Framing::of_mesh(&bust);
        let head = framing.focus.as_deref().expect("the head");
        let lowest = head.iter().map(|p| p.y).fold(f32::MAX, f32::min);
        assert!((6.0..7.0).contains(&lowest), "the head ends at {lowest}");
        assert_eq!(head.len(), 16 * 6, "the crown to the neck's top ring");
        // A head alone (no shoulders), and a column that only widens (the crown of a head
        // cut at the ears), are framed whole.
        let head_alone = super::column(&[(10.0, 0.3), (9.0, 1.0), (7.0, 0.9), (6.5, 0.5)]);
        assert_eq!(Framing::of_mesh(&head_alone).focus, None);
        let widening = super::column(&[(10.0, 0.1), (9.9, 0.5), (9.0, 1.0), (8.0, 3.0)]);
        assert_eq!(Framing::of_mesh(&widening).focus, None);
    }

    #[test]
    fn a_z_up_face_is_stood_up_and_a_face_on_a_bigger_mesh_is_framed_alone() {
        // The built-in face turned to z up (front toward -y), on a mesh with a body below.
        let turn = Mat3::from_rotation_x(std::f32::consts::FRAC_PI_2);
        let mut mesh = builtin::default_mesh();
        let mut rig = builtin::default_rig();
        let face = mesh.positions.len();
        let (lo, hi) = mesh.bounds();
        let body: Vec<Vec3> = (0..4 * face)
            .map(|i| {
                let t = i as f32 / (4 * face) as f32;
                Vec3::new(
                    lo.x * 3.0 * (1.0 - t) + hi.x * 3.0 * t,
                    lo.y - 40.0 * t,
                    lo.z,
                )
            })
            .collect();
        mesh.positions.extend(body);
        for p in &mut mesh.positions {
            *p = turn * *p;
        }
        for muscle in &mut rig.muscles {
            match &mut muscle.kind {
                MuscleKind::Linear(l) => {
                    l.attachment = turn * l.attachment;
                    l.insertion = turn * l.insertion;
                }
                MuscleKind::Sphincter(s) => {
                    s.centre = turn * s.centre;
                    s.frame.x = turn * s.frame.x;
                    s.frame.y = turn * s.frame.y;
                }
                MuscleKind::Sheet(s) => {
                    for p in s.attachment.iter_mut().chain(&mut s.insertion) {
                        *p = turn * *p;
                    }
                }
            }
        }
        if let Some(jaw) = &mut rig.jaw {
            jaw.pivot = turn * jaw.pivot;
        }
        let points: Vec<Vec3> = builtin_points(&builtin::default_mesh())
            .iter()
            .map(|p| turn * *p)
            .collect();
        let by_rig = Framing::of_rig(&rig, &mesh);
        // The face's landmarks alone frame it the same way: its own vertices (the forehead
        // and sides within the margins) and the top of the body just under the chin.
        let by_landmarks = Framing::of_face(None, &mesh, Some(&points), None);
        for framing in [by_rig.clone(), by_landmarks] {
            // Mesh z is the face's up, mesh -y is out of the face.
            assert_eq!(framing.basis.row(1), Vec3::Z);
            assert_eq!(framing.basis.row(2), -Vec3::Y);
            let focus = framing.focus.expect("the face is a small part of the mesh");
            assert!(
                focus.len() >= face * 9 / 10 && focus.len() < face + face / 4,
                "{}",
                focus.len()
            );
        }
        assert_eq!(Framing::of_mesh(&mesh).basis, by_rig.basis);
    }

    #[test]
    fn given_axes_turn_the_view_as_asked() {
        assert_eq!(facing(None, None), None);
        assert_eq!(facing(Some(Vec3::Y), None), Some(Mat3::IDENTITY));
        let z_up = facing(Some(Vec3::Z), None).unwrap();
        assert_eq!(z_up, Framing::of_mesh(&tall_in_z()).basis);
        assert_eq!(facing(None, Some(-Vec3::Y)), Some(z_up));
        assert_eq!(
            facing(Some(Vec3::Z), Some(Vec3::Z)),
            None,
            "not at right angles"
        );
        let rig = builtin::default_rig();
        let mesh = builtin::default_mesh();
        let turned = Framing::of_face(Some(&rig), &mesh, None, Some(z_up));
        assert_eq!(turned.basis, z_up);
        let points = builtin_points(&mesh);
        let turned = Framing::of_face(Some(&rig), &mesh, Some(&points), Some(z_up));
        assert_eq!(turned.basis, z_up, "given axes come before the landmarks'");
    }

    fn builtin_points(mesh: &Mesh) -> Vec<Vec3> {
        builtin::landmarks("face").unwrap().positions(mesh).unwrap()
    }

    #[test]
    fn the_built_in_face_is_framed_by_its_landmarks_as_by_its_rig() {
        let mesh = builtin::default_mesh();
        let rig = builtin::default_rig();
        let points = builtin_points(&mesh);
        let by_marks = Framing::of_face(Some(&rig), &mesh, Some(&points), None);
        assert_eq!(by_marks, Framing::of_face(None, &mesh, Some(&points), None));
        // The landmarks add the irises; the view is the rig's.
        assert_eq!(by_marks.irises.len(), 2);
        let by_marks = Framing {
            irises: Vec::new(),
            ..by_marks
        };
        assert_eq!(by_marks, Framing::of_rig(&rig, &mesh));
        // Points that are no face leave the rig to frame it.
        let flat: Vec<Vec3> = points.iter().map(|p| p.truncate().extend(0.0)).collect();
        assert_eq!(
            Framing::of_face(Some(&rig), &mesh, Some(&flat), None),
            by_marks
        );
        assert_eq!(
            Framing::of_face(None, &mesh, None, None),
            Framing::of_mesh(&mesh)
        );
    }

    fn tall_in_z() -> Mesh {
        let mut mesh = builtin::default_mesh();
        for p in &mut mesh.positions {
            *p = Vec3::new(p.x, -p.z, p.y);
        }
        mesh
    }
}
