//! The files a command reads, so that it never writes over one of them.
//!
//! A command that writes a file (`fit-rig --out`, `export --out`, `export --gltf`,
//! `render --out`, `fit-au --table` for a new table, ...) first collects its inputs: the
//! files named on its command line and the files those name (a table names a rig, a rig
//! names a mesh). [`Inputs::check_output`] then refuses an output that is one of them,
//! however it is spelt: files are compared by identity (device and inode on Unix; the
//! canonical path elsewhere), so `./head.obj`, `../x/head.obj`, a symbolic link to it or a
//! hard link all count as the same file.
//!
//! Writing over an input would lose it: a rig replaced by a GLB, a rest mesh replaced by a
//! smile that every later command silently starts from.

use std::fs;
use std::path::{Path, PathBuf};

use super::builtin::builtin_name;
use super::{LoadedRig, SaveError};

/// The identity of a file: the same for every name it has.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Identity {
    #[cfg(unix)]
    Inode { device: u64, inode: u64 },
    #[cfg(not(unix))]
    Canonical(PathBuf),
}

impl Identity {
    /// The identity of the file at `path` (links followed), or `None` when nothing is there.
    fn of(path: &Path) -> Option<Identity> {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            let meta = fs::metadata(path).ok()?;
            Some(Identity::Inode {
                device: meta.dev(),
                inode: meta.ino(),
            })
        }
        #[cfg(not(unix))]
        {
            fs::canonicalize(path).ok().map(Identity::Canonical)
        }
    }
}

/// One input: what it is to the command (for the message), its name as given, its identity.
#[derive(Debug, Clone)]
struct Input {
    role: String,
    path: PathBuf,
    identity: Identity,
}

/// The files a command reads.
#[derive(Debug, Clone, Default)]
pub struct Inputs {
    files: Vec<Input>,
}

impl Inputs {
    /// No inputs yet.
    pub fn new() -> Inputs {
        Inputs::default()
    }

    /// Adds the file at `path`, described by `role` ("the mesh the rig names", ...).
    /// Built-in references (`builtin:NAME`) and paths with nothing behind them are not files
    /// and are skipped.
    pub fn add(&mut self, role: impl Into<String>, path: &Path) {
        if builtin_name(path).is_some() {
            return;
        }
        if let Some(identity) = Identity::of(path) {
            self.files.push(Input {
                role: role.into(),
                path: path.to_path_buf(),
                identity,
            });
        }
    }

    /// Adds a loaded rig: its file and the mesh it was loaded with (the one it names, or
    /// the one given instead).
    pub fn add_rig(&mut self, rig: &LoadedRig) {
        self.add("the rig", &rig.path);
        if let Some(mesh) = &rig.mesh_path {
            self.add(format!("the mesh of the rig {}", rig.path.display()), mesh);
        }
    }

    /// Refuses `out` when it is one of the inputs. An output that does not exist yet, or
    /// any other existing file, is allowed (saves keep the replaced file as `NAME~`).
    pub fn check_output(&self, out: &Path) -> Result<(), SaveError> {
        let Some(identity) = Identity::of(out) else {
            return Ok(());
        };
        match self.files.iter().find(|input| input.identity == identity) {
            None => Ok(()),
            Some(input) => Err(SaveError::new(
                out,
                if input.path == out {
                    format!(
                        "it is {}, an input of this command; write the output to another file",
                        input.role
                    )
                } else {
                    format!(
                        "it is {} ({}), an input of this command; write the output to another file",
                        input.role,
                        input.path.display()
                    )
                },
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_input_is_refused_however_it_is_spelt() {
        let dir = tempfile::tempdir().unwrap();
        let mesh = dir.path().join("head.obj");
        fs::write(&mesh, "v 0 0 0\n").unwrap();
        fs::create_dir(dir.path().join("sub")).unwrap();
        let mut inputs = Inputs::new();
        inputs.add("the mesh the rig names", &mesh);
        assert!(inputs.check_output(&mesh).is_err());
        let roundabout = dir.path().join("sub").join("..").join("head.obj");
        let err = inputs.check_output(&roundabout).unwrap_err().to_string();
        assert!(err.contains("the mesh the rig names"), "{err}");
        #[cfg(unix)]
        {
            let link = dir.path().join("sub").join("link.obj");
            std::os::unix::fs::symlink(&mesh, &link).unwrap();
            assert!(inputs.check_output(&link).is_err());
            let hard = dir.path().join("hard.obj");
            fs::hard_link(&mesh, &hard).unwrap();
            assert!(inputs.check_output(&hard).is_err());
        }
    }

    #[test]
    fn other_files_and_new_files_are_allowed() {
        let dir = tempfile::tempdir().unwrap();
        let mesh = dir.path().join("head.obj");
        let other = dir.path().join("smile.obj");
        fs::write(&mesh, "v 0 0 0\n").unwrap();
        fs::write(&other, "v 0 0 0\n").unwrap();
        let mut inputs = Inputs::new();
        inputs.add("the mesh", &mesh);
        inputs.add("a built-in rig", Path::new("builtin:default"));
        inputs.add("a missing file", &dir.path().join("missing.obj"));
        assert!(inputs.check_output(&other).is_ok());
        assert!(inputs.check_output(&dir.path().join("new.obj")).is_ok());
    }
}
