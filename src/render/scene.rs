//! What to draw: the mesh in its current pose, options, and overlays (muscles, jaw pivot).

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use super::canvas::Rgb;
use crate::model::{Mesh, MuscleKind, Rig};

/// How the mesh surface is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Style {
    /// Every visible edge of the mesh. Honest about the topology, but a dense mesh turns
    /// into a blot at terminal resolution.
    Wireframe,
    /// Feature lines: silhouette, mesh borders (eyes, mouth, rim), creases and a few
    /// iso-depth contours. The default: it keeps eyes, nose and mouth distinct at 80x24.
    #[default]
    Lines,
    /// A Lambert-lit surface, dithered into dots (4x4 ordered dither) on braille and ASCII
    /// canvases.
    Shaded,
}

impl Style {
    /// All styles, in the order a key cycles through them.
    pub const ALL: [Style; 3] = [Style::Lines, Style::Shaded, Style::Wireframe];

    /// The lower-case name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Style::Wireframe => "wireframe",
            Style::Lines => "lines",
            Style::Shaded => "shaded",
        }
    }

    /// The next style in [`Style::ALL`] (for a toggle key).
    pub fn next(self) -> Style {
        let i = Style::ALL.iter().position(|&s| s == self).unwrap_or(0);
        Style::ALL[(i + 1) % Style::ALL.len()]
    }
}

impl fmt::Display for Style {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Style {
    type Err = String;

    fn from_str(s: &str) -> Result<Style, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "wireframe" | "wire" => Ok(Style::Wireframe),
            "lines" | "line" | "features" => Ok(Style::Lines),
            "shaded" | "shade" => Ok(Style::Shaded),
            other => Err(format!(
                "unknown style `{other}` (expected wireframe, lines or shaded)"
            )),
        }
    }
}

/// Which way the mesh's triangle winding points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Orientation {
    /// Decide from the rest pose: most of the surface's right-hand normals point away from
    /// the mesh's centroid (outward) or toward it (inward).
    #[default]
    Auto,
    /// Right-hand normals point out of the head (the built-in face).
    Outward,
    /// Right-hand normals point into the head (the classic Waters mesh).
    Inward,
}

/// The colours of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Palette {
    /// Mesh lines and the lit surface.
    pub mesh: Rgb,
    /// Iso-depth contour lines (dimmer than the mesh).
    pub contour: Rgb,
    /// The rest pose ghost.
    pub ghost: Rgb,
    /// Linear muscles.
    pub linear: Rgb,
    /// Sphincter muscles.
    pub sphincter: Rgb,
    /// Sheet muscles.
    pub sheet: Rgb,
    /// The jaw pivot.
    pub pivot: Rgb,
    /// The selected muscle.
    pub selected: Rgb,
}

impl Default for Palette {
    fn default() -> Palette {
        Palette {
            mesh: Rgb(225, 225, 225),
            contour: Rgb(150, 150, 160),
            ghost: Rgb(90, 90, 110),
            linear: Rgb(230, 80, 70),
            sphincter: Rgb(240, 170, 60),
            sheet: Rgb(200, 110, 220),
            pivot: Rgb(80, 200, 240),
            selected: Rgb(255, 255, 60),
        }
    }
}

/// A shape drawn over the mesh, in mesh coordinates, always visible (muscles lie under the
/// skin, so they are not hidden by it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// A straight segment (a linear muscle from attachment to insertion).
    Segment {
        /// Start (the attachment), marked with a small cross.
        from: Vec3,
        /// End (the insertion).
        to: Vec3,
    },
    /// An ellipse (a sphincter), in the plane of its two semi-axes.
    Ellipse {
        /// Centre.
        centre: Vec3,
        /// The semi-major axis, as a vector from the centre.
        semi_x: Vec3,
        /// The semi-minor axis, as a vector from the centre.
        semi_y: Vec3,
    },
    /// A closed quadrilateral through four corners in order (a sheet muscle).
    Quad {
        /// The corners, in drawing order.
        corners: [Vec3; 4],
    },
    /// A point, drawn as a small cross (the jaw pivot).
    Point {
        /// Where.
        at: Vec3,
    },
}

/// A shape with its colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlay {
    /// The geometry.
    pub shape: Shape,
    /// The colour.
    pub color: Rgb,
    /// Drawn on the selected layer (wins the cell colour over other overlays).
    pub selected: bool,
}

