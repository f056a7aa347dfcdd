//! The legend: a sample of each series' style, in a box placed where it
//! hides no data: a free corner of the plot, else outside it on the right.

use plotters::chart::{ChartContext, SeriesAnno, SeriesLabelPosition};
use plotters::coord::cartesian::Cartesian2d;
use plotters::coord::Shift;
/// A pixel of the backend (plotters-backend's `BackendCoord`).
type BackendCoord = (i32, i32);
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::DrawingErrorKind;

use super::axis::Axis;
use super::canvas::{err, FONT};
use super::marks::{dash_segments, marker_paths, PUBLISHED_DIAMOND};
use super::prepare::Prepared;
use super::{Chart, LegendPos, Style};

/// How one legend entry's sample is drawn.
#[derive(Clone, Copy)]
pub(super) struct Look {
    /// The series' style as drawn.
    pub(super) style: Style,
    /// Palette slot, 1-based (0: none).
    pub(super) slot: usize,
    /// Dash pattern of dashed styles.
    pub(super) dash: (u32, u32),
    /// Line style.
    pub(super) line: ShapeStyle,
    /// Fill style.
    pub(super) fill: ShapeStyle,
}

/// One stroke or fill of a sample, in backend pixels.
enum Part {
    Path(Vec<BackendCoord>, ShapeStyle),
    Polygon(Vec<BackendCoord>, ShapeStyle),
    Dot(BackendCoord, u32, ShapeStyle),
}

/// The parts of the sample of `look` with its left end at `(x, y)`, 24 px wide.
fn parts((x, y): BackendCoord, look: Look) -> Vec<Part> {
    let Look {
        style,
        slot,
        dash,
        line,
        fill,
    } = look;
    let shift = |p: &[(i32, i32)], dx: i32| p.iter().map(|&(a, b)| (x + dx + a, y + b)).collect();
    match style {
        Style::Line => vec![Part::Path(vec![(x, y), (x + 24, y)], line)],
        Style::LineMarkers => {
            let mut v = vec![Part::Path(vec![(x, y), (x + 24, y)], line)];
            v.extend(
                marker_paths(slot.max(1) - 1)
                    .iter()
                    .map(|p| Part::Path(shift(p, 12), line)),
            );
            v
        }
        // The line's own dash pattern over the 24 px sample.
        Style::Dashed | Style::Guide => dash_segments(24, dash)
            .into_iter()
            .map(|(a, b)| Part::Path(vec![(x + a, y), (x + b, y)], line))
            .collect(),
        Style::Published => vec![
            Part::Polygon(shift(&PUBLISHED_DIAMOND, 12), fill),
            Part::Path(shift(&PUBLISHED_DIAMOND, 12), WHITE.stroke_width(2)),
        ],
        Style::Points => vec![Part::Dot((x + 12, y), 4, fill)],
    }
}

/// A legend sample as a plotters element anchored at its left end.
pub(super) struct Sample {
    at: BackendCoord,
    look: Look,
}

impl<'b> PointCollection<'b, BackendCoord> for &'b Sample {
    type Point = &'b BackendCoord;
    type IntoIter = std::iter::Once<&'b BackendCoord>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<DB: DrawingBackend> Drawable<DB> for Sample {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        backend: &mut DB,
        _parent_dim: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some(at) = pos.next() else { return Ok(()) };
        for part in parts(at, self.look) {
            match part {
                Part::Path(p, s) => backend.draw_path(p, &s)?,
                Part::Polygon(p, s) => backend.fill_polygon(p, &s)?,
                Part::Dot(c, r, s) => backend.draw_circle(c, r, &s, s.filled)?,
            }
        }
        Ok(())
    }
}

/// Attach the sample of `look` to a legend entry inside the plot.
pub(super) fn attach<DB: DrawingBackend>(anno: &mut SeriesAnno<'_, DB>, look: Look) {
    anno.legend(move |at| Sample { at, look });
}

/// Draw the legend `entries` (text, look) outside the plot of `ctx`, on
/// its right, as the plot's own legend box looks.
pub(super) fn draw_outside<'a, DB: DrawingBackend + 'a>(
    root: &DrawingArea<DB, Shift>,
    ctx: &ChartContext<'a, DB, Cartesian2d<Axis, Axis>>,
    entries: &[(String, Look)],
) -> Result<(), String> {
    if entries.is_empty() {
        return Ok(());
    }
    let (xs, ys) = ctx.plotting_area().get_pixel_range();
    let font = (FONT, 16).into_font();
    let text_w = entries
        .iter()
        .filter_map(|(l, _)| {
            root.estimate_text_size(l, &font.clone().into_text_style(root))
                .ok()
        })
        .map(|(w, _)| w as i32)
        .max()
        .unwrap_or(0);
    let (x0, y0) = (xs.end + 10, ys.start);
    let (m, row) = (MARGIN as i32, 22);
    let (w, h) = (
        text_w + SAMPLE as i32 + 2 * m,
        entries.len() as i32 * row + 2 * m,
    );
    let rect = [(x0, y0), (x0 + w, y0 + h)];
    root.draw(&Rectangle::new(rect, WHITE.mix(0.9).filled()))
        .map_err(err)?;
    root.draw(&Rectangle::new(rect, RGBColor(150, 150, 150)))
        .map_err(err)?;
    let text = font
        .color(&BLACK)
        .pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Left,
            plotters::style::text_anchor::VPos::Center,
        ));
    for (i, (label, look)) in entries.iter().enumerate() {
        let y = y0 + m + row / 2 + i as i32 * row;
        root.draw(&Sample {
            at: (x0 + m, y),
            look: *look,
        })
        .map_err(err)?;
        root.draw(&Text::new(
            label.as_str(),
            (x0 + m + SAMPLE as i32, y),
            text.clone(),
        ))
        .map_err(err)?;
    }
    Ok(())
}

