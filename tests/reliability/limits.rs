//! Inputs built to exhaust memory or the stack: each is refused with a message naming the
//! file (exit status 1 through the binary), never an abort, a stack overflow or a panic.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use grimace::io::obj::parse_obj;
use grimace::io::openface::{OpenFaceReader, RowOutcome, MAX_LINE_BYTES};
use grimace::model::mesh::{MAX_TRIANGLES, MAX_VERTICES};

use crate::common;
use common::grimace_in as grimace;

/// Runs the binary and checks it exits 1 with `grimace COMMAND: FILE...` on stderr.
fn refused(dir: &Path, args: &[&str], file: &str) -> String {
    let out = grimace(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    let command = args[0];
    assert!(
        stderr.starts_with(&format!("grimace {command}: ")),
        "{args:?}: {stderr}"
    );
    assert!(
        stderr.contains(file),
        "{args:?} does not name {file}: {stderr}"
    );
    stderr
}

const DEPTH: usize = 100_000;

/// `open` repeated DEPTH times, then `close` as many times.
fn nest(open: &str, close: &str) -> String {
    let mut text = String::with_capacity(DEPTH * (open.len() + close.len()));
    for _ in 0..DEPTH {
        text.push_str(open);
    }
    for _ in 0..DEPTH {
        text.push_str(close);
    }
    text
}

/// Nesting bombs in every place a RON file of grimace could hold one: as a whole file, as
/// a field's value, as an unknown field's value (skipped without type), in an Option.
fn bombs() -> Vec<(&'static str, String)> {
    let lists = nest("[", "]");
    let tuples = nest("(", ")");
    let maps = nest("{\"a\":", "}");
    let somes = nest("Some(", ")");
    vec![
        ("whole_lists", lists.clone()),
        ("whole_tuples", tuples.clone()),
        ("field", format!("(version: 1, muscles: {lists})")),
        ("unknown_field", format!("(version: 1, extra: {tuples})")),
        ("map", format!("(version: 1, aus: {maps})")),
        ("option", format!("(version: 1, jaw: {somes})")),
    ]
}

#[test]
fn a_ron_nesting_bomb_is_refused_with_a_message_not_a_stack_overflow() {
    let dir = tempfile::tempdir().unwrap();
    for (what, text) in bombs() {
        for ext in ["rig.ron", "au.ron"] {
            let name = format!("{what}.{ext}");
            std::fs::write(dir.path().join(&name), &text).unwrap();
            let stderr = refused(dir.path(), &["validate", &name], &name);
            assert!(stderr.lines().count() == 1, "{name}: {stderr}");
        }
        let name = format!("{what}.timeline.ron");
        std::fs::write(dir.path().join(&name), &text).unwrap();
        refused(dir.path(), &["play", "--headless", &name], &name);
    }
}

#[test]
fn a_ron_nesting_bomb_is_an_error_value_in_the_library() {
    let path = Path::new("bomb.rig.ron");
    for (what, text) in bombs() {
        let err = grimace::io::parse_rig(&text, path).expect_err(what);
        assert_eq!(err.path, path);
        assert!(!err.message.is_empty(), "{what}");
        let err = grimace::io::parse_table(&text, path).expect_err(what);
        assert!(!err.message.is_empty(), "{what}");
        let err = grimace::io::timeline::parse_timeline(&text, path).expect_err(what);
        assert!(!err.message.is_empty(), "{what}");
    }
}

#[test]
fn one_face_with_more_corners_than_the_triangle_limit_is_refused() {
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    for _ in 0..MAX_TRIANGLES + 3 {
        text.push_str(" 1");
    }
    text.push('\n');
    let err = parse_obj(&text, Path::new("fan.obj")).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "fan.obj:4:1: more than {MAX_TRIANGLES} triangles; grimace refuses meshes this large"
        )
    );
}

