//! The picker's state ([`PickApp`]) and its pure update: [`PickApp::update`] takes a
//! [`PickAction`] and returns the [`PickEffect`]s for the event loop, touching no files and
//! no terminal.

use std::path::PathBuf;

use glam::{Vec2, Vec3};
use ratatui::layout::Rect;

use super::screen::Screen;
use super::{layout, order, LEFT, MIDLINE, MINIMAL};
use crate::fit::propose::{carry, MirrorPlane};
use crate::landmarks::Landmarks;
use crate::landmarks::{mirror, NAMES};
use crate::model::Mesh;
use crate::render::{Camera, CellMode, ColorMode, Framing, Orientation, Renderer};
use crate::tui::app::{Message, Severity};

/// Landmark count.
const COUNT: usize = crate::landmarks::COUNT;
/// Degrees per turn (`[` `]`) and tilt (`{` `}`).
pub const TURN_DEGREES: f32 = 15.0;
/// Degrees per tilt step.
pub const TILT_DEGREES: f32 = 10.0;
/// Zoom factor per `+` / `-`.
pub const ZOOM_STEP: f32 = 1.5;
/// Cells per coarse cursor step (Shift).
pub const COARSE: i16 = 5;
const ZOOM_RANGE: (f32, f32) = (0.5, 64.0);

/// Everything the picker's user can ask for.
#[derive(Debug, Clone, PartialEq)]
pub enum PickAction {
    /// Move the cursor by cells (x right, y down).
    Move(i16, i16),
    /// Take the vertex under the cursor for the current landmark.
    Confirm,
    /// Leave the current landmark for later.
    Skip,
    /// Take back the last pick or skip.
    Undo,
    /// Go to the next or the previous landmark (to look again or correct).
    Step(i8),
    /// Turn (yaw) and tilt (pitch) the view, in degrees.
    Turn(f32, f32),
    /// Zoom about the cursor by a factor.
    Zoom(f32),
    /// Front view, whole face.
    ResetView,
    /// A click on the screen (column, row).
    Click(u16, u16),
    /// The terminal's new size.
    Resize(u16, u16),
    /// Show the keys.
    Help,
    /// Start a `:` command.
    Command,
    /// A character typed into the command line.
    Input(char),
    /// Delete the last character of the command line.
    Backspace,
    /// Run the command line.
    Submit,
    /// Close the command line, help or question.
    Cancel,
    /// Save the landmarks.
    Save,
    /// Quit (asks when picks would be lost).
    Quit,
    /// Yes or no to the question asked.
    Answer(bool),
    /// The outcome of a save: the error when it failed, and whether to quit after it.
    Saved(Result<(), String>, bool),
    /// The landmark file changed on disk since it was opened (or was made meanwhile):
    /// nothing was written; whether to quit after saving.
    SaveConflict(bool),
}

/// What the event loop must do for an update.
#[derive(Debug, Clone, PartialEq)]
pub enum PickEffect {
    /// Write the landmarks file; answer with [`PickAction::Saved`].
    Save {
        /// The landmarks.
        landmarks: Landmarks,
        /// Quit once saved.
        quit_after: bool,
        /// Write even if the file changed on disk since it was opened (the user said so).
        force: bool,
    },
    /// Write the picks to the recovery file now.
    WriteRecovery,
    /// Remove the recovery file (saved, or given up on purpose).
    RemoveRecovery,
    /// Leave the picker.
    Quit,
}

/// A question waiting for y or n.
#[derive(Debug, Clone, PartialEq)]
pub enum Question {
    /// Quit although picks are not saved.
    Quit,
    /// Overwrite a landmark file that changed on disk since it was opened.
    Overwrite {
        /// Quit once saved.
        quit_after: bool,
    },
    /// Take back picks found in the recovery file.
    Recover {
        /// The picks.
        picks: Vec<Option<u32>>,
        /// The landmarks skipped.
        skipped: Vec<usize>,
        /// How long ago they were written, for the question.
        when: String,
    },
}

