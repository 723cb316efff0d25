//! Carrying a rig from its template face to another mesh.
//!
//! The template's landmarks are aligned with the mesh's by a similarity and a thin-plate
//! spline ([`Warp`]); every muscle point goes through the warp, every length is scaled by
//! the warp's local scale there (a mouth or eye ring by its lip or lid contour instead), the
//! jaw gets a pivot and axis through the warp and weights for the new mesh, the template's
//! per-vertex masks are carried like the jaw's weights, and masks keep muscles to the skin
//! and to their own side of the mouth and eyes. Muscle names stay, so AU tables written for
//! the template drive the new face.

use std::path::PathBuf;

use glam::{DMat3, DVec3, Vec3};
use thiserror::Error;

use super::parts::is_still;
use super::parts::{find_parts, Part, PartOverrides, Parts};
use super::regions::{Extent, Opening, Side, CONTOURS};
use super::sources::{Mirrored, Sources};
use super::warp::{Similarity, Warp};
use super::Template;
use crate::landmarks::{check_shape, order_problems, FaceFrame, LandmarkError, Landmarks};
use crate::model::{
    Convergence, Frame, Jaw, Linear, Mask, Mesh, Muscle, MuscleKind, Rig, Sheet, Sphincter,
};

/// Why a rig cannot be fitted.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FitError {
    /// The target's landmarks are unusable.
    #[error(transparent)]
    Landmarks(#[from] LandmarkError),
    /// The template's landmarks are unusable (not the target's: the message belongs to the
    /// template's landmark file).
    #[error("the template's landmarks: {0}")]
    Template(LandmarkError),
    /// The warp could not be solved (landmarks far too close together).
    #[error("the landmarks cannot be aligned with the template's (are several on one point?)")]
    Warp,
    /// The mesh has no skin vertex.
    #[error("no part of the mesh was taken for skin; name the skin with --skin GROUP")]
    NoSkin,
}

/// The result of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Fitted {
    /// The rig placed on the mesh.
    pub rig: Rig,
    /// Which parts are skin, still or turn with the jaw.
    pub parts: Parts,
    /// The similarity's scale from template to mesh.
    pub scale: f64,
    /// The largest landmark correction after the similarity, relative to the face's size.
    pub bend: f64,
    /// For each opening (mouth, eyes), the muscles kept off the other side of it.
    pub sides: Vec<(String, Vec<String>, Vec<String>)>,
}

/// A fitted muscle whose size or strength is far from the template's times the face's scale.
#[derive(Debug, Clone, PartialEq)]
pub struct Outlier {
    /// The muscle's name.
    pub muscle: String,
    /// What is off: `falloff`, `length`, `width`, `semi-major axis`, `semi-minor axis` or
    /// `strength`.
    pub what: &'static str,
    /// The fitted value over the template's times the scale (1 when it scales with the face).
    pub ratio: f64,
}

impl Fitted {
    /// The muscles whose size (a linear muscle's falloff end, a sheet's length and width, a
    /// ring's semi-axes) or strength (the product of its masks' gains) is more than `factor`
    /// times larger or smaller than `template`'s times the similarity's scale. A linear
    /// muscle's pull scales with its geometry, so its strength is compared with the
    /// template's alone.
    pub fn outliers(&self, template: &Rig, factor: f64) -> Vec<Outlier> {
        let gain = |rig: &Rig, name: &str| {
            rig.masks
                .iter()
                .filter(|m| m.muscles.iter().any(|n| n == name))
                .map(|m| f64::from(m.gain))
                .product::<f64>()
        };
        let mut out = Vec::new();
        for (m, t) in self.rig.muscles.iter().zip(&template.muscles) {
            let sizes: Vec<(&'static str, f32, f32)> = match (&m.kind, &t.kind) {
                (MuscleKind::Linear(a), MuscleKind::Linear(b)) => {
                    vec![("falloff", a.falloff_end, b.falloff_end)]
                }
                (MuscleKind::Sheet(a), MuscleKind::Sheet(b)) => {
                    vec![("length", a.length, b.length), ("width", a.width, b.width)]
                }
                (MuscleKind::Sphincter(a), MuscleKind::Sphincter(b)) => vec![
                    ("semi-major axis", a.semi_major, b.semi_major),
                    ("semi-minor axis", a.semi_minor, b.semi_minor),
                ],
                _ => Vec::new(),
            };
            let strength_scale = match m.kind {
                MuscleKind::Linear(_) => 1.0,
                _ => self.scale,
            };
            let ratios = sizes
                .into_iter()
                .map(|(what, a, b)| (what, f64::from(a) / (f64::from(b) * self.scale)))
                .chain([(
                    "strength",
                    gain(&self.rig, &m.name) / (gain(template, &t.name) * strength_scale),
                )]);
            for (what, ratio) in ratios {
                if !(ratio <= factor && ratio >= 1.0 / factor) {
                    out.push(Outlier {
                        muscle: m.name.clone(),
                        what,
                        ratio,
                    });
                }
            }
        }
        out
    }
}

