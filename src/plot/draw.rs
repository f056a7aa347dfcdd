//! Drawing a [`Chart`]: axes and mesh, each series in its style, the
//! legend, and a note when nothing is drawable.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::Axis;
use super::canvas::{err, Figure, FONT};
use super::marks::{marker_paths, DASH, PALETTE, PUBLISHED_DIAMOND, TWIN_DASHES};
use super::prepare::{
    decimate_line, decimate_points, extent, simplify_collinear, valid_runs, Prepared,
};
use super::{legend, Chart, LegendPos, PlotError, Style, GUIDE_DASHES, HEIGHT, WIDTH};
use plotters::coord::cartesian::Cartesian2d;

impl Figure for Chart {
    fn size(&self) -> (u32, u32) {
        (WIDTH, HEIGHT)
    }

    fn check(&self, path: &Path) -> Result<(), PlotError> {
        for (index, s) in self.series.iter().enumerate() {
            if s.x.len() != s.y.len() {
                return Err(PlotError::LengthMismatch {
                    path: path.to_path_buf(),
                    index,
                    label: s.label.clone(),
                    nx: s.x.len(),
                    ny: s.y.len(),
                });
            }
        }
        Ok(())
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        raster: bool,
    ) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;

        let raw: Vec<Vec<Vec<(f64, f64)>>> = self
            .series
            .iter()
            .map(|s| valid_runs(s, self.log_x, self.log_y))
            .collect();
        let has_data = raw.iter().any(|r| !r.is_empty());
        let xa = Axis::new(extent(&raw, |p| p.0), self.log_x);
        let ya = Axis::new(extent(&raw, |p| p.1), self.log_y);
        let twins = coincident(&self.series, &raw, &xa, &ya);

        let prepared: Vec<Prepared> = self
            .series
            .iter()
            .zip(raw)
            .map(|(s, runs)| Prepared {
                runs: runs
                    .iter()
                    .map(|r| match s.style {
                        Style::Points | Style::Published => decimate_points(r, &xa, &ya),
                        Style::Line | Style::LineMarkers => decimate_line(r, &xa),
                        Style::Dashed | Style::Guide => {
                            simplify_collinear(&decimate_line(r, &xa), &xa, &ya)
                        }
                    })
                    .collect(),
            })
            .collect();

        let tick_font = (FONT, 16).into_font();
        let y_tick_w = ya
            .bold
            .iter()
            .map(|&v| {
                root.estimate_text_size(&ya.format(v), &tick_font.clone().into_text_style(root))
            })
            .filter_map(Result::ok)
            .map(|(w, _)| w)
            .max()
            .unwrap_or(30);

        // The legend's place is chosen before the plot is laid out: outside
        // (on the right) needs room reserved there.
        let labels: Vec<String> = self
            .series
            .iter()
            .zip(&twins)
            .map(|(s, twin)| legend_label(s, twin.map(|(t, exact)| (&self.series[t], exact))))
            .collect();
        let place = if any_labelled(&self.series) && self.legend != LegendPos::Hidden {
            let caption = if self.title.is_empty() { 0 } else { 40 };
            let plot = (
                WIDTH.saturating_sub(40 + y_tick_w + 45),
                HEIGHT.saturating_sub(40 + 60 + caption),
            );
            legend::place(root, self, &labels, &prepared, &xa, &ya, plot)
        } else {
            legend::Place::None
        };
        let mut builder = ChartBuilder::on(root);
        builder
            .margin(20)
            .x_label_area_size(60)
            .y_label_area_size(y_tick_w + 45);
        if let legend::Place::Outside { width } = place {
            builder.margin_right(20 + width);
        }
        if !self.title.is_empty() {
            // Centred on the canvas, not on the area left of an outside
            // legend (plotters' own caption would be, and a long title then
            // ran off the left edge); never left of the margin.
            let style = (FONT, 26).into_font().into_text_style(root);
            let (w, h) = root.estimate_text_size(&self.title, &style).map_err(err)?;
            let pad = (h / 2).min(5);
            let x = (WIDTH.saturating_sub(w) / 2).max(10);
            root.draw_text(&self.title, &style, (x as i32, 20 + pad as i32))
                .map_err(err)?;
            builder.margin_top(20 + h + 2 * pad);
        }
        let mut ctx = builder
            .build_cartesian_2d(xa.clone(), ya.clone())
            .map_err(err)?;

