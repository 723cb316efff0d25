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

use glam::{DVec3, Vec3};

use super::deform::BindError;
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
/// the mouth, toward the major axis for an eye, plus the z bulge (MODEL-NOTES sections 2, 3).
pub fn sphincter_displacement(muscle: &Sphincter, p: Vec3, activation: f32) -> Vec3 {
    SphincterShape::new(muscle).unit_displacement(p) * activation
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
    /// A sphincter.
    Sphincter(SphincterShape),
    /// A sheet muscle.
    Sheet(SheetShape),
}

impl Shape {
    /// Prepares a muscle of any kind.
    pub fn new(kind: &MuscleKind) -> Shape {
        match kind {
            MuscleKind::Linear(m) => Shape::Linear(LinearShape::new(m)),
            MuscleKind::Sphincter(m) => Shape::Sphincter(SphincterShape::new(m)),
            MuscleKind::Sheet(m) => Shape::Sheet(SheetShape::new(m)),
        }
    }

    /// Displacement of the rest point `p` per unit activation.
    pub fn unit_displacement(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Linear(s) => s.unit_displacement(p),
            Shape::Sphincter(s) => s.unit_displacement(p),
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
    pub fn axial_factor(&self, lambda: f64) -> f64 {
        if (0.0..=1.0).contains(&lambda) {
            ((1.0 - lambda) * FRAC_PI_2).cos()
        } else if lambda > 1.0 && lambda <= self.delta {
            ((lambda - 1.0) / (self.delta - 1.0) * FRAC_PI_2).cos()
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

/// Checks a muscle's parameters, naming the muscle and the parameter on failure.
pub fn validate_muscle(muscle: &Muscle) -> Result<(), BindError> {
    let bad = |parameter: &'static str, message: String| BindError::InvalidParameter {
        muscle: muscle.name.clone(),
        parameter,
        message,
    };
    let finite = |parameter: &'static str, v: Vec3| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(bad(parameter, format!("{v} is not finite")))
        }
    };
    match &muscle.kind {
        MuscleKind::Linear(m) => {
            finite("attachment", m.attachment)?;
            finite("insertion", m.insertion)?;
            if !(m.zone.is_finite() && m.zone > 0.0 && m.zone < 90.0) {
                return Err(bad(
                    "zone",
                    format!("{} must lie strictly between 0 and 90 degrees", m.zone),
                ));
            }
            if !(m.falloff_start.is_finite() && m.falloff_start >= 0.0) {
                return Err(bad(
                    "falloff_start",
                    format!("{} must be a finite number >= 0", m.falloff_start),
                ));
            }
            if !(m.falloff_end.is_finite() && m.falloff_end > m.falloff_start) {
                return Err(bad(
                    "falloff_end",
                    format!(
                        "{} must be finite and greater than falloff_start ({})",
                        m.falloff_end, m.falloff_start
                    ),
                ));
            }
            if (m.insertion.as_dvec3() - m.attachment.as_dvec3()).length() == 0.0 {
                return Err(bad(
                    "insertion",
                    "coincides with the attachment, so the muscle has no direction".into(),
                ));
            }
        }
        MuscleKind::Sphincter(m) => {
            finite("centre", m.centre)?;
            for (parameter, v) in [
                ("semi_major", m.semi_major),
                ("semi_minor", m.semi_minor),
                ("bulge", m.bulge),
            ] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(bad(parameter, format!("{v} must be a finite number > 0")));
                }
            }
        }
        MuscleKind::Sheet(m) => {
            for (parameter, v) in [
                ("attachment", m.attachment[0]),
                ("attachment", m.attachment[1]),
                ("insertion", m.insertion[0]),
                ("insertion", m.insertion[1]),
            ] {
                finite(parameter, v)?;
            }
            if !(m.width.is_finite() && m.width > 0.0) {
                return Err(bad(
                    "width",
                    format!("{} must be a finite number > 0", m.width),
                ));
            }
            let shape = SheetShape::new(m);
            if shape.span <= 0.0 {
                return Err(bad(
                    "insertion",
                    "the insertion line's midpoint coincides with the attachment line's".into(),
                ));
            }
            if !(m.length.is_finite() && m.length as f64 >= shape.span) {
                return Err(bad(
                    "length",
                    format!(
                        "{} must be finite and at least the attachment-to-insertion distance {:.6}",
                        m.length, shape.span
                    ),
                ));
            }
            if shape.lateral == DVec3::ZERO {
                return Err(bad(
                    "attachment",
                    "the attachment line has no extent across the sheet's axis".into(),
                ));
            }
        }
    }
    Ok(())
}
