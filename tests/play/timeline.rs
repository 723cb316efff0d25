//! `grimace play` on timelines, end to end.

use crate::play_common;

use play_common::{lines, play_headless, stderr};

const TIMELINE: &str = r#"// a smile that comes and goes
Timeline(
    version: 1,
    frame_rate: 4.0,
    interpolation: INTERP,
    keyframes: [
        (time: 0.0),
        (time: 1.0, aus: "12@0.5"),
        (time: 1.5, aus: "smile", jaw: 1.0),
        (time: 2.0, muscles: {"brow": 0.5}),
    ],
)
"#;

fn play(interpolation: &str) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("smile.timeline.ron");
    std::fs::write(&path, TIMELINE.replace("INTERP", interpolation)).unwrap();
    let out = play_headless(dir.path(), &[path.to_str().unwrap()], None);
    assert!(out.status.success(), "{}", stderr(&out));
    lines(&out)
}

#[test]
fn linear_timeline_sampled_at_its_frame_rate() {
    assert_eq!(
        play("Linear"),
        vec![
            "0.000 | rest",
            "0.250 | cheek=0.06 mouth=0.25",
            "0.500 | cheek=0.12 mouth=0.50",
            "0.750 | cheek=0.19 mouth=0.75",
            // 12@0.5: cheek 0.25, mouth 1.0
            "1.000 | cheek=0.25 mouth=1.00",
            // half way to smile (6+12: cheek 1.5, mouth 2.0) with jaw 1.0
            "1.250 | cheek=0.88 mouth=1.50 jaw=0.50",
            "1.500 | cheek=1.50 mouth=2.00 jaw=1.00",
            "1.750 | brow=0.25 cheek=0.75 mouth=1.00 jaw=0.50",
            "2.000 | brow=0.50",
            "played 9 frames, skipped 0",
        ]
    );
}

#[test]
fn step_timeline_holds_each_keyframe() {
    let lines = play("Step");
    assert_eq!(lines.len(), 10);
    assert_eq!(lines[3], "0.750 | rest");
    assert_eq!(lines[5], "1.250 | cheek=0.25 mouth=1.00");
    assert_eq!(lines[8], "2.000 | brow=0.50");
}

#[test]
fn smooth_timeline_eases() {
    let lines = play("Smooth");
    // smoothstep(0.25) = 0.15625: mouth 0.156
    assert_eq!(lines[1], "0.250 | cheek=0.04 mouth=0.16");
    assert_eq!(lines[2], "0.500 | cheek=0.12 mouth=0.50");
}

#[test]
fn timeline_errors_name_file_line_and_keyframe() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.timeline.ron");
    let cases = [
        (TIMELINE.replace("INTERP", "Bouncy"), "bad.timeline.ron:5:"),
        (
            TIMELINE
                .replace("INTERP", "Linear")
                .replace("\"smile\"", "\"99\""),
            "keyframe 3 (time 1.5): the table has no AU 99",
        ),
        (
            TIMELINE
                .replace("INTERP", "Linear")
                .replace("\"brow\"", "\"nose\""),
            "keyframe 4 (time 2): the rig has no muscle named `nose`",
        ),
        (
            TIMELINE
                .replace("INTERP", "Linear")
                .replace("time: 1.5", "time: 0.5"),
            "keyframe 3 (time 0.5): times must not go backwards",
        ),
    ];
    for (text, expected) in cases {
        std::fs::write(&path, text).unwrap();
        let out = play_headless(dir.path(), &[path.to_str().unwrap()], None);
        assert_eq!(out.status.code(), Some(1));
        assert!(
            stderr(&out).contains(expected),
            "{expected}: {}",
            stderr(&out)
        );
        assert!(lines(&out).is_empty());
    }
}
