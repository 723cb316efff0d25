//! `grimace play` on live streams: stdin (JSON lines, CSV) and loopback UDP JSON, end to end.

use crate::play_common;

use std::io::{BufRead, BufReader, Read};
use std::net::UdpSocket;
use std::process::Stdio;
use std::time::{Duration, Instant};

use play_common::{grimace, lines, play_headless, stderr, write_fixture};

#[test]
fn stdin_json_lines_in_openfacs_shape() {
    let dir = tempfile::tempdir().unwrap();
    let input = concat!(
        "{\"timestamp\": 0.0, \"AU1\": 0, \"AU6\": 0, \"AU12\": 5, \"AU45\": 1}\n",
        "\n",
        "{\"timestamp\": 0.04, \"AU1\": 2.5, \"AU26\": 5}\n",
        "{\"timestamp\": 0.08, \"AU1\": \"up\"}\n",
        "{\"timestamp\": 0.12, \"AU12\": 12.0}\n",
    );
    let out = play_headless(dir.path(), &["--stdin"], Some(input.as_bytes()));
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        lines(&out),
        vec![
            "0.000 AU12=5.00 AU45=1.00 | cheek=0.50 mouth=2.00",
            "0.040 AU1=2.50 AU26=5.00 | brow=0.50 jaw=2.00",
            "0.120 AU12=5.00 | cheek=0.50 mouth=2.00",
            "played 3 frames, skipped 1",
        ]
    );
    let err = stderr(&out);
    assert!(
        err.contains("stdin:4:28: expected a number (row skipped)"),
        "{err}"
    );
    assert_eq!(err.matches("has no AU45").count(), 1, "{err}");
    assert!(
        err.contains("stdin:5: AU12 intensity 12 is outside 0 to 5"),
        "{err}"
    );
}

#[test]
fn stdin_json_with_scale_reads_0_1() {
    let dir = tempfile::tempdir().unwrap();
    let out = play_headless(
        dir.path(),
        &["--stdin", "--scale"],
        Some(b"{\"timestamp\": 1.5, \"AU12\": 0.25}"),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        lines(&out),
        vec![
            "1.500 AU12=0.25 | cheek=0.12 mouth=0.50",
            "played 1 frames, skipped 0"
        ]
    );
}

