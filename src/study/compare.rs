//! `fibresim compare`: every chosen rotator on one scene at one δt, each run
//! written by `run::run` into `DIR/<rotator>/`, plus a combined error figure
//! in the manner of the paper's Figs. 2–4 and a table.
//!
//! The error plotted against time:
//! - scenes with an energy baseline: the full-budget energy error (Eq. 65 with
//!   the elastic energy of live contacts; identical to Eq. 65 whenever no
//!   contact is live), `energy_error_full_window_max_pct`, the largest error
//!   since the previous row, so no spike is hidden. Plain Eq. 65 is not
//!   conserved during a contact (the elastic energy is missing from it);
//! - torque scenes with a closed form: the geodesic angle to it (`err_rad`);
//! - torque scenes without one (test case 4): the geodesic angle to an rk4 run
//!   at δt/10, at the output rows (Eq. 65 is undefined there: E₀ = 0). Not
//!   Eq. 66: its `α_n` is a difference of angles that crosses zero, and its
//!   cusps make an unreadable log plot; `converge` reports Eq. 66–67.

use super::csvplot::Table;
use super::{
    cell, fmt_e, render_both, sample_orientations, scene_name, with_params, write_csv, Progress,
};
use crate::error::{Error, Result};
use crate::integrate::rotate::RotatorKind;
use crate::math::geodesic_angle;
use crate::plot::{Chart, LegendPos, Series, Style};
use crate::run::{run_with_bar, RunOptions};
use crate::scenario::Scene;
use glam::DQuat;
use rayon::prelude::*;
use std::path::PathBuf;
use std::time::Instant;

/// Options of `fibresim compare`.
#[derive(Debug, Clone)]
pub struct CompareOptions {
    /// The rotators run side by side.
    pub rotators: Vec<RotatorKind>,
    /// Time step, s; default the scene's.
    pub dt: Option<f64>,
    /// End time, s; default the scene's.
    pub t_end: Option<f64>,
    /// Folder of the table, the figure and one run folder per rotator.
    pub out_dir: PathBuf,
    /// Draw progress bars (on a terminal only).
    pub progress: bool,
}

/// One rotator's line of the table.
#[derive(Debug, Clone)]
pub struct CompareRow {
    /// The rotator.
    pub rotator: RotatorKind,
    /// Largest error over the output rows, in the metric's unit.
    pub max_error: f64,
    /// Error at the last output row.
    pub final_error: f64,
    /// Wall time of the run, s.
    pub wall_s: f64,
    /// Wall time per body and step, ns.
    pub ns_per_body_step: f64,
    /// The guard's diagnosis if the run stopped.
    pub stopped: Option<String>,
    /// The error series plotted: times, s …
    pub t: Vec<f64>,
    /// … and the errors at them.
    pub err: Vec<f64>,
}

/// The table and figure of `fibresim compare`.
pub struct CompareReport {
    /// Name of the error metric, with its unit.
    pub metric: &'static str,
    /// Stem of the figure (`.png` and `.svg`), named by the metric.
    pub figure: &'static str,
    /// One row per rotator, in the order asked.
    pub rows: Vec<CompareRow>,
}

#[derive(Clone, Copy, PartialEq)]
enum Metric {
    Energy,
    ClosedForm,
    Rk4Angle,
}

impl Metric {
    fn label(self) -> &'static str {
        match self {
            Metric::Energy => {
                "largest |E − E₀|/|E₀| since the previous row, Eq. 65 with elastic energy (%)"
            }
            Metric::ClosedForm => "angle to the closed form (rad)",
            Metric::Rk4Angle => "angle to rk4 at δt/10 (rad)",
        }
    }

    /// File stem of the figure: what it plots.
    fn figure(self) -> &'static str {
        match self {
            Metric::Energy => "energy_error_full",
            Metric::ClosedForm => "angle_error_closed_form",
            Metric::Rk4Angle => "angle_error_rk4",
        }
    }
}

/// The rk4 reference refines δt by this factor (4th order: its error is
/// ~10⁻⁴ of rk4's own at δt, far below every first- and second-order scheme).
const REF_FACTOR: u64 = 10;

