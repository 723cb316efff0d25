//! Irises painted per dot on eyes that have none.
//!
//! Many heads users bring model the eye as a blank ball (MakeHuman's eye proxies), or have no
//! eye behind the opening at all (MediaPipe's mask, whose covered eyes `fit-rig` opens onto a
//! dark `eye_interior`). Drawn as they are, an eye is a white ball or a black slot: a person
//! reads a blind or a closed eye, and so does a face tracker (the mask's open eye read
//! eyeBlink 0.45 against neutral's 0.04 on the built-in face, which models its irises).
//!
//! Where the scene knows the irises ([`Iris`], from the landmarks, through
//! [`crate::render::Framing`]) and the mesh has no `iris` or `pupil` group of its own, the
//! eye's surface (groups named for the eye, the sclera or the cornea, and the opened eye's
//! inside; not lashes, lids or brows) is drawn as an eyeball: every triangle of it near an
//! iris gets, per corner, its coordinates at rest across and up the face's plane from the
//! iris's centre, in iris radii. After the fill, each dot such a triangle drew is lit as the
//! front of an ideal eyeball looking straight out ([`EYEBALL`] iris radii, centred behind the
//! iris: its normal from the dot's place), and toned by where it lies on it: the pupil, the
//! iris, or the sclera, with the built-in face's tones and proportions. The blank eye's own
//! shape is not what is lit: MediaPipe's opened eye is a flat band set back in the opening,
//! lit dimmer than the skin around it, and a face tracker looks for a sclera brighter than
//! the iris it surrounds (a grey band with an iris on it read about as closed as the dark
//! slot). The eye does not move with the muscles (the lids slide over it), so rest
//! coordinates hold in every pose; a lid closing in front hides it by the depth test like
//! any surface.

use glam::Vec2;

use super::fill::AMBIENT;
use super::pieces::{affine, circle, clip_convex, fan};
use super::{LitTriangle, Renderer};
use crate::model::Mesh;
use crate::render::framing::Iris;

/// The pupil's radius in iris radii (the built-in face's eye: 2.0 of 5.75 mm).
const PUPIL: f32 = 0.35;
/// The tones of the pupil and the iris (those of the built-in face's `pupil` and `iris`
/// groups); the sclera is drawn as lit (1.0).
const PUPIL_TONE: f32 = 0.12;
const IRIS_TONE: f32 = 0.45;
/// The eyeball's radius in iris radii (12 mm against 5.9 mm in adults).
const EYEBALL: f32 = 2.05;
/// How far from an iris's centre the eye's surface is drawn as its eyeball, in iris radii:
/// past the eye's corners (half the eye's width is 2.5).
const REACH: f32 = 3.0;

/// A triangle of the eye's surface near an iris.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct IrisTriangle {
    /// Index into the renderer's triangles.
    pub triangle: u32,
    /// Index into the irises.
    pub iris: u32,
    /// Per corner, its place in the disc at rest, across and up, in iris radii.
    pub across: [f32; 3],
    /// See `across`.
    pub up: [f32; 3],
}

/// The tone at a place in an iris's disc (iris radii from its centre).
#[inline]
pub(super) fn tone_at(across: f32, up: f32) -> f32 {
    let r2 = across * across + up * up;
    if r2 < PUPIL * PUPIL {
        PUPIL_TONE
    } else if r2 < 1.0 {
        IRIS_TONE
    } else {
        1.0
    }
}

/// Whether a group is the surface of an eye: named for the eye (not its lashes, lids,
/// brows or corners, not a joint marker or a film over the eye), the sclera or the cornea,
/// or the inside of an eye `fit-rig` opened.
fn eye_name(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    let eye = ["eye", "sclera", "cornea"]
        .iter()
        .any(|w| lower.contains(w));
    let other = ["lid", "brow", "corner", "joint", "target", "socket"]
        .iter()
        .any(|w| lower.contains(w));
    eye && !other && !crate::fit::parts::lash_name(name)
}

/// Per vertex, whether it lies on a blank eye's surface; empty when the mesh has no such
/// group, or models its irises itself (a group named `iris` or `pupil`).
pub(super) fn blank_eyes(mesh: &Mesh) -> Vec<bool> {
    let own = mesh.groups.keys().any(|name| {
        let lower = name.to_ascii_lowercase();
        lower.contains("iris") || lower.contains("pupil")
    });
    let mut on = Vec::new();
    if own {
        return on;
    }
    for (_, members) in mesh.groups.iter().filter(|(name, _)| eye_name(name)) {
        if on.is_empty() {
            on.resize(mesh.positions.len(), false);
        }
        for &v in members {
            if let Some(o) = on.get_mut(v as usize) {
                *o = true;
            }
        }
    }
    on
}

