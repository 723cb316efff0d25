//! The bind cache: a big head's bind kept on disk, so the next start need not bind again.
//!
//! Binding the default deformation to a 431k-vertex head costs seconds of CPU, nearly all of
//! it the muscles' fields and the slide's surface patches. [`bind`] (every front end binds
//! through it) keeps those parts in a binary file named by a key, a 128-bit hash of the
//! rig, the mesh, the skin rules, the file format's version and the source text of the code
//! that computes the parts ([`crate::model::deform::BIND_CODE`]); the next bind of the same
//! rig, mesh and rules reads them back and rebuilds the rest, equal bit for bit to a fresh
//! bind. A file that is missing, damaged, cut short or of another key is never trusted: the
//! rig is bound afresh (with a warning, except when the file is simply not there) and the
//! file written again. A cache that cannot be written is a warning, never an error.
//!
//! Where: `$GRIMACE_CACHE_DIR` (empty: no cache), else `$XDG_CACHE_HOME/grimace`, else
//! `$HOME/.cache/grimace`; one file per key, `KEY.bind`, the oldest removed beyond
//! [`KEEP_FILES`] files or [`KEEP_BYTES`] bytes. Only meshes of [`CACHE_MIN_VERTICES`] or
//! more are cached: smaller ones bind faster than a cache is read. The format is in
//! `docs/formats.md` ("Bind cache").

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::model::deform::BIND_CODE;
use crate::model::{BindError, BoundRig, Deformation, Mesh, Rig, SkinRules};

mod format;
mod hash;

pub use hash::Hasher;

/// The bind cache file format's version, part of every key: a new version misses every
/// file written by the old one.
pub const FORMAT_VERSION: u32 = 1;

/// Meshes with fewer vertices are bound without a cache.
pub const CACHE_MIN_VERTICES: usize = 16_384;

/// At most this many cache files are kept (the newest).
pub const KEEP_FILES: usize = 8;

/// At most this many bytes of cache files are kept (the newest; the file just written is
/// always kept).
pub const KEEP_BYTES: u64 = 1 << 30;

/// A bound rig, with what the cache had to say about it.
#[derive(Debug)]
pub struct CachedBind {
    /// The bound rig.
    pub bound: BoundRig,
    /// Whether it came from the cache.
    pub from_cache: bool,
    /// Why a cache file was not used or not written (the bind itself succeeded).
    pub warnings: Vec<String>,
}

/// Where bind caches are kept, and for which meshes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BindCache {
    /// The folder of the cache files; `None`: no cache.
    pub dir: Option<PathBuf>,
    /// Meshes with fewer vertices are bound without the cache.
    pub min_vertices: usize,
}

impl BindCache {
    /// The user's cache (`$GRIMACE_CACHE_DIR`, `$XDG_CACHE_HOME/grimace` or
    /// `$HOME/.cache/grimace`) for meshes of [`CACHE_MIN_VERTICES`] or more.
    pub fn from_env() -> BindCache {
        let var = |name: &str| std::env::var_os(name).map(PathBuf::from);
        let dir = match var("GRIMACE_CACHE_DIR") {
            // The library's own unit tests leave the user's cache alone (theirs use `at`).
            _ if cfg!(test) => None,
            Some(dir) => (!dir.as_os_str().is_empty()).then_some(dir),
            None => var("XDG_CACHE_HOME")
                .filter(|d| d.is_absolute())
                .or_else(|| var("HOME").map(|h| h.join(".cache")))
                .map(|d| d.join("grimace")),
        };
        BindCache {
            dir,
            min_vertices: CACHE_MIN_VERTICES,
        }
    }

    /// A cache in `dir` for meshes of any size (tests, benchmarks).
    pub fn at(dir: impl Into<PathBuf>) -> BindCache {
        BindCache {
            dir: Some(dir.into()),
            min_vertices: 0,
        }
    }

    /// The file a bind of `rig` on `mesh` with `model` is kept in (`None` without a cache).
    pub fn path(&self, model: Deformation, rig: &Rig, mesh: &Mesh) -> Option<PathBuf> {
        let dir = self.dir.as_ref()?;
        Some(dir.join(format!("{}.bind", hex(&key(model.skin(), rig, mesh)))))
    }

    /// Binds `rig` to `mesh` with `model`, from the cache when it holds this bind, else
    /// afresh (then writing the cache). Fails only as the bind itself fails.
    pub fn bind(
        &self,
        model: Deformation,
        rig: &Rig,
        mesh: &Mesh,
    ) -> Result<CachedBind, BindError> {
        let fresh = |warnings| {
            Ok(CachedBind {
                bound: model.bind(rig, mesh)?,
                from_cache: false,
                warnings,
            })
        };
        let Some(dir) = self
            .dir
            .as_ref()
            .filter(|_| mesh.positions.len() >= self.min_vertices)
        else {
            return fresh(Vec::new());
        };
        let key = key(model.skin(), rig, mesh);
        let path = dir.join(format!("{}.bind", hex(&key)));
        let mut warnings = Vec::new();
        match read(&path, &key, model.skin(), rig, mesh) {
            Ok(Some(bound)) => {
                return Ok(CachedBind {
                    bound,
                    from_cache: true,
                    warnings,
                })
            }
            Ok(None) => {}
            Err(why) => warnings.push(format!(
                "bind cache {}: {why}; bound afresh",
                path.display()
            )),
        }
        let mut done = fresh(warnings)?;
        if let Err(e) = write(dir, &path, &key, &done.bound) {
            done.warnings.push(format!(
                "cannot write the bind cache {}: {e} (the next start binds again)",
                path.display()
            ));
        }
        Ok(done)
    }
}

