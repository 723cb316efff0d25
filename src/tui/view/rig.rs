//! Rig mode's overlay: the selected muscle's zone of influence over the face. A linear
//! muscle shows its cone and its falloff start and end as arcs about the attachment; a
//! sphincter its ellipse in its frame, with the major axis; a sheet its zone (length by width
//! from the attachment line); the jaw its weights as colour and its axis as a line through the
//! pivot. The selected point is marked.

use glam::Vec3;

use crate::model::mesh::bounds_of as bounds;
use crate::model::{Jaw, Linear, MuscleKind, Rig};
use crate::render::{displacement_ramp, Overlay, Palette, Rgb, Shape};
use crate::tui::app::{App, Row};
use crate::tui::rig::{point, point_names};

/// Colour of the zone's outline.
const ZONE: Rgb = Rgb(40, 230, 40);
/// Colour of the falloff arcs.
const FALLOFF: Rgb = Rgb(120, 180, 255);
/// Colour of the jaw's axis and a sphincter's major axis.
const AXIS: Rgb = Rgb(255, 200, 60);
/// Half the length of the jaw's axis line, as a fraction of the face's height.
const AXIS_HALF: f32 = 0.35;
/// Arcs are drawn as this many segments per 90 degrees.
const ARC_STEPS: usize = 12;

/// A plain segment (the renderer marks a `Segment`'s start; a flat quad has no mark).
fn segment(a: Vec3, b: Vec3, color: Rgb) -> Overlay {
    Overlay {
        shape: Shape::Quad {
            corners: [a, b, b, a],
        },
        color,
        selected: false,
    }
}

/// Appends the zone of the selected row and a mark on the selected point.
pub fn zone_overlays(app: &App, out: &mut Vec<Overlay>) {
    let row = app.selected_row();
    zone_of(app.rig(), &app.doc.face.mesh().positions, row, out);
    let names = point_names(match row {
        Row::Muscle(i) => app.rig().muscles.get(i).map(|m| &m.kind),
        Row::Jaw => None,
    });
    let i = app.rig_edit.point.min(names.len().saturating_sub(1));
    if let Some(at) = point(app.rig(), row, i) {
        out.push(Overlay {
            shape: Shape::Point { at },
            color: Palette::default().selected,
            selected: true,
        });
    }
}

/// The selected row's zone: a linear muscle's cone, a ring's ellipse, a sheet's quad, the
/// jaw's axis and weights.
fn zone_of(rig: &Rig, rest: &[Vec3], row: Row, out: &mut Vec<Overlay>) {
    let kind = match row {
        Row::Muscle(i) => match rig.muscles.get(i) {
            Some(m) => &m.kind,
            None => return,
        },
        Row::Jaw => {
            if let Some(jaw) = &rig.jaw {
                jaw_zone(jaw, rest, out);
            }
            return;
        }
    };
    match kind {
        MuscleKind::Linear(m) => linear_zone(m, out),
        MuscleKind::Sphincter(m) => {
            let major = m.frame.axis_x() * m.semi_major;
            out.push(Overlay {
                shape: Shape::Ellipse {
                    centre: m.centre,
                    semi_x: major,
                    semi_y: m.frame.axis_y() * m.semi_minor,
                },
                color: ZONE,
                selected: false,
            });
            out.push(segment(m.centre - major, m.centre + major, AXIS));
        }
        MuscleKind::Sheet(m) => {
            let a = (m.attachment[0] + m.attachment[1]) * 0.5;
            let i = (m.insertion[0] + m.insertion[1]) * 0.5;
            let axis = (i - a).normalize_or_zero();
            let line = (m.attachment[1] - m.attachment[0]).normalize_or(Vec3::X);
            let across = (line - axis * line.dot(axis)).normalize_or(Vec3::X) * (m.width * 0.5);
            let far = a + axis * m.length;
            out.push(Overlay {
                shape: Shape::Quad {
                    corners: [a - across, a + across, far + across, far - across],
                },
                color: ZONE,
                selected: false,
            });
        }
    }
}

/// The jaw's axis, and each weighted vertex coloured from blue (barely moves) to red (turns
/// fully).
fn jaw_zone(jaw: &Jaw, rest: &[Vec3], out: &mut Vec<Overlay>) {
    let (lo, hi) = bounds(rest);
    let half = jaw.axis.normalize_or_zero() * ((hi - lo).y * AXIS_HALF);
    out.push(segment(jaw.pivot - half, jaw.pivot + half, AXIS));
    for &(v, w) in &jaw.weights {
        if let Some(&at) = rest.get(v as usize) {
            out.push(Overlay {
                shape: Shape::Point { at },
                color: displacement_ramp(w),
                selected: false,
            });
        }
    }
}

/// A linear muscle's cone: its two edges and its falloff arcs.
fn linear_zone(m: &Linear, out: &mut Vec<Overlay>) {
    let axis = (m.insertion - m.attachment).normalize_or_zero();
    if axis == Vec3::ZERO {
        return;
    }
    // The cone's edges and arcs are drawn in the plane of the axis and its perpendicular
    // across the face: the cut a front view sees.
    let across = Vec3::Z.cross(axis).normalize_or(Vec3::Y);
    let half = m.zone.to_radians();
    let dir = |a: f32| axis * a.cos() + across * a.sin();
    let reach = m.falloff_end.max(m.falloff_start);
    for a in [-half, half] {
        out.push(segment(m.attachment, m.attachment + dir(a) * reach, ZONE));
    }
    for r in [m.falloff_start, m.falloff_end] {
        let steps = ((half / std::f32::consts::FRAC_PI_2) * ARC_STEPS as f32)
            .ceil()
            .max(2.0) as usize;
        for k in 0..steps {
            let a0 = -half + 2.0 * half * k as f32 / steps as f32;
            let a1 = -half + 2.0 * half * (k + 1) as f32 / steps as f32;
            out.push(segment(
                m.attachment + dir(a0) * r,
                m.attachment + dir(a1) * r,
                FALLOFF,
            ));
        }
    }
}