/// What the keys do now.
#[derive(Debug, Clone, PartialEq)]
pub enum Mode {
    /// Picking.
    Normal,
    /// Typing a `:` command.
    Command(String),
    /// The key list.
    Help,
    /// A question.
    Confirm(Question),
}

/// Where a proposal comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The partner's pick mirrored in the face's midline plane.
    Mirror,
    /// The default face's landmark carried through the warp fitted on the picks.
    Warp,
}

impl Source {
    /// How the info panel says it.
    pub fn describe(self) -> &'static str {
        match self {
            Source::Mirror => "proposed by symmetry from its partner",
            Source::Warp => "proposed from the picks by the warp",
        }
    }
}

/// One undoable step: a landmark as it was before.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Step {
    landmark: usize,
    pick: Option<u32>,
    skipped: bool,
}

/// The built-in default face with its landmarks: the reference picture and the template
/// that proposals are carried from.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The mesh.
    pub mesh: Mesh,
    /// Its 68 landmark points.
    pub points: Vec<Vec3>,
    /// Its winding sign.
    pub sign: f32,
}

impl Reference {
    /// The built-in default face.
    pub fn builtin() -> Reference {
        let mesh = crate::io::builtin::default_mesh();
        let points = crate::io::builtin::landmarks("face")
            .and_then(|l| l.positions(&mesh).ok())
            .unwrap_or_default();
        let sign = winding(&mesh);
        Reference { mesh, points, sign }
    }
}

/// +1 when the mesh's right-hand normals point out of the head, -1 when inward.
pub fn winding(mesh: &Mesh) -> f32 {
    match Renderer::new(mesh).detected_orientation() {
        Orientation::Inward => -1.0,
        _ => 1.0,
    }
}

/// The picker's state.
#[derive(Debug, Clone)]
pub struct PickApp {
    /// The mesh being picked on.
    pub mesh: Mesh,
    /// Its file, for titles and the recovery file.
    pub mesh_path: PathBuf,
    /// The landmark file written by `:w`.
    pub out: PathBuf,
    /// The default face.
    pub reference: Reference,
    /// The mesh's winding sign.
    pub sign: f32,
    /// The vertex picked for each landmark.
    pub picks: Vec<Option<u32>>,
    /// Landmarks skipped (left for later).
    pub skipped: Vec<bool>,
    /// A proposed vertex for landmarks not yet picked.
    pub proposals: Vec<Option<(u32, Source)>>,
    /// The landmark being picked (`None` when every landmark has a vertex and none is
    /// being looked at again).
    pub current: Option<usize>,
    history: Vec<Step>,
    /// The view of the mesh.
    pub camera: Camera,
    /// The cursor, in dots of the mesh viewport (free: it moves by cells, the pick snaps).
    pub cursor: Vec2,
    /// The vertex Enter would take.
    pub snapped: Option<u32>,
    /// The terminal size.
    pub size: (u16, u16),
    /// How dots become characters.
    pub cells: CellMode,
    /// What the terminal can show.
    pub colors: ColorMode,
    /// The mesh as the viewport shows it (rebuilt when the view changes).
    pub screen: Option<Screen>,
    /// What the keys do now.
    pub mode: Mode,
    /// The status line's message.
    pub message: Option<Message>,
    /// Picks changed since the last save.
    pub dirty: bool,
    /// Whether the landmarks were saved in this session.
    pub saved: bool,
    /// The landmark file as opened or last saved (`None`: it did not exist), so that a file
    /// changed by someone else is not replaced without asking.
    pub out_stamp: Option<crate::tui::app::FileStamp>,
    /// A landmark file of points as loaded: each landmark's vertex (as the picker shows it)
    /// and its point. Saved, a landmark still on that vertex keeps its point, so a points
    /// file comes back as points, unchanged where nothing was picked again.
    pub kept_points: Option<Vec<(u32, Vec3)>>,
    /// Mesh vertices used by some triangle (only those can be proposed).
    used: Vec<bool>,
    /// The face's axes and the part of the mesh the view fits.
    pub(crate) framing: Framing,
}

