//! The camera: view angles, zoom and pan, and the fitted projection onto a dot canvas.
//!
//! See the [module documentation](super) for the screen orientation (the subject's left, at
//! positive x, appears on the viewer's right in the front view).

use glam::{Mat3, Vec2, Vec3};

/// Fraction of the canvas left free around the fitted mesh on each side.
const MARGIN: f32 = 0.03;

/// An orthographic camera looking at the subject.
///
/// `yaw` turns the subject about the vertical axis, `pitch` tilts it about the horizontal
/// screen axis, `zoom` scales the fitted view (1.0 fits the mesh to the canvas) and `pan`
/// moves the camera: the point `pan` (in mesh units from the fitted centre, measured on the
/// screen, x right, y up) appears at the canvas centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Rotation about the vertical axis, in radians. Positive yaw brings the subject's left
    /// cheek (positive x) toward the viewer; `FRAC_PI_2` shows the left profile.
    pub yaw: f32,
    /// Rotation about the horizontal screen axis, in radians. Positive pitch looks down on
    /// the subject from above.
    pub pitch: f32,
    /// Magnification over the fitted view; 1.0 fits the whole mesh.
    pub zoom: f32,
    /// Camera shift in mesh units, x to the screen's right, y up: positive x moves the view
    /// right, so the mesh moves left on screen.
    pub pan: Vec2,
    /// Mesh to face coordinates (a rotation; rows: across toward the subject's left, up, out
    /// of the face), applied before `yaw` and `pitch`, so the front view faces the face
    /// whichever way the mesh stands ([`super::Framing`]). The identity for a mesh in
    /// glTF's axes.
    pub basis: Mat3,
}

impl Default for Camera {
    fn default() -> Camera {
        Camera::front()
    }
}

impl Camera {
    /// Facing the subject, as a person standing in front of them sees them.
    pub fn front() -> Camera {
        Camera {
            yaw: 0.0,
            pitch: 0.0,
            zoom: 1.0,
            pan: Vec2::ZERO,
            basis: Mat3::IDENTITY,
        }
    }

    /// The subject's left profile (nose toward the screen's left).
    pub fn side() -> Camera {
        Camera {
            yaw: std::f32::consts::FRAC_PI_2,
            ..Camera::front()
        }
    }

    /// A three-quarter view: turned 35 degrees toward the subject's left and seen from
    /// slightly above.
    pub fn three_quarter() -> Camera {
        Camera {
            yaw: 35f32.to_radians(),
            pitch: 10f32.to_radians(),
            ..Camera::front()
        }
    }

    /// The world-to-view matrix: view x to the screen's right, y up, z toward the viewer.
    ///
    /// A pure rotation (determinant +1): mesh x is screen right in the front view, so the
    /// subject's left (positive x) is on the viewer's right. Positive yaw turns the subject
    /// about +y by `-yaw`, which brings positive x toward the viewer. Both turn about the
    /// face's axes ([`Camera::basis`]).
    pub fn view_matrix(&self) -> Mat3 {
        Mat3::from_rotation_x(self.pitch) * Mat3::from_rotation_y(-self.yaw) * self.basis
    }

    /// The camera's angles, zoom and pan as in `self`, turned about `basis`.
    pub fn with_basis(self, basis: Mat3) -> Camera {
        Camera { basis, ..self }
    }

    /// The unit vector, in mesh coordinates, pointing from the subject toward the viewer.
    pub fn toward_viewer(&self) -> Vec3 {
        self.view_matrix().transpose() * Vec3::Z
    }

