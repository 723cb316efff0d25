//! The landmark picker (`grimace landmarks`, `grimace fit-rig --pick`): the 68 iBUG
//! landmarks of a mesh picked one by one on the projected mesh, with the default face beside
//! it showing where each one lies.
//!
//! The flow: the minimal set first, the subject's left side ([`LEFT`]) and the midline
//! ([`MIDLINE`]); then the right side, each point proposed by mirroring its partner in the
//! plane of the picked midline points; once those 17 are done every other landmark is
//! proposed by carrying the default face's landmarks through a warp fitted on the picks
//! ([`crate::fit::propose`]). A proposal needs only Enter, or a nudge first.
//!
//! The shape is the editor's: [`state`] holds the state and the pure update, [`view`] draws,
//! [`screen`] projects the mesh and finds the visible vertex nearest the cursor, the keys are
//! [`keys`], and [`run`] is the event loop. Every pick is written to a
//! recovery file at once ([`crate::io::pick_recovery`]), so a dropped connection loses none.

pub mod keys;
pub mod screen;
pub mod state;
pub mod view;

use crossterm::event::{Event, KeyEventKind, MouseButton, MouseEventKind};
use ratatui::layout::Rect;

use super::session::Session;
use super::term;
use crate::io::pick_recovery::{self, PickRecovery};
use crate::landmarks::Landmarks;
use crate::tui::app::FileStamp;
pub use state::{PickAction, PickApp, PickEffect};

/// The minimal set's points on the subject's left, picked first: the left eye's outer and
/// inner corners, the left brow's outer and inner ends, the left mouth corner and the left
/// jaw corner.
pub const LEFT: [usize; 6] = [45, 42, 26, 22, 54, 12];
/// The minimal set's midline points: the top of the nose bridge, the nose tip, the middles
/// of the upper and lower lip, the chin.
pub const MIDLINE: [usize; 5] = [27, 30, 51, 57, 8];
/// The minimal set: [`LEFT`], [`MIDLINE`] and the mirror partners of [`LEFT`].
pub const MINIMAL: [usize; 17] = [
    45, 42, 26, 22, 54, 12, 27, 30, 51, 57, 8, 36, 39, 17, 21, 48, 4,
];

/// The picking order: [`MINIMAL`] first, then the other landmarks by number.
pub fn order() -> [usize; 68] {
    let mut out = [0usize; 68];
    out[..17].copy_from_slice(&MINIMAL);
    let mut k = 17;
    for i in 0..68 {
        if !MINIMAL.contains(&i) {
            out[k] = i;
            k += 1;
        }
    }
    out
}

/// The right side of the minimal set is the mirror of the left.
const _: () = {
    let mut i = 0;
    while i < 6 {
        assert!(MINIMAL[11 + i] == mirror_const(LEFT[i]));
        i += 1;
    }
};

const fn mirror_const(i: usize) -> usize {
    match i {
        0..=16 => 16 - i,
        17..=26 => 43 - i,
        36..=39 | 42..=45 => 81 - i,
        48..=54 => 102 - i,
        _ => i,
    }
}

/// Where the picker's parts go on the screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PickLayout {
    /// The mesh panel, with its border.
    pub mesh: Rect,
    /// Inside the mesh panel's border: the viewport.
    pub mesh_inner: Rect,
    /// The landmark's name and the progress.
    pub info: Rect,
    /// The default face with the landmark marked.
    pub reference: Rect,
    /// The status line.
    pub status: Rect,
}

/// The layout for a terminal area: the mesh on the left, the landmark and the default face
/// on the right, the status line at the bottom.
pub fn layout(area: Rect) -> PickLayout {
    let body_h = area.height.saturating_sub(1);
    let status = Rect::new(area.x, area.y + body_h, area.width, area.height.min(1));
    let right_w = (area.width * 2 / 5).clamp(24, 56).min(area.width / 2);
    let mesh = Rect::new(area.x, area.y, area.width - right_w, body_h);
    // Room for the name, the progress and the proposal, wrapped in a narrow panel.
    let info_h = if right_w >= 44 { 8 } else { 10 }.min(body_h);
    let info = Rect::new(area.x + mesh.width, area.y, right_w, info_h);
    let reference = Rect::new(
        area.x + mesh.width,
        area.y + info_h,
        right_w,
        body_h - info_h,
    );
    let mesh_inner = Rect::new(
        mesh.x + 1,
        mesh.y + 1,
        mesh.width.saturating_sub(2),
        mesh.height.saturating_sub(2),
    );
    PickLayout {
        mesh,
        mesh_inner,
        info,
        reference,
        status,
    }
}

/// Runs the picker until the user quits or a signal stops it. Every pick is already in the
/// recovery file when a signal arrives.
pub fn run(app: &mut PickApp, session: &Session) -> anyhow::Result<()> {
    app.colors = term::colors_from_env();
    super::program::run(&mut Picker {
        app,
        session,
        cache: view::PickCache::default(),
        quit: false,
    })
}

/// The picker as the event loop runs it.
struct Picker<'a> {
    app: &'a mut PickApp,
    session: &'a Session,
    cache: view::PickCache,
    quit: bool,
}

