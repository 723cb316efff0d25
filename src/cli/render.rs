//! `grimace render`: one state of the face as braille or ASCII text on stdout, or as an SVG
//! or PNG file; `--all --out DIR` renders every AU and expression of a table, in parallel.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context};
use clap::{Args, ValueEnum};
use glam::Vec3;
use rayon::prelude::*;

use super::export::{self, SourceArgs, Sources, StateArgs};
use crate::io::atomic::{replace_unsynced, write_atomic};
use crate::model::{Activations, BoundRig, Mesh};
use crate::render::{
    muscle_overlays, png, svg, to_ansi, Camera, CellGrid, CellMode, ColorMode, DisplacementLegend,
    Framing, Level, Lod, Overlay, Palette, Renderer, Scene, Style,
};

/// Preset views.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum View {
    /// Facing the subject (the subject's left on the viewer's right).
    Front,
    /// The subject's left profile.
    Side,
    /// Turned 35 degrees toward the subject's left, seen from slightly above.
    ThreeQuarter,
}

/// `--colors`: how text output is coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorChoice {
    /// On a terminal, what it can show ([`crate::tui::term::colors_from_env`], as the editor reads it);
    /// none when stdout is not a terminal or NO_COLOR is set.
    Auto,
    /// This mode, terminal or not (`always` is 24-bit, `never` none).
    Mode(ColorMode),
}

/// Parses `--colors`: `auto`, a colour mode's name as the editor takes it, or `always` and
/// `never`.
fn parse_color_choice(text: &str) -> Result<ColorChoice, String> {
    match text.trim().to_ascii_lowercase().as_str() {
        "always" => Ok(ColorChoice::Mode(ColorMode::TrueColor)),
        "never" => Ok(ColorChoice::Mode(ColorMode::None)),
        other => super::edit::parse_colors(other)
            .map(|c| c.0.map_or(ColorChoice::Auto, ColorChoice::Mode)),
    }
}

/// Output file formats for `--all`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Scalable vector graphics.
    Svg,
    /// PNG image.
    Png,
    /// Text in the cells --cells asks for (braille by default).
    Txt,
}

/// Arguments of `grimace render`.
#[derive(Debug, Args)]
#[command(
    after_help = "Without --rig and --table, the built-in default rig and AU table are used.\n\
Text goes to stdout; --out FILE.svg or FILE.png writes an image (FILE.txt writes the text).\n\
--width/--height are columns and rows for text (default 80x36), pixels for images (default 600x720)."
)]
pub struct RenderArgs {
    /// Rig, mesh and table.
    #[command(flatten)]
    pub source: SourceArgs,
    /// The state to show (the rest state when none is given).
    #[command(flatten)]
    pub state: StateArgs,
    /// An activation CSV (`grimace capture`'s output): render its frame --frame N, its
    /// muscles taken by name onto the rig.
    #[arg(long, value_name = "ACTS.csv", requires = "frame", conflicts_with_all = ["au", "expr", "combo", "set", "jaw", "all"])]
    pub acts: Option<PathBuf>,
    /// The frame of --acts to render (its `frame` column).
    #[arg(long, value_name = "N", requires = "acts")]
    pub frame: Option<u64>,
    /// Render every AU and expression of the table into the folder given by --out.
    #[arg(long, requires = "out", conflicts_with_all = ["au", "expr", "combo", "set", "jaw"])]
    pub all: bool,
    /// File format for --all.
    #[arg(long, value_enum, default_value = "svg", requires = "all")]
    pub format: Format,
    /// How the surface is drawn: lines, shaded or wireframe. By default, what reads best in
    /// each format: feature lines for text, shaded for PNG, shaded under feature lines for SVG.
    #[arg(long, value_parser = parse_style)]
    pub style: Option<Style>,
    /// The preset view.
    #[arg(long, value_enum, default_value = "front")]
    pub view: View,
    /// Turn the head by this many degrees (positive shows the subject's left cheek);
    /// replaces the preset view's yaw.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub yaw: Option<f32>,
    /// Tilt by this many degrees (positive looks down from above); replaces the preset's.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub pitch: Option<f32>,
    /// Magnify the view (1 fits the face).
    #[arg(long, default_value_t = 1.0)]
    pub zoom: f32,
    /// Width: columns for text, pixels for images.
    #[arg(long, value_name = "N")]
    pub width: Option<usize>,
    /// Height: rows for text, pixels for images.
    #[arg(long, value_name = "N")]
    pub height: Option<usize>,
    /// Braille, half-block or ASCII cells for text.
    #[command(flatten)]
    pub cells: super::CellsArgs,
    /// Which way the face stands in its mesh (when the rig would guess wrong).
    #[command(flatten)]
    pub facing: super::FacingArgs,
    /// Colours of text output: auto (on a terminal, what NO_COLOR, TERM, COLORTERM and the
    /// terminal's name say it shows, as the editor reads them; none into a pipe or file),
    /// truecolor, 256 (greys from the 24-step ramp, dithered), 16 or none.
    #[arg(long = "colors", visible_alias = "color", value_name = "MODE", default_value = "auto", value_parser = parse_color_choice)]
    pub color: ColorChoice,
    /// Draw the muscles over the face.
    #[arg(long)]
    pub muscles: bool,
    /// Draw the rest pose faintly behind the face.
    #[arg(long)]
    pub ghost: bool,
    /// Colour the lines by how far the skin moved.
    #[arg(long)]
    pub displacement: bool,
    /// The file to write (format from the extension: .svg, .png, .txt), or the folder for --all.
    #[arg(long, value_name = "FILE|DIR")]
    pub out: Option<PathBuf>,
    /// The deformation.
    #[command(flatten)]
    pub model: export::ModelArgs,
}

