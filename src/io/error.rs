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
pub fn read_text(path: &Path, limit: u64) -> Result<String, LoadError> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| LoadError::io(path, &e))?;
    let meta = file.metadata().map_err(|e| LoadError::io(path, &e))?;
    if meta.is_dir() {
        return Err(LoadError::new(path, "is a folder, expected a file"));
    }
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
pub fn text_from_bytes(path: &Path, bytes: Vec<u8>) -> Result<String, LoadError> {
    String::from_utf8(bytes).map_err(|e| {
        let valid_up_to = e.utf8_error().valid_up_to();
        let bytes = e.into_bytes();
        // The valid prefix is text; the bad byte sits right after it.
        let prefix = std::str::from_utf8(&bytes[..valid_up_to]).unwrap_or_default();
        let (line, column) = line_column(prefix, prefix.len());
        LoadError::at(
            path,
            line,
            column,
            format!(
                "invalid UTF-8 (byte 0x{:02x}); expected a text file",
                bytes[valid_up_to]
            ),
        )
    })
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
    fn invalid_utf8_is_located() {
        let err = text_from_bytes(Path::new("f"), b"ok\nab\xffc".to_vec()).unwrap_err();
        assert_eq!(err.line, Some(2));
        assert_eq!(err.column, Some(3));
        assert!(err.message.contains("0xff"), "{}", err.message);
    }
}
