//! Carrying a rig from its template face to another mesh.
//!
//! The template's landmarks are aligned with the mesh's by a similarity and a thin-plate
//! spline ([`Warp`]); every muscle point goes through the warp, every length is scaled by
//! the warp's local scale there, the jaw gets a pivot and axis through the warp and weights
//! for the new mesh, and masks keep muscles to the skin and to their own side of the mouth
//! and eyes. Muscle names stay, so AU tables written for the template drive the new face.

use std::path::PathBuf;

use glam::{DMat3, DVec3, Vec3};
use thiserror::Error;

use super::landmarks::{FaceFrame, LandmarkError, Landmarks};
use super::parts::{find_parts, Part, PartOverrides, Parts};
use super::regions::{Opening, Side};
use super::warp::Warp;
use crate::model::{Frame, Jaw, Linear, Mask, Mesh, Muscle, MuscleKind, Rig, Sheet, Sphincter};

/// A rig with the mesh it is placed on and that mesh's landmarks: what a fit starts from.
#[derive(Debug, Clone, Copy)]
pub struct Template<'a> {
    /// The rig to carry.
    pub rig: &'a Rig,
    /// The mesh it is placed on.
    pub mesh: &'a Mesh,
    /// The 68 landmark positions on that mesh.
    pub landmarks: &'a [Vec3],
}

/// Why a rig cannot be fitted.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FitError {
    /// The target's (or the template's) landmarks are unusable.
    #[error(transparent)]
    Landmarks(#[from] LandmarkError),
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

/// Gains this close to 1 are written as 1 (no mask).
const GAIN_EPSILON: f64 = 1e-6;

/// Fits `template`'s rig onto `mesh` from the mesh's landmarks; `mesh_path` is what the new
/// rig's `mesh` field names.
pub fn fit_rig(
    template: Template<'_>,
    mesh: &Mesh,
    landmarks: &Landmarks,
    mesh_path: PathBuf,
    overrides: &PartOverrides,
) -> Result<Fitted, FitError> {
    let target = landmarks.positions(mesh)?;
    let from = FaceFrame::of(template.landmarks).ok_or(LandmarkError::Degenerate)?;
    let to = FaceFrame::of(&target).ok_or(LandmarkError::Degenerate)?;
    if from.right_handed != to.right_handed {
        return Err(LandmarkError::Mirrored.into());
    }
    let warp = Warp::fit(template.landmarks, &target).ok_or(FitError::Warp)?;
    let parts = find_parts(mesh, &landmarks.vertices(mesh), &target, overrides);
    if !parts.of_vertex.contains(&Part::Skin) {
        return Err(FitError::NoSkin);
    }
    let mut gains = Vec::new();
    let muscles: Vec<Muscle> = template
        .rig
        .muscles
        .iter()
        .map(|m| {
            let (kind, gain) = carry(&m.kind, &warp);
            // the template's own gains on the muscle (its per-vertex weights are not carried)
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
    let openings_from = Opening::all(template.landmarks);
    let openings_to = Opening::all(&target);
    let jaw = template.rig.jaw.as_ref().map(|jaw| {
        carry_jaw(
            jaw,
            &warp,
            template,
            mesh,
            &parts,
            &openings_from,
            &openings_to,
        )
    });
    let mut rig = Rig {
        version: template.rig.version,
        mesh: mesh_path,
        combine: template.rig.combine,
        muscles,
        jaw,
        masks: Vec::new(),
    };
    let sides = side_masks(
        &mut rig,
        template,
        mesh,
        &parts,
        &openings_from,
        &openings_to,
    );
    rig.masks.extend(still_mask(&rig, &parts));
    rig.masks.extend(depth_masks(&rig, mesh, &parts, &to));
    for (name, gain) in gains {
        rig.masks.push(Mask {
            muscles: vec![name],
            gain: gain as f32,
            weights: Vec::new(),
        });
    }
    Ok(Fitted {
        rig,
        parts,
        scale: warp.similarity.scale,
        bend: warp.bend(&target),
        sides,
    })
}

/// A muscle's geometry through the warp, and the gain for the kinds whose pull is a length
/// of its own (sheets and sphincters move the skin by up to one mesh unit per activation,
/// whatever the face's size).
fn carry(kind: &MuscleKind, warp: &Warp) -> (MuscleKind, f64) {
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
            let j = warp.jacobian(c);
            let axes = m.frame.rotation().unwrap_or(DMat3::IDENTITY);
            let (u, v) = (j * axes.x_axis, j * axes.y_axis);
            (
                MuscleKind::Sphincter(Sphincter {
                    centre: map(m.centre),
                    semi_major: (f64::from(m.semi_major) * u.length()) as f32,
                    semi_minor: (f64::from(m.semi_minor) * v.length()) as f32,
                    frame: carry_frame(u, v),
                    ..m.clone()
                }),
                warp.local_scale(c),
            )
        }
    }
}

/// The jaw through the warp: pivot and axis carried, weights made for the new mesh.
fn carry_jaw(
    jaw: &Jaw,
    warp: &Warp,
    template: Template<'_>,
    mesh: &Mesh,
    parts: &Parts,
    openings_from: &[Opening],
    openings_to: &[Opening],
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
        openings_from.first(),
        openings_to.first(),
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
/// an opening's line gets weight `1 - w` on the vertices below it, and the other way round.
/// Returns, per opening, the muscles kept above and below.
fn side_masks(
    rig: &mut Rig,
    template: Template<'_>,
    mesh: &Mesh,
    parts: &Parts,
    openings_from: &[Opening],
    openings_to: &[Opening],
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
                .filter(|(v, _)| parts.of_vertex[*v] == Part::Skin)
                .filter_map(|(v, p)| {
                    let w = to.side_weight(*p, other);
                    (w > 0.0).then_some((v as u32, (1.0 - w) as f32))
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

/// A sphincter pulls everything inside its ellipse, however deep: on a whole head that would
/// include the back of the head. Each sphincter gets weight 0 on skin more than its
/// semi-major axis behind its centre (along the face's forward direction), fading in over
/// the half-axis in front of that.
fn depth_masks(rig: &Rig, mesh: &Mesh, parts: &Parts, frame: &FaceFrame) -> Vec<Mask> {
    let mut masks = Vec::new();
    for m in &rig.muscles {
        let MuscleKind::Sphincter(s) = &m.kind else {
            continue;
        };
        let field = crate::model::Field::of(&m.kind, &mesh.positions);
        let reach = f64::from(s.semi_major);
        let weights: Vec<(u32, f32)> = field
            .vertices
            .iter()
            .filter(|&&v| parts.of_vertex[v as usize] == Part::Skin)
            .filter_map(|&v| {
                let behind = -(mesh.positions[v as usize] - s.centre)
                    .as_dvec3()
                    .dot(frame.forward);
                let w = 1.0 - super::regions::smoothstep(0.5 * reach, reach, behind);
                (w < 1.0).then_some((v, w as f32))
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
