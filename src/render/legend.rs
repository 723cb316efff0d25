//! The displacement colours' legend: the colour ramp with the distances it stands for.

use super::cells::{Cell, CellGrid, ColorMode};
use super::raster::finite_bounds_of;
use super::scene::{displacement_ramp, Scene};

/// What the displacement colours of a scene mean: the distance drawn in the hottest colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplacementLegend {
    /// The displacement drawn in the hottest colour, in mesh units.
    pub full: f32,
    /// Millimetres per mesh unit, when the mesh's scale is known (the built-in face).
    pub mm_per_unit: Option<f32>,
}

impl DisplacementLegend {
    /// The legend of `scene`'s displacement colours: its full-colour fraction of the rest
    /// pose's bounding-box diagonal, in millimetres when the scene's scale is known
    /// ([`Scene::mm_per_unit`]), else mesh units.
    pub fn of(scene: &Scene) -> DisplacementLegend {
        let rest = scene.rest_positions();
        let (lo, hi) = finite_bounds_of(rest);
        DisplacementLegend {
            full: scene.displacement_full * (hi - lo).length(),
            mm_per_unit: scene.mm_per_unit,
        }
    }

    /// A distance in mesh units as the legend writes it: `2.9 mm` or `0.25 units`.
    pub fn label(&self, units: f32) -> String {
        match self.mm_per_unit {
            Some(mm) => format!("{:.1} mm", units * mm),
            None => format!("{:.2} units", units),
        }
    }

    /// One row of `width` cells: `0`, the ramp in coloured blocks, and the full-colour
    /// distance (`+`: and beyond). Without colour the ramp is named in words instead.
    pub fn row(&self, width: usize, colors: ColorMode) -> CellGrid {
        let mut grid = CellGrid::new(width, 1);
        let end = format!(" {}+", self.label(self.full));
        let text: Vec<(char, Option<super::Rgb>)> = if colors == ColorMode::None {
            format!("moved: blue 0, green, yellow, red{end}")
                .chars()
                .map(|c| (c, None))
                .collect()
        } else {
            let ramp = width.saturating_sub(end.chars().count() + 2).clamp(1, 24);
            let mut cells: Vec<_> = "0 ".chars().map(|c| (c, None)).collect();
            for k in 0..ramp {
                let t = k as f32 / (ramp.max(2) - 1) as f32;
                cells.push(('█', Some(displacement_ramp(t))));
            }
            cells.extend(end.chars().map(|c| (c, None)));
            cells
        };
        for (cell, (ch, fg)) in grid.cells.iter_mut().zip(text) {
            *cell = Cell {
                ch,
                fg: fg.and_then(|c| super::reduce(c, colors)),
                bg: None,
            };
        }
        grid
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Mesh;
    use glam::Vec3;

    #[test]
    fn a_known_scale_is_labelled_in_millimetres_else_in_units() {
        let other = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
        let scaled = Scene {
            mm_per_unit: Some(11.5),
            ..Scene::new(&other, &other.positions)
        };
        let legend = DisplacementLegend::of(&scaled);
        let (lo, hi) = other.bounds();
        assert!((legend.full - 0.04 * (hi - lo).length()).abs() < 1e-5);
        assert_eq!(legend.label(1.0), "11.5 mm");
        let legend = DisplacementLegend::of(&Scene::new(&other, &other.positions));
        assert_eq!(legend.mm_per_unit, None);
        assert_eq!(legend.label(0.5), "0.50 units");
    }

    #[test]
    fn the_row_holds_the_ramp_and_the_full_distance() {
        let legend = DisplacementLegend {
            full: 0.25,
            mm_per_unit: Some(11.5),
        };
        let row = legend.row(40, ColorMode::TrueColor);
        let text: String = row.cells.iter().map(|c| c.ch).collect();
        assert!(text.starts_with("0 █"), "{text}");
        assert!(text.trim_end().ends_with("█ 2.9 mm+"), "{text}");
        let colours: Vec<_> = row.cells.iter().filter_map(|c| c.fg).collect();
        assert_eq!(colours.first(), Some(&displacement_ramp(0.0)));
        assert_eq!(colours.last(), Some(&displacement_ramp(1.0)));
        let plain = legend.row(60, ColorMode::None);
        let text: String = plain.cells.iter().map(|c| c.ch).collect();
        assert!(
            text.contains("blue 0") && text.contains("red 2.9 mm+"),
            "{text}"
        );
        assert!(plain.cells.iter().all(|c| c.fg.is_none()));
    }
}