    /// Fits the box `bounds` (min, max in mesh coordinates) into a canvas of `width` x
    /// `height` dots whose dots are `dot_aspect` times as wide as they are tall, centred,
    /// with a small margin, then applies zoom and pan.
    ///
    /// The fit uses the box's eight corners seen from this camera, so turning the camera
    /// changes the scale smoothly; pass the rest pose's bounds so deformation does not.
    pub fn fit(
        &self,
        bounds: (Vec3, Vec3),
        width: usize,
        height: usize,
        dot_aspect: f32,
    ) -> Projection {
        let (lo, hi) = bounds;
        let corners = (0..8).map(|i| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        });
        self.fit_seen(corners, width, height, dot_aspect)
    }

    /// Like [`Camera::fit`], fitting the points themselves as seen from this camera rather
    /// than their box: a turned face is centred on what is drawn, not on the empty corners
    /// of its box. Non-finite points are ignored. The extent still changes continuously as
    /// the camera turns; pass the rest pose so deformation does not move the fit.
    pub fn fit_points(
        &self,
        points: &[Vec3],
        width: usize,
        height: usize,
        dot_aspect: f32,
    ) -> Projection {
        let finite = points.iter().copied().filter(|p| p.is_finite());
        self.fit_seen(finite, width, height, dot_aspect)
    }

    /// Fits the view-space extent of `points` (mesh coordinates) to the canvas.
    fn fit_seen(
        &self,
        points: impl Iterator<Item = Vec3>,
        width: usize,
        height: usize,
        dot_aspect: f32,
    ) -> Projection {
        let view = self.view_matrix();
        let mut vlo = Vec3::splat(f32::INFINITY);
        let mut vhi = Vec3::splat(f32::NEG_INFINITY);
        for p in points {
            let v = view * p;
            vlo = vlo.min(v);
            vhi = vhi.max(v);
        }
        let finite = vlo.is_finite() && vhi.is_finite();
        let (vlo, vhi) = if finite {
            (vlo, vhi)
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        let centre = (vlo + vhi) * 0.5;
        let extent = (vhi - vlo).max(Vec3::splat(f32::EPSILON));
        let aspect = if dot_aspect.is_finite() && dot_aspect > 0.0 {
            dot_aspect
        } else {
            1.0
        };
        // Physical canvas size in units of one dot's height.
        let phys_w = width as f32 * aspect;
        let phys_h = height as f32;
        let usable = 1.0 - 2.0 * MARGIN;
        let fit_scale = (phys_w * usable / extent.x).min(phys_h * usable / extent.y);
        let zoom = if self.zoom.is_finite() && self.zoom > 0.0 {
            self.zoom
        } else {
            1.0
        };
        let scale_y = fit_scale * zoom;
        let pan = if self.pan.is_finite() {
            self.pan
        } else {
            Vec2::ZERO
        };
        Projection {
            view,
            centre: centre + pan.extend(0.0),
            scale_x: scale_y / aspect,
            scale_y,
            origin: Vec2::new(width as f32 * 0.5, height as f32 * 0.5),
        }
    }
}

/// An angle in degrees brought into (-180, 180]: the one range every view shows its turn in
/// (half a turn either way reads as 180, never -180).
pub fn wrap_degrees(deg: f32) -> f32 {
    let wrapped = (deg + 180.0).rem_euclid(360.0) - 180.0;
    if wrapped == -180.0 {
        180.0
    } else {
        wrapped
    }
}

/// A camera fitted to a canvas: maps mesh points to dot coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// World-to-view matrix (see [`Camera::view_matrix`]).
    pub view: Mat3,
    /// The view-space point that lands on the canvas centre.
    pub centre: Vec3,
    /// Dots per mesh unit horizontally.
    pub scale_x: f32,
    /// Dots per mesh unit vertically (also used for depth, so depth is in dot heights).
    pub scale_y: f32,
    /// The canvas centre, in dots.
    pub origin: Vec2,
}

impl Projection {
    /// Projects a mesh point: x in dots to the right, y in dots downward (row order), z the
    /// depth in dot heights, larger nearer the viewer. Non-finite input gives non-finite
    /// output, which the rasterizer skips.
    #[inline]
    pub fn project(&self, p: Vec3) -> Vec3 {
        let v = self.view * p - self.centre;
        Vec3::new(
            self.origin.x + v.x * self.scale_x,
            self.origin.y - v.y * self.scale_y,
            v.z * self.scale_y,
        )
    }

    /// The point into view space (x right, y up, z toward the viewer), unscaled.
    #[inline]
    pub fn to_view(&self, p: Vec3) -> Vec3 {
        self.view * p
    }
}

#[cfg(test)]
mod angle_tests {
    use super::wrap_degrees;

    #[test]
    fn angles_wrap_into_one_half_open_range() {
        assert_eq!(wrap_degrees(-180.0), 180.0);
        assert_eq!(wrap_degrees(180.0), 180.0);
        assert_eq!(wrap_degrees(190.0), -170.0);
        assert_eq!(wrap_degrees(-540.0), 180.0);
        assert_eq!(wrap_degrees(0.0), 0.0);
    }
}