impl PickApp {
    /// A picker for `mesh` writing `out`, on a terminal of `size`.
    pub fn new(
        mesh: Mesh,
        mesh_path: PathBuf,
        out: PathBuf,
        size: (u16, u16),
        cells: CellMode,
    ) -> PickApp {
        let mut used = vec![false; mesh.vertex_count()];
        for tri in &mesh.triangles {
            for &v in tri {
                used[v as usize] = true;
            }
        }
        let sign = winding(&mesh);
        // Stood up by the mesh's shape: a z-up bust opens facing the viewer, a body with its
        // head filling the view.
        let framing = Framing::of_mesh(&mesh);
        let camera = Camera::front().with_basis(framing.basis);
        let mut app = PickApp {
            mesh,
            mesh_path,
            out,
            reference: Reference::builtin(),
            sign,
            picks: vec![None; COUNT],
            skipped: vec![false; COUNT],
            proposals: vec![None; COUNT],
            current: Some(order()[0]),
            history: Vec::new(),
            camera,
            framing,
            cursor: Vec2::ZERO,
            snapped: None,
            size,
            cells,
            colors: ColorMode::None,
            screen: None,
            mode: Mode::Normal,
            message: None,
            dirty: false,
            saved: false,
            out_stamp: None,
            kept_points: None,
            used,
        };
        app.rebuild_screen();
        if let Some(screen) = &app.screen {
            app.cursor = Vec2::new(screen.width as f32, screen.height as f32) * 0.5;
        }
        app.enter(app.current);
        app
    }

    /// Starts from landmarks already picked (a landmark file being corrected, or recovered
    /// picks): every given vertex must be on the mesh.
    pub fn load_picks(&mut self, picks: &[Option<u32>], skipped: &[usize]) {
        let n = self.mesh.vertex_count();
        for (i, pick) in picks.iter().enumerate().take(COUNT) {
            self.picks[i] = pick.filter(|&v| (v as usize) < n);
        }
        self.skipped = vec![false; COUNT];
        for &i in skipped.iter().filter(|&&i| i < COUNT) {
            self.skipped[i] = self.picks[i].is_none();
        }
        self.history.clear();
        self.propose();
        self.current = self.next_after(None);
        self.enter(self.current);
    }

    /// Says something on the status line.
    pub fn info(&mut self, text: impl Into<String>) {
        self.message = Some(Message::new(Severity::Info, text));
    }

    /// Warns on the status line.
    pub fn warn(&mut self, text: impl Into<String>) {
        self.message = Some(Message::new(Severity::Warning, text));
    }

    fn error(&mut self, text: impl Into<String>) {
        self.message = Some(Message::new(Severity::Error, text));
    }

    /// How many landmarks have a vertex.
    pub fn picked(&self) -> usize {
        self.picks.iter().flatten().count()
    }

    /// The position of the current landmark in the picking order (1-based).
    pub fn step_number(&self) -> Option<usize> {
        let current = self.current?;
        order().iter().position(|&l| l == current).map(|i| i + 1)
    }

    /// The mesh viewport's inner area.
    pub fn viewport(&self) -> Rect {
        layout(Rect::new(0, 0, self.size.0, self.size.1)).mesh_inner
    }

