//! Categorical cell maps (the stress study's stability map): panels of
//! coloured cells under one legend.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::{err, Figure, FONT};

/// One panel of a [`CellMap`]: a grid of coloured cells, `rows` top to bottom
/// and `x_ticks` left to right.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct MapPanel {
    /// Caption above the grid.
    pub(crate) title: String,
    /// Column labels, left to right.
    pub(crate) x_ticks: Vec<String>,
    /// Row labels, top to bottom.
    pub(crate) rows: Vec<String>,
    /// Each row's palette slot (colour and marker shape, drawn beside its
    /// label, as the row's series look in the line figures), if it has one.
    pub(crate) row_slots: Vec<Option<usize>>,
    /// `cells[row][col]`: class index into [`CellMap::classes`] and a short
    /// text drawn in the cell; `None` = not run (left blank).
    pub(crate) cells: Vec<Vec<Option<(usize, String)>>>,
    /// Vertical markers at fractional column positions (0 = left edge of the
    /// first column), e.g. a limit that falls between two columns.
    pub(crate) marks: Vec<(f64, String)>,
}

/// Panels of categorical cells sharing one legend (`classes`: label and RGB).
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct CellMap {
    /// Caption of the figure.
    pub(crate) title: String,
    /// Label under every panel's columns.
    pub(crate) x_label: String,
    /// Legend entries: label and RGB colour, indexed by the cells' class.
    pub(crate) classes: Vec<(String, [u8; 3])>,
    /// The grids, row by row of the figure.
    pub(crate) panels: Vec<MapPanel>,
    /// Panels per row of the figure (≥ 1).
    pub(crate) columns: usize,
}

const MAP_CELL_W: u32 = 58;
const MAP_CELL_H: u32 = 24;
const MAP_ROW_LABEL_W: u32 = 100;
const MAP_PANEL_TITLE_H: u32 = 46;
const MAP_PANEL_FOOT_H: u32 = 58;
const MAP_HEADER_H: u32 = 50;
const MAP_MARGIN: u32 = 20;

impl CellMap {
    fn panel_size(&self) -> (u32, u32) {
        let cols = self
            .panels
            .iter()
            .map(|p| p.x_ticks.len())
            .max()
            .unwrap_or(1) as u32;
        let rows = self.panels.iter().map(|p| p.rows.len()).max().unwrap_or(1) as u32;
        (
            MAP_ROW_LABEL_W + cols.max(1) * MAP_CELL_W + MAP_MARGIN,
            MAP_PANEL_TITLE_H + rows.max(1) * MAP_CELL_H + MAP_PANEL_FOOT_H,
        )
    }

    /// Legend lines: classes packed into lines no wider than the figure.
    fn legend_lines(&self, width: u32) -> Vec<Vec<usize>> {
        let mut lines: Vec<Vec<usize>> = vec![vec![]];
        let mut x = MAP_MARGIN;
        for (i, (label, _)) in self.classes.iter().enumerate() {
            // ~8.5 px per character at 15 px, plus the swatch.
            let w = 40 + (label.chars().count() as u32 * 17) / 2;
            if x + w > width && !lines.last().unwrap().is_empty() {
                lines.push(vec![]);
                x = MAP_MARGIN;
            }
            lines.last_mut().unwrap().push(i);
            x += w;
        }
        lines
    }
}

