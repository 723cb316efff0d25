//! `grimace play --headless` on a Live Link Face CSV recording and on JSON lines with ARKit
//! names, through the built-in face, table and ARKit map.
//!
//! `tests/play_livelink/take.csv` was written for these tests in the layout Live Link Face
//! records (docs/formats.md, "Live Link Face CSV"): the header `Timecode,BlendShapeCount`,
//! the 52 shapes in the app's order and its nine head and eye rotations; 12 frames at 60 fps
//! (timecodes 10:41:07:30.250 to 10:41:07:41.250) of a smile on the subject's left
//! (`MouthSmileLeft` 0 to 1) with the jaw opening (`JawOpen` 0 to 0.5) and `BrowInnerUp`
//! 0.2; line 10 holds `nan?` where `JawOpen` goes.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

fn play(args: &[&str], stdin: Option<&[u8]>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .arg("play")
        .arg("--headless")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(if stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    if let Some(bytes) = stdin {
        let _ = child.stdin.take().unwrap().write_all(bytes);
    }
    child.wait_with_output().unwrap()
}

fn lines(out: &Output) -> Vec<String> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::to_string)
        .collect()
}

const TAKE: &str = "tests/play_livelink/take.csv";

#[test]
fn a_recording_plays_its_frames_and_skips_the_bad_row() {
    assert!(Path::new(env!("CARGO_MANIFEST_DIR")).join(TAKE).exists());
    let out = play(&[TAKE], None);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let mut frames = lines(&out);
    let last = frames.pop().unwrap();
    assert_eq!(last, "played 11 frames, skipped 1");
    assert_eq!(frames.len(), 11);
    // The bad row is named by file, line and column (the 20th field, JawOpen).
    assert!(
        stderr.contains("take.csv:10:") && stderr.contains("jawOpen"),
        "{stderr}"
    );
    // Shapes without an AU and the rotation columns are said once.
    assert!(
        stderr.contains("mouthLeft") && stderr.contains("HeadYaw"),
        "{stderr}"
    );
    // Frame 1: the brow only (AU 1 at 0.2); times from the timecodes at 60 fps.
    assert!(frames[0].starts_with("0.000 AU1=0.20 |"), "{}", frames[0]);
    assert!(frames[1].starts_with("0.017 "), "{}", frames[1]);
    // The last frame (line 13): the smile at 1, the jaw at 0.5, 11 frames after the first.
    let end = &frames[10];
    assert!(end.starts_with("0.183 "), "{end}");
    assert!(
        end.contains("AUL12=1.00") && end.contains("AU26=0.50") && end.contains("jaw="),
        "{end}"
    );
    // L12 moves the subject's left zygomaticus only.
    assert!(end.contains("L_Zygomatic_Major="), "{end}");
    assert!(!end.contains("R_Zygomatic_Major="), "{end}");
}

#[test]
fn frame_rate_and_strict_apply_to_recordings() {
    // The take's frame numbers run 30 to 41: at 50 fps a frame lasts 20 ms.
    let out = play(&[TAKE, "--fps", "50"], None);
    let frames = lines(&out);
    assert!(frames[1].starts_with("0.020 "), "{}", frames[1]);
    // At 30 fps those frame numbers cannot be: every row is refused, naming --fps, instead of
    // time running backwards at each second.
    let out = play(&[TAKE, "--fps", "30"], None);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(lines(&out).last().unwrap(), "played 0 frames, skipped 12");
    assert!(
        stderr.contains(
            "take.csv:2:1: timecode `10:41:07:30.250` frame 30.250 is not below the frame rate 30"
        ) && stderr.contains("--fps"),
        "{stderr}"
    );
    let out = play(&[TAKE, "--strict"], None);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("take.csv:10:"));
}

#[test]
fn a_take_on_stdin_plays_as_the_file_does() {
    let take = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join(TAKE)).unwrap();
    let piped = play(&["--stdin"], Some(&take));
    assert!(
        piped.status.success(),
        "{}",
        String::from_utf8_lossy(&piped.stderr)
    );
    let file = play(&[TAKE], None);
    assert_eq!(lines(&piped), lines(&file));
    assert_eq!(lines(&piped).last().unwrap(), "played 11 frames, skipped 1");
}

#[test]
fn json_lines_accept_arkit_names() {
    let input = b"{\"mouthSmile_L\": 0.5, \"jawOpen\": 1.0, \"mouthLeft\": 0.3, \"AU1\": 2.5}\n";
    let out = play(&["--stdin"], Some(input));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let frames = lines(&out);
    assert_eq!(frames.last().unwrap(), "played 1 frames, skipped 0");
    // ARKit weights are 0-1; the stream's scale is OpenFace's 0-5.
    let frame = &frames[0];
    assert!(
        frame.contains("AUL12=2.50") && frame.contains("AU26=5.00") && frame.contains("AU1=2.50"),
        "{frame}"
    );
    assert!(
        stderr.contains("mouthLeft") && stderr.contains("no AU"),
        "{stderr}"
    );
}
