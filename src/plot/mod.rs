//! Chart rendering for the integrator comparisons (energy error vs time,
//! error vs time step, error vs run time) and the stress study's cell map.
//!
//! Charts are written as PNG or SVG, chosen by the file extension. Text is
//! rendered with a bundled copy of DejaVu Sans (`assets/DejaVuSans.ttf`), so
//! no system font libraries are needed.
//!
//! Rendering never panics on odd input: non-finite values (and values ≤ 0 on a
//! log axis) are skipped, lines are broken at such gaps, and a chart with no
//! drawable data is written as empty axes with a note.

mod axis;
mod canvas;
mod cellmap;
mod chart;
mod draw;
mod legend;
mod marks;
mod prepare;

use std::path::Path;

pub use canvas::PlotError;
pub(crate) use cellmap::{CellMap, MapPanel};
pub use chart::{reference_slope, Chart, LegendPos, Series, Style};
pub use marks::{slot_colour, GUIDE_DASHES, MARKER_SHAPES};

/// Width of rendered charts, in pixels.
pub const WIDTH: u32 = 1000;
/// Height of rendered charts, in pixels.
pub const HEIGHT: u32 = 700;

/// Render `chart` to `path`; the format follows the extension (`.png` or `.svg`,
/// case-insensitive). The output is deterministic for a given chart.
pub fn render(chart: &Chart, path: &Path) -> Result<(), PlotError> {
    canvas::render_figure(chart, path)
}

/// Whether `path` names a format [`render`] writes (`.png` or `.svg`), so a
/// command can refuse it before any work.
pub fn check_format(path: &Path) -> Result<(), PlotError> {
    canvas::Format::of(path).map(|_| ())
}

/// Render `map` to `path` (`.png` or `.svg`); deterministic like [`render`].
pub(crate) fn render_map(map: &CellMap, path: &Path) -> Result<(), PlotError> {
    canvas::render_figure(map, path)
}