impl Figure for CellMap {
    fn size(&self) -> (u32, u32) {
        let (pw, ph) = self.panel_size();
        let cols = self.columns.clamp(1, self.panels.len().max(1)) as u32;
        let rows = (self.panels.len() as u32).div_ceil(cols).max(1);
        let w = 2 * MAP_MARGIN + cols * pw;
        let legend = self.legend_lines(w).len() as u32 * 24 + 10;
        (w, MAP_HEADER_H + legend + rows * ph + MAP_MARGIN)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        _raster: bool,
    ) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;
        let (w, _) = self.size();
        let centre = |size: u32, color: RGBColor| {
            (FONT, size)
                .into_font()
                .color(&color)
                .pos(Pos::new(HPos::Center, VPos::Center))
        };
        let left = |size: u32, color: RGBColor| {
            (FONT, size)
                .into_font()
                .color(&color)
                .pos(Pos::new(HPos::Left, VPos::Center))
        };
        let right = |size: u32| {
            (FONT, size)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Right, VPos::Center))
        };
        let px = |v: u32| v as i32;
        root.draw(&Text::new(
            self.title.as_str(),
            (px(w / 2), px(MAP_HEADER_H / 2)),
            centre(24, BLACK),
        ))
        .map_err(err)?;
        // Legend.
        let lines = self.legend_lines(w);
        for (li, line) in lines.iter().enumerate() {
            let y = px(MAP_HEADER_H + li as u32 * 24 + 10);
            let mut x = px(MAP_MARGIN);
            for &i in line {
                let (label, c) = &self.classes[i];
                let col = RGBColor(c[0], c[1], c[2]);
                root.draw(&Rectangle::new([(x, y - 8), (x + 28, y + 8)], col.filled()))
                    .map_err(err)?;
                root.draw(&Rectangle::new(
                    [(x, y - 8), (x + 28, y + 8)],
                    RGBColor(90, 90, 90).stroke_width(1),
                ))
                .map_err(err)?;
                root.draw(&Text::new(label.as_str(), (x + 34, y), left(15, BLACK)))
                    .map_err(err)?;
                x += px(40 + (label.chars().count() as u32 * 17) / 2);
            }
        }
        let top = MAP_HEADER_H + lines.len() as u32 * 24 + 10;
        let (pw, ph) = self.panel_size();
        let cols = self.columns.clamp(1, self.panels.len().max(1));
        for (k, p) in self.panels.iter().enumerate() {
            let x0 = MAP_MARGIN + (k % cols) as u32 * pw;
            let y0 = top + (k / cols) as u32 * ph;
            let gx = x0 + MAP_ROW_LABEL_W;
            let gy = y0 + MAP_PANEL_TITLE_H;
            let ncol = p.x_ticks.len() as u32;
            root.draw(&Text::new(
                p.title.as_str(),
                (
                    px(gx + ncol * MAP_CELL_W / 2),
                    px(y0 + MAP_PANEL_TITLE_H / 2),
                ),
                centre(17, BLACK),
            ))
            .map_err(err)?;
            for (r, name) in p.rows.iter().enumerate() {
                let y = gy + r as u32 * MAP_CELL_H;
                if let Some(slot) = p.row_slots.get(r).copied().flatten() {
                    let c = super::marks::slot_colour(slot);
                    let style = RGBColor(c[0], c[1], c[2]).stroke_width(2);
                    let at = (px(x0) + 10, px(y + MAP_CELL_H / 2));
                    for path in super::marks::marker_paths(slot) {
                        root.draw(&(EmptyElement::at(at) + PathElement::new(path, style)))
                            .map_err(err)?;
                    }
                }
                root.draw(&Text::new(
                    name.as_str(),
                    (px(gx - 8), px(y + MAP_CELL_H / 2)),
                    right(14),
                ))
                .map_err(err)?;
                for c in 0..ncol {
                    let x = gx + c * MAP_CELL_W;
                    let cell = p
                        .cells
                        .get(r)
                        .and_then(|row| row.get(c as usize))
                        .cloned()
                        .flatten();
                    let rect = [(px(x), px(y)), (px(x + MAP_CELL_W), px(y + MAP_CELL_H))];
                    if let Some((class, text)) = cell {
                        let rgb = self.classes.get(class).map_or([200, 200, 200], |x| x.1);
                        root.draw(&Rectangle::new(
                            rect,
                            RGBColor(rgb[0], rgb[1], rgb[2]).filled(),
                        ))
                        .map_err(err)?;
                        if !text.is_empty() {
                            root.draw(&Text::new(
                                text,
                                (px(x + MAP_CELL_W / 2), px(y + MAP_CELL_H / 2)),
                                centre(12, text_on(rgb)),
                            ))
                            .map_err(err)?;
                        }
                    }
                    root.draw(&Rectangle::new(rect, WHITE.stroke_width(1)))
                        .map_err(err)?;
                }
            }
            let gh = p.rows.len() as u32 * MAP_CELL_H;
            for (c, tick) in p.x_ticks.iter().enumerate() {
                root.draw(&Text::new(
                    tick.as_str(),
                    (
                        px(gx + c as u32 * MAP_CELL_W + MAP_CELL_W / 2),
                        px(gy + gh + 11),
                    ),
                    centre(13, BLACK),
                ))
                .map_err(err)?;
            }
            root.draw(&Text::new(
                self.x_label.as_str(),
                (px(gx + ncol * MAP_CELL_W / 2), px(gy + gh + 32)),
                centre(14, RGBColor(60, 60, 60)),
            ))
            .map_err(err)?;
            for (pos, label) in &p.marks {
                if !pos.is_finite() || *pos < 0.0 || *pos > f64::from(ncol) {
                    continue;
                }
                let x = px(gx) + (pos * f64::from(MAP_CELL_W)).round() as i32;
                let line = RGBColor(40, 40, 40).stroke_width(1);
                root.draw(&PathElement::new(
                    vec![(x, px(gy) - 4), (x, px(gy + gh) + 2)],
                    line,
                ))
                .map_err(err)?;
                root.draw(&Text::new(
                    label.as_str(),
                    (x + 3, px(gy) - 10),
                    left(12, BLACK),
                ))
                .map_err(err)?;
            }
        }
        Ok(())
    }
}

/// Black or white text, whichever reads better on `c` (relative luminance).
fn text_on(c: [u8; 3]) -> RGBColor {
    let l = 0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2]);
    if l > 140.0 {
        BLACK
    } else {
        WHITE
    }
}