fn parse_style(text: &str) -> Result<Style, String> {
    text.parse()
}

/// The text size when none is given.
const TEXT_SIZE: (usize, usize) = (80, 36);
/// The image size when none is given.
const IMAGE_SIZE: (usize, usize) = (600, 720);
/// The largest text size accepted.
const MAX_CELLS: usize = 2000;

/// Everything about how to draw, shared by every picture of a run.
struct Look {
    camera: Camera,
    /// The face's axes and the region the view fits (a bust or body shows its face).
    framing: Framing,
    /// The style asked for; `None`: each format's own (see [`Look::style_for`]).
    style: Option<Style>,
    mode: CellMode,
    colors: ColorMode,
    overlays: Vec<Overlay>,
    ghost: bool,
    displacement: bool,
    /// The mesh's scale when known, for the displacement legend.
    mm_per_unit: Option<f32>,
}

impl Look {
    fn new(args: &RenderArgs, sources: &Sources) -> anyhow::Result<Look> {
        let mut camera = match args.view {
            View::Front => Camera::front(),
            View::Side => Camera::side(),
            View::ThreeQuarter => Camera::three_quarter(),
        };
        if let Some(yaw) = args.yaw {
            camera.yaw = finite("--yaw", yaw)?.to_radians();
        }
        if let Some(pitch) = args.pitch {
            camera.pitch = finite("--pitch", pitch)?.to_radians();
        }
        if !(args.zoom.is_finite() && args.zoom > 0.0) {
            bail!("--zoom {}: must be a positive number", args.zoom);
        }
        camera.zoom = args.zoom;
        let framing = super::framing(&sources.rig, args.facing.basis()?);
        camera.basis = framing.basis;
        let mode = args.cells.mode();
        let mut overlays = Vec::new();
        if args.muscles {
            muscle_overlays(&sources.rig.rig, None, &Palette::default(), &mut overlays);
        }
        Ok(Look {
            camera,
            framing,
            style: args.style,
            mode,
            colors: color_mode(args.color),
            overlays,
            ghost: args.ghost,
            displacement: args.displacement,
            mm_per_unit: crate::io::builtin::mm_per_unit(&sources.rig.mesh),
        })
    }

    /// The style for a format: the one asked for, else feature lines for text and shaded
    /// for images (the SVG adds feature lines over the shading).
    fn style_for(&self, format: Format) -> Style {
        self.style.unwrap_or(match format {
            Format::Txt => Style::Lines,
            Format::Svg | Format::Png => Style::Shaded,
        })
    }

