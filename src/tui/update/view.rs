//! Camera and drawing options.

use super::*;

/// Camera and drawing options: turning, zooming, panning, presets, styles, cells and
/// overlays. None of these is an edit.
pub(crate) fn apply(app: &mut App, action: Action) {
    match action {
        Action::Rotate(yaw, pitch) => {
            app.view.yaw = wrap_degrees(app.view.yaw + yaw);
            app.view.pitch = (app.view.pitch + pitch).clamp(-89.0, 89.0);
        }
        Action::Zoom(factor) if factor.is_finite() && factor > 0.0 => {
            app.view.zoom = (app.view.zoom * factor).clamp(0.25, 8.0);
        }
        Action::Pan(dx, dy) => {
            app.view.pan.0 = (app.view.pan.0 + dx).clamp(-1.0, 1.0);
            app.view.pan.1 = (app.view.pan.1 + dy).clamp(-1.0, 1.0);
        }
        Action::ResetView => app.view.preset(ViewPreset::Front),
        Action::Preset(preset) => app.view.preset(preset),
        Action::CycleStyle => {
            app.view.style = app.view.style.next();
            app.info(format!("style: {}", app.view.style.name()));
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

pub(crate) fn wrap_degrees(deg: f32) -> f32 {
    let wrapped = (deg + 180.0).rem_euclid(360.0) - 180.0;
    if wrapped == -180.0 {
        180.0
    } else {
        wrapped
    }
}