/// The triangles (of `triangles`, whose corners all lie on a blank eye, `eye`) that come
/// within [`REACH`] of one of `irises` at the rest positions `rest`, each with its corners'
/// places about the iris nearest its centre.
pub(super) fn iris_triangles(
    rest: &[glam::Vec3],
    triangles: &[[u32; 3]],
    eye: &[bool],
    irises: &[Iris],
) -> Vec<IrisTriangle> {
    if eye.is_empty() || irises.is_empty() {
        return Vec::new();
    }
    let on_eye = |v: u32| eye.get(v as usize).copied().unwrap_or(false);
    let mut out = Vec::new();
    for (t, tri) in triangles.iter().enumerate() {
        if !tri.iter().all(|&v| on_eye(v)) {
            continue;
        }
        // `eye` has one entry per rest vertex, so the corners are in range.
        let p = tri.map(|v| rest[v as usize]);
        let place = |iris: &Iris, q: glam::Vec3| {
            let d = q - iris.centre;
            Vec2::new(d.dot(iris.across), d.dot(iris.up)) / iris.radius
        };
        let middle = (p[0] + p[1] + p[2]) / 3.0;
        let nearest = irises.iter().enumerate().min_by(|(_, a), (_, b)| {
            let (a, b) = (place(a, middle), place(b, middle));
            a.length_squared().total_cmp(&b.length_squared())
        });
        let Some((index, iris)) = nearest else {
            continue;
        };
        let corners = p.map(|q| place(iris, q));
        if !corners.iter().all(|c| c.is_finite()) {
            continue;
        }
        // The point of the triangle's box nearest the iris's centre, within reach?
        let (lo, hi) = (
            corners[0].min(corners[1]).min(corners[2]),
            corners[0].max(corners[1]).max(corners[2]),
        );
        if Vec2::ZERO.clamp(lo, hi).length_squared() < REACH * REACH {
            out.push(IrisTriangle {
                triangle: t as u32,
                iris: index as u32,
                across: corners.map(|c| c.x),
                up: corners.map(|c| c.y),
            });
        }
    }
    out
}

impl Renderer {
    /// Brings the painted irises up to `irises` (the scene's): the triangles that carry them
    /// and the eyes' tones (a painted eye's surface is a lit sclera, not the dark inside it
    /// is drawn as without one). Nothing to do on a mesh without blank eyes, or when they
    /// are the ones already painted.
    pub(super) fn paint_irises(&mut self, mesh: &Mesh, irises: &[Iris]) {
        if self.blank_eyes.is_empty() || self.painted_irises.as_deref() == Some(irises) {
            return;
        }
        self.painted_irises = Some(irises.to_vec());
        self.irises = iris_triangles(&mesh.positions, &self.triangles, &self.blank_eyes, irises);
        self.compute_tones(mesh);
    }

    /// Shades the dots of the iris triangles as the eyeball's: lit by its normal at the
    /// dot's place, times the tone there.
    #[inline(never)]
    pub(super) fn tone_irises(&mut self, w: usize, h: usize, depth: &[f32]) {
        let Some(irises) = self.painted_irises.take() else {
            return;
        };
        for k in 0..self.irises.len() {
            let i = self.irises[k];
            let light = self.light_in_eye(&irises[i.iris as usize]);
            self.retone_dots(
                i.triangle as usize,
                [1.0; 3],
                [i.across, i.up],
                (w, h, depth),
                |_, [across, up]| eyeball_shade(across, up, light) * tone_at(across, up),
            );
        }
        self.painted_irises = Some(irises);
    }
}

impl Renderer {
    /// The light in the axes of `iris`'s eye: across, up, out.
    fn light_in_eye(&self, iris: &Iris) -> glam::Vec3 {
        let out = iris.across.cross(iris.up);
        let light = self.light_mesh;
        glam::Vec3::new(light.dot(iris.across), light.dot(iris.up), light.dot(out))
    }

    /// For vector output: the eye's triangle `k` of the iris triangles, projected to the
    /// dots `screen`, as flat pieces at its `depth`: the triangle lit as the eyeball at its
    /// middle, then the parts of it the iris and the pupil cover (each a convex polygon, as
    /// triangles), drawn over it in that order.
    pub(super) fn iris_pieces(&self, k: usize, screen: [Vec2; 3], depth: f32) -> Vec<LitTriangle> {
        let i = self.irises[k];
        let Some(iris) = self
            .painted_irises
            .as_ref()
            .and_then(|irises| irises.get(i.iris as usize))
        else {
            return Vec::new();
        };
        let light = self.light_in_eye(iris);
        let place = [0, 1, 2].map(|j| Vec2::new(i.across[j], i.up[j]));
        let middle = (place[0] + place[1] + place[2]) / 3.0;
        let mut out = vec![LitTriangle {
            corners: screen,
            depth,
            shade: eyeball_shade(middle.x, middle.y, light),
        }];
        let Some(to_screen) = affine(place, screen) else {
            return out;
        };
        for (radius, tone) in [(1.0, IRIS_TONE), (PUPIL, PUPIL_TONE)] {
            let piece = clip_convex(&place, &circle(radius));
            if piece.len() < 3 {
                continue;
            }
            let centre = piece.iter().copied().sum::<Vec2>() / piece.len() as f32;
            let shade = eyeball_shade(centre.x, centre.y, light) * tone;
            let corners: Vec<Vec2> = piece.iter().map(|&q| to_screen(q)).collect();
            out.extend(fan(&corners).map(|corners| LitTriangle {
                corners,
                depth,
                shade,
            }));
        }
        out
    }
}