/// Binds through the user's cache ([`BindCache::from_env`]): what every front end calls.
pub fn bind(model: Deformation, rig: &Rig, mesh: &Mesh) -> Result<CachedBind, BindError> {
    BindCache::from_env().bind(model, rig, mesh)
}

/// The key of a bind: the format version, the code that binds, the skin rules, the rig and
/// the mesh.
pub fn key(skin: SkinRules, rig: &Rig, mesh: &Mesh) -> [u8; 16] {
    let mut h = Hasher::default();
    h.u32s([FORMAT_VERSION]);
    for code in BIND_CODE {
        h.text(code);
    }
    h.text(&format!("{skin:?}"));
    hash_rig(&mut h, rig);
    h.u32s([mesh.positions.len() as u32]);
    h.u32s(
        mesh.positions
            .iter()
            .flat_map(|p| p.to_array().map(f32::to_bits)),
    );
    h.u32s([mesh.triangles.len() as u32]);
    h.u32s(mesh.triangles.iter().flatten().copied());
    for (name, vertices) in &mesh.groups {
        h.text(name);
        h.u32s([vertices.len() as u32]);
        h.u32s(vertices.iter().copied());
    }
    h.finish()
}

/// Feeds everything of the rig a bind reads (its mesh's file name is not: the mesh itself
/// is hashed). The muscles and the jaw's and masks' parameters go in by their `Debug` text,
/// which names every field (a field added later is hashed without a change here); their
/// per-vertex weights, most of a big rig, go in as numbers.
fn hash_rig(h: &mut Hasher, rig: &Rig) {
    h.text(&format!("{:?} {:?}", rig.combine, rig.muscles));
    if let Some(jaw) = &rig.jaw {
        let mut head = jaw.clone();
        let weights = std::mem::take(&mut head.weights);
        h.text(&format!("{head:?}"));
        h.u32s([weights.len() as u32]);
        h.u32s(weights.iter().flat_map(|&(v, w)| [v, w.to_bits()]));
    }
    for mask in &rig.masks {
        h.text(&format!("{:?} {}", mask.muscles, mask.gain.to_bits()));
        h.u32s([mask.weights.len() as u32]);
        h.u32s(mask.weights.iter().flat_map(|&(v, w)| [v, w.to_bits()]));
    }
}

/// The key as 32 lowercase hex digits.
fn hex(key: &[u8; 16]) -> String {
    key.iter().map(|b| format!("{b:02x}")).collect()
}

/// The bound rig kept at `path`; `Ok(None)` when there is no such file, an error saying
/// why a file there cannot be used.
fn read(
    path: &Path,
    key: &[u8; 16],
    skin: SkinRules,
    rig: &Rig,
    mesh: &Mesh,
) -> Result<Option<BoundRig>, String> {
    let file = match File::open(path) {
        Ok(file) => file,
        // No file, or no cache folder yet (a file in its place is said when writing).
        Err(e)
            if matches!(
                e.kind(),
                io::ErrorKind::NotFound | io::ErrorKind::NotADirectory
            ) =>
        {
            return Ok(None)
        }
        Err(e) => return Err(e.to_string()),
    };
    let (fields, patches) = format::read(file, key).map_err(|e| e.to_string())?;
    BoundRig::from_cache(rig, mesh, skin, fields, patches).map(Some)
}

/// Writes the cache file of `bound` under `key`: a temporary file in the same folder
/// renamed over `path`, so a reader sees the old file or the whole new one. Not fsynced: a
/// file cut short by a power cut fails its checksum and is bound again.
fn write(dir: &Path, path: &Path, key: &[u8; 16], bound: &BoundRig) -> io::Result<()> {
    fs::create_dir_all(dir)?;
    let temp = dir.join(format!(".{}.{}.tmp", hex(key), std::process::id()));
    let written = (|| {
        let mut out = BufWriter::new(File::create(&temp)?);
        format::write(&mut out, key, &bound.cache_parts())?;
        let mut file = out.into_inner().map_err(|e| e.into_error())?;
        file.flush()?;
        drop(file);
        fs::rename(&temp, path)
    })();
    if written.is_err() {
        let _ = fs::remove_file(&temp);
    }
    written?;
    prune(dir, path);
    Ok(())
}

/// Removes the oldest cache files beyond [`KEEP_FILES`] files or [`KEEP_BYTES`] bytes,
/// never `keep`. Best effort: a file that cannot be removed stays.
fn prune(dir: &Path, keep: &Path) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let mut files: Vec<(std::time::SystemTime, u64, PathBuf)> = entries
        .filter_map(|e| {
            let e = e.ok()?;
            let path = e.path();
            let meta = e.metadata().ok()?;
            let ours = path.extension().is_some_and(|x| x == "bind") && meta.is_file();
            let modified = meta.modified().ok()?;
            ours.then_some((modified, meta.len(), path))
        })
        .collect();
    files.sort_by_key(|f| std::cmp::Reverse(f.0));
    // `keep` is one of the files kept wherever its time puts it (files written within the
    // file system's time resolution tie, in no set order): the others are counted apart.
    let mut total = 0u64;
    let others = files.into_iter().filter(|(_, _, path)| path != keep);
    for (index, (_, len, path)) in others.enumerate() {
        total += len;
        if index + 1 >= KEEP_FILES || total > KEEP_BYTES {
            let _ = fs::remove_file(&path);
        }
    }
}

#[cfg(test)]
mod tests;
