//! Every user intent the editor knows, and the effects `update` asks the event loop to run.

use std::path::PathBuf;

use super::app::{FileStamp, Row, ViewPreset};
use crate::facs::AuTable;

/// Something the user (or the outcome of an effect) asks of the editor.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Move the selection down (muscles or AU table, by focus).
    SelectNext,
    /// Move the selection up.
    SelectPrev,
    /// Select the first line.
    SelectFirst,
    /// Select the last line.
    SelectLast,
    /// Select a muscle panel row (mouse click).
    SelectRow(Row),
    /// Select an AU table line (mouse click).
    SelectTableItem(usize),
    /// Switch focus between the muscle panel and the AU table.
    SwitchFocus,
    /// Open `/` find.
    StartFind,
    /// Change the selected row by this many fine steps.
    StepFine(i8),
    /// Change the selected row by this many coarse steps.
    StepCoarse(i8),
    /// Type an exact value for the selected row.
    StartSetValue,
    /// Set the selected row to zero.
    ZeroSelected,
    /// Set every muscle and the jaw to zero.
    ResetAll,
    /// Turn mirror mode on or off.
    ToggleMirror,
    /// Record the current state as an AU (asks for the AU and its name).
    StartRecord,
    /// Enter: in the AU table, load the selected AU or expression; in the muscle panel, type a value.
    Activate,
    /// Overwrite the selected AU with the current state (asks first).
    OverwriteSelected,
    /// Delete the selected AU or expression (asks first for an AU).
    DeleteSelected,
    /// Rename the selected AU.
    RenameSelected,
    /// Add an AU at an intensity to the current state.
    StartAddAu,
    /// Store a combination as a named expression.
    StartExpression,
    /// Turn the camera (degrees of yaw, degrees of pitch).
    Rotate(f32, f32),
    /// Multiply the zoom.
    Zoom(f32),
    /// Shift the picture (fractions of the viewport).
    Pan(f32, f32),
    /// Back to the front view.
    ResetView,
    /// A preset view.
    Preset(ViewPreset),
    /// Next drawing style.
    CycleStyle,
    /// Next cell mode (braille, half-block, ASCII).
    CycleCells,
    /// Toggle ASCII cells.
    ToggleAscii,
    /// Toggle the muscle overlay.
    ToggleMuscles,
    /// Toggle the rest-pose ghost.
    ToggleGhost,
    /// Toggle displacement colours.
    ToggleDisplacement,
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Save to the table file.
    Save,
    /// Quit (asks when there are unsaved changes).
    Quit,
    /// Open the `:` command line.
    StartCommand,
    /// Open or close the help overlay.
    ToggleHelp,
    /// Run a command line (without the `:`).
    Command(String),
    /// Type a character into the input line.
    InputChar(char),
    /// Delete the character before the cursor.
    InputBackspace,
    /// Delete the character under the cursor.
    InputDelete,
    /// Cursor left.
    InputLeft,
    /// Cursor right.
    InputRight,
    /// Cursor to the start.
    InputHome,
    /// Cursor to the end.
    InputEnd,
    /// Delete everything before the cursor (Ctrl-u).
    InputClear,
    /// Complete the word before the cursor (muscle names, AU numbers, commands).
    InputComplete,
    /// Accept the input line.
    InputSubmit,
    /// Close the input line, help or question without acting.
    Cancel,
    /// Answer a question.
    Answer(bool),
    /// Scroll the help overlay.
    HelpScroll(i16),
    /// The terminal changed size.
    Resize(u16, u16),
    /// Rig mode (`R`): placing muscles.
    Rig(RigAction),
    /// A save finished.
    Saved {
        /// The file written.
        path: PathBuf,
        /// Its new stamp.
        stamp: FileStamp,
        /// Quit now.
        quit_after: bool,
    },
    /// A save failed.
    SaveFailed {
        /// The file.
        path: PathBuf,
        /// Why.
        error: String,
    },
    /// A table to import was read (`:import`).
    TableRead {
        /// What was named: a file or `builtin:NAME`.
        source: String,
        /// The table, or why it could not be read.
        table: Result<AuTable, String>,
    },
    /// A save found the file changed on disk (or present where a new file was expected).
    SaveConflict {
        /// The file.
        path: PathBuf,
        /// Quit after saving.
        quit_after: bool,
    },
}

/// Input and output `update` asks for; the event loop runs them.
#[derive(Debug, Clone, PartialEq)]
pub enum Effect {
    /// Write a table file: atomically, and only if the file on disk still matches `expected`
    /// (`None`: the file must not exist) unless `force`.
    Save {
        /// Where.
        path: PathBuf,
        /// The table to write. Its rig reference is kept absolute (or built in) in the
        /// editor and written relative to the file's real folder ([`crate::io::reference`]).
        table: Box<crate::facs::AuTable>,
        /// What the file should look like now.
        expected: Option<FileStamp>,
        /// Write even if it does not.
        force: bool,
        /// Quit after a successful save.
        quit_after: bool,
    },
    /// Write a rig file, as [`Effect::Save`] does a table file.
    SaveRig {
        /// Where.
        path: PathBuf,
        /// The rig to write. Its mesh reference is kept absolute (or built in) in the editor
        /// and written relative to the file's real folder ([`crate::io::reference`]).
        rig: Box<crate::model::Rig>,
        /// What the file should look like now (`None`: it must not exist).
        expected: Option<FileStamp>,
    },
    /// The unsaved state changed: write the recovery file (debounced by the loop).
    RecoveryDue,
    /// Remove the recovery file (after a save or an explicit discard).
    RemoveRecovery,
    /// Read a table to import its AUs (answered with [`Action::TableRead`]).
    ReadTable(PathBuf),
    /// Leave the editor.
    Quit,
}

/// A rig-mode intent.
#[derive(Debug, Clone, PartialEq)]
pub enum RigAction {
    /// Enter or leave rig mode.
    Toggle,
    /// Select the next point of the selected muscle.
    NextPoint,
    /// Select the next parameter of the selected muscle.
    NextParam,
    /// Move the selected point in the view plane by steps (right, up).
    Move {
        /// Steps to the screen's right.
        right: i8,
        /// Steps up the screen.
        up: i8,
        /// Coarse steps.
        coarse: bool,
    },
    /// Change the selected parameter by steps (an angle turns counter-clockwise on screen).
    Param {
        /// Steps (negative: down).
        by: i8,
        /// Coarse steps.
        coarse: bool,
    },
    /// Change the held activation by steps of [`HELD_STEP`].
    Held(i8),
    /// The rig file was written.
    Saved {
        /// Where, as the user gave it.
        path: PathBuf,
        /// The file written, absolute: what the table names from now on.
        file: PathBuf,
        /// Its new stamp.
        stamp: FileStamp,
    },
    /// Writing the rig file failed (or found it changed on disk).
    SaveFailed {
        /// The file.
        path: PathBuf,
        /// Why.
        error: String,
    },
}
