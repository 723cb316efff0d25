//! End to end: the real binary in a pseudo-terminal, the screen read back through a VT
//! parser (`common::pty`). No system tools are needed.

use std::time::{Duration, Instant};

use crate::common::pty::{Launch, Term, TIMEOUT};

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
    let mut ed = Term::grimace(dir.path(), &["edit", file.to_str().unwrap()], 120, 40);
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
    let mut ed = Term::grimace(dir.path(), &["edit", arg], 120, 40);
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

    let mut ed = Term::grimace(dir.path(), &["edit", arg], 120, 40);
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
    let ed = Launch::program("sh", dir.path())
        .args(&["-c", &script])
        .size(100, 30)
        .start();
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
    let mut ed = Term::grimace(dir.path(), &["edit", file.to_str().unwrap()], 80, 24);
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
    let mut ed = Term::grimace(dir.path(), &[], 100, 30);
    ed.wait_for("Muscles");
    println!(
        "start to first frame (process start included): {:?}",
        started.elapsed()
    );
    if let Ok(status) = std::fs::read_to_string(format!("/proc/{}/status", ed.pid())) {
        let rss = status
            .lines()
            .find(|l| l.starts_with("VmRSS"))
            .unwrap_or("VmRSS: ?");
        println!("resident memory on the default face: {rss}");
    }
    std::thread::sleep(Duration::from_millis(400));
    let before = ed.bytes_read();
    std::thread::sleep(Duration::from_millis(1500));
    let after = ed.bytes_read();
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
    let mut first = Term::grimace(dir.path(), &["edit", arg], 100, 30);
    first.wait_for("new table");
    let mut second = Term::grimace(dir.path(), &["edit", arg], 100, 30);
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
    let mut ed = Term::grimace(dir.path(), &["edit", arg], 100, 30);
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

/// A terminal made larger mid-session: the editor redraws at the new size at once, with the
/// status line on the new last row and the key hints that did not fit before.
#[test]
fn a_resized_terminal_is_redrawn_at_its_new_size() {
    let dir = tempfile::tempdir().unwrap();
    let mut ed = Term::grimace(dir.path(), &[], 80, 24);
    let screen = ed.wait_for("NORMAL");
    assert!(!screen.contains("Tab table"), "{screen}");
    ed.resize(120, 40);
    let status_row = |t: &Term| t.with_screen(|s| s.rows(0, 120).nth(38).unwrap_or_default());
    ed.wait_until("the status line on row 39 with more key hints", |t| {
        let row = status_row(t);
        row.contains("NORMAL") && row.contains("Tab table")
    });
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
}
