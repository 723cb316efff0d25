//! Per-muscle displacement fields, precomputed once per rig and mesh.
//!
//! Every muscle kind moves a vertex by `activation x (a vector that depends only on the rest
//! position and the muscle)` (MODEL-NOTES section 0). That vector, the displacement per unit
//! activation, is what this module computes: per vertex through the pure functions
//! ([`linear_displacement`], [`sphincter_displacement`], [`sheet_displacement`]), and for a
//! whole mesh as a sparse [`Field`].
//!
//! The geometry is evaluated in `f64` and rounded to `f32` once per vertex, so a field holds
//! the exact per-unit vector to within one `f32` rounding. The readings of the paper's
//! equations used here (and where they differ from the paper) are written down in
//! `docs/model.md`.

use std::f64::consts::FRAC_PI_2;

use glam::{DMat3, DVec3, Vec3};

use super::muscle::{Convergence, Linear, Muscle, MuscleKind, Sheet, Sphincter};

/// The displacement field of one muscle per unit activation, sparse and sorted by vertex.
///
/// Only vertices the muscle actually moves are listed (a zero displacement is left out).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Field {
    /// Indices of the moved vertices, strictly increasing.
    pub vertices: Vec<u32>,
    /// Displacement of each listed vertex at activation 1.0, parallel to `vertices`.
    pub displacements: Vec<Vec3>,
}

impl Field {
    /// Number of vertices the muscle moves.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// True when the muscle moves no vertex of the mesh.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// How many of `rest` a muscle moves: [`Field::of`]'s length, without keeping the field
    /// (an upper bound of a masked field's).
    pub fn count(kind: &MuscleKind, rest: &[Vec3]) -> usize {
        let shape = Shape::new(kind);
        rest.iter()
            .filter(|p| shape.unit_displacement(**p) != Vec3::ZERO)
            .count()
    }

    /// The field with each vertex's displacement multiplied by `scale[vertex]` (a mask);
    /// vertices scaled to zero are left out.
    pub fn scaled(self, scale: &[f32]) -> Field {
        let mut out = Field::default();
        for (v, d) in self.vertices.into_iter().zip(self.displacements) {
            let d = d * scale[v as usize];
            if d != Vec3::ZERO {
                out.vertices.push(v);
                out.displacements.push(d);
            }
        }
        out
    }

    /// The field of a muscle over a set of rest positions.
    pub fn of(kind: &MuscleKind, rest: &[Vec3]) -> Field {
        let shape = Shape::new(kind);
        let mut field = Field::default();
        for (index, p) in rest.iter().enumerate() {
            let d = shape.unit_displacement(*p);
            if d != Vec3::ZERO {
                field.vertices.push(index as u32);
                field.displacements.push(d);
            }
        }
        field
    }
}

/// Displacement of the rest point `p` by a linear muscle at `activation`
/// (MODEL-NOTES section 1; the classic Waters routine for one call from rest).
pub fn linear_displacement(muscle: &Linear, p: Vec3, activation: f32) -> Vec3 {
    LinearShape::new(muscle).unit_displacement(p) * activation
}

/// Displacement of the rest point `p` by a sphincter at `activation`: toward the centre for
/// the mouth, toward the major axis for an eye, plus the bulge out of the face (MODEL-NOTES
/// sections 2, 3), all in the sphincter's frame.
pub fn sphincter_displacement(muscle: &Sphincter, p: Vec3, activation: f32) -> Vec3 {
    Shape::sphincter(muscle).unit_displacement(p) * activation
}

/// Displacement of the rest point `p` by a sheet muscle at `activation`
/// (MODEL-NOTES section 4): toward the attachment line, along the sheet's axis.
pub fn sheet_displacement(muscle: &Sheet, p: Vec3, activation: f32) -> Vec3 {
    SheetShape::new(muscle).unit_displacement(p) * activation
}

/// Displacement of the rest point `p` by a muscle of any kind at `activation`.
pub fn muscle_displacement(kind: &MuscleKind, p: Vec3, activation: f32) -> Vec3 {
    Shape::new(kind).unit_displacement(p) * activation
}

