//! The editor's state. [`crate::tui::update::update`] changes it; the views only read it.

use std::path::PathBuf;

use crate::facs::{AuKey, AuTable};
use crate::render::Camera;
use glam::{Vec2, Vec3};

use crate::model::{Activations, Jaw, MuscleKind, Rig};

use super::face::Face;

/// Smallest terminal the editor draws in; below it, it says so instead.
pub const MIN_SIZE: (u16, u16) = (60, 16);

/// Fine adjustment step (h/l, arrows, mouse wheel).
pub const FINE_STEP: f32 = 0.05;
/// Coarse adjustment steps (H/L) per row range: an eighth of the range, so a muscle (0-2)
/// moves by 0.25 and the jaw (0-4) by 0.5.
pub const COARSE_STEPS_PER_RANGE: f32 = 8.0;
/// Activations set by steps are stored rounded to this many parts of one (hundredths), so four
/// fine steps give exactly 0.2.
pub const STEP_RESOLUTION: f32 = 100.0;

/// One row of the muscle panel: a muscle (index into the rig) or the jaw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Row {
    /// A muscle, by its index in [`Rig::muscles`].
    Muscle(usize),
    /// The jaw.
    Jaw,
}

/// The groups of the muscle panel, in display order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    /// Linear (vector) muscles.
    Linear,
    /// Sheet muscles.
    Sheet,
    /// Sphincters.
    Sphincter,
    /// The jaw.
    Jaw,
}

impl Group {
    /// The heading shown in the panel.
    pub fn title(self) -> &'static str {
        match self {
            Group::Linear => "linear",
            Group::Sheet => "sheet",
            Group::Sphincter => "sphincter",
            Group::Jaw => "jaw",
        }
    }

    /// The group of a muscle kind.
    pub fn of(kind: &MuscleKind) -> Group {
        match kind {
            MuscleKind::Linear(_) => Group::Linear,
            MuscleKind::Sheet(_) => Group::Sheet,
            MuscleKind::Sphincter(_) => Group::Sphincter,
        }
    }
}

/// Which panel the selection keys act on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Focus {
    /// The muscle panel.
    Muscles,
    /// The AU table panel.
    Table,
}

/// One selectable line of the AU table panel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TableItem {
    /// A recorded AU.
    Au(AuKey),
    /// A named expression.
    Expression(String),
}

pub use crate::render::{CellMode, ColorMode, Style};

/// The next cell mode in the cycle: braille, half-block colour, ASCII.
pub fn next_cells(mode: CellMode) -> CellMode {
    match mode {
        CellMode::Braille => CellMode::HalfBlock,
        CellMode::HalfBlock => CellMode::Ascii,
        CellMode::Ascii => CellMode::Braille,
    }
}

/// The name of a cell mode, as shown in the status line.
pub fn cells_name(mode: CellMode) -> &'static str {
    match mode {
        CellMode::Braille => "braille",
        CellMode::Ascii => "ascii",
        CellMode::HalfBlock => "half-block",
    }
}

/// The zoom of the initial and preset views: a little room around the rest face, so the chin
/// stays in view when the jaw opens.
pub const DEFAULT_ZOOM: f32 = 0.9;

/// Named camera positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViewPreset {
    /// Straight on.
    Front,
    /// From the subject's right side.
    Side,
    /// Halfway between.
    ThreeQuarter,
}

/// The camera and drawing options of the viewport, and what the terminal offers.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// Turn about the vertical axis, degrees.
    pub yaw: f32,
    /// Tilt about the horizontal axis, degrees.
    pub pitch: f32,
    /// Magnification, 1.0 fits the face.
    pub zoom: f32,
    /// Shift of the picture, as fractions of the viewport (x right, y up).
    pub pan: (f32, f32),
    /// Drawing style.
    pub style: Style,
    /// Dots to cells.
    pub cells: CellMode,
    /// Draw the muscles over the face.
    pub show_muscles: bool,
    /// Draw the rest pose as a faint ghost.
    pub show_ghost: bool,
    /// Colour edges by how far they moved.
    pub show_displacement: bool,
    /// Terminal size (columns, rows).
    pub size: (u16, u16),
    /// Colour support.
    pub colors: ColorMode,
}