/// Run every rotator of `opts` on `scene` and write the runs, `compare.csv`
/// and the error figure.
pub fn compare(scene: &Scene, opts: &CompareOptions) -> Result<CompareReport> {
    let opts = &CompareOptions {
        rotators: super::runnable(scene, &opts.rotators)?,
        ..opts.clone()
    };
    let dt = opts.dt.unwrap_or(scene.sim.dt());
    let t_end = opts.t_end.unwrap_or(scene.sim.t_end());
    let scenes: Vec<Scene> = opts
        .rotators
        .iter()
        .map(|&k| with_params(scene, k, dt, t_end))
        .collect::<Result<_>>()?;
    let steps = scenes[0].sim.steps();
    let nb = scene.bodies.len() as u64;
    let torque_scene = scene.has_prescribed_torque() || scene.reference.is_some();
    let metric = match (torque_scene, scene.reference.is_some()) {
        (false, _) => Metric::Energy,
        (true, true) => Metric::ClosedForm,
        (true, false) => Metric::Rk4Angle,
    };
    let ref_work = if metric == Metric::Rk4Angle {
        steps * REF_FACTOR
    } else {
        0
    };
    let progress = Progress::new(
        opts.progress,
        (steps * scenes.len() as u64 + ref_work) * nb,
        "compare",
    );

    let runs = || {
        scenes
            .par_iter()
            .map(|s| {
                let name = s.sim.rotator().name();
                let ro = RunOptions {
                    out_dir: opts.out_dir.join(name),
                    progress: false,
                    ..Default::default()
                };
                let t0 = Instant::now();
                let r = run_with_bar(s, &ro, progress.run_bar(name, s.sim.steps()));
                let wall = t0.elapsed().as_secs_f64();
                progress.done(s.sim.steps() * nb);
                match r {
                    Ok(o) => Ok((o.wall_s, o.ns_per_body_step, None)),
                    Err(Error::Unstable(d)) => {
                        let body_steps = (d.step.max(1) * nb) as f64;
                        Ok((wall, wall * 1e9 / body_steps, Some(d.to_string())))
                    }
                    Err(e) => Err(e),
                }
            })
            .collect::<Vec<Result<_>>>()
    };
    // rk4 reference orientations at every coarse step (Rk4Angle only).
    let reference = || -> Result<Option<Vec<DQuat>>> {
        if metric != Metric::Rk4Angle {
            return Ok(None);
        }
        let fine = with_params(scene, RotatorKind::Rk4, dt / REF_FACTOR as f64, t_end)?;
        let q = sample_orientations(&fine, REF_FACTOR, &progress, "rk4 reference")
            .map_err(Error::Unstable)?;
        Ok(Some(q))
    };
    let (timings, reference) = rayon::join(runs, reference);
    progress.finish();
    let reference = reference?;

    let mut rows = Vec::new();
    for (s, timing) in scenes.iter().zip(timings) {
        let (wall_s, ns, stopped) = timing?;
        let kind = s.sim.rotator();
        let dir = opts.out_dir.join(kind.name());
        let (t, err) = match metric {
            Metric::Energy => {
                let tab = Table::read(&dir.join("energy.csv"))?;
                let t = tab.numbers(tab.require("t", "energy.csv")?);
                let e = tab.numbers(tab.require("energy_error_full_window_max_pct", "energy.csv")?);
                (t, e)
            }
            Metric::ClosedForm => {
                let tab = Table::read(&dir.join("orientation.csv"))?;
                let body = tab.numbers(tab.require("body", "orientation.csv")?);
                let t = tab.numbers(tab.require("t", "orientation.csv")?);
                let e = tab.numbers(tab.require("err_rad", "orientation.csv")?);
                let keep = |v: Vec<f64>| -> Vec<f64> {
                    v.into_iter()
                        .zip(&body)
                        .filter(|(_, b)| **b == 0.0)
                        .map(|(x, _)| x)
                        .collect()
                };
                (keep(t), keep(e))
            }
            Metric::Rk4Angle => {
                let q_ref = reference.as_ref().expect("reference computed");
                angle_series(scene, &dir, q_ref)?
            }
        };
        // Full-budget error at the last row; the max over all rows (each row's
        // window max covers every step).
        let final_error = match metric {
            Metric::Energy => {
                let tab = Table::read(&dir.join("energy.csv"))?;
                let e = tab.numbers(tab.require("energy_error_full_pct", "energy.csv")?);
                e.last().copied().unwrap_or(f64::NAN)
            }
            _ => err.last().copied().unwrap_or(f64::NAN),
        };
        let max_error = err
            .iter()
            .cloned()
            .filter(|e| e.is_finite())
            .fold(f64::NAN, f64::max);
        rows.push(CompareRow {
            rotator: kind,
            max_error,
            final_error,
            wall_s,
            ns_per_body_step: ns,
            stopped,
            t,
            err,
        });
    }
    let report = CompareReport {
        metric: metric.label(),
        figure: metric.figure(),
        rows,
    };
    write_outputs(scene, &report, opts, dt)?;
    Ok(report)
}