#[test]
fn faces_declared_line_by_line_past_the_triangle_limit_are_refused() {
    // Each line fans into 7998 triangles; the limit is crossed on line 3 + 1001.
    let corners = 8000;
    let mut face = String::from("f");
    for i in 0..corners {
        let _ = write!(face, " {}", 1 + i % 3);
    }
    face.push('\n');
    let lines = MAX_TRIANGLES / (corners - 2) + 1;
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for _ in 0..lines {
        text.push_str(&face);
    }
    let err = parse_obj(&text, Path::new("many.obj")).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "many.obj:{}:1: more than {MAX_TRIANGLES} triangles; grimace refuses meshes this large",
            3 + lines
        )
    );
}

#[test]
fn vertices_past_the_vertex_limit_are_refused() {
    let text = "v 0 0 0\n".repeat(MAX_VERTICES + 1);
    let err = parse_obj(&text, Path::new("cloud.obj")).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "cloud.obj:{}:1: more than {MAX_VERTICES} vertices; grimace refuses meshes this large",
            MAX_VERTICES + 1
        )
    );
}

#[test]
fn a_face_index_past_the_vertex_limit_is_refused_before_any_allocation() {
    let text = format!("v 0 0 0\nf 1 1 {}\n", u64::MAX);
    let err = parse_obj(&text, Path::new("far.obj")).unwrap_err();
    assert_eq!(err.line, Some(2));
    assert_eq!(err.column, Some(7));
    assert!(err.message.contains("is not a face corner"), "{err}");
    let text = format!("v 0 0 0\nf 1 1 {}\n", MAX_VERTICES + 1);
    let err = parse_obj(&text, Path::new("far.obj")).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "far.obj:2:7: vertex index {} is out of range; 1 vertices are defined before this line",
            MAX_VERTICES + 1
        )
    );
}

/// A header of a million columns (about 7 MiB): longer than MAX_LINE_BYTES, so refused with
/// its length, read past in bounded memory.
fn million_column_csv(rows: usize) -> String {
    let mut text = String::from("frame,success,AU12_r");
    for i in 0..1_000_000 {
        let _ = write!(text, ",c{i}");
    }
    text.push('\n');
    for row in 0..rows {
        let _ = write!(text, "{},1,2.5", row + 1);
        text.push_str(&",0".repeat(1_000_000));
        text.push('\n');
    }
    text
}

#[test]
fn a_csv_header_of_a_million_columns_is_refused_with_its_length() {
    let text = million_column_csv(2);
    let header = text.lines().next().unwrap().len();
    let err = OpenFaceReader::new(text.as_bytes(), Path::new("wide.csv")).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "wide.csv:1: the header: the line is {header} bytes long, more than the limit of {} MiB (skipped unread)",
            MAX_LINE_BYTES >> 20
        )
    );
}