impl View {
    /// The initial view: front, feature lines, in `cells`.
    pub fn new(cells: CellMode) -> View {
        View {
            yaw: 0.0,
            pitch: 0.0,
            zoom: DEFAULT_ZOOM,
            pan: (0.0, 0.0),
            style: Style::Lines,
            cells,
            show_muscles: false,
            show_ghost: false,
            show_displacement: false,
            size: (80, 24),
            colors: ColorMode::Ansi16,
        }
    }

    /// The cells the face is drawn in. The shaded style draws braille as half blocks where
    /// the terminal has 256 colours or more: a braille cell has one colour for its eight
    /// dots, so a shaded face in braille is dots of one grey per cell and its eyes and mouth
    /// are lost, while half blocks give every dot of a 1x2 cell its own grey. With 16
    /// colours or none, the dots' density is all there is, so braille stays.
    pub fn drawn_cells(&self) -> CellMode {
        let rich = matches!(self.colors, ColorMode::Ansi256 | ColorMode::TrueColor);
        if self.style == Style::Shaded && self.cells == CellMode::Braille && rich {
            CellMode::HalfBlock
        } else {
            self.cells
        }
    }

    /// Puts the camera at a preset (zoom and pan back to the start).
    pub fn preset(&mut self, preset: ViewPreset) {
        self.yaw = match preset {
            ViewPreset::Front => 0.0,
            ViewPreset::Side => 90.0,
            ViewPreset::ThreeQuarter => 35.0,
        };
        self.pitch = match preset {
            ViewPreset::ThreeQuarter => 10.0,
            _ => 0.0,
        };
        self.zoom = DEFAULT_ZOOM;
        self.pan = (0.0, 0.0);
    }
}

/// The kind of a status message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// Something happened as asked.
    Info,
    /// Worth noticing (another editor has the file open, ...).
    Warning,
    /// Rejected input or a failed operation.
    Error,
}

/// A message for the status line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Message {
    /// What to say.
    pub text: String,
    /// How loudly.
    pub severity: Severity,
}

impl Message {
    /// A message of `severity`: what the editor's and the picker's status lines show.
    pub fn new(severity: Severity, text: impl Into<String>) -> Message {
        Message {
            text: text.into(),
            severity,
        }
    }
}

/// What a line of typed input is for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum InputKind {
    /// A `:` command.
    Command,
    /// `/`: find a muscle by name.
    Find,
    /// `=`: an exact value for the selected row; holds the row's name, value and range, shown
    /// in the prompt (the field itself starts empty).
    Value(String),
    /// Record: the AU to record the current state as.
    RecordKey,
    /// Record: the name of the AU (the FACS name is suggested).
    RecordName(AuKey),
    /// Rename an AU.
    Rename(AuKey),
    /// Add an AU (with an intensity) to the current state.
    AddAu,
    /// The name under which the current combination is stored as an expression.
    ExpressionName,
}

impl InputKind {
    /// The prompt shown before the typed text.
    pub fn prompt(&self) -> String {
        match self {
            InputKind::Command => ":".into(),
            InputKind::Find => "/".into(),
            InputKind::Value(now) => format!("value ({now}): "),
            InputKind::RecordKey => "record as AU (e.g. 12, L12): ".into(),
            InputKind::RecordName(key) => format!("name of AU {key}: "),
            InputKind::Rename(key) => format!("rename AU {key}: "),
            InputKind::AddAu => "add AU [intensity 0-2] (e.g. 12 0.5, 12C, 6+12B): ".into(),
            InputKind::ExpressionName => "expression name = combination (e.g. smile 6+12): ".into(),
        }
    }
}