    /// Recomputes every proposal from the picks: landmarks whose mirror partner is picked
    /// are mirrored in the plane of the picked midline points; once the minimal set is done,
    /// the rest are carried from the default face through a warp fitted on every pick.
    pub fn propose(&mut self) {
        let point = |v: u32| self.mesh.positions[v as usize];
        let picked = |ids: &[usize]| -> Vec<Vec3> {
            ids.iter()
                .filter_map(|&i| self.picks[i])
                .map(point)
                .collect()
        };
        let plane = MirrorPlane::fit(&picked(&MIDLINE), &picked(&LEFT));
        let minimal_done = MINIMAL
            .iter()
            .all(|&i| self.picks[i].is_some() || self.skipped[i]);
        let known: Vec<(usize, Vec3)> = (0..COUNT)
            .filter_map(|i| self.picks[i].map(|v| (i, point(v))))
            .collect();
        let carried = if minimal_done && known.len() >= 8 {
            carry(&self.reference.points, &known)
        } else {
            None
        };
        let mut proposals = vec![None; COUNT];
        for (i, slot) in proposals.iter_mut().enumerate() {
            if self.picks[i].is_some() {
                continue;
            }
            let partner = mirror(i);
            if let (Some(plane), Some(v), true) = (&plane, self.picks[partner], partner != i) {
                *slot = self
                    .nearest_vertex(plane.reflect(point(v)))
                    .map(|v| (v, Source::Mirror));
            } else if let Some(carried) = &carried {
                *slot = self.nearest_vertex(carried[i]).map(|v| (v, Source::Warp));
            }
        }
        self.proposals = proposals;
    }

