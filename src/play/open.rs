//! Opening a recording: the file is opened and read once, its format told from its first line
//! (a Live Link Face header, an activation CSV, else OpenFace CSV), and the same reader handed on, so a pipe, a
//! FIFO or `<(...)` loses nothing to the sniff.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use super::acts::ActsSource;
use super::event::{FrameSource, Input, SourceError, DEFAULT_FRAME_RATE};
use super::livelink::{LiveLinkSource, LIVELINK_FRAME_RATE};
use super::map::{AuMapper, IntensityScale};
use super::source::OpenFaceSource;
use crate::io::arkit::ArkitMap;
use crate::io::lines::sniff_first_line;
use crate::io::livelink::is_header;
use crate::io::openface::OpenFaceError;

/// How a recording's frames are read.
#[derive(Debug, Clone)]
pub struct RecordingOptions {
    /// AU intensities to activations.
    pub mapper: AuMapper,
    /// The scale of OpenFace intensities (Live Link weights are always 0-1).
    pub scale: IntensityScale,
    /// The frame rate given (`--fps`), else each format's own default.
    pub fps: Option<f64>,
    /// The playing rig's muscle names, for activation CSVs (`grimace capture`'s output).
    pub muscles: Vec<String>,
    /// The face followed in an OpenFace recording of several (`--face`; default: the first
    /// tracked face, [`crate::io::faces`]).
    pub face: Option<u32>,
}

/// Opens the recording at `path`: a Live Link Face take when its first line is that header,
/// an activation CSV when it has `explained` and `jaw` columns, else an OpenFace CSV.
pub fn open_file(
    path: &Path,
    options: &RecordingOptions,
) -> Result<Box<dyn FrameSource>, SourceError> {
    refuse_special(path)?;
    let file = File::open(path).map_err(|source| SourceError::Io {
        what: format!("cannot open {}", path.display()),
        source,
    })?;
    let (first, input) =
        sniff_first_line(BufReader::new(file)).map_err(|source| SourceError::Io {
            what: format!("cannot read {}", path.display()),
            source,
        })?;
    let input: Input = Box::new(input);
    if is_header(&first) {
        let fps = options.fps.unwrap_or(LIVELINK_FRAME_RATE);
        let arkit = ArkitMap::builtin();
        let source = LiveLinkSource::new(input, path, options.mapper.clone(), &arkit, fps)?;
        return Ok(Box::new(source));
    }
    let fps = options.fps.unwrap_or(DEFAULT_FRAME_RATE);
    if crate::io::acts::is_header(&first) {
        return Ok(Box::new(ActsSource::new(
            input,
            path,
            &options.muscles,
            fps,
        )?));
    }
    let source = OpenFaceSource::new(input, path, options.mapper.clone(), options.scale, fps)?
        .follow_face(options.face);
    Ok(Box::new(source))
}

/// Refuses a folder, a device or a socket as a recording, saying what it is. A named pipe
/// is fine: the file is read once, as a stream (`grimace play <(tracker ...)`).
fn refuse_special(path: &Path) -> Result<(), SourceError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if std::fs::metadata(path).is_ok_and(|m| m.file_type().is_fifo()) {
            return Ok(());
        }
    }
    match crate::io::error::not_a_file(path) {
        // A missing or unreadable file is reported by the open itself.
        Some(reason) if std::fs::metadata(path).is_ok() => {
            Err(SourceError::OpenFace(OpenFaceError::new(path, reason)))
        }
        _ => Ok(()),
    }
}