/// A muscle's geometry with everything that does not depend on the vertex precomputed.
#[derive(Debug, Clone)]
pub enum Shape {
    /// A linear muscle.
    Linear(LinearShape),
    /// A sphincter in the mesh's own axes.
    Sphincter(SphincterShape),
    /// A sphincter with a frame of its own.
    FramedSphincter(FramedSphincter),
    /// A sheet muscle.
    Sheet(SheetShape),
}

impl Shape {
    /// Prepares a muscle of any kind.
    pub fn new(kind: &MuscleKind) -> Shape {
        match kind {
            MuscleKind::Linear(m) => Shape::Linear(LinearShape::new(m)),
            MuscleKind::Sphincter(m) => Shape::sphincter(m),
            MuscleKind::Sheet(m) => Shape::Sheet(SheetShape::new(m)),
        }
    }

    /// Prepares a sphincter: in the mesh's own axes when its frame is those (so such rigs
    /// compute exactly what they did before frames existed), else in its frame.
    pub fn sphincter(m: &Sphincter) -> Shape {
        match m.frame.rotation() {
            Some(rotation) if !m.frame.is_identity() => Shape::FramedSphincter(FramedSphincter {
                shape: SphincterShape::new(m),
                centre: m.centre.as_dvec3(),
                rotation,
            }),
            _ => Shape::Sphincter(SphincterShape::new(m)),
        }
    }

    /// Displacement of the rest point `p` per unit activation.
    pub fn unit_displacement(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Linear(s) => s.unit_displacement(p),
            Shape::Sphincter(s) => s.unit_displacement(p),
            Shape::FramedSphincter(s) => s.unit_displacement(p),
            Shape::Sheet(s) => s.unit_displacement(p),
        }
    }
}

/// A linear muscle prepared for evaluation.
#[derive(Debug, Clone)]
pub struct LinearShape {
    attachment: DVec3,
    /// Unit muscle direction, attachment toward insertion; zero for a muscle of no length.
    axis: DVec3,
    cos_zone: f64,
    falloff_start: f64,
    falloff_end: f64,
}

impl LinearShape {
    /// Prepares a linear muscle.
    pub fn new(m: &Linear) -> LinearShape {
        let attachment = m.attachment.as_dvec3();
        LinearShape {
            attachment,
            axis: (m.insertion.as_dvec3() - attachment).normalize_or_zero(),
            cos_zone: (m.zone as f64).to_radians().cos(),
            falloff_start: m.falloff_start as f64,
            falloff_end: m.falloff_end as f64,
        }
    }

    /// Displacement of `p` per unit activation: `k t (P - A)` with the angular factor
    /// `k = 1 - cos_a / cos_zone` (zero on the cone's edge, negative inside: a pull toward
    /// the attachment) and the radial factor `t` (1 inside the falloff start, a quarter
    /// cosine down to 0 at the falloff end).
    pub fn unit_displacement(&self, p: Vec3) -> Vec3 {
        if self.axis == DVec3::ZERO {
            return Vec3::ZERO;
        }
        let d = p.as_dvec3() - self.attachment;
        let r = d.length();
        // A vertex on the attachment has no direction (several classic attachments sit on
        // a vertex); the cone test needs r > 0.
        if r == 0.0 || r > self.falloff_end {
            return Vec3::ZERO;
        }
        let cos_a = self.axis.dot(d) / r;
        if cos_a < self.cos_zone {
            return Vec3::ZERO;
        }
        let k = 1.0 - cos_a / self.cos_zone;
        let t = if r < self.falloff_start {
            1.0
        } else {
            ((r - self.falloff_start) / (self.falloff_end - self.falloff_start) * FRAC_PI_2).cos()
        };
        (d * (k * t)).as_vec3()
    }
}

/// A sphincter prepared for evaluation.
#[derive(Debug, Clone)]
pub struct SphincterShape {
    cx: f64,
    cy: f64,
    lx: f64,
    ly: f64,
    convergence: Convergence,
    bulge: f64,
}

impl SphincterShape {
    /// Prepares a sphincter.
    pub fn new(m: &Sphincter) -> SphincterShape {
        SphincterShape {
            cx: m.centre.x as f64,
            cy: m.centre.y as f64,
            lx: m.semi_major as f64,
            ly: m.semi_minor as f64,
            convergence: m.convergence,
            bulge: m.bulge as f64,
        }
    }