/// Rows longer than the limit under a usable header are each skipped with their length.
#[test]
fn csv_rows_over_the_line_limit_are_skipped_with_their_length() {
    let mut text = String::from("frame,success,AU12_r\n1,1,2.5\n");
    let long = format!("2,1,2.5{}", ",0".repeat(MAX_LINE_BYTES));
    text.push_str(&long);
    text.push_str("\n3,1,1.5\n");
    let reader = OpenFaceReader::new(text.as_bytes(), Path::new("long.csv")).unwrap();
    let outcomes: Vec<RowOutcome> = reader.map(Result::unwrap).collect();
    assert_eq!(outcomes.len(), 3);
    match &outcomes[1] {
        RowOutcome::Malformed(err) => {
            assert_eq!(err.line, 3);
            assert!(
                err.message
                    .starts_with(&format!("the line is {} bytes long", long.len())),
                "{}",
                err.message
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(&outcomes[2], RowOutcome::Row(r) if r.line == 4 && r.intensities == [1.5]));
}

#[test]
fn play_of_a_million_column_csv_does_not_crash() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("wide.csv"), million_column_csv(3)).unwrap();
    let out = grimace(dir.path(), &["play", "--headless", "wide.csv"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(matches!(out.status.code(), Some(0 | 1)), "{stderr}");
    if out.status.code() == Some(1) {
        assert!(stderr.starts_with("grimace play: "), "{stderr}");
    }
}

#[test]
fn a_huge_timeline_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let name = "huge.timeline.ron";
    // A sparse file far larger than memory: read whole, it would abort the process.
    let file = std::fs::File::create(dir.path().join(name)).unwrap();
    file.set_len(1 << 40).unwrap();
    let stderr = refused(dir.path(), &["play", "--headless", name], name);
    assert!(stderr.contains("the file is too large"), "{stderr}");
}

#[test]
fn a_huge_csv_is_streamed_not_read_whole() {
    let dir = tempfile::tempdir().unwrap();
    let name = "huge.csv";
    // A sparse file of NUL bytes: one endless line, cut and dropped as it streams by. Only
    // the first 64 MiB are used so the test stays quick.
    let file = std::fs::File::create(dir.path().join(name)).unwrap();
    file.set_len(64 << 20).unwrap();
    let out = grimace(dir.path(), &["play", "--headless", name]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with(&format!("grimace play: {name}")),
        "{stderr}"
    );
}

/// One 48 MB line in an OBJ (an ignored statement, a vertex or a group with endless extra
/// values) is read in a fraction of its size: only the tokens a statement uses are kept.
/// Run under a 400 MB address-space limit, which keeping every token (about 12 bytes per
/// byte of text) would exceed.
#[test]
fn one_huge_obj_line_is_read_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let tail = " 1".repeat(24_000_000);
    for (name, keyword) in [("vt.obj", "vt"), ("v.obj", "v 0 0 0"), ("g.obj", "g mouth")] {
        std::fs::write(dir.path().join(name), format!("{head}{keyword}{tail}\n")).unwrap();
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!(
                "ulimit -v 400000 && exec '{}' validate {name}",
                env!("CARGO_BIN_EXE_grimace")
            ))
            .current_dir(dir.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{name}: {stderr}");
        let vertices = if name == "v.obj" { 4 } else { 3 };
        assert_eq!(
            String::from_utf8_lossy(&out.stdout).trim_end(),
            format!("{name}: ok (mesh: {vertices} vertices, 1 triangles)")
        );
    }
}

/// A rig of `count` centre sphincters spanning the whole built-in face.
fn rig_of_sphincters(count: usize) -> String {
    let mut text = String::from("(version: 2, mesh: \"builtin:face\", muscles: [\n");
    for i in 0..count {
        let _ = writeln!(
            text,
            "(name: \"m{i}\", side: Centre, kind: Sphincter(centre: (0.0, 0.0, 0.0), \
             semi_major: 100.0, semi_minor: 100.0, convergence: Centre, bulge: 0.1)),"
        );
    }
    text.push_str("])\n");
    text
}

/// Each muscle keeps a field over the vertices it moves: 20 000 muscles over the whole face
/// (a 3 MB file) took about 2.6 GB, 200 000 would need tens of gigabytes. Refused by count,
/// before binding.
#[test]
fn a_rig_with_too_many_muscles_is_refused_before_binding() {
    use grimace::io::rig_file::MAX_MUSCLES;
    let dir = tempfile::tempdir().unwrap();
    let name = "crowd.rig.ron";
    std::fs::write(dir.path().join(name), rig_of_sphincters(20_000)).unwrap();
    let stderr = refused(dir.path(), &["validate", name], name);
    assert_eq!(
        stderr.trim_end(),
        format!(
            "grimace validate: {name}:1:36: the rig has 20000 muscles, more than the limit of {MAX_MUSCLES}"
        )
    );
    // At the limit the rig loads and binds.
    let name = "full.rig.ron";
    std::fs::write(dir.path().join(name), rig_of_sphincters(MAX_MUSCLES)).unwrap();
    let out = grimace(dir.path(), &["validate", name]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
