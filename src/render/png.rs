//! PNG output: a dot canvas, or a scene rendered at a requested pixel size.

use ::png as png_crate;

use super::camera::Camera;
use super::canvas::{DotCanvas, Rgb};
use super::raster::Renderer;
use super::scene::{Scene, Style};
use super::svg::BACKGROUND;

/// Why a PNG could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PngError {
    /// The requested image has no pixels or is too large.
    #[error("cannot make a {width}x{height} image (each side must be 1 to 16384 pixels)")]
    BadSize {
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
    },
    /// The encoder failed.
    #[error("PNG encoding failed: {0}")]
    Encoding(#[from] png_crate::EncodingError),
}

/// The largest side accepted, in pixels.
pub const MAX_SIDE: usize = 16384;

/// Encodes `canvas` as a PNG, each dot a `dot_size` x `dot_size` block of its colour on
/// `background`.
pub fn canvas_to_png(
    canvas: &DotCanvas,
    dot_size: usize,
    background: Rgb,
) -> Result<Vec<u8>, PngError> {
    let s = dot_size.max(1);
    let (w, h) = (canvas.width() * s, canvas.height() * s);
    check_size(w, h)?;
    let mut rgb = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        for x in 0..w {
            let c = canvas.color(x / s, y / s).unwrap_or(background);
            rgb.extend_from_slice(&[c.0, c.1, c.2]);
        }
    }
    encode(&rgb, w, h)
}

/// Renders `scene` into a `width` x `height` PNG. Shaded surfaces show grey levels; lines
/// are drawn on a coarser dot grid on large images so they stay visible.
pub fn render_png(
    scene: &Scene,
    camera: &Camera,
    style: Style,
    width: usize,
    height: usize,
) -> Result<Vec<u8>, PngError> {
    render_png_with(
        &mut Renderer::new(scene.mesh),
        scene,
        camera,
        style,
        (width, height),
    )
}

/// [`render_png`] with a renderer already built for the scene's mesh, so many pictures of
/// one mesh (`grimace batch`) build its edges and tones once.
pub fn render_png_with(
    renderer: &mut Renderer,
    scene: &Scene,
    camera: &Camera,
    style: Style,
    (width, height): (usize, usize),
) -> Result<Vec<u8>, PngError> {
    check_size(width, height)?;
    let dot = if style == Style::Shaded {
        1
    } else {
        (width.min(height) / 300).max(1)
    };
    let mut canvas = DotCanvas::new(width.div_ceil(dot), height.div_ceil(dot));
    canvas.dither = false;
    renderer.render(scene, camera, style, &mut canvas);
    let mut rgb = Vec::with_capacity(width * height * 3);
    for y in 0..height {
        for x in 0..width {
            let c = canvas.color(x / dot, y / dot).unwrap_or(BACKGROUND);
            rgb.extend_from_slice(&[c.0, c.1, c.2]);
        }
    }
    encode(&rgb, width, height)
}

fn check_size(width: usize, height: usize) -> Result<(), PngError> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(PngError::BadSize { width, height });
    }
    Ok(())
}

fn encode(rgb: &[u8], width: usize, height: usize) -> Result<Vec<u8>, PngError> {
    let mut out = Vec::new();
    {
        let mut encoder = png_crate::Encoder::new(&mut out, width as u32, height as u32);
        encoder.set_color(png_crate::ColorType::Rgb);
        encoder.set_depth(png_crate::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(rgb)?;
        writer.finish()?;
    }
    Ok(out)
}