    /// Eq. 3: `f = 1 - sqrt(ly^2 Px^2 + lx^2 Py^2) / (lx ly)`, 1 at the centre, 0 on the
    /// ellipse, negative outside. Written as `1 - |(Px/lx, Py/ly)|` (the same number) so
    /// that no product can overflow.
    pub fn ellipse_factor(&self, px: f64, py: f64) -> f64 {
        1.0 - (px / self.lx).hypot(py / self.ly)
    }

    /// Displacement of `p` per unit activation.
    ///
    /// Mouth (`Centre`): in-plane `D (c - P)/d` with `D = f (d - ly)/(lx - ly)` outside the
    /// protected disc `d <= ly` and 0 inside it (a continuous reading of eq. 2, see
    /// `docs/model.md`). Eye (`MajorAxis`): `D (0, -sign(Py), 0)` with `D = f |Py|/ly`
    /// (eq. 3's `f` on the full ellipse, `g = |Py|/ly`). Both: z bulge `f / Z`.
    pub fn unit_displacement(&self, p: Vec3) -> Vec3 {
        let px = p.x as f64 - self.cx;
        let py = p.y as f64 - self.cy;
        let f = self.ellipse_factor(px, py);
        if f.is_nan() || f <= 0.0 {
            return Vec3::ZERO;
        }
        let (dx, dy) = match self.convergence {
            Convergence::Centre => self.toward_centre(px, py, f),
            Convergence::MajorAxis => self.toward_axis(py, f),
        };
        // Eq. 5 with the continuous profile f / Z: peak 1/Z at the centre, 0 on the rim.
        let dz = f / self.bulge;
        DVec3::new(dx, dy, dz).as_vec3()
    }

    /// Mouth: the in-plane pull toward the centre.
    fn toward_centre(&self, px: f64, py: f64, f: f64) -> (f64, f64) {
        let d = px.hypot(py);
        let span = self.lx - self.ly;
        if d <= self.ly || span <= 0.0 {
            return (0.0, 0.0);
        }
        let depth = f * (d - self.ly) / span;
        (-depth * px / d, -depth * py / d)
    }

    /// Eye: the pull straight toward the major axis.
    fn toward_axis(&self, py: f64, f: f64) -> (f64, f64) {
        if py == 0.0 {
            return (0.0, 0.0);
        }
        let g = py.abs() / self.ly;
        (0.0, -f * g * py.signum())
    }
}

/// A sphincter with a frame of its own: the rest point is expressed in the frame (about the
/// centre), the sphincter of the mesh's own axes moves it, and the displacement is turned
/// back, so that the ellipse lies in the frame's x-y plane and bulges along its z.
#[derive(Debug, Clone)]
pub struct FramedSphincter {
    shape: SphincterShape,
    centre: DVec3,
    /// Columns: the frame's unit x, y and z in mesh coordinates.
    rotation: DMat3,
}

impl FramedSphincter {
    /// Displacement of `p` per unit activation: `R d(Rᵀ (p - c) + c)`.
    pub fn unit_displacement(&self, p: Vec3) -> Vec3 {
        let local = self.centre + self.rotation.transpose() * (p.as_dvec3() - self.centre);
        let d = self.shape.unit_displacement(local.as_vec3());
        (self.rotation * d.as_dvec3()).as_vec3()
    }
}

/// A sheet muscle prepared for evaluation.
#[derive(Debug, Clone)]
pub struct SheetShape {
    attachment_mid: DVec3,
    /// Unit axis from the attachment midpoint toward the insertion midpoint.
    axis: DVec3,
    /// Unit lateral direction: the attachment line made orthogonal to the axis.
    lateral: DVec3,
    /// `|Ac lc|`.
    span: f64,
    /// `L / |Ac lc|`.
    delta: f64,
    half_width: f64,
}

/// Fraction of each half-width, at the outer side, over which a sheet tapers to zero.
pub const SHEET_TAPER: f64 = 0.25;

