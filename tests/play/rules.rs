//! The stream rules (`play::rules`), source by source: time is finite, bounded and never goes
//! backwards without a word (midnight wraps a Live Link take into the next day); what the
//! input says reaches the terminal escaped; names seen are kept bounded; a pipe or FIFO is
//! read once; a JSON frame's verdict does not depend on its key order.

use crate::play_common;

use std::io::Write;
use std::net::UdpSocket;
use std::path::Path;
use std::process::Stdio;

use play_common::{lines, output_within, play_command, play_headless, stderr};

/// A Live Link Face take of `rows` (timecode, `JawOpen` weight) in `dir`.
fn take(dir: &Path, extra_header: &str, rows: &[(&str, &str)]) -> String {
    let mut text = format!("Timecode,BlendShapeCount,JawOpen{extra_header}\n");
    let blanks = extra_header.matches(',').count();
    for (timecode, weight) in rows {
        text.push_str(&format!("{timecode},1,{weight}{}\n", ",0".repeat(blanks)));
    }
    let path = dir.join("take.csv");
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

fn times(out: &std::process::Output) -> Vec<String> {
    let all = lines(out);
    all[..all.len().saturating_sub(1)]
        .iter()
        .map(|l| l.split(' ').next().unwrap().to_string())
        .collect()
}

#[test]
fn livelink_a_take_across_midnight_plays_on_into_the_next_day() {
    let dir = tempfile::tempdir().unwrap();
    let path = take(
        dir.path(),
        "",
        &[
            ("23:59:59:58", "0.1"),
            ("23:59:59:59", "0.2"),
            ("00:00:00:00", "0.3"),
            ("00:00:00:01", "0.4"),
        ],
    );
    let out = play_headless(dir.path(), &[&path], None);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(times(&out), ["0.000", "0.017", "0.033", "0.050"]);
}

#[test]
fn livelink_absurd_timecodes_are_refused_and_realtime_keeps_pace() {
    let dir = tempfile::tempdir().unwrap();
    let fraction = format!("00:00:00:02.{}", "9".repeat(400));
    let frames = format!("00:00:00:{}", "9".repeat(400));
    let path = take(
        dir.path(),
        "",
        &[
            ("00:00:00:00", "0.1"),
            ("99999999999999:00:00:00", "0.2"),
            (&frames, "0.3"),
            (&fraction, "0.4"),
        ],
    );
    let out = output_within(&mut play_command(dir.path(), &[&path, "--realtime"]), 30);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert_eq!(times(&out), ["0.000", "0.050"], "{err}");
    assert!(
        err.contains(
            "take.csv:3:1: timecode `99999999999999:00:00:00` hours 99999999999999 is not below 24"
        ),
        "{err}"
    );
    assert!(
        err.contains("take.csv:4:1: timecode `00:00:00:999999999999999...` is not a timecode"),
        "{err}"
    );
}

#[test]
fn livelink_time_going_backwards_is_named_not_played() {
    let dir = tempfile::tempdir().unwrap();
    let path = take(
        dir.path(),
        "",
        &[
            ("00:00:01:00", "0.1"),
            ("00:00:00:30", "0.2"),
            ("00:00:01:30", "0.3"),
        ],
    );
    let out = play_headless(dir.path(), &[&path], None);
    let err = stderr(&out);
    assert_eq!(times(&out), ["0.000", "0.500"], "{err}");
    assert!(
        err.contains("take.csv:3: time -0.500 s is before the previous frame's 0.000 s"),
        "{err}"
    );
}

#[test]
fn livelink_names_and_fields_reach_the_terminal_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let path = take(
        dir.path(),
        ",\u{1b}]0;owned\u{7}",
        &[("00:00:00:00", "0.1"), ("00:00:00:01", "\u{1b}[2J")],
    );
    for args in [vec![path.as_str()], vec!["--stdin"]] {
        let input = std::fs::read(&path).unwrap();
        let out = play_headless(dir.path(), &args, Some(&input));
        let err = stderr(&out);
        assert!(out.status.success(), "{err}");
        assert!(!err.contains('\u{1b}'), "{err:?}");
        assert!(err.contains("\\x1b]0;owned\\x07"), "{err}");
        assert!(err.contains("`\\x1b[2J` is not a number"), "{err}");
    }
}

