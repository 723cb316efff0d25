//! Load and save errors, and the helpers that give them a file, line and column.

use std::fmt;
use std::path::{Path, PathBuf};

use thiserror::Error;

/// Why a file could not be loaded.
///
/// Displayed as `FILE:LINE:COL: message`, `FILE:LINE: message` or `FILE: message`, the form
/// compilers use, so editors and terminals can jump to the place. Lines and columns count
/// from 1; columns count characters, not bytes.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub struct LoadError {
    /// The file that failed to load.
    pub path: PathBuf,
    /// The line (from 1), where the format gives one.
    pub line: Option<usize>,
    /// The column (from 1, in characters), where the format gives one.
    pub column: Option<usize>,
    /// What is wrong and what was expected.
    pub message: String,
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        write!(f, ": {}", self.message)
    }
}

impl LoadError {
    /// An error about the whole file (no position).
    pub fn new(path: &Path, message: impl Into<String>) -> LoadError {
        LoadError {
            path: path.to_path_buf(),
            line: None,
            column: None,
            message: message.into(),
        }
    }

    /// An error at a line and column.
    pub fn at(path: &Path, line: usize, column: usize, message: impl Into<String>) -> LoadError {
        LoadError {
            path: path.to_path_buf(),
            line: Some(line),
            column: Some(column),
            message: message.into(),
        }
    }

    /// An error on a whole line.
    pub fn at_line(path: &Path, line: usize, message: impl Into<String>) -> LoadError {
        LoadError {
            path: path.to_path_buf(),
            line: Some(line),
            column: None,
            message: message.into(),
        }
    }

    /// An error at a byte offset of `text`, converted to line and column.
    pub fn at_offset(
        path: &Path,
        text: &str,
        offset: usize,
        message: impl Into<String>,
    ) -> LoadError {
        let (line, column) = line_column(text, offset);
        LoadError::at(path, line, column, message)
    }

    /// An error reading the file from disk.
    pub fn io(path: &Path, error: &std::io::Error) -> LoadError {
        LoadError::new(path, format!("cannot read the file: {}", io_reason(error)))
    }
}

/// Why a file could not be saved. The previous version of the file, if any, is untouched.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{}: cannot save: {message}", path.display())]
pub struct SaveError {
    /// The file that was being saved.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl SaveError {
    /// A save error with a message.
    pub fn new(path: &Path, message: impl Into<String>) -> SaveError {
        SaveError {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// A save error from a failed write.
    pub fn io(path: &Path, error: &std::io::Error) -> SaveError {
        SaveError::new(path, io_reason(error))
    }
}

/// The reason of an I/O error without the "(os error N)" noise.
pub(crate) fn io_reason(error: &std::io::Error) -> String {
    let text = error.to_string();
    match text.find(" (os error") {
        Some(end) => text[..end].to_lowercase(),
        None => text,
    }
}

/// The 1-based line and column (in characters) of a byte offset in `text`. Offsets past the
/// end map to the end; offsets inside a character map to that character.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = 1 + before.bytes().filter(|&b| b == b'\n').count();
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = 1 + before[line_start..].chars().count();
    (line, column)
}

/// The largest text file grimace reads (rigs, tables, meshes, classic data). A bigger file is
/// refused with a message before it is read, so no input can exhaust memory.
pub const MAX_FILE_BYTES: u64 = 256 * 1024 * 1024;

/// Reads a whole file as UTF-8 text, refusing files over `limit` bytes and naming the line
/// and column of the first byte that is not UTF-8.
///
/// Anything but a regular file (a folder, a named pipe, a device) is refused before it is
/// opened: opening a pipe would wait for a writer, and a device has no end.
pub fn read_text(path: &Path, limit: u64) -> Result<String, LoadError> {
    use std::io::Read;
    let file = open_regular(path)?;
    let meta = file.metadata().map_err(|e| LoadError::io(path, &e))?;
    if meta.len() > limit {
        return Err(too_large(path, meta.len(), limit));
    }
    // Read at most limit + 1 bytes: the size on disk may change, or be wrong (special files).
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| LoadError::io(path, &e))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(path, bytes.len() as u64, limit));
    }
    text_from_bytes(path, bytes)
}

/// What a file system entry is when it is not a regular file (`"a folder"`, `"a named pipe
/// (FIFO)"`, ...); `None` for a regular file.
pub fn special_kind(kind: &std::fs::FileType) -> Option<&'static str> {
    if kind.is_file() {
        return None;
    }
    if kind.is_dir() {
        return Some("a folder");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return Some("a named pipe (FIFO)");
        }
        if kind.is_char_device() {
            return Some("a character device");
        }
        if kind.is_block_device() {
            return Some("a block device");
        }
        if kind.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a regular file")
}

/// Why `path` cannot be read as a file: `None` for a regular file (through symbolic links),
/// else `does not exist`, `is a folder, expected a file`, `is a named pipe (FIFO), expected a
/// regular file`, or the reason it cannot be looked at.
pub fn not_a_file(path: &Path) -> Option<String> {
    match std::fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Some("does not exist".into()),
        Err(e) => Some(format!("cannot be read: {}", io_reason(&e))),
        Ok(meta) => special_kind(&meta.file_type()).map(|kind| match kind {
            "a folder" => "is a folder, expected a file".to_string(),
            "not a regular file" => "is not a regular file".to_string(),
            kind => format!("is {kind}, expected a regular file"),
        }),
    }
}