/// Gains this close to 1 are written as 1 (no mask).
const GAIN_EPSILON: f64 = 1e-6;

/// Fits `template`'s rig onto `mesh` from the mesh's landmarks; `mesh_path` is what the new
/// rig's `mesh` field names. Copies of split vertices in no face ([`Mesh::followers`]) are
/// weighted as the vertex each moves with.
pub fn fit_rig(
    template: Template<'_>,
    mesh: &Mesh,
    landmarks: &Landmarks,
    mesh_path: PathBuf,
    overrides: &PartOverrides,
) -> Result<Fitted, FitError> {
    if let Some(compact) = super::weld::Compact::of(mesh) {
        let landmarks = compact.landmarks(landmarks);
        let mut fitted = fit_rig(template, &compact.mesh, &landmarks, mesh_path, overrides)?;
        compact.expand(&mut fitted.rig, &mut fitted.parts);
        return Ok(fitted);
    }
    let (target, [from, to], warp) = place(template, mesh, landmarks)?;
    let parts = find_parts(mesh, &landmarks.vertices(mesh), &target, overrides);
    if !parts.of_vertex.contains(&Part::Skin) {
        return Err(FitError::NoSkin);
    }
    let rings = RingFit::all(template.landmarks, &target, [&from, &to], &warp.similarity);
    let (mut muscles, gains) = carry_muscles(template, &warp, &rings);
    // the mouth corners' muscles meet the skin at their insertion at the template's angle
    let skins = [
        super::insertion::Skin::of_template(template, super::insertion::front(&from)),
        super::insertion::Skin::of_mesh(mesh, &parts, &target, super::insertion::front(&to)),
    ];
    super::insertion::keep_angles(
        &template.rig.muscles,
        template.landmarks,
        &mut muscles,
        [&skins[0], &skins[1]],
    );
    let openings_from = Opening::all(template.landmarks);
    let openings_to = Opening::all(&target);
    let lips = [
        super::lipsides::LipSides::of_template(template),
        super::lipsides::LipSides::find(mesh, &landmarks.vertices(mesh), &parts),
    ];
    let jaw = template.rig.jaw.as_ref().map(|jaw| {
        carry_jaw(
            jaw,
            &warp,
            template,
            mesh,
            &parts,
            (
                &openings_from,
                &openings_to,
                [lips[0].as_ref(), lips[1].as_ref()],
            ),
        )
    });
    let mut rig = Rig {
        version: template.rig.version,
        mesh: mesh_path,
        landmarks: None,
        combine: template.rig.combine,
        muscles,
        jaw,
        masks: Vec::new(),
    };
    let mut sources = Sources::find(template, &warp, mesh, &parts);
    let mouths = [&openings_from, &openings_to].map(|o| o.iter().find(|o| o.name == "mouth"));
    if let ([Some(a), Some(b)], [Some(c), Some(d)]) = (mouths, &lips) {
        sources = sources.with_lips(template, &warp, mesh, [a, b], [c, d]);
    }
    let sources = sources.with_midline(
        template,
        &warp,
        mesh,
        [&from, &to],
        [template.landmarks, &target],
    );
    let sides = side_masks(
        &mut rig,
        template,
        mesh,
        &sources,
        (
            &openings_from,
            &openings_to,
            [lips[0].as_ref(), lips[1].as_ref()],
        ),
    );
    let mut carried = carry_masks(template, &sources);
    // the lips' muscles' masks no steeper than on the template (a finer mesh read a coarse
    // template's corners and midline in steps)
    let lip_muscles: Vec<String> = sides
        .iter()
        .filter(|(opening, _, _)| opening == "mouth")
        .flat_map(|(_, upper, lower)| upper.iter().chain(lower).cloned())
        .collect();
    let faces = super::ease::Faces {
        template,
        mesh: (mesh, &parts, &rig.muscles),
        gains: &gains,
    };
    super::ease::ease_masks(&faces, &lip_muscles, &mut carried);
    rig.masks.extend(carried.into_iter().map(|(_, mask)| mask));
    rig.masks.extend(still_mask(&rig, &parts));
    rig.masks
        .extend(depth_masks(&rig, template, mesh, &sources, [&from, &to]));
    // the eye rings: sized between the eye's width and its opening, they are capped by the
    // template's reach (the mouth's rings follow the lips' own contour both ways)
    let round = round_rings(template, &rings);
    rig.masks.extend(super::reach::reach_masks(
        &rig, template, mesh, &sources, &warp, &round,
    ));
    // the brow's sheets stop at the eye sockets a mesh models behind its lids
    rig.masks.extend(super::brows::socket_mask(
        &rig,
        template,
        (mesh, &parts),
        &target,
        &gains,
    ));
    rig.masks.extend(gains.into_iter().map(|(name, gain)| Mask {
        muscles: vec![name],
        gain: gain as f32,
        weights: Vec::new(),
    }));
    // the closing eye rings: shaped from the mesh's own lids where the carried mask does
    // not close them as the template's closes the template's
    let marks = landmarks.vertices(mesh);
    super::lids::shape_lids(&mut rig, template, mesh, &warp, &parts, &target, &marks);
    Ok(Fitted {
        rig,
        parts,
        scale: warp.similarity.scale,
        bend: warp.bend(&target),
        sides,
    })
}