/// A line being typed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Input {
    /// What it is for.
    pub kind: InputKind,
    /// The text so far.
    pub text: String,
    /// Cursor position in characters.
    pub cursor: usize,
}

impl Input {
    /// An input line holding `text`, the cursor at its end.
    pub fn new(kind: InputKind, text: impl Into<String>) -> Input {
        let text = text.into();
        Input {
            kind,
            cursor: text.chars().count(),
            text,
        }
    }
}

/// A question waiting for yes or no.
#[derive(Debug, Clone, PartialEq)]
pub enum Question {
    /// Quit with unsaved changes?
    QuitUnsaved,
    /// Replace a recorded AU?
    OverwriteAu {
        /// The AU.
        key: AuKey,
        /// The name to record it under.
        name: String,
    },
    /// Delete a recorded AU?
    DeleteAu(AuKey),
    /// Store an expression after adding the AUs it needs from the built-in table?
    AddMissingAus {
        /// The expression's name.
        name: String,
        /// Its combination.
        combo: String,
        /// The AUs the table lacks, in the order written.
        missing: Vec<AuKey>,
    },
    /// Overwrite a file that changed on disk (or that is not ours)?
    OverwriteFile {
        /// The file.
        path: PathBuf,
        /// Quit after saving.
        quit_after: bool,
    },
    /// Restore the state found in a recovery file?
    Recover(Box<Recovered>),
}

/// Unsaved state found in a recovery file at start.
#[derive(Debug, Clone, PartialEq)]
pub struct Recovered {
    /// Activations as they were.
    pub activations: Activations,
    /// The table as it was.
    pub table: AuTable,
    /// When it was written, for the question.
    pub when: String,
    /// The table file the recovered edits started from (`None`: it did not exist, or the
    /// recovery file does not say). Recovering makes it the file's stamp, so a save asks
    /// before replacing a file that has changed since.
    pub base: Option<FileStamp>,
    /// The rig as edited in rig mode, if it had unsaved changes.
    pub rig: Option<Rig>,
}

/// The editor's mode.
#[derive(Debug, Clone, PartialEq)]
pub enum Mode {
    /// Keys are commands.
    Normal,
    /// Keys edit a line of text.
    Input(Input),
    /// The help overlay is open (scrolled by this many lines).
    Help(u16),
    /// A yes/no question is open.
    Confirm(Question),
}

impl Mode {
    /// The name shown in the status line.
    pub fn name(&self) -> &'static str {
        match self {
            Mode::Normal => "NORMAL",
            Mode::Input(input) if input.kind == InputKind::Command => "COMMAND",
            Mode::Input(_) => "INPUT",
            Mode::Help(_) => "HELP",
            Mode::Confirm(_) => "CONFIRM",
        }
    }
}

/// An undoable state: the activations and the table.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Activations.
    pub activations: Activations,
    /// AU table.
    pub table: AuTable,
    /// The AU marked as loaded.
    pub loaded: Option<AuKey>,
}

/// One entry of the editor's history.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// Activations and the table as they were.
    State(Snapshot),
    /// A rig change: the muscles' or the jaw's parameters as they were (rig mode).
    Rig(RigUndo),
}

/// A file's identity when it was loaded or saved: used to notice changes made by others.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileStamp {
    /// Length in bytes.
    pub len: u64,
    /// A hash of the contents.
    pub hash: u64,
}

impl FileStamp {
    /// The stamp of some file contents.
    pub fn of(bytes: &[u8]) -> FileStamp {
        use std::hash::{Hash, Hasher};
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        bytes.hash(&mut hasher);
        FileStamp {
            len: bytes.len() as u64,
            hash: hasher.finish(),
        }
    }
}