        let fx = |v: &f64| xa.format(*v);
        let fy = |v: &f64| ya.format(*v);
        ctx.configure_mesh()
            .x_desc(self.x_label.as_str())
            .y_desc(self.y_label.as_str())
            .axis_desc_style((FONT, 20))
            .label_style(tick_font.clone())
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .bold_line_style(RGBColor(205, 205, 205))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(err)?;

        let mut next_slot = 0;
        let mut guide = 0;
        let mut outside = vec![];
        for (index, (((s, p), twin), label)) in self
            .series
            .iter()
            .zip(&prepared)
            .zip(&twins)
            .zip(&labels)
            .enumerate()
        {
            // `slot` is 1-based here (0: no palette colour).
            let slot = match s.style {
                Style::Guide | Style::Published => 0,
                _ => {
                    next_slot += 1;
                    s.slot.unwrap_or(next_slot - 1) + 1
                }
            };
            let color = match s.style {
                Style::Guide => RGBColor(120, 120, 120),
                Style::Published => BLACK,
                _ => PALETTE[(slot - 1) % PALETTE.len()],
            };
            // A line over an identical earlier one is dashed, so both show;
            // the k-th such line over the same one gets the k-th pattern.
            let style = match (s.style, twin) {
                (Style::Line, Some(_)) => Style::Dashed,
                (st, _) => st,
            };
            let dash = if s.style == Style::Guide {
                guide += 1;
                GUIDE_DASHES[(guide - 1) % GUIDE_DASHES.len()]
            } else if let Some((base, _)) = twin {
                let k = twins
                    .iter()
                    .take(index)
                    .filter(|t| t.is_some_and(|t| t.0 == *base))
                    .count();
                TWIN_DASHES[k % TWIN_DASHES.len()]
            } else {
                DASH
            };
            let line = color.stroke_width(2);
            let fill = color.filled();
            for run in &p.runs {
                match style {
                    Style::Points => {
                        ctx.draw_series(run.iter().map(|&pt| Circle::new(pt, 3, fill)))
                    }
                    Style::Published => ctx.draw_series(run.iter().map(|&pt| {
                        EmptyElement::at(pt)
                            + Polygon::new(PUBLISHED_DIAMOND.to_vec(), fill)
                            + PathElement::new(PUBLISHED_DIAMOND.to_vec(), WHITE.stroke_width(2))
                    })),
                    Style::LineMarkers => {
                        polyline(&mut ctx, run, line, raster)?;
                        let paths = marker_paths(slot - 1);
                        ctx.draw_series(run.iter().flat_map(|&pt| {
                            paths.iter().map(move |path| {
                                EmptyElement::at(pt) + PathElement::new(path.clone(), line)
                            })
                        }))
                    }
                    _ if run.len() == 1 => {
                        ctx.draw_series(std::iter::once(Circle::new(run[0], 2, fill)))
                    }
                    Style::Line => {
                        polyline(&mut ctx, run, line, raster)?;
                        continue;
                    }
                    Style::Dashed | Style::Guide => ctx.draw_series(DashedLineSeries::new(
                        run.iter().copied(),
                        dash.0,
                        dash.1,
                        line,
                    )),
                }
                .map_err(err)?;
            }
            if s.label.is_empty() {
                continue;
            }
            // The legend entry hangs off an empty series so that broken lines
            // (several runs) still get exactly one entry.
            let anno = ctx
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(err)?;
            let label = if p.runs.is_empty() {
                format!("{label} (no drawable data)")
            } else {
                label.clone()
            };
            let look = legend::Look {
                style,
                slot,
                dash,
                line,
                fill,
            };
            if let legend::Place::Outside { .. } = place {
                outside.push((label, look));
            } else {
                anno.label(label);
                legend::attach(anno, look);
            }
        }