/// The mesh's landmark positions, both faces' frames (template, mesh) and the warp between
/// them, after checking that the two landmark sets can be matched at all.
fn place(
    template: Template<'_>,
    mesh: &Mesh,
    landmarks: &Landmarks,
) -> Result<(Vec<Vec3>, [FaceFrame; 2], Warp), FitError> {
    let target = landmarks.positions(mesh)?;
    check_shape(template.landmarks).map_err(FitError::Template)?;
    let from =
        FaceFrame::of(template.landmarks).ok_or(FitError::Template(LandmarkError::Degenerate))?;
    let to = FaceFrame::of(&target).ok_or(LandmarkError::Degenerate)?;
    check_handedness(&from, &to, &target)?;
    let warp = Warp::fit(template.landmarks, &target).ok_or(FitError::Warp)?;
    Ok((target, [from, to], warp))
}

/// Refuses landmark sets of opposite handedness, naming which one is mirrored (or, for the
/// mesh's, what is out of order when that is the likelier cause).
fn check_handedness(from: &FaceFrame, to: &FaceFrame, target: &[Vec3]) -> Result<(), FitError> {
    if from.right_handed == to.right_handed {
        return Ok(());
    }
    // Meshes are right-handed (docs/model.md), so of two sets that disagree the left-handed
    // one is the mirrored one.
    if !from.right_handed {
        return Err(FitError::Template(LandmarkError::Mirrored));
    }
    // A set out of order can look mirrored; say what is out of order first.
    let problems = order_problems(target);
    if !problems.is_empty() && problems.len() > 2 {
        return Err(LandmarkError::OutOfOrder {
            problems: problems.into_iter().take(3).collect::<Vec<_>>().join("; "),
        }
        .into());
    }
    Err(LandmarkError::Mirrored.into())
}