/// What is being edited: the face and its activations, the AU table and its file.
#[derive(Debug, Clone)]
pub struct Document {
    /// Rig, mesh and deformed positions.
    pub face: Face,
    /// The activations being edited.
    pub activations: Activations,
    /// The AU table being edited.
    pub table: AuTable,
    /// The table as last loaded or saved (unsaved changes = difference from it).
    pub saved_table: AuTable,
    /// Where `:w` writes; `None` for the built-in table until saved as a file.
    pub file: Option<PathBuf>,
    /// The file as loaded or last saved; `None` when it does not exist yet.
    pub file_stamp: Option<FileStamp>,
    /// The AU last loaded (marked in the table panel).
    pub loaded: Option<AuKey>,
}

/// What the selection keys act on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Selection {
    /// The muscle panel's rows in display order.
    pub rows: Vec<Row>,
    /// Index into `rows`.
    pub selected: usize,
    /// Which panel the selection keys act on.
    pub focus: Focus,
    /// Index into [`App::table_items`].
    pub table_selected: usize,
    /// Move mirror partners together.
    pub mirror: bool,
}

/// The way back: undo and redo stacks, and the count of edits.
#[derive(Debug, Clone, Default)]
pub struct History {
    /// Edits to go back over, the last made last: activation and table edits and rig
    /// changes in one list, so undo takes them back in the order they were made.
    pub undo: Vec<Step>,
    /// Edits undone, the last undone last.
    pub redo: Vec<Step>,
    /// The row last adjusted by a step: consecutive steps on one row undo together.
    pub last_step: Option<Row>,
    /// Counts edits; the event loop writes the recovery file when it moves.
    pub edits: u64,
}

/// Everything the editor knows. The renderer's buffers are not part of it: the event loop
/// keeps them beside it ([`super::view::viewport::RenderCache`]).
#[derive(Debug, Clone)]
pub struct App {
    /// The face, the table and its file.
    pub doc: Document,
    /// The selected rows and AUs.
    pub selection: Selection,
    /// Camera, drawing options, terminal size and colours.
    pub view: View,
    /// Undo and redo.
    pub history: History,
    /// Mode.
    pub mode: Mode,
    /// The status message.
    pub message: Option<Message>,
    /// Rig mode: its state and the rig's file.
    pub rig_edit: RigEdit,
}

impl App {
    /// The camera for the view settings: angles in degrees about the face's own axes, pan as a
    /// fraction of the face's size. Every view of the editor (drawing, zoom focus, rig mode's
    /// directions) derives from this one.
    pub fn camera(&self) -> Camera {
        let framing = self.doc.face.framing();
        let extent = framing.size();
        Camera {
            yaw: self.view.yaw.to_radians(),
            pitch: self.view.pitch.to_radians(),
            zoom: self.view.zoom,
            pan: Vec2::new(self.view.pan.0, self.view.pan.1) * extent,
            basis: framing.basis,
        }
    }

    /// A new editor on a scene and a table.
    pub fn new(scene: Face, table: AuTable, file: Option<PathBuf>) -> App {
        let rows = rows_of(scene.rig());
        let activations = Activations::zero(scene.rig());
        App {
            doc: Document {
                face: scene,
                activations,
                saved_table: table.clone(),
                table,
                file,
                file_stamp: None,
                loaded: None,
            },
            selection: Selection {
                rows,
                selected: 0,
                focus: Focus::Muscles,
                table_selected: 0,
                mirror: false,
            },
            view: View::new(CellMode::Braille),
            history: History::default(),
            mode: Mode::Normal,
            message: None,
            rig_edit: RigEdit::default(),
        }
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        self.doc.face.rig()
    }

    /// True when the table differs from the file (or from the built-in table).
    pub fn dirty(&self) -> bool {
        self.doc.table != self.doc.saved_table || self.rig_edit.dirty(self.rig())
    }

    /// True when the table file does not exist yet (`:w` creates it).
    pub fn new_file(&self) -> bool {
        self.doc.file.is_some() && self.doc.file_stamp.is_none()
    }

    /// The selected row.
    pub fn selected_row(&self) -> Row {
        self.selection
            .rows
            .get(self.selection.selected)
            .copied()
            .unwrap_or(Row::Jaw)
    }