    /// The mesh vertex (of some triangle) nearest a point in space.
    fn nearest_vertex(&self, p: Vec3) -> Option<u32> {
        let mut best: Option<(f32, u32)> = None;
        for (i, q) in self.mesh.positions.iter().enumerate() {
            if !self.used[i] {
                continue;
            }
            let d = q.distance_squared(p);
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, i as u32));
            }
        }
        best.map(|(_, i)| i)
    }

    /// The next landmark to pick after `from` in the picking order: one neither picked nor
    /// skipped, then (once all have been seen) the first skipped one.
    fn next_after(&self, from: Option<usize>) -> Option<usize> {
        let order = order();
        let start = from
            .and_then(|f| order.iter().position(|&l| l == f))
            .map_or(0, |i| i + 1);
        let open = |l: usize| self.picks[l].is_none() && !self.skipped[l];
        let rotated: Vec<usize> = order[start..]
            .iter()
            .chain(&order[..start])
            .copied()
            .collect();
        rotated
            .iter()
            .copied()
            .find(|&l| open(l))
            .or_else(|| {
                rotated
                    .iter()
                    .copied()
                    .find(|&l| self.picks[l].is_none() && Some(l) != from)
            })
            .or_else(|| from.filter(|&f| self.picks[f].is_none()))
    }

    /// Runs one action; returns what the event loop must do.
    pub fn update(&mut self, action: PickAction) -> Vec<PickEffect> {
        match (&self.mode, action) {
            (_, PickAction::Resize(w, h)) => {
                if self.size != (w, h) {
                    self.size = (w, h);
                    self.view_changed();
                }
                Vec::new()
            }
            (_, PickAction::Saved(result, quit_after)) => self.saved(result, quit_after),
            (_, PickAction::SaveConflict(quit_after)) => {
                self.mode = Mode::Confirm(Question::Overwrite { quit_after });
                Vec::new()
            }
            (Mode::Help, _) => {
                self.mode = Mode::Normal;
                Vec::new()
            }
            (Mode::Command(_), action) => self.command_key(action),
            (Mode::Confirm(_), PickAction::Answer(yes)) => self.answer(yes),
            (Mode::Confirm(_), PickAction::Cancel) => self.answer(false),
            (Mode::Confirm(_), _) => Vec::new(),
            (Mode::Normal, action) => {
                self.message = None;
                self.normal(action)
            }
        }
    }

    fn normal(&mut self, action: PickAction) -> Vec<PickEffect> {
        match action {
            PickAction::Move(dx, dy) => {
                self.move_cursor(dx, dy);
                Vec::new()
            }
            PickAction::Confirm => self.confirm(),
            PickAction::Skip => self.skip(),
            PickAction::Undo => self.undo(),
            PickAction::Step(by) => {
                self.step(by);
                Vec::new()
            }
            PickAction::Turn(yaw, pitch) => {
                self.camera.yaw =
                    crate::render::camera::wrap_degrees(self.camera.yaw.to_degrees() + yaw)
                        .to_radians();
                self.camera.pitch = (self.camera.pitch.to_degrees() + pitch)
                    .clamp(-90.0, 90.0)
                    .to_radians();
                self.view_changed();
                Vec::new()
            }
            PickAction::Zoom(factor) => {
                self.zoom(factor);
                Vec::new()
            }
            PickAction::ResetView => {
                self.camera = Camera::front().with_basis(self.camera.basis);
                self.view_changed();
                Vec::new()
            }
            PickAction::Click(col, row) => {
                self.click(col, row);
                Vec::new()
            }
            PickAction::Help => {
                self.mode = Mode::Help;
                Vec::new()
            }
            PickAction::Command => {
                self.mode = Mode::Command(String::new());
                Vec::new()
            }
            PickAction::Save => self.save(false, false),
            PickAction::Quit => {
                if self.dirty {
                    self.mode = Mode::Confirm(Question::Quit);
                    Vec::new()
                } else {
                    vec![PickEffect::Quit]
                }
            }
            _ => Vec::new(),
        }
    }

    fn confirm(&mut self) -> Vec<PickEffect> {
        let Some(landmark) = self.current else {
            self.info("every landmark has a vertex: :w saves, n and p go through them");
            return Vec::new();
        };
        let Some(v) = self.snapped else {
            self.error("no visible vertex under the cursor: turn or move the view");
            return Vec::new();
        };
        self.history.push(Step {
            landmark,
            pick: self.picks[landmark],
            skipped: self.skipped[landmark],
        });
        self.picks[landmark] = Some(v);
        self.skipped[landmark] = false;
        self.dirty = true;
        if let Some(other) = (0..COUNT).find(|&i| i != landmark && self.picks[i] == Some(v)) {
            self.warn(format!(
                "landmark {landmark} is vertex {v}, like landmark {other} ({})",
                NAMES[other]
            ));
        }
        self.propose();
        let next = self.next_after(Some(landmark));
        self.enter(next);
        if next.is_none() {
            self.info(format!(
                "all {COUNT} landmarks picked: :w saves them to {}",
                self.out.display()
            ));
        }
        vec![PickEffect::WriteRecovery]
    }

    fn skip(&mut self) -> Vec<PickEffect> {
        let Some(landmark) = self.current else {
            return Vec::new();
        };
        if self.picks[landmark].is_some() {
            // Looking again at a picked landmark: Tab moves on, keeping it.
            let next = self.next_after(Some(landmark));
            self.enter(next);
            return Vec::new();
        }
        self.history.push(Step {
            landmark,
            pick: None,
            skipped: self.skipped[landmark],
        });
        self.skipped[landmark] = true;
        self.propose();
        let next = self.next_after(Some(landmark));
        self.enter(next);
        vec![PickEffect::WriteRecovery]
    }

    fn undo(&mut self) -> Vec<PickEffect> {
        let Some(step) = self.history.pop() else {
            self.info("nothing to undo");
            return Vec::new();
        };
        self.picks[step.landmark] = step.pick;
        self.skipped[step.landmark] = step.skipped;
        self.dirty = true;
        self.propose();
        self.enter(Some(step.landmark));
        self.info(format!(
            "undone: landmark {} ({})",
            step.landmark, NAMES[step.landmark]
        ));
        vec![PickEffect::WriteRecovery]
    }

    fn step(&mut self, by: i8) {
        let order = order();
        let n = order.len() as isize;
        let next = match self
            .current
            .and_then(|c| order.iter().position(|&l| l == c))
        {
            Some(at) => (at as isize + isize::from(by)).rem_euclid(n),
            // Past the end: forward starts at the first landmark, back at the last.
            None if by > 0 => 0,
            None => n - 1,
        };
        self.enter(Some(order[next as usize]));
    }

    fn save(&mut self, quit_after: bool, force: bool) -> Vec<PickEffect> {
        let missing: Vec<usize> = (0..COUNT).filter(|&i| self.picks[i].is_none()).collect();
        if !missing.is_empty() {
            let list: Vec<String> = missing.iter().take(8).map(usize::to_string).collect();
            let more = if missing.len() > 8 { ", ..." } else { "" };
            self.error(format!(
                "not saved: {} landmarks have no vertex yet ({}{more})",
                missing.len(),
                list.join(", ")
            ));
            return Vec::new();
        }
        let vertices: Vec<u32> = self.picks.iter().map(|p| p.unwrap_or(0)).collect();
        let landmarks = match &self.kept_points {
            Some(kept) if kept.len() == vertices.len() => Landmarks::Points(
                vertices
                    .iter()
                    .zip(kept)
                    .map(|(&v, &(was, point))| {
                        if v == was {
                            point
                        } else {
                            self.mesh.positions[v as usize]
                        }
                    })
                    .collect(),
            ),
            _ => Landmarks::Vertices(vertices),
        };
        // The checks `validate` and `fit-rig` make: a set they would refuse is not written.
        if let Err(e) = landmarks.positions(&self.mesh) {
            self.error(format!(
                "not saved: {e}; correct the picks (n, p) and save again"
            ));
            return Vec::new();
        }
        vec![PickEffect::Save {
            landmarks,
            quit_after,
            force,
        }]
    }

    fn saved(&mut self, result: Result<(), String>, quit_after: bool) -> Vec<PickEffect> {
        match result {
            Ok(()) => {
                self.dirty = false;
                self.saved = true;
                self.info(format!("saved {}", self.out.display()));
                let mut effects = vec![PickEffect::RemoveRecovery];
                if quit_after {
                    effects.push(PickEffect::Quit);
                }
                effects
            }
            Err(e) => {
                self.error(format!("not saved: {}: {e}", self.out.display()));
                Vec::new()
            }
        }
    }

    fn answer(&mut self, yes: bool) -> Vec<PickEffect> {
        let mode = std::mem::replace(&mut self.mode, Mode::Normal);
        match mode {
            Mode::Confirm(Question::Quit) if yes => {
                vec![PickEffect::RemoveRecovery, PickEffect::Quit]
            }
            Mode::Confirm(Question::Overwrite { quit_after }) if yes => self.save(quit_after, true),
            Mode::Confirm(Question::Overwrite { .. }) => {
                self.info("not saved: the file on disk is kept as it is");
                Vec::new()
            }
            Mode::Confirm(Question::Recover { picks, skipped, .. }) => {
                if yes {
                    self.load_picks(&picks, &skipped);
                    self.dirty = true;
                    self.info(format!("recovered {} picks", self.picked()));
                    Vec::new()
                } else {
                    self.info("recovered picks dropped");
                    vec![PickEffect::RemoveRecovery]
                }
            }
            _ => Vec::new(),
        }
    }

    fn command_key(&mut self, action: PickAction) -> Vec<PickEffect> {
        let Mode::Command(line) = &mut self.mode else {
            return Vec::new();
        };
        match action {
            PickAction::Input(c) => {
                line.push(c);
                Vec::new()
            }
            PickAction::Backspace => {
                if line.pop().is_none() {
                    self.mode = Mode::Normal;
                }
                Vec::new()
            }
            PickAction::Cancel => {
                self.mode = Mode::Normal;
                Vec::new()
            }
            PickAction::Submit => {
                let line = line.trim().to_string();
                self.mode = Mode::Normal;
                self.message = None;
                self.run_command(&line)
            }
            _ => Vec::new(),
        }
    }

    fn run_command(&mut self, line: &str) -> Vec<PickEffect> {
        match line {
            "w" | "write" => self.save(false, false),
            "wq" | "x" => self.save(true, false),
            "q" | "quit" => self.update(PickAction::Quit),
            "q!" | "quit!" => vec![PickEffect::RemoveRecovery, PickEffect::Quit],
            "" => Vec::new(),
            other => {
                self.error(format!(
                    "unknown command `:{other}` (:w saves, :wq saves and quits, :q quits, :q! quits without saving)"
                ));
                Vec::new()
            }
        }
    }
}

mod cursor;
#[cfg(test)]
mod tests;