/// The template's muscles carried through the warp, and each muscle's gain where it is not 1:
/// the carry's own times the template's gains on the muscle (its per-vertex weights are
/// carried by `carry_masks`).
fn carry_muscles(
    template: Template<'_>,
    warp: &Warp,
    rings: &[RingFit],
) -> (Vec<Muscle>, Vec<(String, f64)>) {
    let mut gains = Vec::new();
    let muscles = template
        .rig
        .muscles
        .iter()
        .map(|m| {
            let (kind, gain) = carry(&m.kind, warp, rings);
            let gain = gain
                * template
                    .rig
                    .masks
                    .iter()
                    .filter(|mask| mask.muscles.contains(&m.name))
                    .map(|mask| f64::from(mask.gain))
                    .product::<f64>();
            if (gain - 1.0).abs() > GAIN_EPSILON {
                gains.push((m.name.clone(), gain));
            }
            Muscle { kind, ..m.clone() }
        })
        .collect();
    (muscles, gains)
}

/// The names of the template's round rings (the eyes').
fn round_rings<'a>(template: Template<'a>, rings: &[RingFit]) -> Vec<&'a str> {
    template
        .rig
        .muscles
        .iter()
        .filter(|m| match &m.kind {
            MuscleKind::Sphincter(s) => {
                RingFit::around(rings, s.centre.as_dvec3()).is_some_and(|r| r.round)
            }
            _ => false,
        })
        .map(|m| m.name.as_str())
        .collect()
}

/// A ring's landmark contour on the template and on the mesh, and the linear map between
/// them: the contour's own axes (across, up, out of the face) onto the mesh's, stretched by
/// the ratios of the contours' half-widths and half-heights across and up, and by the
/// similarity's scale out of the face. An eye's ([`super::regions::Contour::round`]) is
/// stretched up by the geometric mean of the two ratios instead and turned by the
/// similarity's rotation.
#[derive(Debug, Clone)]
struct RingFit {
    from: Extent,
    to: Extent,
    map: DMat3,
    width_ratio: f64,
    height_ratio: f64,
    /// Whether the contour is an eye's ([`super::regions::Contour::round`]); a ring closing on
    /// its major axis there takes its strength from the lids' travel
    /// ([`RingFit::travel_gain`]).
    round: bool,
    /// The contour's upper and lower landmarks facing each other across the opening (37 and
    /// 41, 38 and 40 for the right eye), on the template and on the mesh.
    pairs: [Vec<(Vec3, Vec3)>; 2],
}

impl RingFit {
    /// The fits of the mouth's and the eyes' contours ([`CONTOURS`]) that both faces have.
    fn all(
        template: &[Vec3],
        target: &[Vec3],
        frames: [&FaceFrame; 2],
        similarity: &Similarity,
    ) -> Vec<Self> {
        let scale = similarity.scale;
        CONTOURS
            .iter()
            .filter_map(|contour| {
                let from = Extent::of(template, contour, frames[0].forward)?;
                let to = Extent::of(target, contour, frames[1].forward)?;
                let width_ratio = to.half_width / from.half_width;
                let height_ratio = to.half_height / from.half_height;
                let basis = |e: &Extent| DMat3::from_cols(e.axes[0], e.axes[1], e.axes[2]);
                let map = if contour.round {
                    // turned with the face, not with the corners' line: an eye's corners
                    // lie at different depths on one face and the same on another, which
                    // tilts that line by tens of degrees in the face's plane
                    let up = (width_ratio * height_ratio).sqrt();
                    let stretch = DMat3::from_diagonal(DVec3::new(width_ratio, up, scale));
                    similarity.rotation * basis(&from) * stretch * basis(&from).transpose()
                } else {
                    let stretch =
                        DMat3::from_diagonal(DVec3::new(width_ratio, height_ratio, scale));
                    basis(&to) * stretch * basis(&from).transpose()
                };
                let [right, left] = contour.corners;
                let pairs = |points: &[Vec3]| {
                    (right + 1..left)
                        .zip((left + 1..=contour.last).rev())
                        .map(|(u, l)| (points[u], points[l]))
                        .collect()
                };
                Some(RingFit {
                    from,
                    to,
                    map,
                    width_ratio,
                    height_ratio,
                    round: contour.round,
                    pairs: [pairs(template), pairs(target)],
                })
            })
            .collect()
    }

