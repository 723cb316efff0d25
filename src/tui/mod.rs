//! The terminal editor: state ([`app`]), intents ([`action`]), key bindings ([`keymap`]), the
//! pure [`update::update`], the views ([`view`]), terminal hygiene ([`term`]) and the event
//! loop ([`run`]), which reads events, updates, runs effects, and draws only when something
//! changed, so an idle editor sends nothing down the line.

pub mod action;
pub mod app;
pub mod face;
#[cfg(test)]
mod fixture;
pub mod keymap;
pub mod memory;
pub mod pick;
pub(crate) mod play;
pub(crate) mod program;
pub mod rig;
pub(crate) mod session;
pub mod table_ops;
pub(crate) mod term;
pub mod update;
pub mod view;

use std::fs;
use std::io::{self, Write};
use std::path::Path;
use std::time::{Duration, Instant};

use crossterm::event::{Event, KeyEventKind, MouseButton, MouseEvent, MouseEventKind};
use ratatui::backend::CrosstermBackend;
use ratatui::layout::{Position, Rect};
use ratatui::Terminal;

use crate::io::inputs::Inputs;
use crate::io::recovery::{self, RecoveryState};
use crate::io::reference;
use action::{Action, Effect};
use app::{App, FileStamp, Row};
use session::Session;

/// How long after the last edit the recovery file is written.
pub const RECOVERY_DEBOUNCE: Duration = Duration::from_secs(1);

/// Runs the editor until the user quits or a signal stops it.
pub fn run(app: App, session: Session) -> anyhow::Result<()> {
    program::run(&mut Editor {
        app,
        session,
        state: LoopState::default(),
    })
}

#[derive(Debug, Default)]
struct LoopState {
    /// The face's render buffers, kept between frames.
    cache: view::viewport::RenderCache,
    recovery_due: Option<Instant>,
    quit: bool,
    drag: Option<(u16, u16)>,
}

/// The editor as the event loop runs it: the state, the session's files, the loop's own.
struct Editor {
    app: App,
    session: Session,
    state: LoopState,
}

impl program::Program for Editor {
    const NAME: &'static str = "the editor";

    fn draw(&mut self, frame: &mut ratatui::Frame) {
        view::draw(&self.app, &mut self.state.cache, frame);
    }

    fn event(&mut self, ev: &Event) -> anyhow::Result<bool> {
        let actions = actions_for(&self.app, ev, &mut self.state.drag);
        let changed = !actions.is_empty();
        for action in actions {
            apply(&mut self.app, &mut self.session, &mut self.state, action);
        }
        Ok(changed)
    }

    fn tick(&mut self, now: Instant) -> anyhow::Result<bool> {
        // A big head's rig bound on a thread: its face replaces the rest pose; a rig that
        // does not bind stops the editor with the reason, as it would have before the start.
        let bound = match self.app.doc.face.poll_bind() {
            Some(result) => result.map_err(anyhow::Error::msg).map(|()| true)?,
            None => false,
        };
        for warning in self.app.doc.face.take_bind_warnings() {
            self.app.warn(warning);
        }
        if self.state.recovery_due.is_none_or(|due| now < due) {
            return Ok(bound);
        }
        let before = self.app.message.clone();
        write_recovery(&mut self.app, &self.session);
        self.state.recovery_due = None;
        // Redraw only if writing had something to say (an idle editor sends nothing).
        Ok(bound || self.app.message != before)
    }

    fn wait(&self, now: Instant) -> Duration {
        // While the rig binds, look for it often: its face is shown as soon as it lands.
        let idle = Duration::from_millis(if self.app.doc.face.is_binding() {
            20
        } else {
            200
        });
        self.state
            .recovery_due
            .map_or(idle, |due| due.saturating_duration_since(now).min(idle))
    }

    fn signalled(&mut self) {
        self.left();
    }

    fn panicked(&mut self) {
        // Keep the unsaved state before the panic goes on (the hook restored the terminal).
        if self.app.history.edits > 0 {
            write_recovery(&mut self.app, &self.session);
        }
    }

    fn left(&mut self) {
        if self.state.recovery_due.take().is_some() {
            // Leaving with unwritten state (signal or error): keep it.
            write_recovery(&mut self.app, &self.session);
        }
    }

    fn finished(&self) -> bool {
        self.state.quit
    }
}

/// Draws one frame inside a synchronized update.
pub fn draw<W: Write>(
    terminal: &mut Terminal<CrosstermBackend<W>>,
    app: &App,
    cache: &mut view::viewport::RenderCache,
) -> io::Result<()> {
    term::begin_frame(terminal.backend_mut())?;
    terminal.draw(|frame| view::draw(app, cache, frame))?;
    term::end_frame(terminal.backend_mut())
}

