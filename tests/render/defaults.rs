//! `grimace render` picks the style that reads best per format when none is asked for:
//! feature lines for text, shaded for PNG, shaded under feature lines for SVG.

use super::common::grimace_in;

fn grey_levels_of_png(bytes: &[u8]) -> usize {
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("valid PNG header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("valid PNG data");
    buf.truncate(info.buffer_size());
    let levels: std::collections::BTreeSet<&[u8]> = buf.chunks(3).collect();
    levels.len()
}

#[test]
fn images_default_to_shaded_and_text_to_lines() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["render", "--out", "auto.png"][..],
        &["render", "--out", "shaded.png", "--style", "shaded"],
        &["render", "--out", "lines.png", "--style", "lines"],
        &["render", "--out", "auto.svg"],
        &["render", "--out", "lines.svg", "--style", "lines"],
    ] {
        let out = grimace_in(dir.path(), args);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("auto.png"), read("shaded.png"));
    assert!(
        grey_levels_of_png(&read("auto.png")) > 4 * grey_levels_of_png(&read("lines.png")),
        "a shaded PNG has many more tones than a line drawing"
    );
    let svg = String::from_utf8(read("auto.svg")).unwrap();
    let lines_svg = String::from_utf8(read("lines.svg")).unwrap();
    assert!(svg.matches("<polygon").count() > 1000, "shaded triangles");
    let lines = svg.matches("<line").count();
    assert!(
        lines > 100 && lines == lines_svg.matches("<line").count(),
        "the feature lines over the shading: {lines}"
    );
    let text = grimace_in(dir.path(), &["render", "--color", "never"]);
    let lines_text = grimace_in(
        dir.path(),
        &["render", "--color", "never", "--style", "lines"],
    );
    assert_eq!(text.stdout, lines_text.stdout);
}