/// The Lambert shade of the ideal eyeball at `(across, up)` iris radii from its axis, lit
/// by `light` (unit, in the eye's axes: across, up, out); past its rim, the rim's.
#[inline]
fn eyeball_shade(across: f32, up: f32, light: glam::Vec3) -> f32 {
    let flat = Vec2::new(across, up) / EYEBALL;
    let flat = if flat.length_squared() > 1.0 {
        flat.normalize()
    } else {
        flat
    };
    let normal = flat.extend((1.0 - flat.length_squared()).max(0.0).sqrt());
    AMBIENT + (1.0 - AMBIENT) * normal.dot(light).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn the_eyeball_is_lit_by_its_normal() {
        let front = glam::Vec3::Z;
        assert!((eyeball_shade(0.0, 0.0, front) - 1.0).abs() < 1e-6);
        // Toward the rim it faces away from a light in front; past it, it stays at the rim.
        let rim = eyeball_shade(EYEBALL, 0.0, front);
        assert!((rim - AMBIENT).abs() < 1e-6);
        assert_eq!(eyeball_shade(2.0 * EYEBALL, 0.0, front), rim);
        assert!(eyeball_shade(1.0, 0.0, front) > eyeball_shade(1.5, 0.0, front));
        // A light from the left lights the left of the eyeball more.
        let left = glam::Vec3::new(0.6, 0.0, 0.8);
        assert!(eyeball_shade(1.0, 0.0, left) > eyeball_shade(-1.0, 0.0, left));
    }

    #[test]
    fn tones_go_pupil_iris_sclera_outward() {
        assert_eq!(tone_at(0.0, 0.0), PUPIL_TONE);
        assert_eq!(tone_at(0.5, 0.0), IRIS_TONE);
        assert_eq!(tone_at(0.0, -0.9), IRIS_TONE);
        assert_eq!(tone_at(0.8, 0.8), 1.0);
    }

    #[test]
    fn eye_groups_are_told_from_lashes_lids_and_markers() {
        for name in [
            "helper-l-eye",
            "eye_interior",
            "LeftEye",
            "sclera_r",
            "cornea",
        ] {
            assert!(eye_name(name), "{name}");
        }
        for name in [
            "helper-l-eyelashes-1",
            "upper_eyelid",
            "left_eyebrow",
            "joint-l-eye",
            "eye-target",
            "M_EyeOcclusion",
            "M_EyeBlend",
        ] {
            assert!(!eye_name(name), "{name}");
        }
    }

    fn ball_mesh(groups: &[&str]) -> Mesh {
        let mut mesh = Mesh::new(
            vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2]],
        )
        .unwrap();
        for g in groups {
            mesh.groups.insert(g.to_string(), vec![0, 1, 2]);
        }
        mesh
    }

    #[test]
    fn a_mesh_with_its_own_irises_or_no_eyes_is_not_painted() {
        assert!(blank_eyes(&ball_mesh(&["skin"])).is_empty());
        assert!(blank_eyes(&ball_mesh(&["eye", "iris"])).is_empty());
        assert_eq!(blank_eyes(&ball_mesh(&["eye"])), vec![true; 3]);
    }

    #[test]
    fn triangles_reaching_a_disc_carry_their_places_in_it() {
        let mesh = ball_mesh(&["eye"]);
        let eye = blank_eyes(&mesh);
        let iris = |x: f32| Iris {
            centre: Vec3::new(x, 0.0, 0.0),
            across: Vec3::X,
            up: Vec3::Y,
            radius: 0.5,
        };
        let found = iris_triangles(&mesh.positions, &mesh.triangles, &eye, &[iris(0.0)]);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].across, [-2.0, 2.0, 0.0]);
        assert_eq!(found[0].up, [-2.0, -2.0, 2.0]);
        // An iris far beside the triangle paints nothing.
        assert!(iris_triangles(&mesh.positions, &mesh.triangles, &eye, &[iris(5.0)]).is_empty());
    }
}