impl SheetShape {
    /// Prepares a sheet muscle.
    pub fn new(m: &Sheet) -> SheetShape {
        let a1 = m.attachment[0].as_dvec3();
        let a2 = m.attachment[1].as_dvec3();
        let attachment_mid = (a1 + a2) * 0.5;
        let insertion_mid = (m.insertion[0].as_dvec3() + m.insertion[1].as_dvec3()) * 0.5;
        let along = insertion_mid - attachment_mid;
        let span = along.length();
        let axis = along.normalize_or_zero();
        let line = a2 - a1;
        let lateral = (line - axis * line.dot(axis)).normalize_or_zero();
        SheetShape {
            attachment_mid,
            axis,
            lateral,
            span,
            delta: if span > 0.0 {
                m.length as f64 / span
            } else {
                0.0
            },
            half_width: m.width as f64 * 0.5,
        }
    }

    /// Eq. 11 with n = 1: the profile along the axis as a function of `lambda`
    /// (0 on the attachment line, 1 on the insertion line, `delta` at the far end).
    ///
    /// `cos((1 - lambda) pi/2)` is evaluated as `sin(lambda pi/2)` and
    /// `cos((lambda - 1)/(delta - 1) pi/2)` as `sin((delta - lambda)/(delta - 1) pi/2)`: the
    /// same numbers, but exactly 0 on the two end lines.
    pub fn axial_factor(&self, lambda: f64) -> f64 {
        if (0.0..=1.0).contains(&lambda) {
            (lambda * FRAC_PI_2).sin()
        } else if lambda > 1.0 && lambda <= self.delta {
            ((self.delta - lambda) / (self.delta - 1.0) * FRAC_PI_2).sin()
        } else {
            0.0
        }
    }

    /// The lateral profile: 1 near the axis, a half-cosine taper over the outer
    /// [`SHEET_TAPER`] of each half-width, 0 beyond `W/2`.
    pub fn lateral_factor(&self, offset: f64) -> f64 {
        let s = offset.abs();
        let inner = self.half_width * (1.0 - SHEET_TAPER);
        if s <= inner {
            1.0
        } else if s < self.half_width {
            let u = (s - inner) / (self.half_width - inner);
            0.5 * (1.0 + (u * std::f64::consts::PI).cos())
        } else {
            0.0
        }
    }

    /// Displacement of `p` per unit activation: `D` times the unit pull from the insertion
    /// midpoint toward the attachment midpoint (a contraction pulls skin toward the bone).
    pub fn unit_displacement(&self, p: Vec3) -> Vec3 {
        if self.span <= 0.0 || self.axis == DVec3::ZERO || self.lateral == DVec3::ZERO {
            return Vec3::ZERO;
        }
        let rel = p.as_dvec3() - self.attachment_mid;
        let lambda = rel.dot(self.axis) / self.span;
        let along = self.axial_factor(lambda);
        if along == 0.0 {
            return Vec3::ZERO;
        }
        let across = self.lateral_factor(rel.dot(self.lateral));
        if across == 0.0 {
            return Vec3::ZERO;
        }
        (-self.axis * (along * across)).as_vec3()
    }
}

/// A muscle parameter out of its range or not finite.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("muscle `{muscle}`: {parameter} {message}")]
pub struct InvalidParameter {
    /// The muscle's name.
    pub muscle: String,
    /// The parameter's name as written in rig files.
    pub parameter: &'static str,
    /// What is wrong with it.
    pub message: String,
}

/// Checks a muscle's parameters, naming the muscle and the parameter on failure.
pub fn validate_muscle(muscle: &Muscle) -> Result<(), InvalidParameter> {
    let check = ParameterCheck {
        muscle: &muscle.name,
    };
    match &muscle.kind {
        MuscleKind::Linear(m) => check.linear(m),
        MuscleKind::Sphincter(m) => check.sphincter(m),
        MuscleKind::Sheet(m) => check.sheet(m),
    }
}

/// The parameter checks of one muscle, whose errors name it.
struct ParameterCheck<'a> {
    muscle: &'a str,
}

