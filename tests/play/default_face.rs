//! `grimace play` with no `--rig` or `--table`: the built-in default face, rig and AU table.
//! Each frame's activations must be what the table's own combination evaluation gives.

use crate::play_common;

use std::io::Write;
use std::process::{Output, Stdio};

use grimace::facs::combo::parse_combo;
use grimace::io::builtin;
use play_common::{grimace, shared, stderr};

fn run(args: &[&str], stdin: &[u8]) -> Output {
    let mut child = grimace()
        .arg("play")
        .arg("--headless")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let _ = child.stdin.take().unwrap().write_all(stdin);
    child.wait_with_output().unwrap()
}

/// The activations part of a headless line, as the table evaluates `combo` on the default rig.
fn expected(combo: &str) -> String {
    let rig = builtin::default_rig();
    let table = builtin::default_table();
    let act = table.evaluate(&parse_combo(combo).unwrap(), &rig).unwrap();
    let mut out = String::new();
    for (muscle, value) in rig.muscles.iter().zip(&act.muscles) {
        if value.abs() >= 0.005 {
            out.push_str(&format!(" {}={value:.2}", muscle.name));
        }
    }
    if act.jaw.abs() >= 0.005 {
        out.push_str(&format!(" jaw={:.2}", act.jaw));
    }
    out
}

#[test]
fn intensities_scale_recorded_aus_like_the_table_does() {
    let input = concat!(
        "{\"timestamp\": 0, \"AU12\": 5}\n",
        "{\"timestamp\": 1, \"AU6\": 2.5, \"AU12\": 5}\n",
        "{\"timestamp\": 2, \"AU1\": 1, \"AU2\": 2, \"AU26\": 4}\n",
        "{\"timestamp\": 3, \"AU4\": 5, \"AU15\": 5, \"AU17\": 5}\n",
    );
    let out = run(&["--stdin"], input.as_bytes());
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout.clone()).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let cases = ["12", "6@0.5+12", "1@0.2+2@0.4+26@0.8", "4+15+17"];
    for (line, combo) in lines.iter().zip(cases) {
        let activations = line.split_once(" |").unwrap().1;
        assert_eq!(activations, expected(combo), "{combo}: {line}");
        assert!(!activations.is_empty());
    }
    assert_eq!(lines[4], "played 4 frames, skipped 0");
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
}

#[test]
fn every_openface_sample_plays_on_the_default_face() {
    let cases = [
        (
            "facsvatar_demo_faceid.csv",
            false,
            "played 490 frames, skipped 0",
        ),
        (
            "unityhdrp_ok_nod_test.csv",
            false,
            "played 20 frames, skipped 5",
        ),
        (
            "pyfeat_OpenFace_Test.csv",
            false,
            "played 100 frames, skipped 0",
        ),
        (
            "facsvatar_demo_clean.csv",
            true,
            "played 490 frames, skipped 0",
        ),
    ];
    for (name, scale, summary) in cases {
        let Some(path) = shared(&format!("openface-samples/{name}")) else {
            return;
        };
        let path = path.display().to_string();
        let mut args = vec![path.as_str()];
        if scale {
            args.push("--scale");
        }
        let out = run(&args, b"");
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let text = String::from_utf8(out.stdout.clone()).unwrap();
        assert_eq!(text.lines().last(), Some(summary), "{name}");
        // The default table records all 17 AUs OpenFace reports: nothing to warn about, at
        // most the count of rows where OpenFace found no face.
        let err = stderr(&out);
        assert!(
            err.is_empty()
                || (err.lines().count() == 1
                    && err.ends_with(" untracked (no face found, success 0)\n")),
            "{name}: {err}"
        );
    }
}

#[test]
fn builtin_names_and_custom_rig_without_table() {
    let out = run(
        &[
            "--stdin",
            "--rig",
            "builtin:default",
            "--table",
            "builtin:default",
        ],
        b"{\"AU12\": 5}",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let out = run(&["--stdin", "--rig", "builtin:nope"], b"");
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("no built-in rig named `nope`"),
        "{}",
        stderr(&out)
    );
    // The paper rig lacks muscles the default table uses.
    let out = run(&["--stdin", "--rig", "builtin:paper"], b"");
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("give --table"), "{}", stderr(&out));
}