    /// The contour a sphincter centred at template point `centre` sits in: the nearest,
    /// relative to its half-width, if the centre lies within a half-width of its middle.
    fn around(rings: &[RingFit], centre: DVec3) -> Option<&RingFit> {
        let off = |r: &RingFit| centre.distance(r.from.centre) / r.from.half_width;
        rings
            .iter()
            .filter(|r| off(r) < 1.0)
            .min_by(|a, b| off(a).total_cmp(&off(b)))
    }

    /// The gain that makes `fitted` close the mesh's lids by the same share of the opening as
    /// `template` closes the template's: for the facing lid landmarks, how much nearer the
    /// ring's unit pull brings each pair along the contour's up, summed, over the pairs'
    /// summed opening; on the template over the same on the mesh. An eye ring is not
    /// stretched with the opening, so the ratio of heights alone would not close the lids
    /// where the template's close. Falls back to that ratio when either ring misses the lids.
    fn travel_gain(&self, template: &Sphincter, fitted: &Sphincter) -> f64 {
        let closure = |s: &Sphincter, pairs: &[(Vec3, Vec3)], extent: &Extent| {
            let up = extent.axes[1];
            let pull = |p: Vec3| {
                crate::model::field::sphincter_displacement(s, p, 1.0)
                    .as_dvec3()
                    .dot(up)
            };
            let (closed, open) = pairs.iter().fold((0.0, 0.0), |(c, o), &(u, l)| {
                (c + pull(l) - pull(u), o + (u - l).as_dvec3().dot(up))
            });
            closed / open
        };
        let before = closure(template, &self.pairs[0], &self.from);
        let after = closure(fitted, &self.pairs[1], &self.to);
        let gain = before / after;
        if gain.is_finite() && gain > 0.0 {
            gain
        } else {
            self.height_ratio
        }
    }
}