    fn scene<'a>(&'a self, drawn: &Drawn<'a>) -> Scene<'a> {
        let scene = Scene::new(drawn.mesh, drawn.positions)
            .with_rest(&drawn.mesh.positions)
            .with_overlays(&self.overlays)
            .with_framing(&self.framing);
        Scene {
            ghost: self.ghost,
            displacement: self.displacement,
            mm_per_unit: self.mm_per_unit,
            focus: drawn.focus.or(scene.focus),
            ..scene
        }
    }

    /// The level of detail text of `size` cells is drawn from, like the editor's frame of
    /// that size (`None`: the full mesh; images always draw the full mesh).
    fn level<'l>(&self, lod: &'l Lod, format: Format, (w, h): (usize, usize)) -> Option<&'l Level> {
        if format != Format::Txt {
            return None;
        }
        let canvas = self.mode.canvas(w, h);
        lod.choose(
            &self.camera,
            canvas.width(),
            canvas.height(),
            canvas.dot_aspect,
        )
    }
}

/// What a picture draws: a mesh (the full one or a level of detail), its pose, and the
/// points the view fits when they are not the framing's.
struct Drawn<'a> {
    mesh: &'a Mesh,
    positions: &'a [Vec3],
    focus: Option<&'a [Vec3]>,
}

/// The levels of detail of the rig's mesh, for text output (none for images).
fn text_lod(format: Format, sources: &Sources, look: &Look) -> Lod {
    match format {
        Format::Txt => Lod::of_rig(&sources.rig.rig, &sources.rig.mesh, &look.framing),
        Format::Svg | Format::Png => Lod::default(),
    }
}

/// The positions `act` gives the mesh `level` draws: its vertices only, or the whole mesh.
fn deform_for(
    bound: &BoundRig,
    act: &Activations,
    level: Option<&Level>,
) -> anyhow::Result<Vec<Vec3>> {
    match level {
        Some(level) => {
            let mut positions = Vec::new();
            bound.deform_at(act, &level.source, &mut positions)?;
            Ok(positions)
        }
        None => deform(bound, act),
    }
}

impl<'a> Drawn<'a> {
    fn of(mesh: &'a Mesh, level: Option<&'a Level>, positions: &'a [Vec3]) -> Drawn<'a> {
        Drawn {
            mesh: level.map_or(mesh, |l| &l.mesh),
            positions,
            focus: level.map(|l| &l.frame[..]),
        }
    }
}

fn finite(flag: &str, value: f32) -> anyhow::Result<f32> {
    if value.is_finite() {
        Ok(value)
    } else {
        bail!("{flag} {value}: must be a finite number of degrees")
    }
}

fn color_mode(choice: ColorChoice) -> ColorMode {
    match choice {
        ColorChoice::Mode(mode) => mode,
        ColorChoice::Auto if !std::io::stdout().is_terminal() => ColorMode::None,
        ColorChoice::Auto => crate::tui::term::colors_from_env(),
    }
}

/// An output format chosen from a file name's extension.
fn format_of(path: &Path) -> anyhow::Result<Format> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("svg") => Ok(Format::Svg),
        Some("png") => Ok(Format::Png),
        Some("txt") => Ok(Format::Txt),
        _ => bail!(
            "{}: unknown output format (the file name must end in .svg, .png or .txt)",
            path.display()
        ),
    }
}

fn size(args: &RenderArgs, format: Format) -> anyhow::Result<(usize, usize)> {
    let (dw, dh, max) = match format {
        Format::Txt => (TEXT_SIZE.0, TEXT_SIZE.1, MAX_CELLS),
        Format::Svg | Format::Png => (IMAGE_SIZE.0, IMAGE_SIZE.1, png::MAX_SIDE),
    };
    let (w, h) = (args.width.unwrap_or(dw), args.height.unwrap_or(dh));
    if w == 0 || h == 0 || w > max || h > max {
        bail!("--width {w} --height {h}: each must be 1 to {max} for this output");
    }
    Ok((w, h))
}

