//! The editor against other editors and the system, in a pseudo-terminal: a second editor
//! on the same table, a recovery made after the table changed on disk, and a file-size limit.
//!
//! The pseudo-terminal helper is the one of `tui_e2e.rs`, cut to what these tests use.
#![allow(dead_code)]

use std::io::{Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use portable_pty::{native_pty_system, Child, CommandBuilder, MasterPty, PtySize};

const TIMEOUT: Duration = Duration::from_secs(10);

struct Editor {
    child: Box<dyn Child + Send + Sync>,
    writer: Box<dyn Write + Send>,
    parser: Arc<Mutex<vt100::Parser>>,
    bytes: Arc<Mutex<usize>>,
    master: Box<dyn MasterPty + Send>,
    /// Stops the reader thread, which holds a copy of the master end.
    stop_reading: Arc<AtomicBool>,
    reader: Option<JoinHandle<()>>,
}

impl Editor {
    fn start(state_dir: &Path, args: &[&str], cols: u16, rows: u16) -> Editor {
        Editor::start_command(env!("CARGO_BIN_EXE_grimace"), args, state_dir, cols, rows)
    }

    fn start_command(
        program: &str,
        args: &[&str],
        state_dir: &Path,
        cols: u16,
        rows: u16,
    ) -> Editor {
        let pair = native_pty_system()
            .openpty(PtySize {
                rows,
                cols,
                pixel_width: 0,
                pixel_height: 0,
            })
            .expect("a pseudo-terminal");
        let mut cmd = CommandBuilder::new(program);
        cmd.args(args);
        cmd.env("XDG_STATE_HOME", state_dir);
        cmd.env("TERM", "xterm-256color");
        cmd.env_remove("NO_COLOR");
        let child = pair.slave.spawn_command(cmd).expect("grimace starts");
        drop(pair.slave);
        let mut reader = pair.master.try_clone_reader().unwrap();
        let writer = pair.master.take_writer().unwrap();
        let master_fd = pair.master.as_raw_fd().expect("a unix pseudo-terminal");
        let parser = Arc::new(Mutex::new(vt100::Parser::new(rows, cols, 0)));
        let bytes = Arc::new(Mutex::new(0usize));
        let stop_reading = Arc::new(AtomicBool::new(false));
        let (p, b, stop) = (
            Arc::clone(&parser),
            Arc::clone(&bytes),
            Arc::clone(&stop_reading),
        );
        let reader = std::thread::spawn(move || {
            let mut buf = [0u8; 8192];
            // Wait with a timeout so the thread can be told to let go of the master end.
            while !stop.load(Ordering::SeqCst) {
                if !readable(master_fd, 50) {
                    continue;
                }
                match reader.read(&mut buf) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => {
                        p.lock().unwrap().process(&buf[..n]);
                        *b.lock().unwrap() += n;
                    }
                }
            }
        });
        Editor {
            child,
            writer,
            parser,
            bytes,
            master: pair.master,
            stop_reading,
            reader: Some(reader),
        }
    }

    fn send(&mut self, keys: &str) {
        self.writer.write_all(keys.as_bytes()).unwrap();
        self.writer.flush().unwrap();
    }

    fn screen(&self) -> String {
        self.parser.lock().unwrap().screen().contents()
    }

    /// Waits until the screen contains `needle`; fails with the screen after the timeout.
    fn wait_for(&self, needle: &str) -> String {
        let start = Instant::now();
        loop {
            let screen = self.screen();
            if screen.contains(needle) {
                return screen;
            }
            if start.elapsed() > TIMEOUT {
                panic!("`{needle}` did not appear within {TIMEOUT:?}; the screen:\n{screen}");
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn wait_exit(&mut self) -> portable_pty::ExitStatus {
        let start = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status;
            }
            if start.elapsed() > TIMEOUT {
                let _ = self.child.kill();
                panic!("grimace did not exit; the screen:\n{}", self.screen());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Waits until the editor has left the alternate screen (the terminal is restored).
    fn wait_restored(&self) {
        let start = Instant::now();
        while self.parser.lock().unwrap().screen().alternate_screen() {
            if start.elapsed() > TIMEOUT {
                panic!(
                    "the terminal was not restored; the screen:\n{}",
                    self.screen()
                );
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn hang_up(&mut self) {
        // portable-pty's killer sends SIGHUP on unix, like a dropped SSH connection.
        self.child.clone_killer().kill().unwrap();
    }
}

/// Whether `fd` has something to read within `timeout_ms`.
fn readable(fd: i32, timeout_ms: i32) -> bool {
    let mut pfd = libc::pollfd {
        fd,
        events: libc::POLLIN,
        revents: 0,
    };
    // SAFETY: one valid pollfd, count 1.
    unsafe { libc::poll(&mut pfd, 1, timeout_ms) > 0 }
}

/// Waits until `path` exists (the recovery file is written a second after an edit).
fn wait_for_file(path: &Path) {
    let start = Instant::now();
    while !path.exists() {
        assert!(
            start.elapsed() < TIMEOUT,
            "{} did not appear within {TIMEOUT:?}",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Kills an editor without giving it a chance to clean up, like a crash or `kill -9`.
fn kill_hard(ed: &mut Editor) {
    let pid = ed.child.process_id().expect("a process id") as i32;
    // SAFETY: signalling the editor process this test started.
    unsafe { libc::kill(pid, libc::SIGKILL) };
    ed.wait_exit();
}

/// A second editor on a table says it is open elsewhere and leaves the first editor's
/// recovery file alone, so a crash of the first editor still loses nothing.
#[test]
fn a_second_editor_never_touches_the_first_ones_recovery_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("shared.au.ron");
    let arg = file.to_str().unwrap();
    let recovery = dir.path().join(".shared.au.ron.recover");
    let mut first = Editor::start(dir.path(), &["edit", arg], 200, 30);
    first.wait_for("new table");
    first.send("LL");
    first.wait_for("0.50");
    wait_for_file(&recovery);
    let kept = std::fs::read(&recovery).unwrap();

    let mut second = Editor::start(dir.path(), &["edit", arg], 200, 30);
    let screen = second.wait_for("already open in another grimace");
    assert!(!screen.contains("Recover"), "{screen}");
    // `n` would have discarded the first editor's state; here it is no answer to anything.
    second.send("n");
    second.send("L");
    second.wait_for("0.25");
    std::thread::sleep(Duration::from_millis(1500));
    second.send(":q!\r");
    assert!(second.wait_exit().success());
    assert_eq!(
        std::fs::read(&recovery).unwrap(),
        kept,
        "the recovery file changed"
    );

    kill_hard(&mut first);
    let mut third = Editor::start(dir.path(), &["edit", arg], 200, 30);
    third.wait_for("Recover");
    third.send("y");
    let screen = third.wait_for("recovered");
    assert!(screen.contains("0.50"), "{screen}");
    third.send(":q!\r");
    assert!(third.wait_exit().success());
}

/// The built-in table has no lock; its recovery file names its owner, and an editor whose
/// owner still runs leaves it alone.
#[test]
fn a_recovery_file_whose_owner_runs_is_left_alone() {
    let dir = tempfile::tempdir().unwrap();
    let recovery = dir.path().join("grimace/builtin.recover");
    let mut first = Editor::start(dir.path(), &[], 200, 30);
    first.wait_for("Zygomatic");
    first.send("LLL");
    first.wait_for("0.75");
    wait_for_file(&recovery);
    let kept = std::fs::read(&recovery).unwrap();
    let mut second = Editor::start(dir.path(), &[], 200, 30);
    let screen = second.wait_for("that is still running");
    assert!(!screen.contains("Recover"), "{screen}");
    second.send(":q!\r");
    assert!(second.wait_exit().success());
    assert_eq!(std::fs::read(&recovery).unwrap(), kept);
    first.send(":q!\r");
    assert!(first.wait_exit().success());
}

/// Under `ulimit -f 0` every write fails with "file too large": the editor reports it like a
/// full disk and keeps running, instead of dying of SIGXFSZ with the terminal left in the
/// alternate screen, a temporary file and a stale lock.
#[test]
fn a_file_size_limit_is_a_write_error_not_a_crash() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("small.au.ron");
    let table = "(version: 1, rig: \"builtin:default\", aus: {}, expressions: {})\n";
    std::fs::write(&file, table).unwrap();
    let script = format!(
        "ulimit -f 0 && exec '{}' edit '{}'",
        env!("CARGO_BIN_EXE_grimace"),
        file.display()
    );
    let mut ed = Editor::start_command("sh", &["-c", &script], dir.path(), 200, 30);
    ed.wait_for("no lock file");
    ed.send("L:record 12\r");
    ed.wait_for("recorded AU 12");
    ed.wait_for("could not write the recovery file");
    ed.wait_for("file too large");
    ed.send(":w\r");
    ed.wait_for("could not save");
    ed.wait_for(": file too large; your edits are kept");
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
    ed.wait_restored();
    assert_eq!(std::fs::read_to_string(&file).unwrap(), table);
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["small.au.ron"], "files left behind");
}

/// Edits recovered after the table changed on disk are saved only after asking, like any
/// save over a file changed since it was loaded; unchanged, the table saves without a question.
#[test]
fn recovered_edits_ask_before_replacing_a_table_changed_on_disk() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("t.au.ron");
    let arg = file.to_str().unwrap();
    let recovery = dir.path().join(".t.au.ron.recover");
    let table = "(version: 1, rig: \"builtin:default\", aus: {}, expressions: {})\n";
    for changed in [true, false] {
        std::fs::write(&file, table).unwrap();
        let mut first = Editor::start(dir.path(), &["edit", arg], 200, 30);
        first.wait_for("Zygomatic");
        first.send("L:record 12\r");
        first.wait_for("recorded AU 12");
        wait_for_file(&recovery);
        kill_hard(&mut first);
        let theirs = table.replace(
            "aus: {}",
            "aus: {\"1\": (name: \"Theirs\", muscles: {}, jaw: 0.0)}",
        );
        if changed {
            std::fs::write(&file, &theirs).unwrap();
        }
        let mut second = Editor::start(dir.path(), &["edit", arg], 200, 30);
        second.wait_for("Recover");
        second.send("y");
        second.wait_for("recovered");
        second.send(":w\r");
        if changed {
            second.wait_for("changed on disk");
            second.send("n");
            second.wait_for("cancelled");
            assert_eq!(std::fs::read_to_string(&file).unwrap(), theirs);
            second.send(":q!\r");
        } else {
            second.wait_for(&format!("saved {arg}"));
            let saved = grimace::io::load_table(&file).unwrap();
            assert_eq!(saved.aus.len(), 1);
            second.send(":q\r");
        }
        assert!(second.wait_exit().success());
        let _ = std::fs::remove_file(&recovery);
    }
}

/// A table opened through a symbolic link is locked and saved as the file it points to: a
/// second editor on the file itself sees the lock, and the link stays a link.
#[test]
fn a_table_opened_through_a_link_is_locked_and_saved_as_its_target() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("real")).unwrap();
    let target = dir.path().join("real/t.au.ron");
    let table = "(version: 1, rig: \"builtin:default\", aus: {}, expressions: {})\n";
    std::fs::write(&target, table).unwrap();
    let link = dir.path().join("link.au.ron");
    std::os::unix::fs::symlink("real/t.au.ron", &link).unwrap();
    let mut ed = Editor::start(dir.path(), &["edit", link.to_str().unwrap()], 200, 30);
    ed.wait_for("Zygomatic");
    assert!(dir.path().join("real/.t.au.ron.lock").exists());
    let mut other = Editor::start(dir.path(), &["edit", target.to_str().unwrap()], 200, 30);
    other.wait_for("already open in another grimace");
    other.send(":q!\r");
    assert!(other.wait_exit().success());
    ed.send("L:record 12\r:w\r");
    ed.wait_for(&format!("saved {}", link.display()));
    ed.send(":q\r");
    assert!(ed.wait_exit().success());
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(grimace::io::load_table(&target).unwrap().aus.len(), 1);
    assert_eq!(
        std::fs::read_to_string(dir.path().join("real/t.au.ron~")).unwrap(),
        table
    );
    let mut names: Vec<String> = std::fs::read_dir(dir.path().join("real"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["t.au.ron", "t.au.ron~"]);
}
