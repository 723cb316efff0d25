//! SVG and PNG output.

use glam::Vec3;
use grimace::model::Mesh;
use grimace::render::png::{canvas_to_png, render_png, PngError};
use grimace::render::svg::render_svg;
use grimace::render::{Camera, DotCanvas, Layer, Rgb, Scene, Style};

/// An octahedron with outward normals.
fn octahedron() -> Mesh {
    let positions = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let triangles = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    Mesh::new(positions, triangles).unwrap()
}

/// A minimal XML check: one root `svg` element, every tag closed in order, attributes
/// quoted, and the viewBox as asked.
fn check_svg(svg: &str, width: usize, height: usize) -> Vec<String> {
    let body = svg
        .trim_start()
        .strip_prefix("<?xml")
        .expect("xml declaration");
    let body = &body[body.find("?>").expect("declaration end") + 2..];
    let mut stack: Vec<String> = Vec::new();
    let mut elements = Vec::new();
    let mut rest = body;
    let mut roots = 0;
    while let Some(start) = rest.find('<') {
        assert!(
            rest[..start].trim().is_empty(),
            "stray text {:?}",
            &rest[..start]
        );
        let end = rest[start..].find('>').expect("unclosed tag") + start;
        let tag = &rest[start + 1..end];
        rest = &rest[end + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(
                stack.pop().as_deref(),
                Some(name.trim()),
                "mismatched </{name}>"
            );
            continue;
        }
        let self_closing = tag.ends_with('/');
        let tag = tag.trim_end_matches('/');
        let name = tag.split_whitespace().next().expect("tag name").to_string();
        assert_eq!(
            tag.matches('"').count() % 2,
            0,
            "unbalanced quotes in <{tag}>"
        );
        if stack.is_empty() {
            roots += 1;
            assert_eq!(name, "svg");
            assert!(
                tag.contains(&format!(r#"viewBox="0 0 {width} {height}""#)),
                "{tag}"
            );
        }
        elements.push(name.clone());
        if !self_closing {
            stack.push(name);
        }
    }
    assert!(
        rest.trim().is_empty() && stack.is_empty(),
        "unclosed {stack:?}"
    );
    assert_eq!(roots, 1);
    elements
}

#[test]
fn svg_is_well_formed_with_visible_lines() {
    let mesh = octahedron();
    let scene = Scene::new(&mesh, &mesh.positions);
    for style in [Style::Lines, Style::Wireframe, Style::Shaded] {
        let svg = render_svg(&scene, &Camera::three_quarter(), style, 320, 240);
        let elements = check_svg(&svg, 320, 240);
        let lines = elements.iter().filter(|e| *e == "line").count();
        let polygons = elements.iter().filter(|e| *e == "polygon").count();
        match style {
            Style::Shaded => assert!((3..=5).contains(&polygons), "{polygons} faces seen"),
            // The octahedron seen from a general direction shows 4 faces; wireframe and lines
            // draw their edges (at least the 6 outline edges).
            _ => assert!(lines >= 6, "{style}: {lines} lines"),
        }
        for (i, _) in svg.match_indices("x1=\"") {
            let v: f32 = svg[i + 4..].split('"').next().unwrap().parse().unwrap();
            assert!((0.0..=320.0).contains(&v));
        }
    }
}

#[test]
fn svg_of_nothing_is_still_well_formed() {
    let empty = Mesh::default();
    let scene = Scene::new(&empty, &[]);
    check_svg(
        &render_svg(&scene, &Camera::front(), Style::Lines, 0, 0),
        0,
        0,
    );
}

fn decode(bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("valid PNG header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("valid PNG data");
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn png_decodes_to_the_requested_size() {
    let mesh = octahedron();
    let scene = Scene::new(&mesh, &mesh.positions);
    for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
        for (w, h) in [(64, 48), (640, 700), (1, 1)] {
            let bytes = render_png(&scene, &Camera::front(), style, w, h).unwrap();
            let (pw, ph, data) = decode(&bytes);
            assert_eq!((pw as usize, ph as usize), (w, h));
            assert_eq!(data.len(), w * h * 3);
            if w > 1 {
                let bright = data.chunks(3).filter(|p| p[0] > 100).count();
                assert!(bright > 10, "{style} {w}x{h}: something is drawn");
            }
        }
    }
    assert!(matches!(
        render_png(&scene, &Camera::front(), Style::Lines, 0, 10),
        Err(PngError::BadSize { .. })
    ));
}

#[test]
fn canvas_png_scales_dots() {
    let mut canvas = DotCanvas::new(3, 2);
    canvas.plot(1, 1, Rgb(255, 0, 0), Layer::Mesh);
    let (w, h, data) = decode(&canvas_to_png(&canvas, 4, Rgb(0, 0, 0)).unwrap());
    assert_eq!((w, h), (12, 8));
    let at = |x: usize, y: usize| &data[(y * 12 + x) * 3..(y * 12 + x) * 3 + 3];
    assert_eq!(at(5, 5), &[255, 0, 0]);
    assert_eq!(at(3, 5), &[0, 0, 0]);
}
