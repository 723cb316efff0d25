//! Helpers shared by the integration tests (`mod common;` in each test file).
#![allow(dead_code)]

pub mod pty;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `grimace` binary with `args` in `dir`, capturing its output. Its bind cache is
/// kept in `dir` (`GRIMACE_CACHE_DIR`), so a test never writes to the user's own cache.
pub fn grimace_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grimace"))
        .args(args)
        .env("GRIMACE_CACHE_DIR", dir.join(".grimace-cache"))
        .current_dir(dir)
        .output()
        .unwrap()
}

/// The shared reference folder: `GRIMACE_SHARED`, else `../shared` beside the package.
fn shared_root() -> PathBuf {
    std::env::var_os("GRIMACE_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"))
}

/// The shared reference folder when every path in `needed` (relative to it) exists.
/// Missing: a panic naming what is missing when `CI=true`, else `None` with the reason
/// printed, so the caller skips.
pub fn shared_with(needed: &[&str]) -> Option<PathBuf> {
    let dir = shared_root();
    let missing: Vec<String> = needed
        .iter()
        .map(|sub| dir.join(sub))
        .filter(|path| !path.exists())
        .map(|path| path.display().to_string())
        .collect();
    if missing.is_empty() {
        return Some(dir);
    }
    let what = missing.join(", ");
    if std::env::var("CI").as_deref() == Ok("true") {
        panic!("shared reference material missing: {what} (CI=true; set GRIMACE_SHARED)");
    }
    eprintln!("skipped: shared reference material missing: {what} (set GRIMACE_SHARED)");
    None
}

/// The shared reference folder with its classic golden outputs and Waters mesh files.
pub fn shared() -> Option<PathBuf> {
    shared_with(&["golden", "waters-geoface"])
}

