//! `grimace play` in its terminal view, driven through a pseudo-terminal (`common::pty`): it
//! draws the face, answers the keys, and leaves the terminal as it found it.

use crate::common::pty::{Launch, Term};
use crate::play_common;

use std::path::Path;
use std::time::Duration;

const COLS: u16 = 100;
const ROWS: u16 = 30;

/// `grimace play --rig R --table T ARGS` in `dir`, with a small rig and table written there.
fn play(dir: &Path, args: &[&str]) -> Launch {
    let (rig, table) = play_common::write_fixture(dir);
    Launch::grimace(dir)
        .args(&["play", "--rig", rig.to_str().unwrap()])
        .args(&["--table", table.to_str().unwrap()])
        .args(args)
        .size(COLS, ROWS)
}

fn start(dir: &Path, args: &[&str]) -> Term {
    play(dir, args).start()
}

fn has_braille(screen: &str) -> bool {
    screen
        .chars()
        .any(|c| ('\u{2801}'..='\u{28ff}').contains(&c))
}

/// Long enough that a loaded machine cannot reach its end before a test's keys arrive.
const TIMELINE: &str = r#"Timeline(
    version: 1,
    frame_rate: 30.0,
    keyframes: [(time: 0.0), (time: 1.0, aus: "12"), (time: 60.0, aus: "26")],
)"#;

#[test]
fn plays_a_timeline_pauses_steps_and_quits_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let timeline = dir.path().join("t.timeline.ron");
    std::fs::write(&timeline, TIMELINE).unwrap();
    let mut session = start(dir.path(), &[timeline.to_str().unwrap(), "--stats"]);
    session.wait_screen("a face drawn, playing", |s| {
        has_braille(s) && s.contains("playing")
    });
    session.capture("play_view_playing.txt");
    session.send(" ");
    session.wait_screen("paused", |s| s.contains("paused"));
    session.send("+");
    session.wait_screen("speed x2.00", |s| s.contains("x2.00"));
    let before = session.screen();
    session.send("n");
    session.wait_screen("a step changing the screen", |s| s != before);
    session.send("q");
    let code = session.wait_exit().exit_code();
    assert_eq!(code, 0, "{}", session.screen());
    assert!(
        !session.with_screen(|s| s.alternate_screen()),
        "the terminal must leave the alternate screen"
    );
    let screen = session.screen();
    assert!(screen.contains("played "), "{screen}");
    assert!(screen.contains("frames shown"), "--stats line: {screen}");
}

/// The end of piped input is not the terminal going away: the view stays until `q`.
#[test]
fn piped_input_that_ends_keeps_the_view_open() {
    let dir = tempfile::tempdir().unwrap();
    let mut session = play(dir.path(), &["--stdin"])
        .stdin("{\"AU12\": 5}\n")
        .start();
    session.wait_screen("the end of the input, one frame shown", |s| {
        s.contains(" end ") && s.contains("frames 1  shown 1")
    });
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        session.try_wait().is_none(),
        "the view closed by itself:\n{}",
        session.screen()
    );
    session.send("q");
    assert_eq!(session.wait_exit().exit_code(), 0, "{}", session.screen());
    assert!(
        session.screen().contains("played 1 frames"),
        "{}",
        session.screen()
    );
}

#[test]
fn reaches_the_end_of_a_file_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("short.csv");
    std::fs::write(
        &csv,
        "timestamp, success, AU12_r\n0.0, 1, 5\n0.04, 0, 0\n0.08, 1, 2\nbad\n",
    )
    .unwrap();
    let mut session = start(dir.path(), &[csv.to_str().unwrap()]);
    session.wait_screen("the end of the file", |s| s.contains(" end "));
    session.capture("play_view_end.txt");
    session.send("q");
    assert_eq!(session.wait_exit().exit_code(), 0);
    let screen = session.screen();
    assert!(screen.contains("played 2 frames, skipped 2"), "{screen}");
    assert!(
        screen.contains("short.csv:5: 1 of 3 fields, the row is cut short"),
        "malformed row named: {screen}"
    );
}

#[test]
fn frame_limit_ends_the_view_by_itself() {
    let dir = tempfile::tempdir().unwrap();
    let timeline = dir.path().join("t.timeline.ron");
    std::fs::write(&timeline, TIMELINE).unwrap();
    let mut session = start(
        dir.path(),
        &[timeline.to_str().unwrap(), "--frames", "10", "--speed", "4"],
    );
    assert_eq!(session.wait_exit().exit_code(), 0);
    assert!(
        session.screen().contains("played 10 frames"),
        "{}",
        session.screen()
    );
}

#[test]
fn live_udp_frames_show_on_arrival() {
    let dir = tempfile::tempdir().unwrap();
    let mut session = start(dir.path(), &["--udp", "127.0.0.1:0"]);
    // The address is printed before the view opens; the vt100 screen keeps it in the main
    // screen, so read it from the raw output instead.
    let address = |output: &str| {
        let rest = output.split("listening on udp ").nth(1)?;
        rest.find(['\r', '\n']).map(|end| rest[..end].to_string())
    };
    session.wait_until("the address printed", |t| address(&t.output()).is_some());
    let address = address(&session.output()).unwrap();
    session.wait_screen("playing", |s| s.contains("playing"));
    let socket = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .send_to(b"{\"AU12\": 5, \"AU26\": 2.5}", &address)
        .unwrap();
    session.wait_screen("the frame sent shown", |s| {
        s.contains("AU12   5.00") && s.contains("jaw")
    });
    session.send("q");
    assert_eq!(session.wait_exit().exit_code(), 0);
    assert!(
        session.screen().contains("played 1 frames, skipped 0"),
        "{}",
        session.screen()
    );
}

#[test]
fn ascii_view_draws_without_braille() {
    let dir = tempfile::tempdir().unwrap();
    let timeline = dir.path().join("t.timeline.ron");
    std::fs::write(&timeline, TIMELINE).unwrap();
    let mut session = start(dir.path(), &[timeline.to_str().unwrap(), "--ascii"]);
    session.wait_screen("an ASCII face, playing", |s| {
        s.contains("playing") && s.contains(['/', '\\', '|', '_'])
    });
    assert!(!has_braille(&session.screen()), "{}", session.screen());
    session.send("q");
    assert_eq!(session.wait_exit().exit_code(), 0);
}
