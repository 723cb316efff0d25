//! SVG output: visible lines as line segments (and, for the shaded style, lit triangles
//! painted back to front under the feature lines), with a viewBox in pixels.

use std::fmt::Write as _;

use super::camera::Camera;
use super::canvas::{DotCanvas, Rgb};
use super::legend::DisplacementLegend;
use super::raster::Renderer;
use super::scene::{displacement_ramp, Scene, Style};

/// The background colour of image output.
pub const BACKGROUND: Rgb = Rgb(16, 16, 16);

/// Renders `scene` as a standalone SVG document of `width` x `height` pixels.
///
/// Lines are hidden-line-removed at pixel resolution, so the SVG shows what the terminal
/// shows, only sharper. A zero size gives an empty (but well-formed) document.
pub fn render_svg(
    scene: &Scene,
    camera: &Camera,
    style: Style,
    width: usize,
    height: usize,
) -> String {
    let mut renderer = Renderer::new(scene.mesh);
    let mut canvas = DotCanvas::new(width, height);
    canvas.dither = false;
    let mut out = String::new();
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}">"#
    );
    let _ = writeln!(
        out,
        r#"<rect width="100%" height="100%" fill="{}"/>"#,
        hex(BACKGROUND)
    );
    if style == Style::Shaded {
        let base = scene.palette.mesh;
        let _ = writeln!(out, r#"<g stroke-width="0.5" stroke-linejoin="round">"#);
        for t in renderer.lit_triangles(scene, camera, width, height, 1.0) {
            let fill = hex(Rgb::default().mix(base, t.shade));
            let [a, b, c] = t.corners;
            let _ = writeln!(
                out,
                r#"<polygon points="{:.2},{:.2} {:.2},{:.2} {:.2},{:.2}" fill="{fill}" stroke="{fill}"/>"#,
                a.x, a.y, b.x, b.y, c.x, c.y
            );
        }
        let _ = writeln!(out, "</g>");
    }
    // Over the shading, the feature lines keep eyes, lids and lips sharp at any scale.
    let line_style = if style == Style::Shaded {
        Style::Lines
    } else {
        style
    };
    let runs = renderer.render_runs(scene, camera, line_style, &mut canvas);
    let _ = writeln!(
        out,
        r#"<g stroke-width="1" stroke-linecap="round" fill="none">"#
    );
    for run in runs {
        let _ = writeln!(
            out,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{}"/>"#,
            run.from.x,
            run.from.y,
            run.to.x,
            run.to.y,
            hex(run.color)
        );
    }
    let _ = writeln!(out, "</g>");
    if scene.displacement {
        legend(&mut out, scene, width, height);
    }
    out.push_str("</svg>\n");
    out
}

/// The displacement colours' scale along the bottom edge: the ramp from `0` to the
/// distance drawn in the hottest colour.
fn legend(out: &mut String, scene: &Scene, width: usize, height: usize) {
    let legend = DisplacementLegend::of(scene);
    let (w, h) = (width as f32, height as f32);
    let bar = (w * 0.4).max(20.0);
    let (x, y) = (w * 0.05, h - 14.0);
    let _ = writeln!(
        out,
        r#"<defs><linearGradient id="displacement" x1="0" x2="1" y1="0" y2="0">"#
    );
    for k in 0..=6 {
        let t = k as f32 / 6.0;
        let _ = writeln!(
            out,
            r#"<stop offset="{t:.3}" stop-color="{}"/>"#,
            hex(displacement_ramp(t))
        );
    }
    let _ = writeln!(out, "</linearGradient></defs>");
    let _ = writeln!(
        out,
        r#"<g font-family="sans-serif" font-size="10" fill="{}"><text x="{:.1}" y="{:.1}" text-anchor="end">0</text><rect x="{x:.1}" y="{:.1}" width="{bar:.1}" height="8" fill="url(#displacement)"/><text x="{:.1}" y="{:.1}">{}+</text></g>"#,
        hex(scene.palette.mesh),
        x - 3.0,
        y + 8.0,
        y,
        x + bar + 3.0,
        y + 8.0,
        legend.label(legend.full)
    );
}

fn hex(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}
