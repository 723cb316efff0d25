//! The editor against other editors and the system, in a pseudo-terminal (`common::pty`):
//! a second editor on the same table, a recovery made after the table changed on disk, and a
//! file-size limit.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::common::pty::{Launch, Term, TIMEOUT};

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

/// A second editor on a table says it is open elsewhere and leaves the first editor's
/// recovery file alone, so a crash of the first editor still loses nothing.
#[test]
fn a_second_editor_never_touches_the_first_ones_recovery_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("shared.au.ron");
    let arg = file.to_str().unwrap();
    let recovery = dir.path().join(".shared.au.ron.recover");
    let mut first = Term::grimace(dir.path(), &["edit", arg], 200, 30);
    first.wait_for("new table");
    first.send("LL");
    first.wait_for("0.50");
    wait_for_file(&recovery);
    let kept = std::fs::read(&recovery).unwrap();

    let mut second = Term::grimace(dir.path(), &["edit", arg], 200, 30);
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

    first.kill_hard();
    let mut third = Term::grimace(dir.path(), &["edit", arg], 200, 30);
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
    let mut first = Term::grimace(dir.path(), &[], 200, 30);
    first.wait_for("Zygomatic");
    first.send("LLL");
    first.wait_for("0.75");
    wait_for_file(&recovery);
    let kept = std::fs::read(&recovery).unwrap();
    let mut second = Term::grimace(dir.path(), &[], 200, 30);
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
    let mut ed = Launch::program("sh", dir.path())
        .args(&["-c", &script])
        .size(200, 30)
        .start();
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
        let mut first = Term::grimace(dir.path(), &["edit", arg], 200, 30);
        first.wait_for("Zygomatic");
        first.send("L:record 12\r");
        first.wait_for("recorded AU 12");
        wait_for_file(&recovery);
        first.kill_hard();
        let theirs = table.replace(
            "aus: {}",
            "aus: {\"1\": (name: \"Theirs\", muscles: {}, jaw: 0.0)}",
        );
        if changed {
            std::fs::write(&file, &theirs).unwrap();
        }
        let mut second = Term::grimace(dir.path(), &["edit", arg], 200, 30);
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
    let mut ed = Term::grimace(dir.path(), &["edit", link.to_str().unwrap()], 200, 30);
    ed.wait_for("Zygomatic");
    assert!(dir.path().join("real/.t.au.ron.lock").exists());
    let mut other = Term::grimace(dir.path(), &["edit", target.to_str().unwrap()], 200, 30);
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