/// Where the legend goes, decided before the plot is laid out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Place {
    /// No legend.
    None,
    /// In a corner of the plot.
    Corner(LegendPos),
    /// Right of the plot, in a margin `width` px wide.
    Outside {
        /// Room reserved for it, px.
        width: u32,
    },
}

/// Margin around the entries and width of the samples, px (as drawn).
const MARGIN: u32 = 12;
const SAMPLE: u32 = 34;

/// Where the legend of `chart` (entries `labels`) goes in a plot of about
/// `plot` px: `Auto` takes a corner whose box (with a marker's width of
/// clearance) covers no data, in the order upper right, upper left, lower
/// right, lower left; else outside the plot on the right.
pub(super) fn place<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart,
    labels: &[String],
    prepared: &[Prepared],
    xa: &Axis,
    ya: &Axis,
    plot: (u32, u32),
) -> Place {
    let font = (FONT, 16).into_font().into_text_style(root);
    let shown: Vec<&String> = chart
        .series
        .iter()
        .zip(labels)
        .filter(|(s, _)| !s.label.is_empty())
        .map(|(_, l)| l)
        .collect();
    let text_w = shown
        .iter()
        .filter_map(|l| root.estimate_text_size(l, &font).ok())
        .map(|(w, _)| w)
        .max()
        .unwrap_or(0);
    let (w, h) = (
        text_w + SAMPLE + 2 * MARGIN + 12,
        shown.len() as u32 * 22 + 2 * MARGIN + 6,
    );
    let pos = match chart.legend {
        LegendPos::Hidden => return Place::None,
        LegendPos::Outside => return Place::Outside { width: w + 10 },
        LegendPos::Auto => {
            // Clearance: half a marker plus the line width.
            let pad = 9.0;
            let (pw, ph) = (f64::from(plot.0.max(1)), f64::from(plot.1.max(1)));
            let (bw, bh) = ((f64::from(w) + pad) / pw, (f64::from(h) + pad) / ph);
            let free = [
                LegendPos::UpperRight,
                LegendPos::UpperLeft,
                LegendPos::LowerRight,
                LegendPos::LowerLeft,
            ]
            .into_iter()
            .find(|&c| corner_score(prepared, xa, ya, c, bw, bh) == 0);
            match free {
                Some(c) => c,
                None => return Place::Outside { width: w + 10 },
            }
        }
        corner => corner,
    };
    Place::Corner(pos)
}

/// Draw the legend box on `ctx` where `place` says (a corner; outside,
/// [`draw_outside`] draws it).
pub(super) fn draw<'a, DB: DrawingBackend + 'a>(
    ctx: &mut ChartContext<'a, DB, Cartesian2d<Axis, Axis>>,
    place: Place,
) -> Result<(), String> {
    let pos = match place {
        Place::None | Place::Outside { .. } => return Ok(()),
        Place::Corner(LegendPos::UpperLeft) => SeriesLabelPosition::UpperLeft,
        Place::Corner(LegendPos::LowerLeft) => SeriesLabelPosition::LowerLeft,
        Place::Corner(LegendPos::LowerRight) => SeriesLabelPosition::LowerRight,
        Place::Corner(_) => SeriesLabelPosition::UpperRight,
    };
    ctx.configure_series_labels()
        .position(pos)
        .margin(MARGIN)
        .legend_area_size(SAMPLE)
        .label_font((FONT, 16).into_font())
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(150, 150, 150))
        .draw()
        .map_err(err)
}

/// How many samples along the data fall inside a corner box of normalised
/// size (w, h).
fn corner_score(
    prepared: &[Prepared],
    x: &Axis,
    y: &Axis,
    corner: LegendPos,
    w: f64,
    h: f64,
) -> usize {
    let (u0, u1) = match corner {
        LegendPos::UpperLeft | LegendPos::LowerLeft => (0.0, w),
        _ => (1.0 - w, 1.0),
    };
    let (v0, v1) = match corner {
        LegendPos::LowerLeft | LegendPos::LowerRight => (0.0, h),
        _ => (1.0 - h, 1.0),
    };
    let norm = |p: &(f64, f64)| ((p.0 - x.lo) / (x.hi - x.lo), (p.1 - y.lo) / (y.hi - y.lo));
    let inside = |(u, v): (f64, f64)| u >= u0 && u <= u1 && v >= v0 && v <= v1;
    let mut score = 0;
    for run in prepared.iter().flat_map(|p| &p.runs) {
        if run.len() == 1 {
            score += usize::from(inside(norm(&run[0])));
        }
        for seg in run.windows(2) {
            let (a, b) = (norm(&seg[0]), norm(&seg[1]));
            let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
            let k = ((len / 0.01).ceil() as usize).clamp(1, 100);
            for i in 0..=k {
                let t = i as f64 / k as f64;
                score += usize::from(inside((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))));
            }
        }
    }
    score
}
