//! The picker's view and cursor: the projected screen, panning, turning and zooming, and
//! the cursor that snaps to the nearest visible vertex.

use glam::Vec2;

use super::super::screen::Screen;
use super::{PickApp, ZOOM_RANGE};

impl PickApp {
    /// Rebuilds the projection and visibility for the view and terminal size.
    pub(super) fn rebuild_screen(&mut self) {
        let area = self.viewport();
        self.screen = (!area.is_empty()).then(|| {
            Screen::new(
                &self.mesh,
                self.framing.frame(&self.mesh),
                self.sign,
                &self.camera,
                (usize::from(area.width), usize::from(area.height)),
                self.cells,
            )
        });
    }

    /// Snaps to the nearest visible vertex under the cursor.
    pub(super) fn snap(&mut self) {
        self.snapped = self
            .screen
            .as_ref()
            .and_then(|s| s.nearest_visible(self.cursor));
    }

    /// Makes `landmark` the current one: its pick or proposal under the cursor, if it has
    /// one; otherwise the cursor stays and snaps.
    pub(super) fn enter(&mut self, landmark: Option<usize>) {
        self.current = landmark;
        let Some(landmark) = landmark else {
            return;
        };
        let known = self.picks[landmark].or(self.proposals[landmark].map(|(v, _)| v));
        match known {
            Some(v) => {
                self.snapped = Some(v);
                self.follow(v);
            }
            None => self.snap(),
        }
    }

    /// Puts the cursor on vertex `v`, panning the view when it is off the viewport.
    pub(super) fn follow(&mut self, v: u32) {
        let Some(screen) = &self.screen else {
            return;
        };
        let Some(at) = screen.dot_of(v) else {
            return;
        };
        if screen.contains(at) {
            self.cursor = at;
            return;
        }
        let centre = Vec2::new(screen.width as f32, screen.height as f32) * 0.5;
        self.pan_by(at - centre);
        self.cursor = centre;
    }

    /// Moves the view so that what was `dots` away from the centre comes to it.
    pub(super) fn pan_by(&mut self, dots: Vec2) {
        let Some(screen) = &self.screen else {
            return;
        };
        let p = &screen.projection;
        self.camera.pan.x += dots.x / p.scale_x;
        self.camera.pan.y -= dots.y / p.scale_y;
        self.rebuild_screen();
    }

    /// Frames the face as `framing` says: its axes (`--up`, `--front`, or the landmarks of a
    /// file being corrected) and the part of the mesh the view fits; `v` comes back to them.
    pub fn face(&mut self, framing: crate::render::Framing) {
        self.camera.basis = framing.basis;
        self.framing = framing;
        self.view_changed();
    }

    /// After the view changed: the cursor back on the vertex it held.
    pub(super) fn view_changed(&mut self) {
        self.rebuild_screen();
        match self.snapped {
            Some(v) => {
                let proposal = self.current.is_some_and(|c| {
                    self.picks[c] == Some(v) || self.proposals[c].map(|p| p.0) == Some(v)
                });
                self.follow(v);
                let visible = self.screen.as_ref().is_some_and(|s| s.visible[v as usize]);
                if !visible && !proposal {
                    self.snap();
                }
            }
            None => {
                if let Some(s) = &self.screen {
                    self.cursor = self.cursor.clamp(
                        Vec2::ZERO,
                        Vec2::new(s.width as f32 - 1.0, s.height as f32 - 1.0),
                    );
                }
                self.snap();
            }
        }
    }

    pub(super) fn move_cursor(&mut self, dx: i16, dy: i16) {
        let Some(screen) = &self.screen else {
            return;
        };
        let step = Vec2::new(screen.cell.0 as f32, screen.cell.1 as f32);
        let mut to = self.cursor + Vec2::new(f32::from(dx), f32::from(dy)) * step;
        let (w, h) = (screen.width as f32, screen.height as f32);
        let inside = to.clamp(Vec2::splat(0.5), Vec2::new(w - 0.5, h - 0.5));
        if inside != to {
            // Off the edge: the view moves instead, the cursor stays at the edge.
            self.pan_by(to - inside);
            to = inside;
        }
        self.cursor = to;
        self.snap();
    }

    pub(super) fn click(&mut self, col: u16, row: u16) {
        let area = self.viewport();
        if !area.contains(ratatui::layout::Position { x: col, y: row }) {
            return;
        }
        if let Some(screen) = &self.screen {
            self.cursor = screen.cell_centre(col - area.x, row - area.y);
            self.snap();
        }
    }

    pub(super) fn zoom(&mut self, factor: f32) {
        let Some(screen) = &self.screen else {
            return;
        };
        let old = self.camera.zoom;
        let new = (old * factor).clamp(ZOOM_RANGE.0, ZOOM_RANGE.1);
        if new == old {
            self.info(format!("zoom is at its limit ({new})"));
            return;
        }
        // Keep the cursor's point where it is on the screen.
        let p = &screen.projection;
        let off = self.cursor - p.origin;
        let ratio = 1.0 - old / new;
        self.camera.pan.x += off.x / p.scale_x * ratio;
        self.camera.pan.y -= off.y / p.scale_y * ratio;
        self.camera.zoom = new;
        self.view_changed();
    }
}