/// Runs one action and its effects (feeding effect outcomes back as actions).
fn apply(app: &mut App, session: &mut Session, state: &mut LoopState, action: Action) {
    let mut queue = vec![action];
    while let Some(action) = queue.pop() {
        for effect in update::update(app, action) {
            match effect {
                Effect::Save {
                    path,
                    table,
                    expected,
                    force,
                    quit_after,
                } => queue.push(match protected_files(app, true).check_output(&path) {
                    Err(e) => Action::SaveFailed {
                        path,
                        error: e.message,
                    },
                    Ok(()) => {
                        let contents = table_ops::to_ron(&reference::table_for_file(&path, &table));
                        save(&path, &contents, expected, force, quit_after)
                    }
                }),
                Effect::SaveRig {
                    path,
                    rig,
                    expected,
                } => queue.push(rig::saved_action(
                    match protected_files(app, false).check_output(&path) {
                        Err(e) => Action::SaveFailed {
                            path,
                            error: e.message,
                        },
                        Ok(()) => {
                            let contents =
                                crate::io::rig_to_ron(&reference::rig_for_file(&path, &rig));
                            save(&path, &contents, expected, false, false)
                        }
                    },
                )),
                Effect::RecoveryDue => {
                    if session.recovery.is_some() {
                        state.recovery_due = Some(Instant::now() + RECOVERY_DEBOUNCE);
                    }
                }
                Effect::RemoveRecovery => {
                    state.recovery_due = None;
                    if let Some(path) = &session.recovery {
                        if let Err(e) = recovery::remove(path) {
                            app.warn(format!("could not remove {}: {e}", path.display()));
                        }
                    }
                    // After "save as" the unsaved state belongs to the new file.
                    if session.recovery.is_some() {
                        session.recovery = recovery::recovery_path(app.doc.file.as_deref());
                    }
                }
                Effect::ReadTable(path) => queue.push(Action::TableRead {
                    source: path.display().to_string(),
                    table: table_ops::read(&path),
                }),
                Effect::Quit => state.quit = true,
            }
        }
    }
}

/// The files a save must not replace: the mesh and, for a table save, the rig; for a rig
/// save, the table. (A table save replaces its own file, a rig save its own.)
fn protected_files(app: &App, saving_table: bool) -> Inputs {
    let mut inputs = Inputs::new();
    inputs.add("the mesh of the rig", &app.rig().mesh);
    if saving_table {
        inputs.add("the rig the table names", &app.doc.table.rig);
        if let Some(rig) = &app.rig_edit.path {
            inputs.add("the rig being edited", rig);
        }
    } else if let Some(table) = &app.doc.file {
        inputs.add("the AU table being edited", table);
    }
    inputs
}

fn write_recovery(app: &mut App, session: &Session) {
    let Some(path) = &session.recovery else {
        return;
    };
    let mut state = RecoveryState::new(
        app.doc.file.as_deref(),
        app.rig(),
        &app.doc.activations,
        &app.doc.table,
    );
    state.base = app.doc.file_stamp.map(|s| (s.len, s.hash));
    state.rig = app.rig_edit.dirty(app.rig()).then(|| app.rig().clone());
    if let Err(e) = recovery::write(path, &state) {
        app.warn(format!(
            "could not write the recovery file {}: {}",
            path.display(),
            crate::io::error::io_reason(&e)
        ));
    }
}

/// Saves a table file unless it changed on disk since `expected` (`None`: it must not exist).
pub fn save(
    path: &Path,
    contents: &str,
    expected: Option<FileStamp>,
    force: bool,
    quit_after: bool,
) -> Action {
    // Reading a named pipe would wait for a writer: refuse what a save would refuse anyway.
    if let Some(kind) = fs::metadata(path)
        .ok()
        .and_then(|m| crate::io::error::special_kind(&m.file_type()))
    {
        return Action::SaveFailed {
            path: path.to_path_buf(),
            error: format!("it is {kind}; grimace only replaces regular files"),
        };
    }
    let current = match fs::read(path) {
        Ok(bytes) => Some(FileStamp::of(&bytes)),
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => {
            return Action::SaveFailed {
                path: path.to_path_buf(),
                error: crate::io::error::io_reason(&e),
            }
        }
    };
    let conflict = match (expected, current) {
        (_, None) => false,
        (Some(e), Some(c)) => e != c,
        (None, Some(_)) => true,
    };
    if conflict && !force {
        return Action::SaveConflict {
            path: path.to_path_buf(),
            quit_after,
        };
    }
    match crate::io::atomic::write_atomic(path, contents.as_bytes()) {
        Ok(()) => Action::Saved {
            path: path.to_path_buf(),
            stamp: FileStamp::of(contents.as_bytes()),
            quit_after,
        },
        Err(e) => Action::SaveFailed {
            path: path.to_path_buf(),
            error: crate::io::error::io_reason(&e),
        },
    }
}

