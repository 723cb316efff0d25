//! Lines of a stream read in bounded memory, whatever their line ends.
//!
//! OpenFace CSV files and live streams on stdin are read one line at a time. A line ends at
//! LF, CRLF or a lone CR (old Mac files), a UTF-8 byte order mark at the start of the input is
//! dropped, and a line longer than the limit is read to its end but only its first bytes are
//! kept: its full length is reported, so the caller can say why it skips it.

use std::io::{self, BufRead, Chain, Cursor, Read};

use super::error::BOM;

/// One line, without its line end.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Line {
    /// 1-based line number.
    pub number: usize,
    /// The text, at most the reader's limit in bytes; bytes that are not UTF-8 are replaced.
    pub text: String,
    /// The full length of the line in bytes; more than the limit when it was cut.
    pub length: usize,
}

impl Line {
    /// The message for a line over `limit` bytes, `None` for one within it.
    pub fn too_long(&self, limit: usize) -> Option<String> {
        (self.length > limit).then(|| {
            format!(
                "the line is {} bytes long, more than the limit of {} (skipped unread)",
                self.length,
                describe_bytes(limit)
            )
        })
    }
}

/// `1 MiB`, `64 KiB` or `N bytes`.
pub fn describe_bytes(bytes: usize) -> String {
    if bytes >= 1 << 20 && bytes % (1 << 20) == 0 {
        format!("{} MiB", bytes >> 20)
    } else if bytes >= 1 << 10 && bytes % (1 << 10) == 0 {
        format!("{} KiB", bytes >> 10)
    } else {
        format!("{bytes} bytes")
    }
}

/// The most bytes [`sniff_first_line`] reads to tell a format by its first line.
pub const SNIFF_BYTES: u64 = 64 * 1024;

/// An input read again from its start: the bytes already read, then the rest.
pub type Replayed<R> = Chain<Cursor<Vec<u8>>, R>;

/// The input's first line (at most [`SNIFF_BYTES`], lossily decoded) and a reader that yields
/// every byte of the input from the start: the bytes read for the sniff, then the rest. A pipe,
/// a FIFO or `<(...)` is read once, so telling its format loses nothing.
pub fn sniff_first_line<R: BufRead>(mut input: R) -> io::Result<(String, Replayed<R>)> {
    let mut head = Vec::new();
    (&mut input)
        .take(SNIFF_BYTES)
        .read_until(b'\n', &mut head)?;
    let first = String::from_utf8_lossy(&head).into_owned();
    Ok((first, Cursor::new(head).chain(input)))
}

/// Reads lines from any buffered input; see the module documentation.
#[derive(Debug)]
pub struct LineReader<R> {
    input: R,
    limit: usize,
    buffer: Vec<u8>,
    number: usize,
    /// The last line ended with CR: an LF right after it belongs to that line end.
    after_cr: bool,
}

impl<R: BufRead> LineReader<R> {
    /// A reader keeping at most `limit` bytes of each line.
    pub fn new(input: R, limit: usize) -> LineReader<R> {
        LineReader {
            input,
            limit,
            buffer: Vec::new(),
            number: 0,
            after_cr: false,
        }
    }

    /// The number of the last line read (0 before the first).
    pub fn number(&self) -> usize {
        self.number
    }

    /// The next line, `Ok(None)` at the end of the input. It never waits for more input
    /// than the line needs, so a live stream's line is handed over as soon as it ends.
    pub fn next_line(&mut self) -> io::Result<Option<Line>> {
        self.buffer.clear();
        let mut length = 0usize;
        let mut ended = false;
        let mut any = false;
        while !ended {
            let available = match self.input.fill_buf() {
                Ok(bytes) => bytes,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if available.is_empty() {
                break;
            }
            let mut start = 0;
            if self.after_cr {
                self.after_cr = false;
                if available[0] == b'\n' {
                    start = 1;
                }
            }
            let rest = &available[start..];
            let (content, used) = match rest.iter().position(|&b| b == b'\n' || b == b'\r') {
                Some(end) => {
                    ended = true;
                    self.after_cr = rest[end] == b'\r';
                    (&rest[..end], start + end + 1)
                }
                None => (rest, start + rest.len()),
            };
            any |= used > start;
            // A byte order mark opening the input does not count against the limit.
            let bom = if self.number == 0 { BOM.len() } else { 0 };
            let room = (self.limit + bom).saturating_sub(self.buffer.len());
            self.buffer
                .extend_from_slice(&content[..content.len().min(room)]);
            length += content.len();
            self.input.consume(used);
        }
        if !any {
            return Ok(None);
        }
        self.number += 1;
        let mut bytes = &self.buffer[..];
        if self.number == 1 && bytes.starts_with(BOM) {
            bytes = &bytes[BOM.len()..];
            length -= BOM.len();
        }
        let bytes = &bytes[..bytes.len().min(self.limit)];
        Ok(Some(Line {
            number: self.number,
            text: String::from_utf8_lossy(bytes).into_owned(),
            length,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sniffed_input_is_read_whole_from_its_start() {
        let (first, mut input) = sniff_first_line(&b"Timecode,x\r\n1,2\n"[..]).unwrap();
        assert_eq!(first, "Timecode,x\r\n");
        let mut all = String::new();
        input.read_to_string(&mut all).unwrap();
        assert_eq!(all, "Timecode,x\r\n1,2\n");
        let (first, _) = sniff_first_line(&vec![b'a'; 100_000][..]).unwrap();
        assert_eq!(
            first.len() as u64,
            SNIFF_BYTES,
            "a sniff reads a bounded prefix"
        );
    }

    fn lines(bytes: &[u8], limit: usize) -> Vec<(usize, String, usize)> {
        // A one-byte buffer: every split of a line end across reads is exercised.
        let mut reader = LineReader::new(io::BufReader::with_capacity(1, bytes), limit);
        let mut out = Vec::new();
        while let Some(line) = reader.next_line().unwrap() {
            out.push((line.number, line.text, line.length));
        }
        out
    }

    #[test]
    fn lf_crlf_and_cr_each_end_one_line() {
        let expected = vec![
            (1, "a".to_string(), 1),
            (2, "".to_string(), 0),
            (3, "bc".to_string(), 2),
            (4, "d".to_string(), 1),
        ];
        assert_eq!(lines(b"a\n\nbc\nd", 9), expected);
        assert_eq!(lines(b"a\r\n\r\nbc\r\nd\r\n", 9), expected);
        assert_eq!(lines(b"a\r\rbc\rd\r", 9), expected);
        assert_eq!(lines(b"", 9), vec![]);
    }

    #[test]
    fn a_bom_is_dropped_and_long_lines_cut_with_their_length() {
        assert_eq!(
            lines(b"\xef\xbb\xbfab\nabcdef\nx", 4),
            vec![
                (1, "ab".to_string(), 2),
                (2, "abcd".to_string(), 6),
                (3, "x".to_string(), 1)
            ]
        );
        let line = Line {
            number: 2,
            text: String::new(),
            length: 3 << 20,
        };
        assert_eq!(
            line.too_long(1 << 20).unwrap(),
            "the line is 3145728 bytes long, more than the limit of 1 MiB (skipped unread)"
        );
    }
}