    /// The value of a row.
    pub fn value(&self, row: Row) -> f32 {
        match row {
            Row::Muscle(i) => self.doc.activations.muscles.get(i).copied().unwrap_or(0.0),
            Row::Jaw => self.doc.activations.jaw,
        }
    }

    /// The name of a row (`jaw` for the jaw).
    pub fn row_name(&self, row: Row) -> &str {
        match row {
            Row::Muscle(i) => self.rig().muscles.get(i).map_or("?", |m| m.name.as_str()),
            Row::Jaw => "jaw",
        }
    }

    /// The allowed range of a row.
    pub fn range(&self, row: Row) -> (f32, f32) {
        let range = match row {
            Row::Muscle(_) => crate::model::MUSCLE_RANGE,
            Row::Jaw => crate::model::JAW_RANGE,
        };
        (*range.start(), *range.end())
    }

    /// The coarse step of a row: an eighth of its range.
    pub fn coarse_step(&self, row: Row) -> f32 {
        let (lo, hi) = self.range(row);
        (hi - lo) / COARSE_STEPS_PER_RANGE
    }

    /// The row mirrored to `row` when mirror mode is on.
    pub fn partner(&self, row: Row) -> Option<Row> {
        match row {
            Row::Muscle(i) => self.rig().mirror_of(i).map(Row::Muscle),
            Row::Jaw => None,
        }
    }

    /// The AU table panel's lines: AUs in order, then expressions.
    pub fn table_items(&self) -> Vec<TableItem> {
        self.doc
            .table
            .aus
            .keys()
            .map(|k| TableItem::Au(*k))
            .chain(
                self.doc
                    .table
                    .expressions
                    .keys()
                    .map(|n| TableItem::Expression(n.clone())),
            )
            .collect()
    }

    /// The current undoable state.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            activations: self.doc.activations.clone(),
            table: self.doc.table.clone(),
            loaded: self.doc.loaded,
        }
    }

    /// The file name shown in the status line.
    pub fn file_label(&self) -> String {
        match &self.doc.file {
            Some(path) => path.display().to_string(),
            None => "[built-in table]".into(),
        }
    }

    /// Sets an info message.
    pub fn info(&mut self, text: impl Into<String>) {
        self.message = Some(Message::new(Severity::Info, text));
    }

    /// Sets a warning.
    pub fn warn(&mut self, text: impl Into<String>) {
        self.message = Some(Message::new(Severity::Warning, text));
    }

    /// Sets an error message.
    pub fn error(&mut self, text: impl Into<String>) {
        self.message = Some(Message::new(Severity::Error, text));
    }
}

/// The muscle panel's rows: linear, sheet, sphincter muscles (rig order within a group), then
/// the jaw if the rig has one.
pub fn rows_of(rig: &Rig) -> Vec<Row> {
    let mut rows = Vec::with_capacity(rig.muscles.len() + 1);
    for group in [Group::Linear, Group::Sheet, Group::Sphincter] {
        rows.extend(
            rig.muscles
                .iter()
                .enumerate()
                .filter(|(_, m)| Group::of(&m.kind) == group)
                .map(|(i, _)| Row::Muscle(i)),
        );
    }
    if rig.jaw.is_some() {
        rows.push(Row::Jaw);
    }
    rows
}

/// The group a row belongs to.
pub fn group_of(rig: &Rig, row: Row) -> Group {
    match row {
        Row::Muscle(i) => rig
            .muscles
            .get(i)
            .map_or(Group::Linear, |m| Group::of(&m.kind)),
        Row::Jaw => Group::Jaw,
    }
}