/// Draws one state in `format` as bytes (text already coloured as `look` asks).
fn picture(
    look: &Look,
    renderer: &mut Renderer,
    drawn: &Drawn,
    format: Format,
    (w, h): (usize, usize),
    colors: ColorMode,
) -> anyhow::Result<Vec<u8>> {
    let scene = look.scene(drawn);
    Ok(match format {
        Format::Txt => {
            let mut canvas = look.mode.canvas(w, h);
            renderer.render(&scene, &look.camera, look.style_for(format), &mut canvas);
            let mut grid = CellGrid::default();
            grid.fill(&canvas, look.mode, colors);
            let mut text = to_ansi(&grid, colors);
            if look.displacement {
                // What the colours stand for, on a line of its own under the face.
                let legend = DisplacementLegend::of(&scene).row(w, colors);
                text.push_str(&to_ansi(&legend, colors));
            }
            text.into_bytes()
        }
        Format::Svg => {
            svg::render_svg(&scene, &look.camera, look.style_for(format), w, h).into_bytes()
        }
        Format::Png => png::render_png(&scene, &look.camera, look.style_for(format), w, h)?,
    })
}

fn deform(bound: &BoundRig, act: &Activations) -> anyhow::Result<Vec<Vec3>> {
    let mut positions = Vec::new();
    bound.deform(act, &mut positions)?;
    Ok(positions)
}

/// The rig, mesh and table `render` draws, bound with the deformation its arguments name.
pub fn load(args: &RenderArgs) -> anyhow::Result<(Sources, BoundRig)> {
    let sources = export::load_sources(&args.source)?;
    let bound = export::bind(&sources.rig, args.model.deformation)?;
    Ok((sources, bound))
}

/// The vertex positions `render` draws for the state its arguments ask for.
pub fn state_positions(
    args: &RenderArgs,
    sources: &Sources,
    bound: &BoundRig,
) -> anyhow::Result<Vec<Vec3>> {
    deform(bound, &state_activations(args, sources)?)
}

/// The activations `render` draws: the frame of `--acts`, or the state `--au`, `--expr`,
/// `--combo` or `--set` ask for.
fn state_activations(args: &RenderArgs, sources: &Sources) -> anyhow::Result<Activations> {
    Ok(match (&args.acts, args.frame) {
        (Some(path), Some(frame)) => {
            let muscles: Vec<String> = sources
                .rig
                .rig
                .muscles
                .iter()
                .map(|m| m.name.clone())
                .collect();
            crate::io::acts::read_frame(path, frame, &muscles)?
        }
        _ => export::activations(&args.state, sources)?,
    })
}

/// Runs `grimace render`.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    // A big head's bind frees blocks the levels of detail would otherwise pile on top of.
    crate::tui::memory::give_back_big_blocks();
    let (sources, bound) = load(args)?;
    let look = Look::new(args, &sources)?;
    if args.all {
        return render_all(args, &sources, &bound, &look);
    }
    let act = state_activations(args, &sources)?;
    let format = match &args.out {
        None => Format::Txt,
        Some(path) => format_of(path)?,
    };
    let size = size(args, format)?;
    if let Some(path) = &args.out {
        sources.inputs().check_output(path)?;
    }
    let lod = text_lod(format, &sources, &look);
    let level = look.level(&lod, format, size);
    let positions = deform_for(&bound, &act, level)?;
    let drawn = Drawn::of(&sources.rig.mesh, level, &positions);
    let mut renderer = Renderer::new(drawn.mesh);
    match &args.out {
        None => {
            let text = picture(&look, &mut renderer, &drawn, format, size, look.colors)?;
            super::print_raw(&text)?;
        }
        Some(path) => {
            // Files never carry colour escapes.
            let bytes = picture(&look, &mut renderer, &drawn, format, size, ColorMode::None)?;
            write_atomic(path, &bytes).map_err(|e| crate::io::SaveError::io(path, &e))?;
        }
    }
    Ok(())
}

/// One picture of `--all`: its file name and the activations.
struct Job {
    file: String,
    act: Activations,
}

