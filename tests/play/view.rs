//! `grimace play` in its terminal view, driven through a pseudo-terminal: it draws the face,
//! answers the keys, and leaves the terminal as it found it.

use crate::play_common;

use std::io::{Read, Write};
use std::path::Path;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use portable_pty::{native_pty_system, CommandBuilder, PtySize};

const COLS: u16 = 100;
const ROWS: u16 = 30;

/// A running `grimace play` in a pseudo-terminal, its screen parsed by vt100.
struct Session {
    child: Box<dyn portable_pty::Child + Send + Sync>,
    writer: Box<dyn Write + Send>,
    output: mpsc::Receiver<Vec<u8>>,
    parser: vt100::Parser,
}

impl Session {
    fn start(dir: &Path, args: &[&str]) -> Session {
        Session::start_with(dir, args, None)
    }

    /// Like [`Session::start`], with `input` piped into standard input by a shell.
    fn start_piped(dir: &Path, input: &str, args: &[&str]) -> Session {
        Session::start_with(dir, args, Some(input))
    }

    fn start_with(dir: &Path, args: &[&str], input: Option<&str>) -> Session {
        let (rig, table) = play_common::write_fixture(dir);
        let pty = native_pty_system()
            .openpty(PtySize {
                rows: ROWS,
                cols: COLS,
                pixel_width: 0,
                pixel_height: 0,
            })
            .unwrap();
        let mut play = vec![
            env!("CARGO_BIN_EXE_grimace").to_string(),
            "play".into(),
            "--rig".into(),
            rig.display().to_string(),
            "--table".into(),
            table.display().to_string(),
        ];
        play.extend(args.iter().map(|a| a.to_string()));
        let mut command = match input {
            None => {
                let mut command = CommandBuilder::new(&play[0]);
                command.args(&play[1..]);
                command
            }
            Some(input) => {
                let file = dir.join("piped-input");
                std::fs::write(&file, input).unwrap();
                let quoted: Vec<String> = play.iter().map(|a| format!("'{a}'")).collect();
                let mut command = CommandBuilder::new("sh");
                command.arg("-c");
                command.arg(format!("cat '{}' | {}", file.display(), quoted.join(" ")));
                command
            }
        };
        command.env("TERM", "xterm-256color");
        command.cwd(dir);
        let child = pty.slave.spawn_command(command).unwrap();
        drop(pty.slave);
        let mut reader = pty.master.try_clone_reader().unwrap();
        let writer = pty.master.take_writer().unwrap();
        let (sender, output) = mpsc::channel();
        std::thread::spawn(move || {
            let mut buffer = [0u8; 8192];
            while let Ok(n) = reader.read(&mut buffer) {
                if n == 0 || sender.send(buffer[..n].to_vec()).is_err() {
                    break;
                }
            }
        });
        // Keep the master open for the session's life.
        std::mem::forget(pty.master);
        Session {
            child,
            writer,
            output,
            parser: vt100::Parser::new(ROWS, COLS, 0),
        }
    }

    /// Reads output until `done(screen)` holds or `secs` pass; returns whether it held.
    fn wait_for(&mut self, secs: f64, done: impl Fn(&str) -> bool) -> bool {
        let deadline = Instant::now() + Duration::from_secs_f64(secs);
        loop {
            if done(&self.parser.screen().contents()) {
                return true;
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return false;
            }
            if let Ok(bytes) = self
                .output
                .recv_timeout(left.min(Duration::from_millis(50)))
            {
                self.parser.process(&bytes);
            }
        }
    }

    fn screen(&self) -> String {
        self.parser.screen().contents()
    }

    fn key(&mut self, text: &str) {
        self.writer.write_all(text.as_bytes()).unwrap();
        self.writer.flush().unwrap();
    }