/// Appends one overlay per muscle of `rig` (segments, ellipses, quads) and a point for the
/// jaw pivot, coloured by kind; muscle `selected` gets the palette's highlight colour.
pub fn muscle_overlays(
    rig: &Rig,
    selected: Option<usize>,
    palette: &Palette,
    out: &mut Vec<Overlay>,
) {
    for (i, muscle) in rig.muscles.iter().enumerate() {
        let (shape, color) = match &muscle.kind {
            MuscleKind::Linear(l) => (
                Shape::Segment {
                    from: l.attachment,
                    to: l.insertion,
                },
                palette.linear,
            ),
            MuscleKind::Sphincter(s) => (
                Shape::Ellipse {
                    centre: s.centre,
                    semi_x: s.frame.axis_x() * s.semi_major,
                    semi_y: s.frame.axis_y() * s.semi_minor,
                },
                palette.sphincter,
            ),
            MuscleKind::Sheet(s) => (
                Shape::Quad {
                    corners: [
                        s.attachment[0],
                        s.attachment[1],
                        s.insertion[1],
                        s.insertion[0],
                    ],
                },
                palette.sheet,
            ),
        };
        let is_selected = selected == Some(i);
        out.push(Overlay {
            shape,
            color: if is_selected { palette.selected } else { color },
            selected: is_selected,
        });
    }
    if let Some(jaw) = &rig.jaw {
        out.push(Overlay {
            shape: Shape::Point { at: jaw.pivot },
            color: palette.pivot,
            selected: false,
        });
    }
}

/// The default facing contours: one line where the surface turns about 60 degrees away.
pub const DEFAULT_FACING_CONTOURS: &[f32] = &[0.5];

/// Everything one frame shows.
#[derive(Debug, Clone, Copy)]
pub struct Scene<'a> {
    /// The mesh: its triangles (and, when `rest` is `None`, its rest positions).
    pub mesh: &'a Mesh,
    /// The current (deformed) positions, one per mesh vertex.
    pub positions: &'a [Vec3],
    /// The rest pose, for the ghost, the displacement colours and a framing that does not
    /// move as the face deforms. `None` uses `mesh.positions`.
    pub rest: Option<&'a [Vec3]>,
    /// The points the view is fitted to (the face region of a bigger mesh, see
    /// [`super::Framing`]); `None` fits the whole rest pose.
    pub focus: Option<&'a [Vec3]>,
    /// Irises the shaded style paints on blank eyes (see [`super::framing::Iris`]); set by
    /// [`Scene::with_framing`].
    pub irises: &'a [super::framing::Iris],
    /// Shapes drawn on top.
    pub overlays: &'a [Overlay],
    /// Draw the rest pose's outline faintly where the mesh leaves dots dark.
    pub ghost: bool,
    /// Colour mesh lines by how far their vertices moved from rest.
    pub displacement: bool,
    /// The displacement drawn in the hottest colour, as a fraction of the rest pose's bounding
    /// box diagonal.
    pub displacement_full: f32,
    /// Which way the winding points.
    pub orientation: Orientation,
    /// Colours.
    pub palette: Palette,
    /// Feature lines: edges whose two faces meet at more than this angle (degrees) are drawn.
    pub crease_degrees: f32,
    /// Feature lines: how many iso-depth contours to draw across the mesh's depth.
    pub contours: usize,
    /// Feature lines: iso-lines of how squarely the surface faces the viewer (the cosine
    /// between vertex normal and view direction, 0 at the silhouette, 1 facing).
    pub facing_contours: &'a [f32],
    /// Millimetres per mesh unit when the caller knows the mesh's scale (the legend then
    /// speaks in millimetres); `None`: mesh units.
    pub mm_per_unit: Option<f32>,
}

impl<'a> Scene<'a> {
    /// A scene of `mesh` posed at `positions`, with default options and no overlays.
    pub fn new(mesh: &'a Mesh, positions: &'a [Vec3]) -> Scene<'a> {
        Scene {
            mesh,
            positions,
            rest: None,
            focus: None,
            irises: &[],
            overlays: &[],
            ghost: false,
            displacement: false,
            displacement_full: 0.04,
            orientation: Orientation::Auto,
            palette: Palette::default(),
            crease_degrees: 40.0,
            contours: 0,
            facing_contours: DEFAULT_FACING_CONTOURS,
            mm_per_unit: None,
        }
    }

    /// The same scene with a rest pose.
    pub fn with_rest(mut self, rest: &'a [Vec3]) -> Scene<'a> {
        self.rest = Some(rest);
        self
    }

    /// The same scene with overlays.
    pub fn with_overlays(mut self, overlays: &'a [Overlay]) -> Scene<'a> {
        self.overlays = overlays;
        self
    }

    /// The rest positions: `rest` if given, else the mesh's own.
    pub fn rest_positions(&self) -> &'a [Vec3] {
        self.rest.unwrap_or(&self.mesh.positions)
    }

    /// The points the view is fitted to: the focus, else the rest pose.
    pub fn framed_points(&self) -> &'a [Vec3] {
        self.focus.unwrap_or_else(|| self.rest_positions())
    }

    /// The same scene fitted to `framing`'s face region (unchanged when it has none), with
    /// its irises.
    pub fn with_framing(self, framing: &'a super::Framing) -> Scene<'a> {
        Scene {
            focus: framing.focus.as_deref().or(self.focus),
            irises: &framing.irises,
            ..self
        }
    }
}

/// The displacement colour ramp: 0.0 (unmoved) blue through green and yellow to 1.0 red.
pub fn displacement_ramp(t: f32) -> Rgb {
    const STOPS: [Rgb; 4] = [
        Rgb(70, 120, 255),
        Rgb(60, 220, 100),
        Rgb(250, 220, 50),
        Rgb(255, 60, 40),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    STOPS[i].mix(STOPS[i + 1], x - i as f32)
}