/// Opens a file for reading after checking it is a regular file (see [`not_a_file`]).
pub fn open_regular(path: &Path) -> Result<std::fs::File, LoadError> {
    if let Some(reason) = not_a_file(path) {
        return Err(match std::fs::metadata(path) {
            Err(e) => LoadError::io(path, &e),
            Ok(_) => LoadError::new(path, reason),
        });
    }
    std::fs::File::open(path).map_err(|e| LoadError::io(path, &e))
}

fn too_large(path: &Path, size: u64, limit: u64) -> LoadError {
    LoadError::new(
        path,
        format!(
            "the file is too large ({size} bytes); grimace reads files up to {} MiB",
            limit / (1024 * 1024)
        ),
    )
}

/// Converts bytes to text, naming the line and column of the first invalid UTF-8 byte.
///
/// A leading UTF-8 byte order mark is dropped, and line ends are made `\n` (CRLF and a lone
/// CR, the old Mac line end, both count as one line end), so every format reads the same
/// whatever editor wrote it and lines and columns count as the user sees them.
pub fn text_from_bytes(path: &Path, mut bytes: Vec<u8>) -> Result<String, LoadError> {
    if bytes.starts_with(BOM) {
        bytes.drain(..BOM.len());
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        let valid_up_to = e.utf8_error().valid_up_to();
        let bytes = e.into_bytes();
        // The valid prefix is text; the bad byte sits right after it.
        let prefix = std::str::from_utf8(&bytes[..valid_up_to]).unwrap_or_default();
        let prefix = unix_line_ends(prefix.to_string());
        let (line, column) = line_column(&prefix, prefix.len());
        LoadError::at(
            path,
            line,
            column,
            format!(
                "invalid UTF-8 (byte 0x{:02x}); expected a text file",
                bytes[valid_up_to]
            ),
        )
    })?;
    Ok(unix_line_ends(text))
}

/// The UTF-8 byte order mark some editors put at the start of a text file.
pub const BOM: &[u8] = "\u{feff}".as_bytes();

/// `text` with CRLF and lone CR line ends made LF.
pub fn unix_line_ends(text: String) -> String {
    if text.contains('\r') {
        text.replace("\r\n", "\n").replace('\r', "\n")
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_forms() {
        let p = Path::new("a/b.rig.ron");
        assert_eq!(LoadError::new(p, "bad").to_string(), "a/b.rig.ron: bad");
        assert_eq!(
            LoadError::at(p, 3, 7, "bad").to_string(),
            "a/b.rig.ron:3:7: bad"
        );
        assert_eq!(
            LoadError::at_line(p, 3, "bad").to_string(),
            "a/b.rig.ron:3: bad"
        );
        assert_eq!(
            SaveError::new(p, "disk full").to_string(),
            "a/b.rig.ron: cannot save: disk full"
        );
    }

    #[test]
    fn line_column_counts_characters() {
        let text = "ab\nçd\nx";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 2), (1, 3));
        assert_eq!(line_column(text, 3), (2, 1));
        // 'ç' is two bytes; 'd' is the second character of line 2.
        assert_eq!(line_column(text, 5), (2, 2));
        // Inside a character: that character.
        assert_eq!(line_column(text, 4), (2, 1));
        assert_eq!(line_column(text, 999), (3, 2));
    }

    #[test]
    fn a_bom_and_any_line_end_read_as_plain_lines() {
        let text = text_from_bytes(Path::new("f"), b"\xef\xbb\xbfa\rb\r\nc\n".to_vec()).unwrap();
        assert_eq!(text, "a\nb\nc\n");
        // A bad byte after a BOM and CR line ends is placed as the user sees it.
        let err = text_from_bytes(Path::new("f"), b"\xef\xbb\xbfok\rab\xffc".to_vec()).unwrap_err();
        assert_eq!((err.line, err.column), (Some(2), Some(3)));
    }

    #[test]
    fn special_files_are_named_for_what_they_are() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(
            not_a_file(dir.path()).as_deref(),
            Some("is a folder, expected a file")
        );
        assert_eq!(
            not_a_file(&dir.path().join("none")).as_deref(),
            Some("does not exist")
        );
        assert_eq!(
            not_a_file(Path::new("/dev/null")).as_deref(),
            Some("is a character device, expected a regular file")
        );
        let file = dir.path().join("f");
        std::fs::write(&file, "x").unwrap();
        assert_eq!(not_a_file(&file), None);
    }

    #[test]
    fn invalid_utf8_is_located() {
        let err = text_from_bytes(Path::new("f"), b"ok\nab\xffc".to_vec()).unwrap_err();
        assert_eq!(err.line, Some(2));
        assert_eq!(err.column, Some(3));
        assert!(err.message.contains("0xff"), "{}", err.message);
    }
}