/// A muscle's geometry through the warp, and the gain for the kinds whose pull is a length
/// of its own (sheets and sphincters move the skin by up to one mesh unit per activation,
/// whatever the face's size).
///
/// A sphincter in a contour of landmarks (the lips, an eye) takes its frame and semi-axes
/// from that contour ([`RingFit`]), not from the warp at its centre: there the lip or lid
/// landmarks nearly coincide on a closed mouth or eye, and the spline's Jacobian swings with
/// them. Its gain is the contour's ratio along the direction it pulls: the width for a ring
/// that closes on its centre (the mouth's pucker), the height for one that closes on its
/// major axis (lids, lips pressed together).
fn carry(kind: &MuscleKind, warp: &Warp, rings: &[RingFit]) -> (MuscleKind, f64) {
    let map = |p: Vec3| warp.apply_f32(p);
    match kind {
        MuscleKind::Linear(m) => {
            let (a, i) = (map(m.attachment), map(m.insertion));
            let ratio = f64::from(a.distance(i)) / f64::from(m.attachment.distance(m.insertion));
            let ratio = if ratio.is_finite() && ratio > 0.0 {
                ratio
            } else {
                warp.local_scale(m.attachment.as_dvec3())
            };
            (
                MuscleKind::Linear(Linear {
                    attachment: a,
                    insertion: i,
                    zone: m.zone,
                    falloff_start: (f64::from(m.falloff_start) * ratio) as f32,
                    falloff_end: (f64::from(m.falloff_end) * ratio) as f32,
                }),
                1.0,
            )
        }
        MuscleKind::Sheet(m) => {
            let attachment = m.attachment.map(map);
            let insertion = m.insertion.map(map);
            let mid = |p: [Vec3; 2]| 0.5 * (p[0] + p[1]);
            let axis_ratio = f64::from(mid(attachment).distance(mid(insertion)))
                / f64::from(mid(m.attachment).distance(mid(m.insertion)));
            let across_ratio = f64::from(attachment[0].distance(attachment[1]))
                / f64::from(m.attachment[0].distance(m.attachment[1]));
            let centre = 0.5 * (mid(m.attachment) + mid(m.insertion));
            let scale = warp.local_scale(centre.as_dvec3());
            let finite_or = |r: f64| if r.is_finite() && r > 0.0 { r } else { scale };
            (
                MuscleKind::Sheet(Sheet {
                    attachment,
                    insertion,
                    length: (f64::from(m.length) * finite_or(axis_ratio)) as f32,
                    width: (f64::from(m.width) * finite_or(across_ratio)) as f32,
                }),
                scale,
            )
        }
        MuscleKind::Sphincter(m) => {
            let c = m.centre.as_dvec3();
            let ring = RingFit::around(rings, c);
            let j = ring.map_or_else(|| warp.jacobian(c), |ring| ring.map);
            let axes = m.frame.rotation().unwrap_or(DMat3::IDENTITY);
            let (u, v) = (j * axes.x_axis, j * axes.y_axis);
            let fitted = Sphincter {
                centre: map(m.centre),
                semi_major: (f64::from(m.semi_major) * u.length()) as f32,
                semi_minor: (f64::from(m.semi_minor) * v.length()) as f32,
                frame: carry_frame(u, v),
                ..m.clone()
            };
            let gain = match (ring, m.convergence) {
                (None, _) => warp.local_scale(c),
                (Some(ring), Convergence::Centre) => ring.width_ratio,
                (Some(ring), Convergence::MajorAxis) if ring.round => ring.travel_gain(m, &fitted),
                (Some(ring), Convergence::MajorAxis) => ring.height_ratio,
            };
            (MuscleKind::Sphincter(fitted), gain)
        }
    }
}

/// The template's openings, the mesh's, and the lips of each found by connectivity (the
/// mouth's sides go by them, [`super::lipsides`]).
type Openings<'a> = (
    &'a [Opening],
    &'a [Opening],
    [Option<&'a super::lipsides::LipSides>; 2],
);

/// The jaw through the warp: pivot and axis carried, weights made for the new mesh.
fn carry_jaw(
    jaw: &Jaw,
    warp: &Warp,
    template: Template<'_>,
    mesh: &Mesh,
    parts: &Parts,
    (openings_from, openings_to, lips): Openings<'_>,
) -> Jaw {
    let j: DMat3 = warp.jacobian(jaw.pivot.as_dvec3());
    let axis = (j * jaw.axis.as_dvec3()).normalize_or_zero();
    let axis = if axis == DVec3::ZERO { DVec3::X } else { axis };
    let axis = snap_axis(axis.as_vec3());
    let weights = super::jaw::weights(
        template,
        jaw,
        warp,
        mesh,
        parts,
        [
            (openings_from.first(), lips[0]),
            (openings_to.first(), lips[1]),
        ],
    );
    Jaw {
        pivot: warp.apply_f32(jaw.pivot),
        degrees_per_unit: jaw.degrees_per_unit,
        weights,
        axis,
        slide: super::jaw::carried_slide(jaw, j, axis),
    }
}

/// A sphincter's frame through the warp from its axes carried by the warp's local linear part
/// (`u`, `v`): `u` normalised, `v` made perpendicular to it, each snapped to a coordinate axis
/// within rounding, so that a rig fitted to a face in the template's axes keeps the mesh's
/// own frame. A warp that flattens the ellipse (never for a fit that passed its checks) keeps
/// the mesh's axes.
fn carry_frame(u: DVec3, v: DVec3) -> Frame {
    let x = u.normalize_or_zero();
    let y = (v - x * x.dot(v)).normalize_or_zero();
    let frame = Frame {
        x: snap_axis(x.as_vec3()),
        y: snap_axis(y.as_vec3()),
    };
    if frame.check().is_ok() {
        frame
    } else {
        Frame::IDENTITY
    }
}