impl ParameterCheck<'_> {
    fn bad(&self, parameter: &'static str, message: String) -> InvalidParameter {
        InvalidParameter {
            muscle: self.muscle.to_string(),
            parameter,
            message,
        }
    }

    fn finite(&self, parameter: &'static str, v: Vec3) -> Result<(), InvalidParameter> {
        if v.is_finite() {
            Ok(())
        } else {
            Err(self.bad(parameter, format!("{v} is not finite")))
        }
    }

    fn linear(&self, m: &Linear) -> Result<(), InvalidParameter> {
        self.finite("attachment", m.attachment)?;
        self.finite("insertion", m.insertion)?;
        if !(m.zone.is_finite() && m.zone > 0.0 && m.zone < 90.0) {
            return Err(self.bad(
                "zone",
                format!("{} must lie strictly between 0 and 90 degrees", m.zone),
            ));
        }
        if !(m.falloff_start.is_finite() && m.falloff_start >= 0.0) {
            return Err(self.bad(
                "falloff_start",
                format!("{} must be a finite number >= 0", m.falloff_start),
            ));
        }
        if !(m.falloff_end.is_finite() && m.falloff_end > m.falloff_start) {
            return Err(self.bad(
                "falloff_end",
                format!(
                    "{} must be finite and greater than falloff_start ({})",
                    m.falloff_end, m.falloff_start
                ),
            ));
        }
        if (m.insertion.as_dvec3() - m.attachment.as_dvec3()).length() == 0.0 {
            return Err(self.bad(
                "insertion",
                "coincides with the attachment, so the muscle has no direction".into(),
            ));
        }
        Ok(())
    }

    fn sphincter(&self, m: &Sphincter) -> Result<(), InvalidParameter> {
        self.finite("centre", m.centre)?;
        m.frame
            .check()
            .map_err(|message| self.bad("frame", message))?;
        for (parameter, v) in [
            ("semi_major", m.semi_major),
            ("semi_minor", m.semi_minor),
            ("bulge", m.bulge),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(self.bad(parameter, format!("{v} must be a finite number > 0")));
            }
        }
        Ok(())
    }

    fn sheet(&self, m: &Sheet) -> Result<(), InvalidParameter> {
        for (parameter, v) in [
            ("attachment", m.attachment[0]),
            ("attachment", m.attachment[1]),
            ("insertion", m.insertion[0]),
            ("insertion", m.insertion[1]),
        ] {
            self.finite(parameter, v)?;
        }
        if !(m.width.is_finite() && m.width > 0.0) {
            return Err(self.bad("width", format!("{} must be a finite number > 0", m.width)));
        }
        let shape = SheetShape::new(m);
        if shape.span <= 0.0 {
            return Err(self.bad(
                "insertion",
                "the insertion line's midpoint coincides with the attachment line's".into(),
            ));
        }
        // L = |Ac lc| would end the sheet at full strength on its insertion line: a tear.
        if !(m.length.is_finite() && m.length as f64 > shape.span) {
            return Err(self.bad(
                "length",
                format!(
                    "{} must be finite and longer than the attachment-to-insertion distance \
                     {:.6} (a sheet ending on its insertion line tears the skin there)",
                    m.length, shape.span
                ),
            ));
        }
        if shape.lateral == DVec3::ZERO {
            return Err(self.bad(
                "attachment",
                "the attachment line has no extent across the sheet's axis".into(),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    //! Hand-computed examples (MODEL-NOTES sections 1-4); the arithmetic is in the comments.

    use super::*;
    use crate::model::muscle::{Frame, Side};

    fn close(got: Vec3, want: [f32; 3]) {
        let want = Vec3::from(want);
        assert!(
            (got - want).abs().max_element() < 1e-6,
            "got {got}, want {want}"
        );
    }

    /// Axis +z from the origin, zone 60 deg (cos 0.5), falloff 1 to 3.
    fn linear() -> Linear {
        Linear {
            attachment: Vec3::ZERO,
            insertion: Vec3::Z,
            zone: 60.0,
            falloff_start: 1.0,
            falloff_end: 3.0,
        }
    }

    #[test]
    fn linear_on_axis_inside_falloff_start() {
        // P = (0,0,0.5): r = 0.5 < fs so t = 1; cos_a = 1, k = 1 - 1/0.5 = -1;
        // displacement = -1 * (0,0,0.5); at activation 0.5: (0,0,-0.25).
        close(
            linear_displacement(&linear(), Vec3::new(0.0, 0.0, 0.5), 1.0),
            [0.0, 0.0, -0.5],
        );
        close(
            linear_displacement(&linear(), Vec3::new(0.0, 0.0, 0.5), 0.5),
            [0.0, 0.0, -0.25],
        );
    }

    #[test]
    fn linear_on_axis_in_the_falloff() {
        // P = (0,0,2): t = cos((2-1)/(3-1) * 90 deg) = cos 45 deg; k = -1;
        // displacement = -2 cos 45 deg = -1.41421356 along z.
        close(
            linear_displacement(&linear(), Vec3::new(0.0, 0.0, 2.0), 1.0),
            [0.0, 0.0, -std::f32::consts::SQRT_2],
        );
    }

    #[test]
    fn linear_off_axis() {
        // P = (1,0,1): r = sqrt 2, cos_a = 1/sqrt 2, k = 1 - 0.70711/0.5 = -0.41421;
        // t = cos((sqrt 2 - 1)/2 * 90 deg) = 0.94755; k t = -0.39249 times (1,0,1).
        close(
            linear_displacement(&linear(), Vec3::new(1.0, 0.0, 1.0), 1.0),
            [-0.392_487_1, 0.0, -0.392_487_1],
        );
    }

    #[test]
    fn linear_outside_cone_reach_and_at_apex_is_zero() {
        let m = linear();
        // cos_a = 1/sqrt 5 = 0.447 < 0.5: outside the cone.
        assert_eq!(
            linear_displacement(&m, Vec3::new(2.0, 0.0, 1.0), 1.0),
            Vec3::ZERO
        );
        // r = 3.5 > fe.
        assert_eq!(
            linear_displacement(&m, Vec3::new(0.0, 0.0, 3.5), 1.0),
            Vec3::ZERO
        );
        // Behind the attachment.
        assert_eq!(
            linear_displacement(&m, Vec3::new(0.0, 0.0, -1.0), 1.0),
            Vec3::ZERO
        );
        // On the attachment: no direction.
        assert_eq!(linear_displacement(&m, Vec3::ZERO, 1.0), Vec3::ZERO);
        // A muscle of no length moves nothing.
        let dead = Linear {
            insertion: Vec3::ZERO,
            ..m
        };
        assert_eq!(
            linear_displacement(&dead, Vec3::new(0.0, 0.0, 0.5), 1.0),
            Vec3::ZERO
        );
    }

    /// Ellipse at the origin, lx = 2, ly = 1.
    fn sphincter(convergence: Convergence, bulge: f32) -> Sphincter {
        Sphincter {
            centre: Vec3::ZERO,
            semi_major: 2.0,
            semi_minor: 1.0,
            convergence,
            bulge,
            frame: Frame::IDENTITY,
        }
    }

    #[test]
    fn mouth_on_the_major_axis() {
        // P = (1.5,0): f = 1 - 1.5/2 = 0.25; d = 1.5 > ly;
        // D = f (d - ly)/(lx - ly) = 0.25 * 0.5 = 0.125 toward the centre; z = f/10 = 0.025.
        let m = sphincter(Convergence::Centre, 10.0);
        close(
            sphincter_displacement(&m, Vec3::new(1.5, 0.0, 0.0), 1.0),
            [-0.125, 0.0, 0.025],
        );
        close(
            sphincter_displacement(&m, Vec3::new(1.5, 0.0, 0.0), 2.0),
            [-0.25, 0.0, 0.05],
        );
    }

    #[test]
    fn mouth_off_axis() {
        // P = (1.2,0.6): f = 1 - |(0.6, 0.6)| = 0.151472; d = 1.341641;
        // D = 0.151472 * 0.341641 = 0.051749 along -(1.2,0.6)/d = (-0.894427,-0.447214);
        // z = f/10.
        let m = sphincter(Convergence::Centre, 10.0);
        close(
            sphincter_displacement(&m, Vec3::new(1.2, 0.6, 7.0), 1.0),
            [-0.046_285_68, -0.023_142_84, 0.015_147_19],
        );
    }

    #[test]
    fn mouth_protected_disc_only_bulges() {
        // P = (0.5,0): d = 0.5 <= ly, no in-plane pull; f = 0.75, z = 0.075.
        let m = sphincter(Convergence::Centre, 10.0);
        close(
            sphincter_displacement(&m, Vec3::new(0.5, 0.0, 0.0), 1.0),
            [0.0, 0.0, 0.075],
        );
        // The centre itself (d = 0): z = 1/10.
        close(sphincter_displacement(&m, Vec3::ZERO, 1.0), [0.0, 0.0, 0.1]);
        // Outside the ellipse.
        assert_eq!(
            sphincter_displacement(&m, Vec3::new(3.0, 0.0, 0.0), 1.0),
            Vec3::ZERO
        );
        assert_eq!(
            sphincter_displacement(&m, Vec3::new(0.0, 1.0, 0.0), 1.0),
            Vec3::ZERO
        );
    }

    #[test]
    fn eye_on_the_minor_axis_is_t_times_one_minus_t() {
        // P = (0,0.5): t = 0.5, f = 1 - t = 0.5, g = t, D = 0.25, straight down;
        // z = f/30 = 0.0166667.
        let m = sphincter(Convergence::MajorAxis, 30.0);
        close(
            sphincter_displacement(&m, Vec3::new(0.0, 0.5, 0.0), 1.0),
            [0.0, -0.25, 0.016_666_67],
        );
        // P = (0,-0.25): f = 0.75, g = 0.25, D = 0.1875, straight up; z = 0.025.
        close(
            sphincter_displacement(&m, Vec3::new(0.0, -0.25, 0.0), 1.0),
            [0.0, 0.1875, 0.025],
        );
    }

    #[test]
    fn eye_off_axis_uses_the_full_ellipse_factor() {
        // P = (1,0.5): f = 1 - |(0.5,0.5)| = 0.292893, g = 0.5, D = 0.146447; no x pull.
        let m = sphincter(Convergence::MajorAxis, 30.0);
        close(
            sphincter_displacement(&m, Vec3::new(1.0, 0.5, 0.0), 1.0),
            [0.0, -0.146_446_6, 0.009_763_107],
        );
        // On the major axis: only the bulge (f = 0.05 at x = 1.9).
        close(
            sphincter_displacement(&m, Vec3::new(1.9, 0.0, 0.0), 1.0),
            [0.0, 0.0, 0.05 / 30.0],
        );
    }

    /// Attachment line y = 2 (x in -1..1), insertion line y = 0: axis -y, pull +y;
    /// |Ac lc| = 2, L = 3 (delta = 1.5), W = 2 (taper from 0.75 to 1).
    fn sheet() -> Sheet {
        Sheet {
            attachment: [Vec3::new(-1.0, 2.0, 0.0), Vec3::new(1.0, 2.0, 0.0)],
            insertion: [Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)],
            length: 3.0,
            width: 2.0,
        }
    }

    #[test]
    fn sheet_profile_along_the_axis() {
        let m = sheet();
        let at = |y: f32| sheet_displacement(&m, Vec3::new(0.0, y, 0.0), 1.0);
        // y = 1: lambda = 0.5, D = cos(0.5 * 90 deg) = 0.707107, pulled up toward the bone.
        close(at(1.0), [0.0, std::f32::consts::FRAC_1_SQRT_2, 0.0]);
        // y = 0: lambda = 1, D = 1.
        close(at(0.0), [0.0, 1.0, 0.0]);
        // y = -0.5: lambda = 1.25, D = cos((0.25/0.5) * 90 deg) = 0.707107.
        close(at(-0.5), [0.0, std::f32::consts::FRAC_1_SQRT_2, 0.0]);
        // Beyond the far end (lambda = 1.75 > delta) and behind the attachment line.
        assert_eq!(at(-1.5), Vec3::ZERO);
        assert_eq!(at(3.0), Vec3::ZERO);
        // The attachment line itself does not move (lambda = 0).
        assert_eq!(at(2.0), Vec3::ZERO);
    }

    #[test]
    fn sheet_lateral_taper_and_depth() {
        let m = sheet();
        // x = 0.875: halfway through the taper (0.75..1): 0.5 (1 + cos 90 deg) = 0.5.
        close(
            sheet_displacement(&m, Vec3::new(0.875, 0.0, 0.0), 1.0),
            [0.0, 0.5, 0.0],
        );
        close(
            sheet_displacement(&m, Vec3::new(-0.5, 0.0, 0.0), 1.0),
            [0.0, 1.0, 0.0],
        );
        assert_eq!(
            sheet_displacement(&m, Vec3::new(1.2, 0.0, 0.0), 1.0),
            Vec3::ZERO
        );
        // Depth is ignored.
        close(
            sheet_displacement(&m, Vec3::new(0.0, 0.0, 5.0), 0.4),
            [0.0, 0.4, 0.0],
        );
    }

    fn named(kind: MuscleKind) -> Muscle {
        Muscle {
            name: "m".into(),
            side: Side::Centre,
            mirror: None,
            kind,
        }
    }

    fn parameter_of(kind: MuscleKind) -> &'static str {
        match validate_muscle(&named(kind)) {
            Err(InvalidParameter { parameter, .. }) => parameter,
            other => panic!("expected an invalid parameter, got {other:?}"),
        }
    }

    #[test]
    fn invalid_parameters_are_named() {
        let l = linear();
        assert!(validate_muscle(&named(MuscleKind::Linear(l.clone()))).is_ok());
        for zone in [0.0, 90.0, f32::NAN, -5.0] {
            let bad = Linear { zone, ..l.clone() };
            assert_eq!(parameter_of(MuscleKind::Linear(bad)), "zone");
        }
        let bad = Linear {
            falloff_start: -1.0,
            ..l.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Linear(bad)), "falloff_start");
        let bad = Linear {
            falloff_end: 1.0,
            ..l.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Linear(bad)), "falloff_end");
        let bad = Linear {
            attachment: Vec3::new(f32::INFINITY, 0.0, 0.0),
            ..l.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Linear(bad)), "attachment");
        let bad = Linear {
            insertion: Vec3::ZERO,
            ..l
        };
        assert_eq!(parameter_of(MuscleKind::Linear(bad)), "insertion");

        let s = sphincter(Convergence::Centre, 10.0);
        assert!(validate_muscle(&named(MuscleKind::Sphincter(s.clone()))).is_ok());
        let bad = Sphincter {
            semi_major: 0.0,
            ..s.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Sphincter(bad)), "semi_major");
        let bad = Sphincter {
            semi_minor: -1.0,
            ..s.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Sphincter(bad)), "semi_minor");
        let bad = Sphincter {
            bulge: 0.0,
            ..s.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Sphincter(bad)), "bulge");
        let bad = Sphincter {
            centre: Vec3::NAN,
            ..s
        };
        assert_eq!(parameter_of(MuscleKind::Sphincter(bad)), "centre");

        let h = sheet();
        assert!(validate_muscle(&named(MuscleKind::Sheet(h.clone()))).is_ok());
        // |Ac lc| = 2: the sheet must reach beyond its insertion line.
        let longer = Sheet {
            length: 2.01,
            ..h.clone()
        };
        assert!(validate_muscle(&named(MuscleKind::Sheet(longer))).is_ok());
        let exact = Sheet {
            length: 2.0,
            ..h.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Sheet(exact)), "length");
        let bad = Sheet {
            length: 1.5,
            ..h.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Sheet(bad)), "length");
        let bad = Sheet {
            width: 0.0,
            ..h.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Sheet(bad)), "width");
        let bad = Sheet {
            insertion: h.attachment,
            ..h.clone()
        };
        assert_eq!(parameter_of(MuscleKind::Sheet(bad)), "insertion");
        // An attachment line along the axis has no width direction.
        let along = [Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 3.0, 0.0)];
        let bad = Sheet {
            attachment: along,
            insertion: [Vec3::ZERO, Vec3::ZERO],
            ..h
        };
        assert_eq!(parameter_of(MuscleKind::Sheet(bad)), "attachment");
    }

    #[test]
    fn field_lists_only_moved_vertices_in_order() {
        let rest = [
            Vec3::new(0.0, 0.0, 0.5),
            Vec3::new(5.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::ZERO,
        ];
        let field = Field::of(&MuscleKind::Linear(linear()), &rest);
        assert_eq!(field.vertices, vec![0, 2]);
        close(field.displacements[0], [0.0, 0.0, -0.5]);
        close(
            field.displacements[1],
            [0.0, 0.0, -std::f32::consts::SQRT_2],
        );
    }
}