impl super::program::Program for Picker<'_> {
    const NAME: &'static str = "the picker";

    fn draw(&mut self, frame: &mut ratatui::Frame) {
        view::draw(self.app, &mut self.cache, frame);
    }

    fn event(&mut self, ev: &Event) -> anyhow::Result<bool> {
        let actions = actions_for(self.app, ev);
        let changed = !actions.is_empty();
        for action in actions {
            if apply(self.app, self.session, action) {
                self.quit = true;
                break;
            }
        }
        Ok(changed)
    }

    fn finished(&self) -> bool {
        self.quit
    }
}

/// The actions for a terminal event.
pub fn actions_for(app: &PickApp, ev: &Event) -> Vec<PickAction> {
    match ev {
        Event::Key(key) if key.kind != KeyEventKind::Release => {
            keys::dispatch(&app.mode, *key).into_iter().collect()
        }
        Event::Resize(w, h) => vec![PickAction::Resize(*w, *h)],
        Event::Mouse(mouse) if app.mode == state::Mode::Normal => match mouse.kind {
            MouseEventKind::Down(MouseButton::Left) => {
                vec![PickAction::Click(mouse.column, mouse.row)]
            }
            MouseEventKind::ScrollUp => vec![PickAction::Zoom(state::ZOOM_STEP)],
            MouseEventKind::ScrollDown => vec![PickAction::Zoom(1.0 / state::ZOOM_STEP)],
            _ => Vec::new(),
        },
        Event::Paste(text) if matches!(app.mode, state::Mode::Command(_)) => text
            .chars()
            .filter(|c| !c.is_control())
            .map(PickAction::Input)
            .collect(),
        _ => Vec::new(),
    }
}

/// Runs one action and its effects; `true` when the picker should stop.
pub fn apply(app: &mut PickApp, session: &Session, action: PickAction) -> bool {
    let mut queue = vec![action];
    let mut quit = false;
    while let Some(action) = queue.pop() {
        for effect in app.update(action) {
            match effect {
                PickEffect::Save {
                    landmarks,
                    quit_after,
                    force,
                } => queue.push(save(app, &landmarks, quit_after, force)),
                PickEffect::WriteRecovery => write_recovery(app, session),
                PickEffect::RemoveRecovery => {
                    if let Some(path) = &session.recovery {
                        if let Err(e) = pick_recovery::remove(path) {
                            app.warn(format!("could not remove {}: {e}", path.display()));
                        }
                    }
                }
                PickEffect::Quit => quit = true,
            }
        }
    }
    quit
}

/// Saves the landmarks unless the file changed on disk since it was opened (and `force` is
/// off); on success the picker's stamp becomes the new file's.
fn save(app: &mut PickApp, landmarks: &Landmarks, quit_after: bool, force: bool) -> PickAction {
    let on_disk = match std::fs::read(&app.out) {
        Ok(bytes) => Some(FileStamp::of(&bytes)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        // A file that cannot be read is refused by the save itself, with its reason.
        Err(_) => app.out_stamp,
    };
    if !force && on_disk != app.out_stamp {
        return PickAction::SaveConflict(quit_after);
    }
    let result = crate::io::landmarks::save_landmarks(&app.out, landmarks).map_err(|e| e.message);
    if result.is_ok() {
        app.out_stamp = std::fs::read(&app.out).ok().map(|b| FileStamp::of(&b));
    }
    PickAction::Saved(result, quit_after)
}

/// Writes the picks to the recovery file (a failure is said on the status line).
pub fn write_recovery(app: &mut PickApp, session: &Session) {
    let Some(path) = &session.recovery else {
        return;
    };
    let state = PickRecovery::new(
        &app.mesh_path,
        app.mesh.vertex_count(),
        &app.picks,
        &app.skipped,
    );
    if let Err(e) = pick_recovery::write(path, &state) {
        app.warn(format!(
            "could not write the recovery file {}: {}",
            path.display(),
            crate::io::error::io_reason(&e)
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::landmarks::mirror;

    #[test]
    fn the_order_starts_with_the_minimal_set_and_holds_every_landmark_once() {
        let order = order();
        assert_eq!(order[..17], MINIMAL);
        let mut sorted = order.to_vec();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..68).collect::<Vec<_>>());
        for i in 0..68 {
            let covered = (0..=26).contains(&i) || (36..=54).contains(&i);
            if covered && ![40, 41, 46, 47].contains(&i) {
                assert_eq!(mirror_const(i), mirror(i), "{i}");
            }
        }
        for (l, r) in LEFT.iter().zip(&MINIMAL[11..]) {
            assert_eq!(mirror(*l), *r);
        }
    }

    #[test]
    fn the_layout_splits_the_screen() {
        let l = layout(Rect::new(0, 0, 120, 40));
        assert_eq!(l.status, Rect::new(0, 39, 120, 1));
        assert_eq!(l.mesh.width + l.info.width, 120);
        assert_eq!(l.info.x, l.reference.x);
        assert_eq!(l.info.height + l.reference.height, 39);
        assert_eq!(l.mesh_inner, Rect::new(1, 1, l.mesh.width - 2, 37));
    }
}
