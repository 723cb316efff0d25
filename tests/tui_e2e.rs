//! End to end: the real binary in a pseudo-terminal (portable-pty), the screen read back
//! through a VT parser (vt100). No system tools are needed.

use std::io::{Read, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use portable_pty::{native_pty_system, Child, CommandBuilder, MasterPty, PtySize};

const TIMEOUT: Duration = Duration::from_secs(10);

struct Editor {
    child: Box<dyn Child + Send + Sync>,
    writer: Box<dyn Write + Send>,
    parser: Arc<Mutex<vt100::Parser>>,
    bytes: Arc<Mutex<usize>>,
    _master: Box<dyn MasterPty + Send>,
}

impl Editor {
    fn start(state_dir: &Path, args: &[&str], cols: u16, rows: u16) -> Editor {
        let pair = native_pty_system()
            .openpty(PtySize {
                rows,
                cols,
                pixel_width: 0,
                pixel_height: 0,
            })
            .expect("a pseudo-terminal");
        let mut cmd = CommandBuilder::new(env!("CARGO_BIN_EXE_grimace"));
        cmd.args(args);
        cmd.env("XDG_STATE_HOME", state_dir);
        cmd.env("TERM", "xterm-256color");
        cmd.env_remove("NO_COLOR");
        let child = pair.slave.spawn_command(cmd).expect("grimace starts");
        drop(pair.slave);
        let mut reader = pair.master.try_clone_reader().unwrap();
        let writer = pair.master.take_writer().unwrap();
        let parser = Arc::new(Mutex::new(vt100::Parser::new(rows, cols, 0)));
        let bytes = Arc::new(Mutex::new(0usize));
        let (p, b) = (Arc::clone(&parser), Arc::clone(&bytes));
        std::thread::spawn(move || {
            let mut buf = [0u8; 8192];
            while let Ok(n) = reader.read(&mut buf) {
                if n == 0 {
                    break;
                }
                p.lock().unwrap().process(&buf[..n]);
                *b.lock().unwrap() += n;
            }
        });
        Editor {
            child,
            writer,
            parser,
            bytes,
            _master: pair.master,
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