/// An axis within rounding of a coordinate axis is written as that axis.
fn snap_axis(axis: Vec3) -> Vec3 {
    for unit in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
        if axis.distance(unit) < 1e-6 {
            return unit;
        }
    }
    axis
}

/// The masks that keep each muscle of one lip (or lid) off the other: a muscle working above
/// an opening's line gets less weight on the vertices below it, and the other way round, by
/// as much more as they lie on the other side than their template sources ([`Sources`]) do
/// on the template. What the template's own fields do across its lines is kept (a fit to the
/// template itself adds nothing); a vertex carried across the line by the warp or the
/// nearest-point lookup is cut off. Returns, per opening, the muscles kept above and below.
fn side_masks(
    rig: &mut Rig,
    template: Template<'_>,
    mesh: &Mesh,
    sources: &Sources,
    (openings_from, openings_to, lips): Openings<'_>,
) -> Vec<(String, Vec<String>, Vec<String>)> {
    let mut report = Vec::new();
    for (from, to) in openings_from.iter().zip(openings_to) {
        let mut upper = Vec::new();
        let mut lower = Vec::new();
        for m in &template.rig.muscles {
            match from.side_of(action_point(&m.kind)) {
                Some(Side::Upper) => upper.push(m.name.clone()),
                Some(Side::Lower) => lower.push(m.name.clone()),
                None => {}
            }
        }
        for (muscles, other) in [(&upper, Side::Lower), (&lower, Side::Upper)] {
            if muscles.is_empty() {
                continue;
            }
            let weights: Vec<(u32, f32)> = mesh
                .positions
                .iter()
                .enumerate()
                .filter_map(|(v, p)| {
                    let (_, share) = sources.of_vertex[v]?;
                    let w = super::lipsides::side_weight(lips[1], to, v, *p, other);
                    let was = share
                        * sources.read(v, |u| {
                            let at = template.mesh.positions[u as usize];
                            super::lipsides::side_weight(lips[0], from, u as usize, at, other)
                        });
                    let cut = w - was;
                    (cut > GAIN_EPSILON).then_some((v as u32, (1.0 - cut) as f32))
                })
                .collect();
            if !weights.is_empty() {
                rig.masks.push(Mask {
                    muscles: muscles.clone(),
                    gain: 1.0,
                    weights,
                });
            }
        }
        report.push((to.name.to_string(), upper, lower));
    }
    report
}

/// Where a muscle acts on the skin: a linear muscle's insertion, the middle of a sheet's
/// insertion line, a sphincter's centre.
fn action_point(kind: &MuscleKind) -> Vec3 {
    match kind {
        MuscleKind::Linear(m) => m.insertion,
        MuscleKind::Sheet(m) => 0.5 * (m.insertion[0] + m.insertion[1]),
        MuscleKind::Sphincter(m) => m.centre,
    }
}

/// How far behind its centre a fitted sphincter stops pulling, as fractions of its semi-major
/// axis: full weight in front of the first, none behind the second.
const DEPTH_REACH: (f64, f64) = (0.5, 1.0);