#[test]
fn livelink_header_names_are_kept_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let extra: String = (0..200)
        .map(|i| format!(",{i}{}", "R".repeat(5000)))
        .collect();
    let path = take(dir.path(), &extra, &[("00:00:00:00", "0.1")]);
    let out = play_headless(dir.path(), &[&path], None);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("and 168 more not named"), "{err}");
    assert!(err.len() < 5_000, "{} bytes of messages", err.len());
}

#[test]
fn openface_time_going_backwards_or_out_of_range_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.csv");
    std::fs::write(
        &path,
        "frame, timestamp, AU12_r\n1, 0.5, 1\n2, 0.25, 1\n3, 1e8, 1\n4, 1.0, 1\n",
    )
    .unwrap();
    let out = play_headless(dir.path(), &[path.to_str().unwrap()], None);
    let err = stderr(&out);
    assert_eq!(times(&out), ["0.500", "1.000"], "{err}");
    assert!(
        err.contains("a.csv:3: time 0.250 s is before the previous frame's 0.500 s"),
        "{err}"
    );
    assert!(err.contains("a.csv:4: time 1e8 s is out of range"), "{err}");
}

#[test]
fn openface_fields_reach_the_terminal_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.csv");
    std::fs::write(&path, "frame, AU12_r\n1, \u{1b}]0;owned\u{7}\n").unwrap();
    let out = play_headless(dir.path(), &[path.to_str().unwrap()], None);
    let err = stderr(&out);
    assert!(
        !err.contains('\u{1b}') && err.contains("\\x1b]0;owned\\x07"),
        "{err:?}"
    );
}

#[cfg(unix)]
#[test]
fn a_fifo_is_read_once() {
    let dir = tempfile::tempdir().unwrap();
    let openface = "frame, timestamp, AU12_r\n1, 0.0, 1\n2, 0.04, 2\n".to_string();
    let livelink = "Timecode,BlendShapeCount,JawOpen\n00:00:00:00,1,0.5\n00:00:00:01,1,0.25\n";
    for (text, expected) in [(openface, "0.040"), (livelink.to_string(), "0.017")] {
        let fifo = dir.path().join("take.fifo");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        // One writer, as `<(...)` gives: what a second open would wait for never comes.
        let writer = {
            let fifo = fifo.clone();
            std::thread::spawn(move || {
                let mut pipe = std::fs::OpenOptions::new().write(true).open(fifo).unwrap();
                let _ = pipe.write_all(text.as_bytes());
            })
        };
        let out = output_within(&mut play_command(dir.path(), &[fifo.to_str().unwrap()]), 30);
        writer.join().unwrap();
        assert!(out.status.success(), "{}", stderr(&out));
        assert_eq!(times(&out), ["0.000", expected], "{}", stderr(&out));
    }
}

#[test]
fn json_time_going_backwards_is_named_not_played() {
    let dir = tempfile::tempdir().unwrap();
    let input = "{\"timestamp\": 1.0, \"AU12\": 1}\n{\"timestamp\": 0.5, \"AU12\": 2}\n{\"timestamp\": 1e300, \"AU12\": 2}\n{\"Timestamp\": 2, \"timestamp\": 3}\n";
    let out = play_headless(dir.path(), &["--stdin"], Some(input.as_bytes()));
    let err = stderr(&out);
    assert_eq!(times(&out), ["1.000"], "{err}");
    assert!(
        err.contains("stdin:2: time 0.500 s is before the previous frame's 1.000 s"),
        "{err}"
    );
    assert!(
        err.contains("stdin:3: time 1e300 s is out of range"),
        "{err}"
    );
    assert!(err.contains("stdin:4: the time is given twice"), "{err}");
}

