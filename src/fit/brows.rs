//! The brow's sheets stop at the eye socket and behind the face.
//!
//! A sheet muscle (the frontalis, its medial fibres) pulls everything in its zone through
//! the whole head's depth. On the template the zone ends above the lids, but a head whose
//! eye sockets are modelled inside (MakeHuman's base mesh: a lining runs from the inner
//! corner back and up behind the globe, 8-19 mm behind the corner) has that lining under the
//! fitted sheet, and the lining took the carried mask of the template's skin in front of it:
//! at AU1 rows of it rose 10 mm beside rows that stayed (26 triangles turned over, an edge
//! stretched 4.2x). The frontalis inserts into the brow's skin; what lies behind the globe
//! does not go with it.
//!
//! A whole head lies in a sheet's zone through its depth as well: the back of MakeHuman's
//! head, level with the brows, came down 14.7 mm with the brow lowerer's sheet (its carried
//! mask, beyond the template's face, is 1 there) and turned 22 triangles over. So the cut
//! also takes the skin two to three eye widths and more behind the eyes' corners.
//!
//! Each eye's socket, from its six lid landmarks: in the face's plane an ellipse about the
//! landmarks' middle, 1.3 half-widths across and 1.2 up (the lids and the lining behind
//! them, not the brow nor the temple), fading out to 1.3 times that; in depth, the skin
//! behind the eye's deeper corner, cut from a tenth of the half-width in front of it fully
//! by a fifth behind it (the face's forward leans with the head, and a lining starting right
//! behind the lid's fold must not be spared while the fold is pulled). Sizes go by the eye's
//! width, so they scale with the face. Each sheet's mask weakens it
//! there by the cut. Fitting the template to itself cuts nothing (its own fields are the
//! rig's). Measured against the template's own cut at each vertex's source instead, the
//! template's upper lid skin (behind its corners too) spared MakeHuman's lid fold while the
//! lining right behind it was cut: a fold turned over.

use glam::{DVec3, Vec3};

use super::parts::{Part, Parts};
use super::regions::smoothstep;
use super::Template;
use crate::landmarks::FaceFrame;
use crate::model::{Mask, Mesh, MuscleKind, Rig};

/// The most the socket's cut may change along an edge, times the sheets' pull at activation 1
/// there, per unit of the edge's length: the share of its length an edge may stretch or
/// shrink by the cut's change alone. Measured against depth, the cut changed by half across
/// a 1.6 mm edge of MakeHuman's lid fold cut in four (AU1 turned 6 triangles over); on the
/// mesh itself, no edge of the fold is steeper than this.
const SOCKET_STRAIN: f64 = 0.5;

/// Weights this close to 1 are left out of the mask.
const EPSILON: f64 = 1e-6;

/// The socket's ellipse in the face's plane, in the eye's half-widths: across, up.
const SOCKET_AXES: (f64, f64) = (1.3, 1.2);
/// The ellipse's cut fades out between these multiples of its size.
const SOCKET_FADE: (f64, f64) = (1.0, 1.3);
/// Behind the eye's deeper corner, the cut grows from nothing to full over these depths, in
/// the eye's half-widths (negative: in front of it).
const SOCKET_DEPTH: (f64, f64) = (-0.1, 0.2);
/// Behind the face, anywhere across it, the cut grows from nothing to full over these depths
/// behind the eyes' deeper corners, in the eye's half-widths (two to three eye widths: past
/// the forehead's and the temples' sides, short of the ears and the back of the head).
const BEHIND_FACE: (f64, f64) = (4.0, 6.0);

/// One eye's socket, from its lid landmarks.
struct Socket {
    centre: DVec3,
    lateral: DVec3,
    up: DVec3,
    forward: DVec3,
    half_width: f64,
    /// The deeper corner's place along `forward`, from `centre`.
    corner_depth: f64,
}

impl Socket {
    /// Both eyes' sockets of a face's 68 landmarks; `None` when its frame is degenerate.
    fn both(points: &[Vec3]) -> Option<[Socket; 2]> {
        let frame = FaceFrame::of(points)?;
        let eye = |first: usize, corners: [usize; 2]| {
            let centre = (first..first + 6)
                .map(|i| points[i].as_dvec3())
                .sum::<DVec3>()
                / 6.0;
            let [a, b] = corners.map(|i| points[i].as_dvec3());
            Socket {
                centre,
                lateral: frame.lateral,
                up: frame.up,
                forward: frame.forward,
                half_width: 0.5 * a.distance(b),
                corner_depth: (a - centre)
                    .dot(frame.forward)
                    .min((b - centre).dot(frame.forward)),
            }
        };
        let sockets = [eye(36, [36, 39]), eye(42, [42, 45])];
        sockets
            .iter()
            .all(|s| s.half_width > 0.0)
            .then_some(sockets)
    }