/// A sphincter pulls everything inside its ellipse, however deep: on a whole head that would
/// include the back of the head. Each sphincter gets weight 0 on skin more than its
/// semi-major axis behind its centre (along the face's forward direction), fading in over
/// the half-axis in front of that, less what the template's own ring reaches at the vertex's
/// source ([`Sources`]): a fit to the template itself cuts nothing, a head behind the
/// template's face is cut.
fn depth_masks(
    rig: &Rig,
    template: Template<'_>,
    mesh: &Mesh,
    sources: &Sources,
    frames: [&FaceFrame; 2],
) -> Vec<Mask> {
    let [from, to] = frames;
    // How much of a ring at `centre` reaching `reach` is cut at `p`.
    let cut = |s: &Sphincter, frame: &FaceFrame, p: Vec3| {
        let reach = f64::from(s.semi_major);
        let behind = -(p - s.centre).as_dvec3().dot(frame.forward);
        super::regions::smoothstep(DEPTH_REACH.0 * reach, DEPTH_REACH.1 * reach, behind)
    };
    let mut masks = Vec::new();
    for (m, t) in rig.muscles.iter().zip(&template.rig.muscles) {
        let (MuscleKind::Sphincter(s), MuscleKind::Sphincter(ts)) = (&m.kind, &t.kind) else {
            continue;
        };
        let field = crate::model::Field::of(&m.kind, &mesh.positions);
        let weights: Vec<(u32, f32)> = field
            .vertices
            .iter()
            .filter_map(|&v| {
                let share = sources.of_vertex[v as usize].map_or(0.0, |(_, share)| share);
                let was = if share > 0.0 {
                    share
                        * sources.read(v as usize, |u| {
                            cut(ts, from, template.mesh.positions[u as usize])
                        })
                } else {
                    0.0
                };
                let more = cut(s, to, mesh.positions[v as usize]) - was;
                (more > GAIN_EPSILON).then_some((v, (1.0 - more) as f32))
            })
            .collect();
        if !weights.is_empty() {
            masks.push(Mask {
                muscles: vec![m.name.clone()],
                gain: 1.0,
                weights,
            });
        }
    }
    masks
}

/// The template's per-vertex masks carried to the mesh: each skin vertex takes the weight of
/// its source ([`Sources`]), blended back to 1 by the source's share. A mask holding the
/// template's still parts is not carried: the mesh's own parts make its still mask. The
/// masks' gains are folded into each muscle's gain by [`fit_rig`], so a carried mask has
/// gain 1. Each comes with the template's mask it was carried from.
fn carry_masks<'a>(template: Template<'a>, sources: &Sources) -> Vec<(&'a Mask, Mask)> {
    let count = template.mesh.vertex_count();
    template
        .rig
        .masks
        .iter()
        .filter(|m| !m.weights.is_empty() && !is_still(template.rig, m))
        .filter_map(|mask| {
            let mut dense = vec![1.0f32; count];
            for &(v, w) in &mask.weights {
                if let Some(slot) = dense.get_mut(v as usize) {
                    *slot = w;
                }
            }
            let weights: Vec<(u32, f32)> = sources
                .of_vertex
                .iter()
                .enumerate()
                .filter_map(|(v, source)| {
                    let (_, share) = (*source)?;
                    let carried =
                        Mirrored::blend(sources.midline.get(v).and_then(|m| m.as_ref()), |image| {
                            // read at the sources, or at their mirror images
                            let at = |u: u32| match image {
                                true => {
                                    let image = sources.mirror_of.get(u as usize).copied();
                                    f64::from(dense[image.unwrap_or(u) as usize])
                                }
                                false => f64::from(dense[u as usize]),
                            };
                            sources.read(v, at)
                        });
                    let w = 1.0 - share * (1.0 - carried);
                    (w < 1.0 - GAIN_EPSILON).then_some((v as u32, w as f32))
                })
                .collect();
            (!weights.is_empty()).then(|| {
                let carried = Mask {
                    muscles: mask.muscles.clone(),
                    gain: 1.0,
                    weights,
                };
                (mask, carried)
            })
        })
        .collect()
}

/// One mask for every muscle: weight 0 on every vertex that is not skin.
fn still_mask(rig: &Rig, parts: &Parts) -> Option<Mask> {
    let weights: Vec<(u32, f32)> = parts
        .of_vertex
        .iter()
        .enumerate()
        .filter(|(_, p)| **p != Part::Skin)
        .map(|(v, _)| (v as u32, 0.0))
        .collect();
    (!weights.is_empty() && !rig.muscles.is_empty()).then(|| Mask {
        muscles: rig.muscles.iter().map(|m| m.name.clone()).collect(),
        gain: 1.0,
        weights,
    })
}