/// One JSON line per key order of a frame giving AU26 by name and by ARKit shape, and one of
/// two shapes of one AU.
const ORDERS: &str = concat!(
    "{\"AU26\": 1, \"jawOpen\": 0.5}\n",
    "{\"jawOpen\": 0.5, \"AU26\": 1}\n",
    "{\"AU12\": 1, \"AU12_r\": 2}\n",
    "{\"AU12_r\": 2, \"AU12\": 1}\n",
);

fn check_orders(err: &str, source: &str) {
    for line in 1..=2 {
        let want = format!("{source}:{line}: AU26 is given twice, as `AU26` and `jawOpen`");
        assert!(err.contains(&want), "{want}\n{err}");
    }
    for line in 3..=4 {
        let want = format!("{source}:{line}: AU12 is given twice, as `AU12` and `AU12_r`");
        assert!(err.contains(&want), "{want}\n{err}");
    }
}

#[test]
fn json_verdict_does_not_depend_on_key_order() {
    let dir = tempfile::tempdir().unwrap();
    let out = play_headless(dir.path(), &["--stdin"], Some(ORDERS.as_bytes()));
    assert_eq!(lines(&out).last().unwrap(), "played 0 frames, skipped 4");
    check_orders(&stderr(&out), "stdin");
}

/// `count` frames, each with one unknown key of `size` bytes holding an escape.
fn unknown_keys(count: usize, size: usize) -> Vec<String> {
    (0..count)
        .map(|i| {
            format!(
                "{{\"\\u001b[2J{i:05}{}\": 1, \"AU12\": 1}}\n",
                "k".repeat(size)
            )
        })
        .collect()
}

#[test]
fn json_unknown_names_are_kept_bounded_and_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let input: String = unknown_keys(300, 20_000).concat();
    let out = play_headless(dir.path(), &["--stdin"], Some(input.as_bytes()));
    let err = stderr(&out);
    assert_eq!(lines(&out).last().unwrap(), "played 300 frames, skipped 0");
    assert!(!err.contains('\u{1b}'), "escaped");
    assert!(err.contains("more than 32 names ignored"), "{err}");
    assert!(
        err.contains("268 more ignored names were not named"),
        "{err}"
    );
    assert!(err.len() < 8_000, "{} bytes of messages", err.len());
}

#[test]
fn udp_keeps_the_same_rules() {
    let dir = tempfile::tempdir().unwrap();
    let mut command = play_command(dir.path(), &["--udp", "127.0.0.1:0", "--idle-timeout", "2"]);
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The first stderr line names the port.
    let mut err = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut first = String::new();
    std::io::BufRead::read_line(&mut err, &mut first).unwrap();
    let address = first
        .trim()
        .strip_prefix("listening on udp ")
        .unwrap()
        .to_string();
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    let mut datagrams: Vec<String> = ORDERS.lines().map(str::to_string).collect();
    datagrams.extend(unknown_keys(100, 2_000));
    datagrams.push("{\"timestamp\": 5, \"AU12\": 1}".into());
    datagrams.push("{\"timestamp\": 4, \"AU12\": 1}".into());
    for datagram in &datagrams {
        socket.send_to(datagram.as_bytes(), &address).unwrap();
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let out = child.wait_with_output().unwrap();
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut err, &mut rest).unwrap();
    let source = format!("udp {address}");
    check_orders(&rest, &source);
    assert!(!rest.contains('\u{1b}'), "escaped");
    assert!(rest.contains("more than 32 names ignored"), "{rest}");
    assert!(rest.len() < 8_000, "{} bytes of messages", rest.len());
    assert!(
        rest.contains(&format!(
            "{source}:106: time 4.000 s is before the previous frame's 5.000 s"
        )),
        "{rest}"
    );
    assert!(out.status.success());
}

#[test]
fn timeline_time_is_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long.timeline.ron");
    std::fs::write(
        &path,
        "Timeline(version: 1, frame_rate: 1.0, keyframes: [(time: 0.0), (time: 5e7)])",
    )
    .unwrap();
    let out = play_headless(dir.path(), &[path.to_str().unwrap()], None);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.contains("the last keyframe: time 5e7 s is out of range"),
        "{err}"
    );
}