#[test]
fn stdin_csv_with_a_header_line() {
    let dir = tempfile::tempdir().unwrap();
    let input = "frame, timestamp, success, AU06_r\r\n1, 0.0, 1, 2.5\r\n2, 0.1, 0, 0\r\n3, 0.2, 1\r\n4, 0.3, 1, 5";
    let out = play_headless(dir.path(), &["--stdin"], Some(input.as_bytes()));
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        lines(&out),
        vec![
            "0.000 AU6=2.50 | cheek=0.50",
            "0.300 AU6=5.00 | cheek=1.00",
            "played 2 frames, skipped 2",
        ]
    );
    assert!(
        stderr(&out).contains("stdin:4: 3 of 4 fields, the row is cut short"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn stdin_empty_plays_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = play_headless(dir.path(), &["--stdin"], Some(b""));
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(lines(&out), vec!["played 0 frames, skipped 0"]);
}

/// Reads the `listening on udp ADDR` line from a child's stderr.
fn listening_address(stderr: &mut impl BufRead) -> String {
    let mut line = String::new();
    while stderr.read_line(&mut line).unwrap() > 0 {
        if let Some(address) = line.trim().strip_prefix("listening on udp ") {
            return address.to_string();
        }
        line.clear();
    }
    panic!("grimace did not say where it listens");
}

#[test]
fn udp_json_on_loopback() {
    let dir = tempfile::tempdir().unwrap();
    let (rig, table) = write_fixture(dir.path());
    let mut child = grimace()
        .args(["play", "--headless", "--udp", "127.0.0.1:0"])
        .args(["--frames", "3", "--idle-timeout", "10"])
        .arg("--rig")
        .arg(&rig)
        .arg("--table")
        .arg(&table)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let address = listening_address(&mut err);
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    for message in [
        "{\"AU12\": 5}",
        "not json",
        "{\"AU1\": 5, \"AU6\": 2.5}",
        "{\"AU26\": 2.5}",
        "{\"AU1\": 1}",
    ] {
        socket.send_to(message.as_bytes(), &address).unwrap();
        // Loopback datagrams are not lost, but keep them in order on a busy machine.
        std::thread::sleep(Duration::from_millis(20));
    }
    let deadline = Instant::now() + Duration::from_secs(20);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            child.kill().unwrap();
            panic!("grimace play --udp did not stop after 3 frames");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    let mut rest = String::new();
    err.read_to_string(&mut rest).unwrap();
    assert!(status.success(), "{rest}");
    let frames: Vec<&str> = out.lines().collect();
    assert_eq!(frames.len(), 4, "{out}");
    // Live frames without a timestamp are timed by arrival: check the part after the time.
    let tail = |line: &str| line.split_once(' ').unwrap().1.to_string();
    assert_eq!(tail(frames[0]), "AU12=5.00 | cheek=0.50 mouth=2.00");
    assert_eq!(tail(frames[1]), "AU1=5.00 AU6=2.50 | brow=1.00 cheek=0.50");
    assert_eq!(tail(frames[2]), "AU26=2.50 | jaw=1.00");
    assert_eq!(frames[3], "played 3 frames, skipped 1");
    assert!(rest.contains("udp 127.0.0.1:"), "{rest}");
    assert!(rest.contains(":2:1: expected `{`"), "{rest}");
}

#[test]
fn udp_idle_timeout_ends_a_silent_stream() {
    let dir = tempfile::tempdir().unwrap();
    let started = Instant::now();
    let out = play_headless(
        dir.path(),
        &["--udp", "127.0.0.1:0", "--idle-timeout", "0.3"],
        None,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(lines(&out), vec!["played 0 frames, skipped 0"]);
    assert!(started.elapsed() < Duration::from_secs(10));
}

#[test]
fn udp_refuses_addresses_other_machines_can_reach() {
    let dir = tempfile::tempdir().unwrap();
    for address in ["0.0.0.0:0", "8.8.8.8:9000"] {
        let out = play_headless(dir.path(), &["--udp", address], None);
        assert_eq!(out.status.code(), Some(1), "{address}");
        assert!(stderr(&out).contains("only loopback"), "{}", stderr(&out));
    }
    let out = play_headless(dir.path(), &["--udp", "nonsense"], None);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("is not an address"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn inputs_are_mutually_exclusive_usage_errors() {
    let out = grimace()
        .args(["play", "--stdin", "--udp", "127.0.0.1:0"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let out = grimace().args(["play"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn the_view_needs_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let (rig, table) = write_fixture(dir.path());
    let out = grimace()
        .args(["play", "--stdin", "--rig"])
        .arg(&rig)
        .arg("--table")
        .arg(&table)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("use --headless"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn stdin_json_frames_naming_an_au_twice_are_refused_not_added() {
    let dir = tempfile::tempdir().unwrap();
    let input = concat!(
        "{\"timestamp\": 0.0, \"AU12\": 1, \"AU12\": 2}\n",
        "{\"timestamp\": 0.04, \"AU12\": 1, \"AU12_r\": 2}\n",
        "{\"timestamp\": 0.08, \"AU12\": 3}\n",
    );
    let out = play_headless(dir.path(), &["--stdin"], Some(input.as_bytes()));
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        lines(&out),
        vec![
            "0.080 AU12=3.00 | cheek=0.30 mouth=1.20",
            "played 1 frames, skipped 2",
        ]
    );
    let err = stderr(&out);
    assert!(
        err.contains(
            "stdin:1:39: key `AU12` appears twice (first value at column 28) (row skipped)"
        ),
        "{err}"
    );
    assert!(
        err.contains("stdin:2: AU12 is given twice, as `AU12` and `AU12_r` (row skipped)"),
        "{err}"
    );
}