/// What rig mode knows: whether it is on, the rig's file, the selected point and parameter
/// and the held activation. Its changes are undone with the rest of the editor's edits
/// ([`crate::tui::app::History`]), each kept as a [`RigUndo`].
#[derive(Debug, Clone, PartialEq)]
pub struct RigEdit {
    /// Rig mode is on.
    pub on: bool,
    /// The rig file `:w` writes; `None` for a built-in rig (`:w` asks for a name).
    pub path: Option<PathBuf>,
    /// The rig file as loaded or last saved, to notice changes made by others.
    pub stamp: Option<FileStamp>,
    /// The rig as loaded or last saved, once it has been edited.
    pub saved: Option<Rig>,
    /// Index of the selected point of the selected muscle (`Tab` cycles).
    pub point: usize,
    /// Index of the selected parameter of the selected muscle (`p` cycles).
    pub param: usize,
    /// The activation the selected muscle is held at.
    pub held: f32,
    /// What the face shows: the row held, its activation and the scene generation after
    /// deforming, so a change made elsewhere is noticed and the hold applied again.
    pub(crate) shown: Option<(Row, f32, u64)>,
}

impl Default for RigEdit {
    fn default() -> RigEdit {
        RigEdit {
            on: false,
            path: None,
            stamp: None,
            saved: None,
            point: 0,
            param: 0,
            held: 1.0,
            shown: None,
        }
    }
}

impl RigEdit {
    /// Rig mode for a rig loaded from `path` (`None`: built in) with these file contents.
    pub fn for_file(path: Option<PathBuf>, contents: Option<&[u8]>) -> RigEdit {
        RigEdit {
            path,
            stamp: contents.map(FileStamp::of),
            ..RigEdit::default()
        }
    }

    /// True when the rig differs from its file.
    pub fn dirty(&self, rig: &Rig) -> bool {
        self.saved.as_ref().is_some_and(|saved| saved != rig)
    }
}

/// The jaw's pose: what rig mode changes of the jaw (its weights stay).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JawPose {
    /// The point the jaw turns about.
    pub pivot: Vec3,
    /// The axis it turns about.
    pub axis: Vec3,
    /// Degrees per unit of jaw activation.
    pub degrees_per_unit: f32,
}

impl JawPose {
    pub(crate) fn of(jaw: &Jaw) -> JawPose {
        JawPose {
            pivot: jaw.pivot,
            axis: jaw.axis,
            degrees_per_unit: jaw.degrees_per_unit,
        }
    }
}

/// Parts of a rig, as rig mode changes them and undo puts them back.
#[derive(Debug, Clone, PartialEq)]
pub enum RigParts {
    /// Muscles' kinds with their parameters, by index (a muscle and its mirror partner).
    Muscles(Vec<(usize, MuscleKind)>),
    /// The jaw's pose.
    Jaw(JawPose),
    /// A whole rig (one put back from a recovery file).
    Whole(Box<Rig>),
}

impl RigParts {
    /// The same parts as they are in `rig` now.
    pub(crate) fn current(&self, rig: &Rig) -> RigParts {
        match self {
            RigParts::Muscles(list) => RigParts::Muscles(
                list.iter()
                    .filter_map(|(i, _)| Some((*i, rig.muscles.get(*i)?.kind.clone())))
                    .collect(),
            ),
            RigParts::Jaw(pose) => RigParts::Jaw(rig.jaw.as_ref().map_or(*pose, JawPose::of)),
            RigParts::Whole(_) => RigParts::Whole(Box::new(rig.clone())),
        }
    }

    /// Puts the parts into the scene's rig, binding again only what they touch.
    pub(crate) fn apply(self, scene: &mut Face) -> Result<(), String> {
        match self {
            RigParts::Muscles(list) => scene.rebind_muscles(list),
            RigParts::Jaw(p) => scene.rebind_jaw(p.pivot, p.axis, p.degrees_per_unit),
            RigParts::Whole(rig) => scene.set_rig(*rig),
        }
    }
}

/// A rig change as the editor's history keeps it: what changed, and the parts to put back.
#[derive(Debug, Clone, PartialEq)]
pub struct RigUndo {
    /// What the change was to, for the message line (`L_Zygomatic_Major attachment`).
    pub what: String,
    /// The parts as they were before the change.
    pub parts: RigParts,
}
