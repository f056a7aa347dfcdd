//! The figures of a convergence study: error against δt per metric, with
//! slope guides (or Table 2's values), and work–precision.

use super::reference::ReferenceKind;
use super::{ConvergeOptions, ConvergeReport, MetricFn, Mode, Point};
use crate::error::Result;
use crate::plot::{reference_slope, Chart, LegendPos, Series, Style};
use crate::scenario::{ClosedForm, Scene};
use crate::study::{render_both, scene_name};

/// A convergence figure: file stem, title, y label, metric, reference error.
type PlotSpec = (&'static str, String, String, MetricFn, f64);

/// `x` to 9 significant digits, shortest form (0.09999999999 -> 0.1).
fn short(x: f64) -> String {
    format!("{x:.8e}")
        .parse::<f64>()
        .map_or(x.to_string(), |v| v.to_string())
}

/// The paper's Table 2 applies to test case 3 exactly: the exponential torque
/// on the sphere with A = 1e5, C = 1, T = 1 s.
fn is_test_case_3(scene: &Scene, t_end: f64) -> bool {
    matches!(scene.reference, Some(ClosedForm::ExpTorqueSphere { a, c, .. })
        if a == 1e5 && c == 1.0 && (t_end - 1.0).abs() < 1e-12)
}

/// The convergence figures (one per metric) and the work–precision figure.
pub(super) fn figures(scene: &Scene, r: &ConvergeReport, opts: &ConvergeOptions) -> Result<()> {
    let dir = &opts.out_dir;
    let (dt_lo, dt_hi) = (
        r.dts.iter().cloned().fold(f64::INFINITY, f64::min),
        r.dts.iter().cloned().fold(0.0, f64::max),
    );
    let series_of = |f: &dyn Fn(&Point) -> f64, x: &dyn Fn(&Point) -> f64| -> Vec<Series> {
        opts.rotators
            .iter()
            .map(|&k| {
                let pts: Vec<&Point> = r
                    .points
                    .iter()
                    .filter(|p| p.rotator == k && f(p).is_finite() && f(p) > 0.0)
                    .collect();
                Series::new(
                    k.name(),
                    pts.iter().map(|p| x(p)).collect(),
                    pts.iter().map(|p| f(p)).collect(),
                    Style::LineMarkers,
                )
                .in_slot(crate::study::rotator_slot(k))
            })
            .collect()
    };
    // Slope guides start a factor 3 below the lowest error at the largest δt
    // among the rotators of that nominal order (or all, if none has it).
    let slopes = |f: &dyn Fn(&Point) -> f64| -> Vec<Series> {
        let low = |order: u32| {
            let pick = |strict: bool| {
                r.points
                    .iter()
                    .filter(|p| p.dt == dt_hi && (!strict || p.rotator.info().order == order))
                    .map(f)
                    .filter(|e| e.is_finite() && *e > 0.0)
                    .fold(f64::INFINITY, f64::min)
            };
            Some(pick(true))
                .filter(|v| v.is_finite())
                .unwrap_or_else(|| pick(false))
        };
        [(1u32, "slope 1"), (2, "slope 2")]
            .iter()
            .filter(|(o, _)| low(*o).is_finite())
            .map(|&(o, label)| Series {
                style: Style::Guide,
                ..reference_slope(label, o as f64, (dt_lo, dt_hi), (dt_hi, low(o) / 3.0))
            })
            .collect()
    };
    let name = scene_name(scene);
    let mut plots: Vec<PlotSpec> = Vec::new();
    match r.mode {
        Mode::Orientation => {
            plots.push((
                "convergence",
                format!(
                    "{name}: Eq. 66-67 angle error vs time step (T = {} s)",
                    short(r.t_end)
                ),
                "angle error α, Eq. 67 (rad)".into(),
                |p: &Point| p.alpha_rad,
                r.reference.alpha_err,
            ));
            plots.push((
                "convergence_geodesic",
                format!(
                    "{name}: geodesic angle to the reference at T = {} s",
                    short(r.t_end)
                ),
                "2 acos|q·q_ref| at T (rad)".into(),
                |p: &Point| p.geodesic_rad,
                r.reference.geodesic_err,
            ));
            if r.reference.kind == ReferenceKind::ClosedForm {
                plots.push((
                    "convergence_x_error",
                    format!("{name}: Table 2 x-error at T = {} s", short(r.t_end)),
                    "relative error of x-component (%)".into(),
                    |p: &Point| p.x_error_pct,
                    f64::NAN,
                ));
            }
        }
        Mode::Energy => {
            plots.push((
                "convergence",
                format!(
                    "{name}: full-budget energy error vs time step (T = {} s)",
                    short(r.t_end)
                ),
                "largest |E − E₀|/|E₀| over the run, Eq. 65 with elastic energy (%)".into(),
                |p: &Point| p.energy_full_max_pct,
                f64::NAN,
            ));
            if let ReferenceKind::Fine(k) = r.reference.kind {
                plots.push((
                    "convergence_position",
                    format!(
                        "{name}: distance to {k} at δt_ref at T = {} s",
                        short(r.t_end)
                    ),
                    "largest distance of a body to the reference at T (m)".into(),
                    |p: &Point| p.position_m,
                    r.reference.position_err,
                ));
                plots.push((
                    "convergence_geodesic",
                    format!(
                        "{name}: geodesic angle to {k} at δt_ref at T = {} s",
                        short(r.t_end)
                    ),
                    "largest 2 acos|q·q_ref| of a body at T (rad)".into(),
                    |p: &Point| p.geodesic_rad,
                    r.reference.geodesic_err,
                ));
            }
        }
    }
    for (stem, title, ylab, f, ref_err) in &plots {
        let mut chart = Chart::new(title.clone(), "time step δt (s)", ylab.clone());
        chart.log_x = true;
        chart.log_y = true;
        chart.legend = LegendPos::Auto;
        chart.series = series_of(f, &|p| p.dt);
        if *stem == "convergence_x_error" {
            // Table 2's points instead of slope guides (the orders are in
            // orders.csv), drawn last so they sit on top of our markers.
            if is_test_case_3(scene, r.t_end) {
                chart.series.push(Series::new(
                    "paper Table 2 at δt = 1e-4 s: scalar 2.15 %, PCDM 0.63 %",
                    vec![1e-4, 1e-4],
                    vec![2.15, 0.63],
                    Style::Published,
                ));
            }
        } else {
            chart.series.extend(slopes(f));
        }
        if ref_err.is_finite() && *ref_err > 0.0 {
            // A guide (grey, its own dash pattern): a bound, not data.
            chart.series.push(Series::new(
                format!("{} reference's own error (Richardson)", r.reference.kind),
                vec![dt_lo, dt_hi],
                vec![*ref_err, *ref_err],
                Style::Guide,
            ));
        }
        render_both(&chart, dir, stem)?;
    }
    // Work–precision: the primary metric (and with a trajectory reference,
    // the position error too) against the measured stepping time.
    let mut wp = vec![("work_precision", &plots[0])];
    if let Some(pos) = plots.iter().find(|p| p.0 == "convergence_position") {
        wp.push(("work_precision_position", pos));
    }
    for (stem, (_, _, ylab, f, _)) in wp {
        let mut chart = Chart::new(
            format!("{name}: work-precision"),
            "wall time of the run, timed alone (s)",
            ylab.clone(),
        );
        chart.log_x = true;
        chart.log_y = true;
        chart.legend = LegendPos::Auto;
        chart.series = series_of(f, &|p| p.wall_s);
        render_both(&chart, dir, stem)?;
    }
    Ok(())
}