fn render_all(
    args: &RenderArgs,
    sources: &Sources,
    bound: &BoundRig,
    look: &Look,
) -> anyhow::Result<()> {
    let dir = args
        .out
        .as_deref()
        .ok_or_else(|| anyhow!("--all needs --out DIR"))?;
    let table = sources
        .table
        .as_ref()
        .ok_or_else(|| anyhow!("--all needs an AU table: pass --table TABLE"))?;
    let rig = &sources.rig.rig;
    let ext = match args.format {
        Format::Svg => "svg",
        Format::Png => "png",
        Format::Txt => "txt",
    };
    let mut jobs = Vec::new();
    let mut names = FileNames::default();
    for key in table.aus.keys() {
        let act = table
            .entry_activations(key, rig)
            .map_err(|e| anyhow!("AU {key}: {e}"))?;
        jobs.push(Job {
            file: names.take(&format!("au-{key}"), ext),
            act,
        });
    }
    // Names that are file names already keep them; the others are changed around them.
    let (plain, changed): (Vec<&String>, Vec<&String>) = table
        .expressions
        .keys()
        .partition(|name| file_safe(name) == **name);
    for name in plain.into_iter().chain(changed) {
        let act = table
            .expression_activations(name, rig)
            .map_err(|e| anyhow!("expression `{name}`: {e}"))?;
        let file = names.take(&format!("expr-{}", file_safe(name)), ext);
        if file != format!("expr-{name}.{ext}") {
            eprintln!(
                "expression `{}` is written as {file}",
                crate::io::printable::printable(name)
            );
        }
        jobs.push(Job { file, act });
    }
    let inputs = sources.inputs();
    for job in &jobs {
        inputs.check_output(&dir.join(&job.file))?;
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
    let size = size(args, args.format)?;
    let lod = text_lod(args.format, sources, look);
    let level = look.level(&lod, args.format, size);
    let mesh = level.map_or(&sources.rig.mesh, |l| &l.mesh);
    jobs.par_iter().try_for_each_init(
        || Renderer::new(mesh),
        |renderer, job| -> anyhow::Result<()> {
            let positions = deform_for(bound, &job.act, level)?;
            let drawn = Drawn::of(&sources.rig.mesh, level, &positions);
            let bytes = picture(look, renderer, &drawn, args.format, size, ColorMode::None)?;
            let path = dir.join(&job.file);
            // A folder of regenerated pictures: each replaced whole, without the two fsyncs
            // per file a synced save costs (they dominated the run time).
            replace_unsynced(&path, &bytes).map_err(|e| crate::io::SaveError::io(&path, &e).into())
        },
    )?;
    eprintln!("rendered {} pictures into {}", jobs.len(), dir.display());
    Ok(())
}

/// A name made safe for a file name: letters, digits, `-` and `_` kept, the rest `_`.
/// The file names of one `--all` run, kept distinct: two names that become the same file
/// name (`a/b` and `a_b`, or `Smile` and `smile` on a file system that ignores case) get
/// `-2`, `-3`, ... on the later ones.
#[derive(Debug, Default)]
struct FileNames {
    taken: std::collections::HashSet<String>,
}

impl FileNames {
    /// A file name `STEM.EXT` not yet taken, taking it.
    fn take(&mut self, stem: &str, ext: &str) -> String {
        let mut file = format!("{stem}.{ext}");
        let mut n = 1;
        while !self.taken.insert(file.to_lowercase()) {
            n += 1;
            file = format!("{stem}-{n}.{ext}");
        }
        file
    }
}

fn file_safe(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_come_from_the_extension() {
        assert_eq!(format_of(Path::new("a/b.SVG")).unwrap(), Format::Svg);
        assert_eq!(format_of(Path::new("b.png")).unwrap(), Format::Png);
        assert_eq!(format_of(Path::new("b.txt")).unwrap(), Format::Txt);
        let err = format_of(Path::new("b.jpg")).unwrap_err().to_string();
        assert!(err.contains("b.jpg") && err.contains(".svg"), "{err}");
        assert!(format_of(Path::new("noext")).is_err());
    }

    #[test]
    fn file_names_are_made_safe() {
        assert_eq!(file_safe("happy face/2"), "happy_face_2");
        assert_eq!(file_safe("anger"), "anger");
    }

    #[test]
    fn file_names_stay_distinct() {
        let mut names = FileNames::default();
        assert_eq!(names.take("expr-a_b", "svg"), "expr-a_b.svg");
        assert_eq!(names.take("expr-a_b", "svg"), "expr-a_b-2.svg");
        assert_eq!(names.take("expr-A_b", "svg"), "expr-A_b-3.svg");
        assert_eq!(names.take("expr-a_b-2", "svg"), "expr-a_b-2-2.svg");
    }
}
