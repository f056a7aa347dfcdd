//! The legend: a sample of each series' style, and a box placed where it
//! hides the least data.

use plotters::chart::{ChartContext, SeriesAnno, SeriesLabelPosition};
use plotters::coord::cartesian::Cartesian2d;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::Axis;
use super::canvas::{err, FONT};
use super::marks::{dash_segments, marker_paths, PUBLISHED_DIAMOND};
use super::prepare::Prepared;
use super::{Chart, LegendPos, Series, Style};

/// Attach the legend sample of a series drawn in `style` to its entry:
/// `slot` is its palette slot (1-based), `dash` its dash pattern.
pub(super) fn sample<'a, DB: DrawingBackend + 'a>(
    anno: &mut SeriesAnno<'a, DB>,
    style: Style,
    slot: usize,
    dash: (u32, u32),
    line: ShapeStyle,
    fill: ShapeStyle,
) {
    match style {
        Style::Line => {
            anno.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], line));
        }
        Style::LineMarkers => {
            // Up to two strokes per shape (× and +); a closed shape repeats.
            let paths = marker_paths(slot - 1);
            let stroke = move |i: usize| {
                let p: Vec<(i32, i32)> = paths[i.min(paths.len() - 1)]
                    .iter()
                    .map(|&(a, b)| (a + 12, b))
                    .collect();
                PathElement::new(p, line)
            };
            anno.legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (24, 0)], line)
                    + stroke(0)
                    + stroke(1)
            });
        }
        Style::Dashed | Style::Guide => {
            // The line's own dash pattern over the 24 px sample: at most
            // 4 dashes (the shortest pattern), padded by repeating the last.
            let segs = dash_segments(24, dash);
            let seg = move |i: usize| {
                let (a, b) = segs[i.min(segs.len() - 1)];
                PathElement::new(vec![(a, 0), (b, 0)], line)
            };
            anno.legend(move |(x, y)| EmptyElement::at((x, y)) + seg(0) + seg(1) + seg(2) + seg(3));
        }
        Style::Published => {
            anno.legend(move |(x, y)| {
                EmptyElement::at((x + 12, y))
                    + Polygon::new(PUBLISHED_DIAMOND.to_vec(), fill)
                    + PathElement::new(PUBLISHED_DIAMOND.to_vec(), WHITE.stroke_width(2))
            });
        }
        Style::Points => {
            anno.legend(move |(x, y)| Circle::new((x + 12, y), 4, fill));
        }
    }
}

/// Draw the legend box of `chart` on `ctx`.
pub(super) fn draw<'a, DB: DrawingBackend + 'a>(
    root: &DrawingArea<DB, Shift>,
    ctx: &mut ChartContext<'a, DB, Cartesian2d<Axis, Axis>>,
    chart: &Chart,
    prepared: &[Prepared],
    xa: &Axis,
    ya: &Axis,
) -> Result<(), String> {
    let legend_font = (FONT, 16).into_font();
    let (pw, ph) = ctx.plotting_area().dim_in_pixel();
    let labelled: Vec<&Series> = chart
        .series
        .iter()
        .filter(|s| !s.label.is_empty())
        .collect();
    let text_w = labelled
        .iter()
        .filter_map(|s| {
            root.estimate_text_size(&s.label, &legend_font.clone().into_text_style(root))
                .ok()
        })
        .map(|(w, _)| w)
        .max()
        .unwrap_or(0);
    let box_w = f64::from(text_w + 75) / f64::from(pw.max(1));
    let box_h = (labelled.len() as f64 * 22.0 + 30.0) / f64::from(ph.max(1));
    let pos = match chart.legend {
        LegendPos::Auto => least_covered_corner(prepared, xa, ya, box_w, box_h),
        other => other,
    };
    let pos = match pos {
        LegendPos::UpperLeft => SeriesLabelPosition::UpperLeft,
        LegendPos::LowerLeft => SeriesLabelPosition::LowerLeft,
        LegendPos::LowerRight => SeriesLabelPosition::LowerRight,
        _ => SeriesLabelPosition::UpperRight,
    };
    ctx.configure_series_labels()
        .position(pos)
        .margin(12)
        .legend_area_size(34)
        .label_font(legend_font)
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(150, 150, 150))
        .draw()
        .map_err(err)
}

/// The plot corner where a legend box of normalised size (w, h) covers the
/// least data; the upper right on a tie.
fn least_covered_corner(prepared: &[Prepared], x: &Axis, y: &Axis, w: f64, h: f64) -> LegendPos {
    let order = [
        LegendPos::UpperRight,
        LegendPos::UpperLeft,
        LegendPos::LowerRight,
        LegendPos::LowerLeft,
    ];
    let mut best = (usize::MAX, LegendPos::UpperRight);
    for c in order {
        let s = corner_score(prepared, x, y, c, w, h);
        if s < best.0 {
            best = (s, c);
        }
    }
    best.1
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
