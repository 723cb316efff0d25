//! End to end: the real binary in a pseudo-terminal (portable-pty), the screen read back
//! through a VT parser (vt100). No system tools are needed.

use std::io::{Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use portable_pty::{native_pty_system, Child, CommandBuilder, MasterPty, PtySize};

const TIMEOUT: Duration = Duration::from_secs(10);

pub(super) struct Editor {
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
    pub(super) fn start(state_dir: &Path, args: &[&str], cols: u16, rows: u16) -> Editor {
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

    /// Closes every copy of the master end, as when a terminal emulator is killed: the
    /// terminal is gone, and only the session leader gets a SIGHUP from the kernel.
    fn close_terminal(mut self) {
        self.stop_reading.store(true, Ordering::SeqCst);
        if let Some(reader) = self.reader.take() {
            reader.join().unwrap();
        }
        // portable-pty's writer types end-of-file on drop; a vanishing emulator types
        // nothing, so clear the end-of-file character first.
        let fd = self.master.as_raw_fd().unwrap();
        // SAFETY: plain termios calls on an open descriptor with a zeroed struct to fill.
        unsafe {
            let mut t: libc::termios = std::mem::zeroed();
            if libc::tcgetattr(fd, &mut t) == 0 {
                t.c_cc[libc::VEOF] = 0;
                libc::tcsetattr(fd, libc::TCSANOW, &t);
            }
        }
        drop(self.writer);
        drop(self.master);
    }

    pub(super) fn send(&mut self, keys: &str) {
        self.writer.write_all(keys.as_bytes()).unwrap();
        self.writer.flush().unwrap();
    }

    pub(super) fn screen(&self) -> String {
        self.parser.lock().unwrap().screen().contents()
    }

    /// Waits until the screen contains `needle`; fails with the screen after the timeout.
    pub(super) fn wait_for(&self, needle: &str) -> String {
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

    pub(super) fn wait_exit(&mut self) -> portable_pty::ExitStatus {
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
    pub(super) fn wait_restored(&self) {
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

    pub(super) fn hang_up(&mut self) {
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

/// The value shown on the selected muscle row (the row drawn with the marker).
fn values_on_screen(screen: &str) -> Vec<String> {
    screen
        .split_whitespace()
        .filter(|w| w.len() == 4 && w.as_bytes()[1] == b'.' && w.parse::<f32>().is_ok())
        .map(str::to_string)
        .collect()
}

#[test]
fn change_a_muscle_record_an_au_save_and_quit() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("smile.au.ron");
    let mut ed = Editor::start(dir.path(), &["edit", file.to_str().unwrap()], 120, 40);
    ed.wait_for("new table");
    ed.send("L"); // a coarse step on the first muscle
    let screen = ed.wait_for("0.25");
    assert!(values_on_screen(&screen).contains(&"0.25".to_string()));
    ed.send(":record 12\r");
    ed.wait_for("recorded AU 12");
    ed.send(":w\r");
    ed.wait_for("saved");
    ed.send(":q\r");
    let status = ed.wait_exit();
    assert!(status.success(), "{status:?}");
    ed.wait_restored();

    let table = grimace::io::load_table(&file).expect("the saved table loads");
    let entry = &table.aus[&"12".parse().unwrap()];
    assert_eq!(entry.muscles.len(), 1, "{entry:?}");
    assert_eq!(entry.muscles.values().next(), Some(&0.25));
    let recovery = dir.path().join(".smile.au.ron.recover");
    assert!(
        !recovery.exists(),
        "the recovery file is removed after a save"
    );
    assert!(
        !dir.path().join(".smile.au.ron.lock").exists(),
        "the lock is released"
    );
}

#[test]
fn a_hangup_loses_nothing_and_the_next_launch_offers_to_recover() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("work.au.ron");
    let arg = file.to_str().unwrap();
    let mut ed = Editor::start(dir.path(), &["edit", arg], 120, 40);
    ed.wait_for("new table");
    ed.send("LL:record 6\r");
    ed.wait_for("recorded AU 6");
    ed.hang_up();
    ed.wait_exit();
    ed.wait_restored();
    assert!(
        !file.exists(),
        "the table file is untouched until the user saves"
    );
    assert!(dir.path().join(".work.au.ron.recover").exists());

    let mut ed = Editor::start(dir.path(), &["edit", arg], 120, 40);
    ed.wait_for("recover");
    ed.send("y");
    let screen = ed.wait_for("recovered");
    assert!(
        values_on_screen(&screen).contains(&"0.50".to_string()),
        "{screen}"
    );
    assert!(
        screen.contains("[+]"),
        "recovered changes are unsaved: {screen}"
    );
    ed.send(":wq\r");
    assert!(ed.wait_exit().success());
    let table = grimace::io::load_table(&file).unwrap();
    let entry = &table.aus[&"6".parse().unwrap()];
    assert_eq!(entry.muscles.values().next(), Some(&0.5));
    assert!(!dir.path().join(".work.au.ron.recover").exists());
}

/// The editor started by a shell that outlives it (`sh -c "grimace ...; ..."`): when the
/// terminal goes away, the kernel's SIGHUP reaches only the shell.
#[test]
fn a_terminal_that_vanishes_without_a_signal_loses_nothing_and_the_editor_exits() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("gone.au.ron");
    let script = format!(
        "'{}' edit '{}'; sleep 30",
        env!("CARGO_BIN_EXE_grimace"),
        file.display()
    );
    let ed = Editor::start_command("sh", &["-c", &script], dir.path(), 100, 30);
    ed.wait_for("new table");
    let lock = dir.path().join(".gone.au.ron.lock");
    let pid: i32 = std::fs::read_to_string(&lock)
        .expect("the editor holds a lock")
        .trim()
        .parse()
        .expect("the lock names the editor's process");
    let mut ed = ed;
    ed.send("LL");
    ed.wait_for("0.50");
    ed.close_terminal();

    // The editor releases its lock as it exits.
    let start = Instant::now();
    while lock.exists() {
        if start.elapsed() > TIMEOUT {
            // SAFETY: signalling the editor process this test started.
            unsafe { libc::kill(pid, libc::SIGKILL) };
            panic!("the editor did not exit within {TIMEOUT:?} after its terminal vanished");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let recovery = dir.path().join(".gone.au.ron.recover");
    let state = grimace::io::recovery::read(&recovery)
        .expect("the recovery file reads")
        .expect("the unsaved state is kept");
    let changed: Vec<f32> = state
        .muscles
        .values()
        .copied()
        .filter(|&v| v != 0.0)
        .collect();
    assert_eq!(changed, [0.5], "{:?}", state.muscles);
    assert!(!file.exists(), "the table file is untouched");
}

#[test]
fn quitting_with_unsaved_changes_asks_first() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("q.au.ron");
    let mut ed = Editor::start(dir.path(), &["edit", file.to_str().unwrap()], 80, 24);
    ed.wait_for("new table");
    ed.send(":record 1\r");
    ed.wait_for("recorded AU 1");
    ed.send("q");
    ed.wait_for("Quit and discard");
    ed.send("n");
    ed.wait_for("cancelled");
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
    assert!(!file.exists());
}

#[test]
fn an_idle_editor_sends_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let started = Instant::now();
    let mut ed = Editor::start(dir.path(), &[], 100, 30);
    ed.wait_for("Muscles");
    println!(
        "start to first frame (process start included): {:?}",
        started.elapsed()
    );
    if let Some(pid) = ed.child.process_id() {
        if let Ok(status) = std::fs::read_to_string(format!("/proc/{pid}/status")) {
            let rss = status
                .lines()
                .find(|l| l.starts_with("VmRSS"))
                .unwrap_or("VmRSS: ?");
            println!("resident memory on the default face: {rss}");
        }
    }
    std::thread::sleep(Duration::from_millis(400));
    let before = *ed.bytes.lock().unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let after = *ed.bytes.lock().unwrap();
    assert_eq!(
        before,
        after,
        "an idle editor wrote {} bytes",
        after - before
    );
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
}

#[test]
fn a_table_that_fails_to_load_stops_with_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bad.au.ron");
    std::fs::write(
        &file,
        "(\n  version: 1,\n  rig: \"builtin:default\",\n  aus: {\"12\": oops},\n)\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["edit", file.to_str().unwrap()])
        .env("XDG_STATE_HOME", dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!("{}:4:", file.display())),
        "stderr: {stderr}"
    );
}

#[test]
fn a_second_editor_on_the_same_table_is_warned() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("shared.au.ron");
    let arg = file.to_str().unwrap();
    let mut first = Editor::start(dir.path(), &["edit", arg], 100, 30);
    first.wait_for("new table");
    let mut second = Editor::start(dir.path(), &["edit", arg], 100, 30);
    second.wait_for("already open in another grimace");
    second.send(":q!\r");
    assert!(second.wait_exit().success());
    assert!(
        dir.path().join(".shared.au.ron.lock").exists(),
        "the first editor's lock stays"
    );
    first.send(":q!\r");
    assert!(first.wait_exit().success());
    assert!(!dir.path().join(".shared.au.ron.lock").exists());
}

#[test]
fn a_file_changed_on_disk_is_not_overwritten_without_asking() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("c.au.ron");
    let arg = file.to_str().unwrap();
    let mut ed = Editor::start(dir.path(), &["edit", arg], 100, 30);
    ed.wait_for("new table");
    ed.send(":record 1\r:w\r");
    ed.wait_for("saved");
    // Someone else saves the table meanwhile.
    let theirs = std::fs::read_to_string(&file)
        .unwrap()
        .replace("Inner Brow Raiser", "Theirs");
    std::fs::write(&file, &theirs).unwrap();
    ed.send(":record 2\r:w\r");
    ed.wait_for("changed on disk");
    ed.send("n");
    ed.wait_for("cancelled");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), theirs);
    ed.send(":w\r");
    ed.wait_for("changed on disk");
    ed.send("y");
    ed.wait_for("saved");
    let table = grimace::io::load_table(&file).unwrap();
    assert_eq!(table.aus.len(), 2);
    assert!(
        dir.path().join("c.au.ron~").exists(),
        "the previous version is kept"
    );
    ed.send("q");
    assert!(ed.wait_exit().success());
}