    /// Waits for the process to end; its exit code.
    fn finish(&mut self, secs: f64) -> u32 {
        let deadline = Instant::now() + Duration::from_secs_f64(secs);
        loop {
            while let Ok(bytes) = self.output.try_recv() {
                self.parser.process(&bytes);
            }
            if let Some(status) = self.child.try_wait().unwrap() {
                // Drain what it printed last.
                std::thread::sleep(Duration::from_millis(100));
                while let Ok(bytes) = self.output.try_recv() {
                    self.parser.process(&bytes);
                }
                return status.exit_code();
            }
            if Instant::now() > deadline {
                let _ = self.child.kill();
                panic!("grimace play did not exit; screen:\n{}", self.screen());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

/// Saves the screen for a look (`GRIMACE_CAPTURE=DIR`), e.g. with screen2png.
fn capture(session: &Session, name: &str) {
    if let Some(dir) = std::env::var_os("GRIMACE_CAPTURE") {
        std::fs::write(Path::new(&dir).join(name), session.screen()).unwrap();
    }
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
    let mut session = Session::start(dir.path(), &[timeline.to_str().unwrap(), "--stats"]);
    assert!(
        session.wait_for(10.0, |s| has_braille(s) && s.contains("playing")),
        "no face drawn:\n{}",
        session.screen()
    );
    capture(&session, "play_view_playing.txt");
    session.key(" ");
    assert!(
        session.wait_for(5.0, |s| s.contains("paused")),
        "{}",
        session.screen()
    );
    session.key("+");
    assert!(
        session.wait_for(5.0, |s| s.contains("x2.00")),
        "{}",
        session.screen()
    );
    let before = session.screen();
    session.key("n");
    assert!(
        session.wait_for(5.0, |s| s != before),
        "step changed nothing"
    );
    session.key("q");
    let code = session.finish(10.0);
    assert_eq!(code, 0, "{}", session.screen());
    assert!(
        !session.parser.screen().alternate_screen(),
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
    let mut session = Session::start_piped(dir.path(), "{\"AU12\": 5}\n", &["--stdin"]);
    assert!(
        session.wait_for(10.0, |s| s.contains(" end ")
            && s.contains("frames 1  shown 1")),
        "{}",
        session.screen()
    );
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        session.child.try_wait().unwrap().is_none(),
        "the view closed by itself:\n{}",
        session.screen()
    );
    session.key("q");
    assert_eq!(session.finish(10.0), 0, "{}", session.screen());
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
    let mut session = Session::start(dir.path(), &[csv.to_str().unwrap()]);
    assert!(
        session.wait_for(10.0, |s| s.contains(" end ")),
        "{}",
        session.screen()
    );
    capture(&session, "play_view_end.txt");
    session.key("q");
    assert_eq!(session.finish(10.0), 0);
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
    let mut session = Session::start(
        dir.path(),
        &[timeline.to_str().unwrap(), "--frames", "10", "--speed", "4"],
    );
    assert_eq!(session.finish(20.0), 0);
    assert!(
        session.screen().contains("played 10 frames"),
        "{}",
        session.screen()
    );
}

#[test]
fn live_udp_frames_show_on_arrival() {
    let dir = tempfile::tempdir().unwrap();
    let mut session = Session::start(dir.path(), &["--udp", "127.0.0.1:0"]);
    // The address is printed before the view opens; the vt100 screen keeps it in the main
    // screen, so read it from the raw output instead.
    let mut raw = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(10);
    let address = loop {
        if let Ok(bytes) = session.output.recv_timeout(Duration::from_millis(50)) {
            raw.extend_from_slice(&bytes);
            session.parser.process(&bytes);
        }
        let text = String::from_utf8_lossy(&raw);
        if let Some(rest) = text.split("listening on udp ").nth(1) {
            if let Some(end) = rest.find(['\r', '\n']) {
                break rest[..end].to_string();
            }
        }
        assert!(Instant::now() < deadline, "no address printed");
    };
    assert!(
        session.wait_for(10.0, |s| s.contains("playing")),
        "{}",
        session.screen()
    );
    let socket = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .send_to(b"{\"AU12\": 5, \"AU26\": 2.5}", &address)
        .unwrap();
    assert!(
        session.wait_for(10.0, |s| s.contains("AU12   5.00") && s.contains("jaw")),
        "{}",
        session.screen()
    );
    session.key("q");
    assert_eq!(session.finish(10.0), 0);
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
    let mut session = Session::start(dir.path(), &[timeline.to_str().unwrap(), "--ascii"]);
    assert!(
        session.wait_for(10.0, |s| s.contains("playing")
            && s.contains(['/', '\\', '|', '_'])),
        "{}",
        session.screen()
    );
    assert!(!has_braille(&session.screen()), "{}", session.screen());
    session.key("q");
    assert_eq!(session.finish(10.0), 0);
}