        if !has_data {
            let msg = if self.series.is_empty() {
                "no data series"
            } else {
                "no finite data to plot"
            };
            let style = (FONT, 22)
                .into_font()
                .color(&RGBColor(120, 120, 120))
                .pos(Pos::new(HPos::Center, VPos::Center));
            ctx.plotting_area()
                .draw(&Text::new(
                    msg,
                    ((xa.lo + xa.hi) / 2.0, (ya.lo + ya.hi) / 2.0),
                    style,
                ))
                .map_err(err)?;
        }

        legend::draw(&mut ctx, place)?;
        legend::draw_outside(root, &ctx, &outside)?;
        Ok(())
    }
}

/// Whether any series has a legend entry.
fn any_labelled(series: &[crate::plot::Series]) -> bool {
    series.iter().any(|s| !s.label.is_empty())
}

/// The legend text of `s`; a series drawn over an earlier `twin` says so:
/// `(= twin)` when their values are equal, `(≈ twin)` when they differ by
/// less than a pixel.
fn legend_label(s: &crate::plot::Series, twin: Option<(&crate::plot::Series, bool)>) -> String {
    match twin {
        Some((t, exact)) if !s.label.is_empty() && !t.label.is_empty() => {
            format!(
                "{} ({} {})",
                s.label,
                if exact { "=" } else { "≈" },
                t.label
            )
        }
        _ => s.label.clone(),
    }
}

/// A solid line through `run`. In PNG each segment is its own two-point
/// stroke: a quad within a pixel of its segment, so a line never leaves the
/// data's box (plotters' one-polygon outline of a whole spiky line can cover
/// the tick labels and the title: plotters issue #549). SVG keeps one
/// polyline, which viewers stroke correctly.
fn polyline<DB: DrawingBackend>(
    ctx: &mut ChartContext<'_, DB, Cartesian2d<Axis, Axis>>,
    run: &[(f64, f64)],
    line: ShapeStyle,
    raster: bool,
) -> Result<(), String> {
    if raster && line.stroke_width > 1 {
        ctx.draw_series(
            run.windows(2)
                .map(|w| PathElement::new(vec![w[0], w[1]], line)),
        )
        .map_err(err)?;
    } else {
        ctx.draw_series(LineSeries::new(run.iter().copied(), line))
            .map_err(err)?;
    }
    Ok(())
}

/// For each series, the earlier series it coincides with, if any, and
/// whether exactly: the same number of drawable points, each within a pixel
/// of the other's (in a 1000 × 700 frame). Guides and published values are
/// never twins.
fn coincident(
    series: &[crate::plot::Series],
    raw: &[Vec<Vec<(f64, f64)>>],
    xa: &Axis,
    ya: &Axis,
) -> Vec<Option<(usize, bool)>> {
    // Largest distance of two runs' points (same count), in axis units.
    let deviation = |a: &[Vec<(f64, f64)>], b: &[Vec<(f64, f64)>]| {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .map(|(p, q)| (p.0 - q.0).abs().max((p.1 - q.1).abs()))
            .fold(0.0, f64::max)
    };
    let data = |i: usize| {
        !matches!(series[i].style, Style::Guide | Style::Published) && !raw[i].is_empty()
    };
    let (tx, ty) = (
        (xa.hi - xa.lo) / f64::from(WIDTH),
        (ya.hi - ya.lo) / f64::from(HEIGHT),
    );
    let same = |a: &[Vec<(f64, f64)>], b: &[Vec<(f64, f64)>]| {
        let (pa, pb): (Vec<_>, Vec<_>) =
            (a.iter().flatten().collect(), b.iter().flatten().collect());
        pa.len() == pb.len()
            && pa
                .iter()
                .zip(&pb)
                .all(|(p, q)| (p.0 - q.0).abs() <= tx && (p.1 - q.1).abs() <= ty)
    };
    (0..series.len())
        .map(|j| {
            if !data(j) {
                return None;
            }
            // The closest of the earlier series within a pixel (the first
            // of equally close ones); exact when equal.
            (0..j)
                .filter(|&i| data(i) && same(&raw[i], &raw[j]))
                .map(|i| (i, deviation(&raw[i], &raw[j])))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, d)| (i, d == 0.0))
        })
        .collect()
}