/// The actions for a terminal event.
pub fn actions_for(app: &App, ev: &Event, drag: &mut Option<(u16, u16)>) -> Vec<Action> {
    match ev {
        Event::Key(key) if key.kind != KeyEventKind::Release => {
            keymap::dispatch_for(app, *key).into_iter().collect()
        }
        Event::Resize(w, h) => vec![Action::Resize(*w, *h)],
        Event::Mouse(mouse) => mouse_actions(app, *mouse, drag),
        Event::Paste(text) if matches!(app.mode, app::Mode::Input(_)) => text
            .chars()
            .filter(|c| !c.is_control())
            .map(Action::InputChar)
            .collect(),
        _ => Vec::new(),
    }
}

fn mouse_actions(app: &App, mouse: MouseEvent, drag: &mut Option<(u16, u16)>) -> Vec<Action> {
    if app.mode != app::Mode::Normal {
        return Vec::new();
    }
    let area = Rect::new(0, 0, app.view.size.0, app.view.size.1);
    let Some(panels) = view::layout(area, app) else {
        return Vec::new();
    };
    let (x, y) = (mouse.column, mouse.row);
    let at = Position { x, y };
    match mouse.kind {
        MouseEventKind::Down(MouseButton::Left) => {
            *drag = None;
            if let Some(row) = view::muscles::row_at(app, panels.muscles, x, y) {
                vec![Action::SelectRow(row)]
            } else if let Some(i) = view::table::item_at(app, panels.table, x, y) {
                vec![Action::SelectTableItem(i)]
            } else if panels.viewport.contains(at) {
                *drag = Some((x, y));
                Vec::new()
            } else {
                Vec::new()
            }
        }
        MouseEventKind::Drag(MouseButton::Left) => match *drag {
            Some((x0, y0)) => {
                *drag = Some((x, y));
                let dx = f32::from(x) - f32::from(x0);
                let dy = f32::from(y) - f32::from(y0);
                vec![Action::Rotate(dx * 3.0, -dy * 6.0)]
            }
            None => Vec::new(),
        },
        MouseEventKind::Up(_) => {
            *drag = None;
            Vec::new()
        }
        MouseEventKind::ScrollUp | MouseEventKind::ScrollDown => {
            let up = mouse.kind == MouseEventKind::ScrollUp;
            if panels.viewport.contains(at) {
                vec![Action::Zoom(if up { 1.1 } else { 1.0 / 1.1 })]
            } else if panels.muscles.contains(at) {
                // The wheel adjusts the row under the pointer (selecting it first).
                let mut out = Vec::new();
                if let Some(row) = view::muscles::row_at(app, panels.muscles, x, y) {
                    if row != app.selected_row() {
                        out.push(Action::SelectRow(row));
                    }
                }
                out.push(Action::StepFine(if up { 1 } else { -1 }));
                out
            } else if panels.table.contains(at) {
                vec![if up {
                    Action::SelectPrev
                } else {
                    Action::SelectNext
                }]
            } else {
                Vec::new()
            }
        }
        _ => Vec::new(),
    }
}

/// Selects the row of a muscle (helper for callers that know names).
pub fn row_of(app: &App, name: &str) -> Option<Row> {
    app.rig().muscle_index(name).map(Row::Muscle)
}

#[cfg(test)]
mod tests {
    use crossterm::event::{KeyModifiers, MouseEvent};

    use super::*;
    use crate::tui::app::Focus;

    fn mouse(kind: MouseEventKind, column: u16, row: u16) -> Event {
        Event::Mouse(MouseEvent {
            kind,
            column,
            row,
            modifiers: KeyModifiers::NONE,
        })
    }

    fn app() -> App {
        let mut app = fixture::app();
        app.view.size = (120, 40);
        app
    }

    /// The screen row of a muscle panel row (after its heading lines).
    fn screen_row(app: &App, row: Row) -> u16 {
        let lines = view::muscles::lines(app);
        1 + lines
            .iter()
            .position(|l| *l == view::muscles::PanelLine::Row(row))
            .unwrap() as u16
    }

