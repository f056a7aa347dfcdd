//! Drawing a [`Chart`]: axes and mesh, each series in its style, the
//! legend, and a note when nothing is drawable.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::Axis;
use super::canvas::{err, Figure, FONT};
use super::marks::{marker_paths, DASH, PALETTE, PUBLISHED_DIAMOND};
use super::prepare::{
    decimate_line, decimate_points, extent, simplify_collinear, valid_runs, Prepared,
};
use super::{legend, Chart, LegendPos, PlotError, Style, GUIDE_DASHES, HEIGHT, WIDTH};

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

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;

        let raw: Vec<Vec<Vec<(f64, f64)>>> = self
            .series
            .iter()
            .map(|s| valid_runs(s, self.log_x, self.log_y))
            .collect();
        let has_data = raw.iter().any(|r| !r.is_empty());
        let xa = Axis::new(extent(&raw, |p| p.0), self.log_x);
        let ya = Axis::new(extent(&raw, |p| p.1), self.log_y);

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

        let mut builder = ChartBuilder::on(root);
        builder
            .margin(20)
            .x_label_area_size(60)
            .y_label_area_size(y_tick_w + 45);
        if !self.title.is_empty() {
            builder.caption(&self.title, (FONT, 26));
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

        let mut any_label = false;
        let mut slot = 0;
        let mut guide = 0;
        for (s, p) in self.series.iter().zip(&prepared) {
            let color = if s.style == Style::Guide {
                RGBColor(120, 120, 120)
            } else if s.style == Style::Published {
                BLACK
            } else {
                slot += 1;
                PALETTE[(slot - 1) % PALETTE.len()]
            };
            let dash = if s.style == Style::Guide {
                guide += 1;
                GUIDE_DASHES[(guide - 1) % GUIDE_DASHES.len()]
            } else {
                DASH
            };
            let line = color.stroke_width(2);
            let fill = color.filled();
            for run in &p.runs {
                match s.style {
                    Style::Points => {
                        ctx.draw_series(run.iter().map(|&pt| Circle::new(pt, 3, fill)))
                    }
                    Style::Published => ctx.draw_series(run.iter().map(|&pt| {
                        EmptyElement::at(pt)
                            + Polygon::new(PUBLISHED_DIAMOND.to_vec(), fill)
                            + PathElement::new(PUBLISHED_DIAMOND.to_vec(), WHITE.stroke_width(2))
                    })),
                    _ if run.len() == 1 => {
                        ctx.draw_series(std::iter::once(Circle::new(run[0], 2, fill)))
                    }
                    Style::Line => ctx.draw_series(LineSeries::new(run.iter().copied(), line)),
                    Style::LineMarkers => {
                        ctx.draw_series(LineSeries::new(run.iter().copied(), line))
                            .map_err(err)?;
                        let paths = marker_paths(slot - 1);
                        ctx.draw_series(run.iter().flat_map(|&pt| {
                            paths.iter().map(move |path| {
                                EmptyElement::at(pt) + PathElement::new(path.clone(), line)
                            })
                        }))
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
            any_label = true;
            let label = if p.runs.is_empty() {
                format!("{} (no drawable data)", s.label)
            } else {
                s.label.clone()
            };
            anno.label(label);
            legend::sample(anno, s.style, slot, dash, line, fill);
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

        if any_label && self.legend != LegendPos::Hidden {
            legend::draw(root, &mut ctx, self, &prepared, &xa, &ya)?;
        }
        Ok(())
    }
}
