//! A failed save leaves the previous file intact: a full disk (a tiny tmpfs) at the write of
//! the new version or of the backup, and a read-only folder. Through
//! `io::atomic::write_atomic` and `io::table_file::save_table`.
//!
//! Mounting needs root; without it the full-disk tests skip with a printed reason (and fail
//! under `CI=true`, where they must run) and the read-only folder is made with permissions
//! instead.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

use grimace::facs::AuTable;
use grimace::io::atomic::{backup_path, write_atomic};
use grimace::io::table_file::{load_table, save_table, table_to_ron};

/// A tmpfs mounted on a temporary folder, unmounted when dropped.
struct Tmpfs {
    dir: tempfile::TempDir,
}

impl Tmpfs {
    /// Mounts a tmpfs of `kib` KiB, or says why it cannot.
    fn mount(kib: usize) -> Result<Tmpfs, String> {
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        let out = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={kib}k"), "tmpfs"])
            .arg(dir.path())
            .output()
            .map_err(|e| format!("cannot run mount: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "mount -t tmpfs failed: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
        Ok(Tmpfs { dir })
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    fn remount_read_only(&self) {
        let out = Command::new("mount")
            .args(["-o", "remount,ro"])
            .arg(self.path())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

macro_rules! mount_or_skip {
    ($kib:expr) => {
        match Tmpfs::mount($kib) {
            Ok(fs) => fs,
            Err(reason) => {
                // CI runs as root: a full-disk test that did not run there is a failure.
                assert!(
                    std::env::var("CI").as_deref() != Ok("true"),
                    "CI=true but the full-disk test cannot run: {reason}"
                );
                eprintln!("skipped: {reason}");
                return;
            }
        }
    };
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The built-in table with `extra` named expressions added: about 30 bytes each.
fn table_with(extra: usize) -> AuTable {
    let mut table = grimace::io::builtin::default_table();
    let key = *table.aus.keys().next().expect("the built-in table has AUs");
    for i in 0..extra {
        table
            .set_expression(&format!("expression_{i:06}"), &key.to_string())
            .unwrap();
    }
    table
}

/// Fills the file system at `dir` with a filler file, then frees `room` bytes of it.
fn fill_leaving(dir: &Path, room: u64) -> PathBuf {
    let filler = dir.join("filler");
    let mut file = fs::File::create(&filler).unwrap();
    let block = [0u8; 4096];
    let mut written = 0u64;
    loop {
        match file.write(&block) {
            Ok(0) | Err(_) => break,
            Ok(n) => written += n as u64,
        }
    }
    let _ = file.sync_all();
    file.set_len(written.saturating_sub(room)).unwrap();
    filler
}

/// The file system at `dir` is full and the new version cannot even be written: the old
/// file stays, no temporary and no backup is left behind.
#[test]
fn a_full_disk_fails_the_save_and_keeps_the_old_table() {
    let fs_ = mount_or_skip!(64);
    let path = fs_.path().join("face.au.ron");
    let old = table_with(0);
    save_table(&path, &old).unwrap();
    let old_bytes = fs::read(&path).unwrap();
    // Far more than 64 KiB of text.
    let new = table_with(4000);
    assert!(table_to_ron(&new).len() > 100_000);
    let err = save_table(&path, &new).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!("{}: cannot save: no space left on device", path.display())
    );
    assert_eq!(fs::read(&path).unwrap(), old_bytes);
    assert_eq!(load_table(&path).unwrap(), old);
    assert_eq!(names_in(fs_.path()), ["face.au.ron"]);
}

/// Room for the new version but not for the backup of the old one: the save fails before
/// the rename, so the file is still the old version, and the half-made backup is gone.
#[test]
fn a_disk_that_fills_while_backing_up_keeps_the_old_table() {
    let fs_ = mount_or_skip!(256);
    let path = fs_.path().join("face.au.ron");
    let old = table_with(1500);
    save_table(&path, &old).unwrap();
    let old_bytes = fs::read(&path).unwrap();
    let new = table_with(1600);
    let new_len = table_to_ron(&new).len() as u64;
    assert!(old_bytes.len() > 40_000, "{}", old_bytes.len());
    // Room for the new file (rounded up to pages) and a little, not for a second copy.
    let room = new_len.div_ceil(4096) * 4096 + 4096;
    assert!(room < new_len + old_bytes.len() as u64);
    fill_leaving(fs_.path(), room);
    let err = save_table(&path, &new).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!("{}: cannot save: no space left on device", path.display())
    );
    assert_eq!(fs::read(&path).unwrap(), old_bytes);
    assert_eq!(names_in(fs_.path()), ["face.au.ron", "filler"]);
}

#[test]
fn write_atomic_on_a_full_disk_keeps_the_old_file_and_its_backup() {
    let fs_ = mount_or_skip!(64);
    let path = fs_.path().join("notes.txt");
    write_atomic(&path, b"first").unwrap();
    write_atomic(&path, b"second").unwrap();
    let err = write_atomic(&path, &vec![b'x'; 200_000]).unwrap_err();
    assert_eq!(err.kind(), std::io::ErrorKind::StorageFull, "{err}");
    assert_eq!(fs::read(&path).unwrap(), b"second");
    assert_eq!(fs::read(backup_path(&path)).unwrap(), b"first");
    assert_eq!(names_in(fs_.path()), ["notes.txt", "notes.txt~"]);
    // Once there is room again, saving works and the backup moves on.
    write_atomic(&path, b"third").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"third");
    assert_eq!(fs::read(backup_path(&path)).unwrap(), b"second");
}

/// A read-only folder: a read-only mount when running as root (root ignores permissions),
/// otherwise a folder without write permission.
#[test]
fn a_read_only_folder_fails_the_save_and_keeps_the_old_table() {
    let old = table_with(0);
    let new = table_with(3);
    let check = |dir: &Path, expected: &str| {
        let path = dir.join("face.au.ron");
        let old_bytes = fs::read(&path).unwrap();
        let err = save_table(&path, &new).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("{}: cannot save: {expected}", path.display())
        );
        assert_eq!(fs::read(&path).unwrap(), old_bytes);
        assert_eq!(names_in(dir), ["face.au.ron"]);
        let err = write_atomic(&path, b"x").unwrap_err();
        // The raw error reads "Read-only file system (os error 30)".
        assert!(
            err.to_string().to_lowercase().starts_with(expected),
            "{err}"
        );
        assert_eq!(fs::read(&path).unwrap(), old_bytes);
    };
    match Tmpfs::mount(64) {
        Ok(fs_) => {
            save_table(&fs_.path().join("face.au.ron"), &old).unwrap();
            fs_.remount_read_only();
            check(fs_.path(), "read-only file system");
        }
        Err(reason) => {
            use std::os::unix::fs::PermissionsExt;
            eprintln!("no read-only mount ({reason}); using folder permissions");
            let dir = tempfile::tempdir().unwrap();
            save_table(&dir.path().join("face.au.ron"), &old).unwrap();
            fs::set_permissions(dir.path(), fs::Permissions::from_mode(0o555)).unwrap();
            check(dir.path(), "permission denied");
            fs::set_permissions(dir.path(), fs::Permissions::from_mode(0o755)).unwrap();
        }
    }
}