    #[test]
    fn clicking_a_muscle_row_selects_it() {
        let app = app();
        let y = screen_row(&app, Row::Muscle(3));
        let actions = actions_for(
            &app,
            &mouse(MouseEventKind::Down(MouseButton::Left), 5, y),
            &mut None,
        );
        assert_eq!(actions, vec![Action::SelectRow(Row::Muscle(3))]);
        // A heading is not a row.
        let actions = actions_for(
            &app,
            &mouse(MouseEventKind::Down(MouseButton::Left), 5, 1),
            &mut None,
        );
        assert!(actions.is_empty());
    }

    #[test]
    fn the_wheel_adjusts_the_row_under_the_pointer() {
        let mut app = app();
        let y = screen_row(&app, Row::Jaw);
        let ev = mouse(MouseEventKind::ScrollUp, 5, y);
        let actions = actions_for(&app, &ev, &mut None);
        assert_eq!(
            actions,
            vec![Action::SelectRow(Row::Jaw), Action::StepFine(1)]
        );
        for action in actions {
            update::update(&mut app, action);
        }
        assert!((app.doc.activations.jaw - 0.05).abs() < 1e-6);
        assert_eq!(app.selection.focus, Focus::Muscles);
    }

    #[test]
    fn dragging_in_the_viewport_rotates() {
        let app = app();
        let panels = view::layout(Rect::new(0, 0, 120, 40), &app).unwrap();
        let (x, y) = (panels.viewport.x + 10, panels.viewport.y + 10);
        let mut drag = None;
        assert!(actions_for(
            &app,
            &mouse(MouseEventKind::Down(MouseButton::Left), x, y),
            &mut drag
        )
        .is_empty());
        let actions = actions_for(
            &app,
            &mouse(MouseEventKind::Drag(MouseButton::Left), x + 2, y),
            &mut drag,
        );
        assert_eq!(actions, vec![Action::Rotate(6.0, 0.0)]);
        actions_for(
            &app,
            &mouse(MouseEventKind::Up(MouseButton::Left), x + 2, y),
            &mut drag,
        );
        assert_eq!(drag, None);
        let zoom = actions_for(&app, &mouse(MouseEventKind::ScrollUp, x, y), &mut drag);
        assert_eq!(zoom, vec![Action::Zoom(1.1)]);
    }

    #[test]
    fn saving_refuses_to_overwrite_a_file_changed_on_disk() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.au.ron");
        std::fs::write(&path, "old").unwrap();
        let loaded = FileStamp::of(b"old");
        // Unchanged on disk: saved, with the previous version kept as a backup.
        let action = save(&path, "new", Some(loaded), false, false);
        assert!(matches!(action, Action::Saved { .. }), "{action:?}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        // Someone else changed it: the save asks instead.
        std::fs::write(&path, "theirs").unwrap();
        let action = save(&path, "mine", Some(FileStamp::of(b"new")), false, false);
        assert!(matches!(action, Action::SaveConflict { .. }), "{action:?}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "theirs");
        // Saving as a new file that exists asks too.
        let action = save(&path, "mine", None, false, false);
        assert!(matches!(action, Action::SaveConflict { .. }));
        // Forced after the user said yes.
        let action = save(&path, "mine", None, true, false);
        assert!(matches!(action, Action::Saved { .. }));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "mine");
    }

    #[cfg(unix)]
    #[test]
    fn a_save_over_a_named_pipe_is_refused_without_waiting() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("pipe.au.ron");
        let made = std::process::Command::new("mkfifo")
            .arg(&path)
            .status()
            .unwrap();
        assert!(made.success());
        match save(&path, "mine", None, true, false) {
            Action::SaveFailed { error, .. } => assert_eq!(
                error,
                "it is a named pipe (FIFO); grimace only replaces regular files"
            ),
            other => panic!("{other:?}"),
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_failed_save_leaves_the_old_file_and_reports_why() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        // A folder that is a file: fails for every user, root included.
        let blocker = dir.path().join("not-a-folder");
        std::fs::write(&blocker, "x").unwrap();
        let action = save(&blocker.join("t.au.ron"), "new", None, false, false);
        assert!(
            matches!(&action, Action::SaveFailed { error, .. } if !error.is_empty()),
            "{action:?}"
        );
        let path = dir.path().join("t.au.ron");
        std::fs::write(&path, "old").unwrap();
        std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o555)).unwrap();
        let action = save(&path, "new", Some(FileStamp::of(b"old")), false, false);
        std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
        if std::fs::metadata(dir.path()).is_ok() && matches!(action, Action::Saved { .. }) {
            // Running as root: permissions do not stop the write; nothing to check here.
            eprintln!("skipped: permissions are not enforced for this user");
            return;
        }
        assert!(
            matches!(&action, Action::SaveFailed { error, .. } if !error.is_empty()),
            "{action:?}"
        );
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    }
}
