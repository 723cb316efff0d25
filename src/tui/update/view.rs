//! Camera and drawing options.

use super::*;

/// Camera and drawing options: turning, zooming, panning, presets, styles, cells and
/// overlays. None of these is an edit.
pub(crate) fn apply(app: &mut App, action: Action) {
    match action {
        Action::Rotate(yaw, pitch) => {
            app.view.yaw = crate::render::camera::wrap_degrees(app.view.yaw + yaw);
            app.view.pitch = (app.view.pitch + pitch).clamp(-90.0, 90.0);
            // Zoomed in, the focus stays at the centre as the head turns.
            if app.view.zoom > crate::tui::app::DEFAULT_ZOOM {
                app.view.pan = focus_pan(app).unwrap_or(app.view.pan);
            }
        }
        Action::Zoom(factor) if factor.is_finite() && factor > 0.0 => {
            app.view.zoom = (app.view.zoom * factor).clamp(0.25, 8.0);
            app.view.pan = if app.view.zoom > crate::tui::app::DEFAULT_ZOOM {
                focus_pan(app).unwrap_or(app.view.pan)
            } else {
                (0.0, 0.0)
            };
        }
        Action::Pan(dx, dy) => {
            app.view.pan.0 = (app.view.pan.0 + dx).clamp(-1.0, 1.0);
            app.view.pan.1 = (app.view.pan.1 + dy).clamp(-1.0, 1.0);
        }
        Action::ResetView => app.view.preset(ViewPreset::Front),
        Action::Preset(preset) => app.view.preset(preset),
        Action::CycleStyle => {
            app.view.style = app.view.style.next();
            let drawn = app.view.drawn_cells();
            if drawn == app.view.cells {
                app.info(format!("style: {}", app.view.style.name()));
            } else {
                app.info(format!(
                    "style: {} (in {} cells)",
                    app.view.style.name(),
                    crate::tui::app::cells_name(drawn)
                ));
            }
        }
        Action::CycleCells => {
            app.view.cells = crate::tui::app::next_cells(app.view.cells);
            app.info(format!(
                "cells: {}",
                crate::tui::app::cells_name(app.view.cells)
            ));
        }
        Action::ToggleAscii => {
            app.view.cells = if app.view.cells == CellMode::Ascii {
                CellMode::Braille
            } else {
                CellMode::Ascii
            };
            app.info(format!(
                "cells: {}",
                crate::tui::app::cells_name(app.view.cells)
            ));
        }
        Action::ToggleMuscles => {
            app.view.show_muscles = !app.view.show_muscles;
            app.info(on_off("muscle overlay", app.view.show_muscles));
        }
        Action::ToggleGhost => {
            app.view.show_ghost = !app.view.show_ghost;
            app.info(on_off("rest-pose ghost", app.view.show_ghost));
        }
        Action::ToggleDisplacement => {
            app.view.show_displacement = !app.view.show_displacement;
            app.info(on_off("displacement colours", app.view.show_displacement));
        }
        _ => {}
    }
}

pub(crate) fn on_off(what: &str, on: bool) -> String {
    format!("{what} {}", if on { "on" } else { "off" })
}

/// Where zooming in centres: the selected muscle's region, or with the jaw (or no muscle)
/// selected, the mouth; `None` when the rig has no mouth to find.
pub(crate) fn zoom_focus(app: &App) -> Option<glam::Vec3> {
    use crate::model::MuscleKind;
    let rig = app.rig();
    let region = |kind: &MuscleKind| match kind {
        // The skin it moves: between the falloff's start and end along the muscle.
        MuscleKind::Linear(l) => {
            let dir = (l.insertion - l.attachment).normalize_or_zero();
            l.attachment + dir * (0.5 * (l.falloff_start + l.falloff_end))
        }
        MuscleKind::Sphincter(s) => s.centre,
        MuscleKind::Sheet(s) => {
            (s.attachment[0] + s.attachment[1] + s.insertion[0] + s.insertion[1]) / 4.0
        }
    };
    if let Row::Muscle(i) = app.selected_row() {
        if let Some(m) = rig.muscles.get(i) {
            return Some(region(&m.kind)).filter(|p| p.is_finite());
        }
    }
    // The mouth: its sphincter, else the mesh's lip or mouth vertices.
    let mouth = rig.muscles.iter().find(|m| {
        let name = m.name.to_ascii_lowercase();
        matches!(m.kind, MuscleKind::Sphincter(_)) && name.contains("oris")
    });
    if let Some(m) = mouth {
        return Some(region(&m.kind)).filter(|p| p.is_finite());
    }
    let mesh = app.doc.face.mesh();
    let group = mesh
        .groups
        .iter()
        .find(|(name, v)| {
            let name = name.to_ascii_lowercase();
            !v.is_empty() && (name.contains("mouth") || name.contains("lip"))
        })
        .map(|(_, v)| v)?;
    let points: Vec<glam::Vec3> = group
        .iter()
        .filter_map(|&i| mesh.positions.get(i as usize).copied())
        .collect();
    let centre = points.iter().copied().sum::<glam::Vec3>() / points.len().max(1) as f32;
    Some(centre).filter(|p| p.is_finite() && !points.is_empty())
}

/// The pan (fractions of the face's size, as [`crate::tui::app::View::pan`]) that puts the
/// zoom focus at the viewport's centre for the current view angles.
fn focus_pan(app: &App) -> Option<(f32, f32)> {
    let focus = zoom_focus(app)?;
    let mesh = app.doc.face.mesh();
    let framing = app.doc.face.framing();
    let view = app.camera().view_matrix();
    // The centre the camera fits the framed points around, as it sees it.
    let (mut lo, mut hi) = (glam::Vec3::INFINITY, glam::Vec3::NEG_INFINITY);
    let framed = framing.frame(mesh);
    for p in framed.iter().filter(|p| p.is_finite()) {
        let v = view * *p;
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return None;
    }
    let extent = framing.size();
    let offset = (view * focus - (lo + hi) * 0.5).truncate() / extent;
    Some((offset.x.clamp(-1.0, 1.0), offset.y.clamp(-1.0, 1.0)))
}