/// Checks where a render's ink is against where the face lands: every lit dot of `canvas`
/// lies within the box of `points` as `proj` places them (one dot of slack for rounding),
/// and the lit dots reach across at least `span` (0 to 1) of that box both ways, so the
/// face is drawn whole and in its place, not cut off or shifted.
pub fn assert_ink_fills_the_face(
    canvas: &grimace::render::DotCanvas,
    proj: &grimace::render::Projection,
    points: &[glam::Vec3],
    span: f32,
    what: &str,
) {
    let (mut lo, mut hi) = (
        glam::Vec2::splat(f32::INFINITY),
        glam::Vec2::splat(f32::NEG_INFINITY),
    );
    for p in points {
        let p = proj.project(*p).truncate();
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let (mut ink_lo, mut ink_hi) = (
        glam::Vec2::splat(f32::INFINITY),
        glam::Vec2::splat(f32::NEG_INFINITY),
    );
    for y in 0..canvas.height() {
        for x in 0..canvas.width() {
            if canvas.is_on(x, y) {
                let dot = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                assert!(
                    dot.cmpge(lo - 1.0).all() && dot.cmple(hi + 1.0).all(),
                    "{what}: dot ({x}, {y}) is lit outside the face's box {lo}..{hi}"
                );
                ink_lo = ink_lo.min(dot);
                ink_hi = ink_hi.max(dot);
            }
        }
    }
    let (face, ink) = (hi - lo, ink_hi - ink_lo);
    assert!(
        ink.x >= span * face.x && ink.y >= span * face.y,
        "{what}: ink spans {ink} of the face's {face}"
    );
}

/// Whether some dot within `r` dots of `p` (dot coordinates) is lit.
pub fn lit_near(canvas: &grimace::render::DotCanvas, p: glam::Vec2, r: f32) -> bool {
    let (x0, x1) = (
        (p.x - r).floor().max(0.0) as usize,
        (p.x + r).ceil().max(0.0) as usize,
    );
    let (y0, y1) = (
        (p.y - r).floor().max(0.0) as usize,
        (p.y + r).ceil().max(0.0) as usize,
    );
    (y0..=y1).any(|y| {
        (x0..=x1).any(|x| {
            let d = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - p;
            d.length() <= r + 0.71 && canvas.is_on(x, y)
        })
    })
}

/// Writes `text` to `$GRIMACE_RENDER_DUMP/NAME` when that folder is set, to look at renders.
pub fn dump(name: &str, text: &str) {
    if let Some(dir) = std::env::var_os("GRIMACE_RENDER_DUMP") {
        std::fs::write(PathBuf::from(dir).join(name), text).unwrap();
    }
}

/// Renders `mesh` at rest in every style, from the front, side and three-quarter views, at
/// 80x24, 200x60 and 50x38 cells: each braille picture's ink must fill the face (see
/// [`assert_ink_fills_the_face`]) and is handed to `check` with its projection, style,
/// view name and a label for messages; each style's front view in ASCII must be ASCII.
/// Pictures are dumped (see [`dump`]) as `PREFIX-STYLE-VIEW-COLSxROWS.txt`.
pub fn render_every_view(
    mesh: &grimace::model::Mesh,
    prefix: &str,
    mut check: impl FnMut(
        &grimace::render::DotCanvas,
        &grimace::render::Projection,
        grimace::render::Style,
        &str,
        &str,
    ),
) {
    use grimace::render::{render_text, Camera, CellMode, Renderer, Scene, Style};
    let scene = Scene::new(mesh, &mesh.positions);
    let mut renderer = Renderer::new(mesh);
    for (cols, rows) in [(80, 24), (200, 60), (50, 38)] {
        for style in [Style::Lines, Style::Shaded, Style::Wireframe] {
            for (view, camera) in [
                ("front", Camera::front()),
                ("side", Camera::side()),
                ("three", Camera::three_quarter()),
            ] {
                let what = format!("{style} {view} {cols}x{rows}");
                let text = render_text(&scene, &camera, style, CellMode::Braille, cols, rows);
                dump(&format!("{prefix}-{style}-{view}-{cols}x{rows}.txt"), &text);
                let mut canvas = CellMode::Braille.canvas(cols, rows);
                renderer.render(&scene, &camera, style, &mut canvas);
                let proj = camera.fit_points(
                    &mesh.positions,
                    canvas.width(),
                    canvas.height(),
                    canvas.dot_aspect,
                );
                assert_ink_fills_the_face(&canvas, &proj, &mesh.positions, 0.9, &what);
                check(&canvas, &proj, style, view, &what);
            }
            let ascii = render_text(&scene, &Camera::front(), style, CellMode::Ascii, cols, rows);
            dump(&format!("{prefix}-{style}-ascii-{cols}x{rows}.txt"), &ascii);
            assert!(ascii.is_ascii());
        }
    }
}

/// The built-in face written in `dir` as a textured OBJ a user might bring (`head.obj`: a
/// `mtllib`, an object, three texture coordinates and a normal, every face corner
/// `v/vt/vn` under `g face` and `usemtl skin`), with its landmarks beside it, and fitted by
/// `grimace fit-rig` into `head.rig.ron`. Panics with `fit-rig`'s output when it fails.
pub fn fit_textured_head(dir: &Path) {
    let mesh = grimace::io::builtin::default_mesh();
    let mut text = String::from("mtllib head.mtl\no head\n");
    for p in &mesh.positions {
        text.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
    }
    text.push_str("vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\ng face\nusemtl skin\n");
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| v + 1);
        text.push_str(&format!("f {a}/1/1 {b}/2/1 {c}/3/1\n"));
    }
    std::fs::write(dir.join("head.obj"), text).unwrap();
    std::fs::write(
        dir.join("head.landmarks.ron"),
        grimace::io::builtin::DEFAULT_LANDMARKS,
    )
    .unwrap();
    fit_head(dir);
}

/// Runs `grimace fit-rig head.obj --landmarks head.landmarks.ron --out head.rig.ron` in
/// `dir` and returns what it did (for tests that read what it printed).
pub fn fit_head_output(dir: &Path) -> std::process::Output {
    grimace_in(
        dir,
        &[
            "fit-rig",
            "head.obj",
            "--landmarks",
            "head.landmarks.ron",
            "--out",
            "head.rig.ron",
        ],
    )
}

/// [`fit_head_output`], and returns the rig's path. Panics with `fit-rig`'s output when it
/// fails.
pub fn fit_head(dir: &Path) -> PathBuf {
    let fit = fit_head_output(dir);
    assert!(
        fit.status.success(),
        "{}{}",
        String::from_utf8_lossy(&fit.stdout),
        String::from_utf8_lossy(&fit.stderr)
    );
    dir.join("head.rig.ron")
}
