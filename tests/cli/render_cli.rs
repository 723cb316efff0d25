//! `grimace render` end to end through the built binary.

use std::process::{Command, Output};

use grimace::facs::combo::parse_combo;
use grimace::io::builtin;
use grimace::model::{BoundRig, SkinRules};
use grimace::render::{render_text, Camera, CellMode, Scene, Style};

fn grimace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(args)
        .env_remove("NO_COLOR")
        .output()
        .expect("the binary runs")
}

fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("UTF-8 output")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn text_to_stdout_has_the_requested_size() {
    let out = grimace(&["render", "--au", "12", "--width", "60", "--height", "20"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 20);
    assert!(lines.iter().all(|l| l.chars().count() <= 60));
    assert!(!text.contains('\x1b'), "no colour into a pipe");
    // The very picture the library draws of AU 12 on the built-in face, from the front.
    let (mesh, rig, table) = (
        builtin::default_mesh(),
        builtin::default_rig(),
        builtin::default_table(),
    );
    let act = table.evaluate(&parse_combo("12").unwrap(), &rig).unwrap();
    let mut positions = Vec::new();
    // `grimace render` keeps the skin on the face (docs/model.md)
    BoundRig::bind_with(&rig, &mesh, SkinRules::DEFAULT)
        .unwrap()
        .deform(&act, &mut positions)
        .unwrap();
    let scene = Scene::new(&mesh, &positions).with_rest(&mesh.positions);
    let expected = render_text(
        &scene,
        &Camera::front(),
        Style::Lines,
        CellMode::Braille,
        60,
        20,
    );
    let trimmed = |t: &str| t.lines().map(str::trim_end).collect::<Vec<_>>().join("\n");
    assert_eq!(trimmed(&text), trimmed(&expected));
    assert!(expected
        .chars()
        .any(|c| ('\u{2801}'..='\u{28ff}').contains(&c)));
}

#[test]
fn ascii_text_is_plain_ascii_and_states_differ() {
    let rest = grimace(&["render", "--ascii", "--width", "70", "--height", "30"]);
    let smile = grimace(&[
        "render",
        "--ascii",
        "--expr",
        "happiness",
        "--width",
        "70",
        "--height",
        "30",
    ]);
    let open = grimace(&[
        "render",
        "--ascii",
        "--set",
        "L_Zygomatic_Major=1.5",
        "--jaw",
        "3",
        "--width",
        "70",
        "--height",
        "30",
    ]);
    for out in [&rest, &smile, &open] {
        assert!(out.status.success(), "{}", stderr(out));
        assert!(stdout(out).is_ascii());
        assert_eq!(stdout(out).lines().count(), 30);
    }
    assert_ne!(stdout(&rest), stdout(&smile));
    assert_ne!(stdout(&rest), stdout(&open));
}

#[test]
fn colour_is_forced_or_refused() {
    let out = grimace(&[
        "render",
        "--color",
        "always",
        "--muscles",
        "--width",
        "40",
        "--height",
        "16",
    ]);
    assert!(stdout(&out).contains("\x1b[38;2;"), "24-bit colour escapes");
    let out = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args([
            "render", "--color", "auto", "--width", "40", "--height", "16",
        ])
        .env("NO_COLOR", "1")
        .output()
        .unwrap();
    assert!(!stdout(&out).contains('\x1b'));
}

#[test]
fn views_and_styles_all_render() {
    for style in ["lines", "shaded", "wireframe"] {
        for view in ["front", "side", "three-quarter"] {
            let out = grimace(&[
                "render", "--style", style, "--view", view, "--width", "50", "--height", "20",
            ]);
            assert!(out.status.success(), "{style} {view}: {}", stderr(&out));
            assert!(
                stdout(&out)
                    .chars()
                    .filter(|c| *c != ' ' && *c != '\n')
                    .count()
                    > 50
            );
        }
    }
    let out = grimace(&[
        "render",
        "--yaw",
        "-30",
        "--pitch",
        "10",
        "--half-block",
        "--width",
        "40",
        "--height",
        "20",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains(['▀', '▄', '█']));
}

fn check_svg(svg: &str, w: usize, h: usize) {
    assert!(svg.starts_with("<?xml"));
    assert!(svg.contains(&format!(r#"viewBox="0 0 {w} {h}""#)));
    assert!(svg.trim_end().ends_with("</svg>"));
    let opens = svg.matches("<g").count();
    assert_eq!(opens, svg.matches("</g>").count());
    for tag in svg.split('<').skip(1) {
        let tag = tag.split('>').next().unwrap();
        assert_eq!(
            tag.matches('"').count() % 2,
            0,
            "quotes balanced in <{tag}>"
        );
    }
    assert!(svg.matches("<line ").count() > 50);
}

#[test]
fn svg_and_png_files_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("smile.svg");
    let out = grimace(&[
        "render",
        "--au",
        "12",
        "--width",
        "300",
        "--height",
        "400",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    check_svg(&std::fs::read_to_string(&svg).unwrap(), 300, 400);

    let png_path = dir.path().join("smile.png");
    let out = grimace(&[
        "render",
        "--combo",
        "6+12",
        "--style",
        "shaded",
        "--width",
        "240",
        "--height",
        "320",
        "--out",
        png_path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let file = std::fs::File::open(&png_path).unwrap();
    let reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    assert_eq!((reader.info().width, reader.info().height), (240, 320));
}

#[test]
fn all_renders_every_au_and_expression() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("stimuli");
    let out = grimace(&[
        "render",
        "--all",
        "--out",
        folder.to_str().unwrap(),
        "--width",
        "120",
        "--height",
        "150",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let table = grimace::io::builtin::default_table();
    let expected = table.aus.len() + table.expressions.len();
    let names: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), expected, "{names:?}");
    assert!(names.contains(&"au-12.svg".to_string()));
    assert!(names.contains(&"expr-happiness.svg".to_string()));
    check_svg(
        &std::fs::read_to_string(folder.join("au-12.svg")).unwrap(),
        120,
        150,
    );

    let pngs = dir.path().join("pngs");
    let out = grimace(&[
        "render",
        "--all",
        "--format",
        "png",
        "--out",
        pngs.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "80",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(std::fs::read_dir(&pngs).unwrap().count(), expected);
}

#[test]
fn bad_requests_fail_with_clear_messages() {
    let out = grimace(&["render", "--au", "99"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("99"), "{}", stderr(&out));

    let out = grimace(&["render", "--set", "No_Such_Muscle=1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("No_Such_Muscle"));

    let out = grimace(&["render", "--out", "face.jpg"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("face.jpg"));

    let out = grimace(&["render", "--style", "cubist"]);
    assert_eq!(out.status.code(), Some(2));
    let out = grimace(&["render", "--all"]);
    assert_eq!(out.status.code(), Some(2), "--all needs --out");
    let out = grimace(&["render", "--width", "0"]);
    assert_eq!(out.status.code(), Some(1));
    let out = grimace(&["render", "--table", "/nonexistent/t.au.ron"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("/nonexistent/t.au.ron"));
}
