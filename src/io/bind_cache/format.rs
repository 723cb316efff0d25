//! The bind cache file's bytes (`docs/formats.md`, "Bind cache"), all little-endian:
//!
//! ```text
//! header   magic "GRIMBIND", format version u32, 0u32, key [u8; 16],
//!          payload length u64, payload checksum u64
//! payload  muscles u32, patches u32, each muscle's field length u32,
//!          then per muscle: its vertices u32 x len, its displacements f32 x 3 x len,
//!          then the patches, f32 x CACHE_PATCH_FLOATS each
//! ```
//!
//! The reader trusts nothing: every count is checked against the bytes left before
//! anything is allocated, and the checksum of the payload against the header before the
//! parts are given out.

use std::fs::File;
use std::io::{self, BufReader, Read, Seek, SeekFrom, Write};

use glam::Vec3;

use super::{Hasher, FORMAT_VERSION};
use crate::model::deform::{CacheParts, CACHE_PATCH_FLOATS};
use crate::model::Field;

/// The file's first bytes.
const MAGIC: &[u8; 8] = b"GRIMBIND";
/// Bytes before the payload.
const HEADER: u64 = 8 + 4 + 4 + 16 + 8 + 8;
/// Where the checksum sits in the header.
const CHECKSUM_AT: u64 = HEADER - 8;

/// Kept fields and patches, as [`read`] gives them.
pub type Parts = (Vec<Field>, Vec<[f32; CACHE_PATCH_FLOATS]>);

/// A damaged or foreign file as an error of kind `InvalidData`.
fn bad(message: impl Into<String>) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message.into())
}

/// Writes the header and the payload of `parts` under `key`.
pub fn write<W: Write + Seek>(out: &mut W, key: &[u8; 16], parts: &CacheParts) -> io::Result<()> {
    out.write_all(MAGIC)?;
    out.write_all(&FORMAT_VERSION.to_le_bytes())?;
    out.write_all(&0u32.to_le_bytes())?;
    out.write_all(key)?;
    // length and checksum filled in once the payload is written
    out.write_all(&[0u8; 16])?;
    let mut payload = Payload {
        out,
        hash: Hasher::default(),
        len: 0,
    };
    payload.u32s([parts.fields.len() as u32, parts.patches.len() as u32])?;
    payload.u32s(parts.fields.iter().map(|f| f.vertices.len() as u32))?;
    for field in parts.fields {
        payload.u32s(field.vertices.iter().copied())?;
        let d = field.displacements.iter();
        payload.u32s(d.flat_map(|d| d.to_array().map(f32::to_bits)))?;
    }
    payload.u32s(parts.patches.iter().flatten().map(|x| x.to_bits()))?;
    let (len, sum) = (payload.len, checksum(payload.hash));
    out.seek(SeekFrom::Start(CHECKSUM_AT - 8))?;
    out.write_all(&len.to_le_bytes())?;
    out.write_all(&sum.to_le_bytes())?;
    out.seek(SeekFrom::End(0))?;
    Ok(())
}

/// The payload being written, hashed as it goes.
struct Payload<'a, W> {
    out: &'a mut W,
    hash: Hasher,
    len: u64,
}

impl<W: Write> Payload<'_, W> {
    fn u32s(&mut self, words: impl IntoIterator<Item = u32>) -> io::Result<()> {
        let mut buf = Vec::with_capacity(1 << 16);
        for w in words {
            buf.extend_from_slice(&w.to_le_bytes());
            if buf.len() == buf.capacity() {
                self.flush(&mut buf)?;
            }
        }
        self.flush(&mut buf)
    }

    fn flush(&mut self, buf: &mut Vec<u8>) -> io::Result<()> {
        self.hash.bytes(buf);
        self.len += buf.len() as u64;
        self.out.write_all(buf)?;
        buf.clear();
        Ok(())
    }
}

/// The payload's checksum: the first half of its hash.
fn checksum(hash: Hasher) -> u64 {
    let h = hash.finish();
    u64::from_le_bytes([h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7]])
}

/// Reads the parts kept in `file` under `key`: an error when the file is not a bind cache
/// of this format, has another key, is cut short, too long or fails its checksum.
pub fn read(file: File, key: &[u8; 16]) -> io::Result<Parts> {
    let size = file.metadata()?.len();
    let mut input = BufReader::with_capacity(1 << 16, file);
    let mut header = [0u8; HEADER as usize];
    input
        .read_exact(&mut header)
        .map_err(|_| bad("shorter than its header"))?;
    if &header[..8] != MAGIC {
        return Err(bad("not a bind cache file"));
    }
    let word = |at: usize| u32::from_le_bytes(header[at..at + 4].try_into().expect("4 bytes"));
    let long = |at: usize| u64::from_le_bytes(header[at..at + 8].try_into().expect("8 bytes"));
    if word(8) != FORMAT_VERSION {
        return Err(bad(format!(
            "format version {}, not {FORMAT_VERSION}",
            word(8)
        )));
    }
    if &header[16..32] != key {
        return Err(bad("made for another rig, mesh or deformation"));
    }
    if size.checked_sub(HEADER) != Some(long(32)) {
        return Err(bad(
            "cut short or too long: its length is not what its header says",
        ));
    }
    let mut payload = Source {
        input,
        hash: Hasher::default(),
        left: long(32),
    };
    let [muscles, patches] = <[u32; 2]>::try_from(payload.u32s(2)?).expect("two counts");
    let lengths = payload.u32s(muscles as usize)?;
    let mut fields = Vec::with_capacity(lengths.len());
    for &len in &lengths {
        let vertices = payload.u32s(len as usize)?;
        let d = payload.u32s(3 * len as usize)?;
        let displacements = d
            .chunks_exact(3)
            .map(|c| {
                Vec3::new(
                    f32::from_bits(c[0]),
                    f32::from_bits(c[1]),
                    f32::from_bits(c[2]),
                )
            })
            .collect();
        fields.push(Field {
            vertices,
            displacements,
        });
    }
    let numbers = payload.u32s(CACHE_PATCH_FLOATS * patches as usize)?;
    let patches = numbers
        .chunks_exact(CACHE_PATCH_FLOATS)
        .map(|c| std::array::from_fn(|i| f32::from_bits(c[i])))
        .collect();
    if payload.left != 0 {
        return Err(bad("longer than its parts"));
    }
    if payload.input.read(&mut [0u8; 1])? != 0 {
        return Err(bad("bytes after its payload"));
    }
    if checksum(payload.hash) != long(40) {
        return Err(bad("checksum mismatch (damaged)"));
    }
    Ok((fields, patches))
}

/// The payload being read: bytes left as the header says, hashed as they are read.
struct Source<R> {
    input: BufReader<R>,
    hash: Hasher,
    left: u64,
}

impl<R: Read> Source<R> {
    /// The next `count` words; an error when fewer bytes are left.
    fn u32s(&mut self, count: usize) -> io::Result<Vec<u32>> {
        let bytes = (count as u64).saturating_mul(4);
        if bytes > self.left {
            return Err(bad("cut short, or a count beyond its length"));
        }
        self.left -= bytes;
        let mut out = Vec::with_capacity(count);
        let mut buf = vec![0u8; (bytes as usize).min(1 << 16)];
        let mut todo = bytes as usize;
        while todo > 0 {
            let chunk = &mut buf[..todo.min(1 << 16)];
            self.input.read_exact(chunk).map_err(|_| bad("cut short"))?;
            self.hash.bytes(chunk);
            out.extend(
                chunk
                    .chunks_exact(4)
                    .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            );
            todo -= chunk.len();
        }
        Ok(out)
    }
}