    /// Whether `p` lies within the socket's ellipse (as seen from the front, at any depth),
    /// where its cut may be more than nothing.
    fn around(&self, p: DVec3) -> bool {
        let d = p - self.centre;
        let w = self.half_width;
        let r =
            (d.dot(self.lateral) / (SOCKET_AXES.0 * w)).hypot(d.dot(self.up) / (SOCKET_AXES.1 * w));
        r <= SOCKET_FADE.1
    }

    /// How much of a sheet's pull the socket takes away at `p`: 1 in the lining behind the
    /// eye, 0 in front of its corners and outside its ellipse.
    fn cut(&self, p: DVec3) -> f64 {
        let d = p - self.centre;
        let w = self.half_width;
        let r =
            (d.dot(self.lateral) / (SOCKET_AXES.0 * w)).hypot(d.dot(self.up) / (SOCKET_AXES.1 * w));
        let inside = 1.0 - smoothstep(SOCKET_FADE.0, SOCKET_FADE.1, r);
        let behind = self.corner_depth - d.dot(self.forward);
        inside * smoothstep(SOCKET_DEPTH.0 * w, SOCKET_DEPTH.1 * w, behind)
    }

    /// How much of a sheet's pull is taken away at `p` for lying behind the face, far behind
    /// this eye's deeper corner.
    fn behind_face(&self, p: DVec3) -> f64 {
        let behind = self.corner_depth - (p - self.centre).dot(self.forward);
        let w = self.half_width;
        smoothstep(BEHIND_FACE.0 * w, BEHIND_FACE.1 * w, behind)
    }
}

/// The larger cut of both sockets at `p`, or of the face's back if larger (the lesser of
/// the two eyes' measures of it).
fn cut(sockets: &[Socket; 2], p: Vec3) -> f64 {
    let p = p.as_dvec3();
    let behind = sockets[0].behind_face(p).min(sockets[1].behind_face(p));
    sockets[0].cut(p).max(sockets[1].cut(p)).max(behind)
}

/// The masks for the rig's sheets: one weakening each skin vertex by how far it lies in an
/// eye socket or behind the face (module docs), and the brow lowerer's ramp caps
/// (`fit::brow_ramp`). `target` are the mesh's landmark positions. None when the rig has no
/// sheet or the mesh is the template itself.
pub(super) fn socket_mask(
    rig: &Rig,
    template: Template<'_>,
    (mesh, parts): (&Mesh, &Parts),
    target: &[Vec3],
    gains: &[(String, f64)],
) -> Vec<Mask> {
    let sheets: Vec<String> = rig
        .muscles
        .iter()
        .filter(|m| matches!(m.kind, MuscleKind::Sheet(_)))
        .map(|m| m.name.clone())
        .collect();
    // the template fitted to itself: its own fields are the rig's, nothing to cut
    let itself = mesh.positions == template.mesh.positions && target == template.landmarks;
    let Some(sockets) = Socket::both(target).filter(|_| !sheets.is_empty() && !itself) else {
        return Vec::new();
    };
    let mut kept: Vec<f32> = mesh
        .positions
        .iter()
        .zip(&parts.of_vertex)
        .map(|(p, part)| match part {
            Part::Skin => (1.0 - cut(&sockets, *p)) as f32,
            _ => 1.0,
        })
        .collect();
    // the cut goes by depth, and a fold's rows lie millimetres apart in depth whatever the
    // mesh's resolution: eased to the strain the sheets' pull may put on an edge
    let pull = super::ease::pull(&rig.muscles, &sheets, &mesh.positions, &|name| {
        gains
            .iter()
            .find(|(n, _)| n == name)
            .map_or(1.0, |&(_, g)| g)
    });
    let strength = |v: usize| pull[v];
    // (only round the sockets: behind the face the cut changes over centimetres)
    let around = |p: Vec3| sockets.iter().any(|s| s.around(p.as_dvec3()));
    super::ease::ease(
        mesh,
        parts,
        &mut kept,
        (&around, &|_, _| false),
        (SOCKET_STRAIN, &strength),
    );
    let weights: Vec<(u32, f32)> = kept
        .iter()
        .enumerate()
        .filter(|&(_, &w)| f64::from(w) < 1.0 - EPSILON)
        .map(|(v, &w)| (v as u32, w))
        .collect();
    let kept: Vec<f64> = kept.iter().map(|&w| f64::from(w)).collect();
    let eyes = super::brow_ramp::Eyes {
        width: sockets.iter().map(|s| s.half_width).sum::<f64>(),
        corners: [36, 39, 42, 45].map(|i| target[i]),
    };
    let ramps = super::brow_ramp::ramp_masks(rig, mesh, parts, &kept, &eyes);
    let mut masks: Vec<Mask> = (!weights.is_empty())
        .then_some(Mask {
            muscles: sheets,
            gain: 1.0,
            weights,
        })
        .into_iter()
        .collect();
    masks.extend(ramps);
    masks
}
