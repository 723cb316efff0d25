//! Files that are not what they seem, through the binary: symbolic links, named pipes,
//! devices and folders where a file is expected, a byte order mark, CR line ends, a
//! file-size limit, output that cannot be written, picture names that collide, and text
//! holding terminal escapes.

use std::io::Write;
use std::os::unix::fs::{symlink, FileTypeExt};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common;
use common::grimace_in as grimace;

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs")
}

/// A folder holding the corpus' good rig, mesh and table.
fn good_files() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in ["good.rig.ron", "good.obj", "good.au.ron"] {
        std::fs::copy(corpus().join(name), dir.path().join(name)).unwrap();
    }
    dir
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Exit 1 with exactly `grimace COMMAND: MESSAGE` on stderr.
fn assert_refused(out: &Output, expected: &str) {
    assert_eq!(out.status.code(), Some(1), "{}", stderr(out));
    assert_eq!(stderr(out).trim_end(), expected);
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(status.success());
}

/// Runs grimace with stdout sent to `stdout`, failing the test if it has not finished within
/// 60 seconds (a hang is the bug some of these tests look for).
fn grimace_with(dir: &Path, args: &[&str], stdout: Stdio) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("grimace {args:?} hangs");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn saves_write_through_symbolic_links() {
    let dir = good_files();
    std::fs::create_dir(dir.path().join("real")).unwrap();
    std::fs::write(dir.path().join("real/out.obj"), "old").unwrap();
    symlink("real/out.obj", dir.path().join("link.obj")).unwrap();
    let out = grimace(
        dir.path(),
        &[
            "export",
            "--table",
            "good.au.ron",
            "--au",
            "12",
            "--out",
            "link.obj",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let link = std::fs::symlink_metadata(dir.path().join("link.obj")).unwrap();
    assert!(link.file_type().is_symlink(), "the link was replaced");
    let written = std::fs::read_to_string(dir.path().join("real/out.obj")).unwrap();
    assert!(
        written.starts_with("# ") || written.contains("\nv "),
        "{written}"
    );
    // The replaced file is kept beside the real file, not beside the link.
    assert_eq!(names_in(&dir.path().join("real")), ["out.obj", "out.obj~"]);
    assert_eq!(
        std::fs::read_to_string(dir.path().join("real/out.obj~")).unwrap(),
        "old"
    );
}

#[test]
fn nothing_but_a_regular_file_is_replaced() {
    let dir = good_files();
    let fifo = dir.path().join("pipe.obj");
    mkfifo(&fifo);
    let out = grimace_with(
        dir.path(),
        &["export", "--au", "12", "--out", "pipe.obj"],
        Stdio::null(),
    );
    assert_refused(
        &out,
        "grimace export: pipe.obj: cannot save: it is a named pipe (FIFO); grimace only replaces regular files",
    );
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    let out = grimace(dir.path(), &["export", "--out", "/dev/null"]);
    assert_refused(
        &out,
        "grimace export: /dev/null: cannot save: it is a character device; grimace only replaces regular files",
    );
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    // A link to a device is refused like the device.
    symlink("/dev/null", dir.path().join("null.svg")).unwrap();
    for args in [
        &["gen-face", "--out", "/dev/null"][..],
        &["render", "--out", "null.svg"][..],
    ] {
        let out = grimace(dir.path(), args);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        assert!(
            stderr(&out)
                .ends_with("it is a character device; grimace only replaces regular files\n"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
    mkfifo(&dir.path().join("pipe.svg"));
    let out = grimace_with(dir.path(), &["render", "--out", "pipe.svg"], Stdio::null());
    assert!(
        stderr(&out).contains("it is a named pipe (FIFO)"),
        "{}",
        stderr(&out)
    );
}

/// `ulimit -f`: writes past the limit fail with "file too large" instead of killing grimace
/// with SIGXFSZ; the old file stays whole and no temporary file is left.
#[test]
fn a_file_size_limit_fails_a_write_like_a_full_disk() {
    let dir = good_files();
    let face = dir.path().join("face.obj");
    std::fs::write(&face, "the previous face\n").unwrap();
    let limited = |args: &str| {
        Command::new("sh")
            .arg("-c")
            .arg(format!(
                "ulimit -f 8 && exec '{}' {args}",
                env!("CARGO_BIN_EXE_grimace")
            ))
            .current_dir(dir.path())
            .output()
            .unwrap()
    };
    let out = limited("gen-face --out face.obj");
    assert_refused(
        &out,
        "grimace gen-face: face.obj: cannot save: file too large",
    );
    assert_eq!(
        std::fs::read_to_string(&face).unwrap(),
        "the previous face\n"
    );
    let out = limited("render --out big.png --width 2000 --height 2000");
    assert_refused(&out, "grimace render: big.png: cannot save: file too large");
    assert_eq!(
        names_in(dir.path()),
        ["face.obj", "good.au.ron", "good.obj", "good.rig.ron"]
    );
}

#[test]
fn output_that_cannot_be_written_fails_the_command() {
    let dir = good_files();
    for (args, command) in [
        (&["list", "--table", "good.au.ron"][..], "list"),
        (&["list"][..], "list"),
        (&["render"][..], "render"),
        (&["validate", "good.rig.ron"][..], "validate"),
        (&["completions", "bash"][..], "completions"),
        (&["play", "--headless", "--stdin"][..], "play"),
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = grimace_with(dir.path(), args, Stdio::from(full));
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        assert!(
            stderr(&out).starts_with(&format!("grimace {command}: cannot write to stdout")),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

#[test]
fn a_closed_pipe_ends_a_command_quietly() {
    let dir = good_files();
    for args in [
        &["list"][..],
        &["render", "--width", "600", "--height", "400"][..],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_grimace"))
            .args(args)
            .current_dir(dir.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // No reader: the first write finds the pipe closed.
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
        assert_eq!(stderr(&out), "", "{args:?}");
    }
}

#[test]
fn render_all_keeps_every_picture_name_distinct() {
    let dir = good_files();
    let table = std::fs::read_to_string(dir.path().join("good.au.ron"))
        .unwrap()
        .replace(
            "\"open smile\": \"12+26B\",",
            "\"a/b\": \"12\", \"a_b\": \"26\", \"a:b\": \"12+26\", \"A_B\": \"12\",",
        );
    std::fs::write(dir.path().join("names.au.ron"), table).unwrap();
    let out = grimace(
        dir.path(),
        &[
            "render",
            "--table",
            "names.au.ron",
            "--all",
            "--out",
            "pics",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let files = names_in(&dir.path().join("pics"));
    assert_eq!(
        files,
        [
            "au-12.svg",
            "au-26.svg",
            "expr-A_B.svg",
            "expr-a_b-2.svg",
            "expr-a_b-3.svg",
            "expr-a_b-4.svg",
        ]
    );
    let err = stderr(&out);
    assert!(err.contains("rendered 6 pictures into pics"), "{err}");
    // `a_b` keeps its name only if nothing took it first; every changed name is reported.
    for name in ["a/b", "a:b", "a_b"] {
        assert!(
            err.contains(&format!("expression `{name}` is written as expr-a_b-")),
            "{name}: {err}"
        );
    }
}

/// Named pipes are refused up front, so nothing waits for a writer that never comes.
#[test]
fn a_named_pipe_where_a_file_is_expected_is_refused_at_once() {
    let dir = good_files();
    for name in ["p.au.ron", "p.rig.ron", "p.obj"] {
        mkfifo(&dir.path().join(name));
        let out = grimace_with(dir.path(), &["validate", name], Stdio::null());
        assert_refused(
            &out,
            &format!("grimace validate: {name}: is a named pipe (FIFO), expected a regular file"),
        );
    }
    for (args, command) in [
        (&["edit", "p.au.ron"][..], "edit"),
        (&["list", "--table", "p.au.ron"][..], "list"),
        (
            &["export", "--rig", "p.rig.ron", "--out", "x.obj"][..],
            "export",
        ),
        (&["play", "--headless", "p.timeline.ron"][..], "play"),
    ] {
        if !dir.path().join(args[args.len() - 1]).exists() && command == "play" {
            mkfifo(&dir.path().join("p.timeline.ron"));
        }
        let out = grimace_with(dir.path(), args, Stdio::null());
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        assert!(
            stderr(&out).contains("is a named pipe (FIFO), expected a regular file"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

#[test]
fn a_folder_or_a_device_as_a_file_is_named_for_what_it_is() {
    let dir = good_files();
    std::fs::create_dir(dir.path().join("folder.rig.ron")).unwrap();
    let out = grimace(dir.path(), &["list", "--rig", "folder.rig.ron"]);
    assert_refused(
        &out,
        "grimace list: folder.rig.ron: is a folder, expected a file",
    );
    let out = grimace(
        dir.path(),
        &["export", "--rig", "/dev/zero", "--out", "x.obj"],
    );
    assert_refused(
        &out,
        "grimace export: /dev/zero: is a character device, expected a regular file",
    );
    let out = grimace(dir.path(), &["play", "--headless", "/dev/zero"]);
    assert_refused(
        &out,
        "grimace play: /dev/zero: is a character device, expected a regular file",
    );
    // A table whose rig is a folder, a rig whose mesh is a device.
    let table = std::fs::read_to_string(dir.path().join("good.au.ron"))
        .unwrap()
        .replace("\"good.rig.ron\"", "\"folder.rig.ron\"");
    std::fs::write(dir.path().join("t.au.ron"), table).unwrap();
    let out = grimace(dir.path(), &["validate", "t.au.ron"]);
    assert_refused(
        &out,
        "grimace validate: t.au.ron:4:5: the rig file `folder.rig.ron` is a folder, expected a file (paths are relative to the table file)",
    );
    let rig = std::fs::read_to_string(dir.path().join("good.rig.ron"))
        .unwrap()
        .replace("\"good.obj\"", "\"/dev/zero\"");
    std::fs::write(dir.path().join("r.rig.ron"), rig).unwrap();
    let out = grimace(dir.path(), &["validate", "r.rig.ron"]);
    assert!(
        stderr(&out)
            .contains("the mesh file `/dev/zero` is a character device, expected a regular file"),
        "{}",
        stderr(&out)
    );
}

const BOM: &str = "\u{feff}";

#[test]
fn a_byte_order_mark_is_read_past_in_every_format() {
    let dir = good_files();
    let p = dir.path();
    // The OBJ's first line is a vertex: with the mark it must still be vertex 1.
    let obj = std::fs::read_to_string(p.join("good.obj")).unwrap();
    let first_vertex = obj.lines().position(|l| l.starts_with("v ")).unwrap();
    let from_vertex: String = obj
        .lines()
        .skip(first_vertex)
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(p.join("plain.obj"), &from_vertex).unwrap();
    std::fs::write(p.join("marked.obj"), format!("{BOM}{from_vertex}")).unwrap();
    let plain = grimace(p, &["validate", "plain.obj"]);
    let marked = grimace(p, &["validate", "marked.obj"]);
    assert!(marked.status.success(), "{}", stderr(&marked));
    assert_eq!(
        stdout(&marked).replace("marked.obj", "plain.obj"),
        stdout(&plain)
    );
    for name in ["good.rig.ron", "good.au.ron"] {
        let text = std::fs::read_to_string(p.join(name)).unwrap();
        std::fs::write(p.join(name), format!("{BOM}{text}")).unwrap();
        let out = grimace(p, &["validate", name]);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
    }
    std::fs::write(
        p.join("t.timeline.ron"),
        format!("{BOM}(version: 1, frame_rate: 10.0, keyframes: [(time: 0.0), (time: 0.2, aus: Some(\"12\"))])"),
    )
    .unwrap();
    let out = grimace(
        p,
        &[
            "play",
            "--headless",
            "--table",
            "good.au.ron",
            "t.timeline.ron",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).ends_with("played 3 frames, skipped 0\n"),
        "{}",
        stdout(&out)
    );
    let out = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["play", "--headless", "--stdin", "--table", "good.au.ron"])
        .current_dir(p)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .and_then(|mut child| {
            let mut input = child.stdin.take().unwrap();
            input.write_all(format!("{BOM}{{\"timestamp\": 0.5, \"AU12\": 5}}\n").as_bytes())?;
            drop(input);
            child.wait_with_output()
        })
        .unwrap();
    assert_eq!(
        stdout(&out),
        "0.500 AU12=5.00 | L_pull=1.00 R_pull=1.00\nplayed 1 frames, skipped 0\n",
        "{}",
        stderr(&out)
    );
}

#[test]
fn cr_line_ends_read_like_lf() {
    let dir = good_files();
    let p = dir.path();
    for name in ["good.rig.ron", "good.au.ron", "good.obj"] {
        let text = std::fs::read_to_string(p.join(name)).unwrap();
        let lf = grimace(p, &["validate", name]);
        std::fs::write(p.join(name), text.replace('\n', "\r")).unwrap();
        let cr = grimace(p, &["validate", name]);
        assert!(cr.status.success(), "{name}: {}", stderr(&cr));
        assert_eq!(stdout(&cr), stdout(&lf), "{name}");
    }
    // An error in a CR file is placed at its line as the user sees it.
    std::fs::write(
        p.join("bad.au.ron"),
        "(\r    version: 1,\r    nonsense: 2,\r)\r",
    )
    .unwrap();
    let out = grimace(p, &["validate", "bad.au.ron"]);
    assert!(
        stderr(&out).starts_with("grimace validate: bad.au.ron:3:5: unknown field `nonsense`"),
        "{}",
        stderr(&out)
    );
    std::fs::write(
        p.join("mac.csv"),
        "frame, timestamp, success, AU12_r\r1, 0.0, 1, 5\r2, 0.1, 1, 2.5\r3, 0.2, 1, 0\r",
    )
    .unwrap();
    let out = grimace(
        p,
        &["play", "--headless", "--table", "good.au.ron", "mac.csv"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        stdout(&out),
        "0.000 AU12=5.00 | L_pull=1.00 R_pull=1.00\n0.100 AU12=2.50 | L_pull=0.50 R_pull=0.50\n0.200 | rest\nplayed 3 frames, skipped 0\n"
    );
}

#[test]
fn a_row_cut_short_is_named_with_its_line_and_field_count() {
    let dir = good_files();
    std::fs::write(
        dir.path().join("cut.csv"),
        "frame, timestamp, success, AU12_r, AU26_r\n1, 0.0, 1, 5, 0\n2, 0.1, 1",
    )
    .unwrap();
    let out = grimace(
        dir.path(),
        &["play", "--headless", "--table", "good.au.ron", "cut.csv"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("cut.csv:3: 3 of 5 fields, the row is cut short (row skipped)"),
        "{}",
        stderr(&out)
    );
}

/// Text from files reaches the terminal with its escapes shown, never obeyed.
#[test]
fn escapes_in_files_are_shown_not_sent_to_the_terminal() {
    let dir = good_files();
    let p = dir.path();
    let title = "\u{1b}]0;owned\u{7}";
    let clear = "\u{1b}[2J";
    let table = std::fs::read_to_string(p.join("good.au.ron"))
        .unwrap()
        .replace("Lip Corner Puller", &format!("Lip{title}Puller{clear}"));
    std::fs::write(p.join("esc.au.ron"), table).unwrap();
    let out = grimace(p, &["list", "--table", "esc.au.ron"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        !text.contains('\u{1b}') && !text.contains('\u{7}'),
        "{text:?}"
    );
    assert!(
        text.contains("Lip\\x1b]0;owned\\x07Puller\\x1b[2J"),
        "{text}"
    );
    // A path inside a rig, quoted in an error.
    let rig = std::fs::read_to_string(p.join("good.rig.ron"))
        .unwrap()
        .replace("\"good.obj\"", &format!("\"{title}{clear}.obj\""));
    std::fs::write(p.join("esc.rig.ron"), rig).unwrap();
    let out = grimace(p, &["validate", "esc.rig.ron"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(!err.contains('\u{1b}') && !err.contains('\u{7}'), "{err:?}");
    assert!(err.contains("`\\x1b]0;owned\\x07\\x1b[2J.obj`"), "{err}");
}

/// A line of a live stream longer than the limit is skipped with its length, and a producer
/// faster than grimace waits on its pipe instead of growing a backlog in memory.
#[test]
fn live_input_is_read_in_bounded_memory() {
    let dir = good_files();
    let mut child = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(["play", "--headless", "--stdin", "--table", "good.au.ron"])
        .current_dir(dir.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut input = child.stdin.take().unwrap();
    let long = format!("{{\"AU12\": 1, \"x\": \"{}\"}}\n", "y".repeat(3 << 20));
    let long_length = long.len() - 1;
    let line = "{\"timestamp\": 1, \"AU12\": 5}\n";
    // grimace's stdout is not read yet: it blocks writing, and the input must stop flowing.
    let writer = std::thread::spawn(move || {
        let mut sent = 0usize;
        if input.write_all(long.as_bytes()).is_err() {
            return sent;
        }
        for _ in 0..300_000 {
            if input.write_all(line.as_bytes()).is_err() {
                break;
            }
            sent += 1;
        }
        sent
    });
    std::thread::sleep(Duration::from_secs(3));
    let status = std::fs::read_to_string(format!("/proc/{}/status", child.id())).unwrap();
    let rss_kib: u64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap();
    assert!(
        !writer.is_finished(),
        "all the input went in without back-pressure"
    );
    assert!(rss_kib < 100 * 1024, "{rss_kib} KiB resident");
    let out = child.wait_with_output().unwrap();
    let sent = writer.join().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains(&format!(
            "stdin:1: the line is {} bytes long, more than the limit of 1 MiB (skipped unread)",
            long_length
        )),
        "{}",
        stderr(&out)
    );
    let played = stdout(&out)
        .lines()
        .filter(|l| l.contains("AU12=5.00"))
        .count();
    assert_eq!(played, sent);
    assert!(stdout(&out).ends_with(&format!("played {sent} frames, skipped 1\n")));
}