/// The geodesic angle at every output row of `dir/orientation.csv` (max over
/// the bodies it holds) to the reference orientations `q_ref` (one per
/// coarse step and body).
fn angle_series(
    scene: &Scene,
    dir: &std::path::Path,
    q_ref: &[DQuat],
) -> Result<(Vec<f64>, Vec<f64>)> {
    let tab = Table::read(&dir.join("orientation.csv"))?;
    let col = |n: &str| -> Result<Vec<f64>> { Ok(tab.numbers(tab.require(n, "orientation.csv")?)) };
    let (step, t, body) = (col("step")?, col("t")?, col("body")?);
    let (qw, qx, qy, qz) = (col("qw")?, col("qx")?, col("qy")?, col("qz")?);
    let nb = scene.bodies.len();
    let (mut ts, mut es): (Vec<f64>, Vec<f64>) = (vec![], vec![]);
    for i in 0..tab.rows.len() {
        let (n, b) = (step[i] as usize, body[i] as usize);
        let q = DQuat::from_xyzw(qx[i], qy[i], qz[i], qw[i]);
        let a = geodesic_angle(q, q_ref[n * nb + b]);
        // A row's bodies share its step: a new step starts a new point.
        if i > 0 && step[i] == step[i - 1] {
            if let Some(last) = es.last_mut() {
                *last = last.max(a);
            }
        } else {
            ts.push(t[i]);
            es.push(a);
        }
    }
    Ok((ts, es))
}

fn write_outputs(scene: &Scene, r: &CompareReport, opts: &CompareOptions, dt: f64) -> Result<()> {
    let dir = &opts.out_dir;
    let rows: Vec<Vec<String>> = r
        .rows
        .iter()
        .map(|x| {
            vec![
                x.rotator.name().to_string(),
                r.metric.to_string(),
                cell(x.max_error),
                cell(x.final_error),
                cell(x.wall_s),
                cell(x.ns_per_body_step),
                x.stopped.clone().unwrap_or_default(),
            ]
        })
        .collect();
    write_csv(
        &dir.join("compare.csv"),
        &[
            "rotator",
            "metric",
            "max_error",
            "final_error",
            "wall_s",
            "ns_per_body_step",
            "stopped",
        ],
        &rows,
    )?;

    let name = scene_name(scene);
    let mut chart = Chart::new(
        format!("{name}: rotators at δt = {dt:e} s"),
        "time t (s)",
        r.metric,
    );
    chart.series = r
        .rows
        .iter()
        .map(|x| {
            let label = match &x.stopped {
                Some(_) => format!("{} (stopped)", x.rotator.name()),
                None => x.rotator.name().to_string(),
            };
            Series::new(label, x.t.clone(), x.err.clone(), Style::Line)
                .in_slot(super::rotator_slot(x.rotator))
        })
        .collect();
    // Log y when the positive errors span more than two decades (Figs. 2–4).
    let pos: Vec<f64> = r
        .rows
        .iter()
        .flat_map(|x| x.err.iter().cloned())
        .filter(|e| e.is_finite() && *e > 0.0)
        .collect();
    let (lo, hi) = pos
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &e| (a.min(e), b.max(e)));
    chart.log_y = hi / lo > 100.0;
    chart.legend = LegendPos::Auto;
    render_both(&chart, dir, r.figure)
}

/// The table as printed by `fibresim compare`.
pub fn print_report(r: &CompareReport) {
    println!("error metric: {} (figure {}.png/.svg)", r.metric, r.figure);
    println!(
        "{:<11} {:>12} {:>12} {:>10} {:>14}  stopped",
        "rotator", "max error", "final error", "wall_s", "ns/body-step"
    );
    for x in &r.rows {
        println!(
            "{:<11} {:>12} {:>12} {:>10.4} {:>14.1}  {}",
            x.rotator.name(),
            fmt_e(x.max_error),
            fmt_e(x.final_error),
            x.wall_s,
            x.ns_per_body_step,
            x.stopped.as_deref().unwrap_or("")
        );
    }
}
