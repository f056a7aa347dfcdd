//! `fibresim converge`: error against δt for each rotator, observed orders
//! (log–log least squares), and work–precision (error against run time).
//!
//! Metrics (paper §4.2):
//! - torque scenes: Eq. 66–67, `α = δt/T Σ_n |acos(b_n·B) − acos(B_n·B)|` with
//!   `b_n` the body-x axis from the run, `B_n` from the reference at `t_n`, `B`
//!   the initial axis; and the geodesic angle `2 acos|q·q_ref|` at `T`.
//!   Closed-form scenes also give Table 2's x-error (percent).
//! - other scenes: the full-budget energy error (Eq. 65 on Eq. 64 plus the
//!   elastic energy of live contacts, the budget that is conserved), max over
//!   the run and final. Plain Eq. 65 (no elastic term) is also written, but
//!   not fitted: it dips by up to ~100 % during every contact. With
//!   `--trajectory`, also the trajectory error at T: the largest distance and
//!   geodesic angle of a body to a fine run of the named rotator.
//!
//! Timing: the errors are computed in parallel, but each point's `wall_s` is
//! taken afterwards in a sequential pass of unobserved runs (median of
//! several repeats for short runs), so no run competes with another study
//! run for the cores.
//!
//! Reference: the scene's closed form, else `rk4` (in energy mode the
//! `--trajectory` rotator) on a grid `factor`× finer than `dt_min`. Every δt is a whole multiple `m` of that grid step, so the
//! reference is sampled exactly at the coarse times. The reference's own error
//! is estimated by Richardson from a run at twice its step: diff / (2⁴ − 1).

mod figures;
mod grid;
mod measure;
mod outputs;
mod reference;
mod report;

pub use reference::{ReferenceInfo, ReferenceKind};
pub use report::print_report;

use super::fit::{fit_order, OrderFit};
use super::{with_params, Progress};
use crate::error::Result;
use crate::integrate::rotate::RotatorKind;
use crate::scenario::Scene;
use grid::Grid;
use measure::{measure, time_run, Study};
use rayon::prelude::*;
use reference::Reference;
use std::path::PathBuf;
use std::time::Instant;

/// `--rotators` default of `fibresim converge`: every scheme, so the
/// work–precision figure shows each one; `src/cli/args.rs` uses it as
/// `#[arg(long, default_value = crate::study::converge::DEFAULT_ROTATORS)]`.
pub const DEFAULT_ROTATORS: &str = "all";

/// Options of a convergence study.
#[derive(Debug, Clone)]
pub struct ConvergeOptions {
    /// The rotators measured.
    pub rotators: Vec<RotatorKind>,
    /// Largest and smallest δt; default 10× above and below the scene's δt
    /// (for test case 4: 1e-5 and 1e-7 s, the paper's range).
    pub dt_max: Option<f64>,
    /// See [`ConvergeOptions::dt_max`].
    pub dt_min: Option<f64>,
    /// Number of δt, geometric from `dt_max` to `dt_min` (each rounded to a
    /// whole multiple of the reference step).
    pub points: usize,
    /// End time, s; default the scene's.
    pub t_end: Option<f64>,
    /// The rk4 reference step is `dt_min / ref_factor`.
    pub ref_factor: f64,
    /// Folder of the tables and figures.
    pub out_dir: PathBuf,
    /// Draw progress bars (on a terminal only).
    pub progress: bool,
    /// Contact scenes: also measure the trajectory error at T against this
    /// rotator on the fine grid (none: the energy error only).
    pub trajectory: Option<RotatorKind>,
}

/// What is measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Eq. 66–67 and the geodesic angle against a reference orientation.
    Orientation,
    /// Full-budget Eq. 65 energy error (with the elastic energy).
    Energy,
}

/// One (rotator, δt) run.
#[derive(Debug, Clone)]
pub struct Point {
    /// The rotator run.
    pub rotator: RotatorKind,
    /// The step, s.
    pub dt: f64,
    /// Steps to the end time.
    pub steps: u64,
    /// Eq. 67, rad (orientation mode; NaN otherwise).
    pub alpha_rad: f64,
    /// Geodesic angle to the reference at T, rad (max over bodies).
    pub geodesic_rad: f64,
    /// Table 2's relative x-error at T, percent (closed-form scenes).
    pub x_error_pct: f64,
    /// Largest distance of a body to its trajectory reference at T, m
    /// (energy mode with `--trajectory`; NaN otherwise).
    pub position_m: f64,
    /// Plain Eq. 65 (Eq. 64, no elastic energy), percent: max and final.
    pub energy_max_pct: f64,
    /// See [`Point::energy_max_pct`].
    pub energy_final_pct: f64,
    /// Full budget (Eq. 65 with the elastic energy), percent: max and final.
    pub energy_full_max_pct: f64,
    /// See [`Point::energy_full_max_pct`].
    pub energy_full_final_pct: f64,
    /// Wall time of an unobserved run (stepping only), s: the median of
    /// `timing_runs` sequential runs, none concurrent with another run.
    pub wall_s: f64,
    /// Number of timing runs behind `wall_s`.
    pub timing_runs: u32,
    /// The guard's diagnosis if the run stopped (its errors are NaN).
    pub stopped: Option<String>,
}

/// Fitted orders of one rotator for one metric.
#[derive(Debug, Clone)]
pub struct Orders {
    /// The rotator.
    pub rotator: RotatorKind,
    /// The metric's column name in `convergence.csv`.
    pub metric: &'static str,
    /// Over all valid points.
    pub all: Option<OrderFit>,
    /// Over the three finest valid points (the asymptotic regime).
    pub fine: Option<OrderFit>,
}

/// Everything a convergence study found.
pub struct ConvergeReport {
    /// What was measured.
    pub mode: Mode,
    /// End time of every run, s.
    pub t_end: f64,
    /// The δt run, largest first, s.
    pub dts: Vec<f64>,
    /// Every (rotator, δt) run, per rotator in `dts` order.
    pub points: Vec<Point>,
    /// Fitted orders per rotator and metric.
    pub orders: Vec<Orders>,
    /// The reference measured against.
    pub reference: ReferenceInfo,
    /// Wall time of the whole study, s.
    pub wall_s: f64,
}

/// A metric of a point, as plotted and fitted.
type MetricFn = fn(&Point) -> f64;

/// Run the convergence study and write its outputs.
pub fn converge(scene: &Scene, opts: &ConvergeOptions) -> Result<ConvergeReport> {
    let opts = &ConvergeOptions {
        rotators: super::runnable(scene, &opts.rotators)?,
        ..opts.clone()
    };
    let start = Instant::now();
    crate::output::create_out_dir(&opts.out_dir)?;
    let t_end = opts.t_end.unwrap_or(scene.sim.t_end());
    let dt_max = opts.dt_max.unwrap_or(10.0 * scene.sim.dt());
    let dt_min = opts.dt_min.unwrap_or(0.1 * scene.sim.dt());
    let mode = if scene.has_prescribed_torque() || scene.reference.is_some() {
        Mode::Orientation
    } else {
        Mode::Energy
    };
    let grid = Grid::new(t_end, dt_max, dt_min, opts.points, opts.ref_factor)?;
    let (n_ref, ms) = (grid.n_ref, &grid.ms);
    let nb = scene.bodies.len();
    if let (Mode::Orientation, Some(_)) = (mode, opts.trajectory) {
        return Err(crate::error::Error::bad(
            "command line",
            "--trajectory",
            "this scene is measured by its orientation against the closed form or rk4 already; --trajectory is for scenes without prescribed torques or a closed form; drop it",
        ));
    }
    if let Some(k) = opts.trajectory {
        super::runnable(scene, &[k])?;
    }
    let needs_run = matches!(
        ReferenceKind::of(scene, mode, opts.trajectory),
        ReferenceKind::Rk4 | ReferenceKind::Fine(_)
    );

    // Per point: the measured run and the first timing run.
    let work: u64 = ms.iter().map(|m| 2 * (n_ref / m)).sum::<u64>() * opts.rotators.len() as u64
        + if needs_run { n_ref + n_ref / 2 } else { 0 };
    let progress = Progress::new(opts.progress, work * nb as u64, "converge");

    let (reference, ref_info) =
        Reference::new(scene, mode, &grid, t_end, &progress, opts.trajectory)?;
    let study = Study {
        scene,
        mode,
        t_end,
        dt_ref: grid.dt_ref,
        reference: &reference,
        progress: &progress,
    };

    // All (rotator, δt) runs; longest first for load balance.
    let mut jobs: Vec<(usize, RotatorKind, u64)> = Vec::new();
    for &k in &opts.rotators {
        for &m in ms {
            jobs.push((jobs.len(), k, m));
        }
    }
    let mut by_cost = jobs.clone();
    by_cost.sort_by_key(|&(_, k, m)| (m, k));
    let results: Vec<(usize, Result<Point>)> = by_cost
        .par_iter()
        .map(|&(idx, kind, m)| (idx, measure(&study, kind, m)))
        .collect();
    let mut points: Vec<Option<Point>> = vec![None; jobs.len()];
    for (idx, r) in results {
        points[idx] = Some(r?);
    }
    let mut points: Vec<Point> = points
        .into_iter()
        .map(|p| p.expect("every job ran"))
        .collect();
    // Timing pass, sequential: two runs sharing the cores slow each other
    // down, which would bend the work-precision figure.
    for p in &mut points {
        let s = with_params(scene, p.rotator, p.dt, t_end)?;
        (p.wall_s, p.timing_runs) = time_run(&s);
        progress.done(s.sim.steps() * nb as u64);
    }
    progress.finish();

    let report = ConvergeReport {
        mode,
        t_end,
        dts: ms.iter().map(|&m| m as f64 * grid.dt_ref).collect(),
        orders: fit_orders(&points, &opts.rotators, mode, opts.trajectory.is_some()),
        points,
        reference: ref_info,
        wall_s: start.elapsed().as_secs_f64(),
    };
    outputs::write_outputs(scene, &report, opts)?;
    Ok(report)
}

/// Observed orders of each rotator for the metrics of `mode`, over all
/// points and over the finest three.
fn fit_orders(
    points: &[Point],
    rotators: &[RotatorKind],
    mode: Mode,
    trajectory: bool,
) -> Vec<Orders> {
    let mut metrics: Vec<(&'static str, MetricFn)> = match mode {
        Mode::Orientation => vec![
            ("alpha_rad", |p| p.alpha_rad),
            ("geodesic_rad", |p| p.geodesic_rad),
        ],
        Mode::Energy => vec![
            ("energy_error_full_max_pct", |p| p.energy_full_max_pct),
            ("energy_error_full_final_pct", |p| p.energy_full_final_pct),
        ],
    };
    if mode == Mode::Energy && trajectory {
        metrics.push(("position_error_m", |p| p.position_m));
        metrics.push(("geodesic_rad", |p| p.geodesic_rad));
    }
    let mut orders = Vec::new();
    for &k in rotators {
        let pts: Vec<&Point> = points.iter().filter(|p| p.rotator == k).collect();
        for (name, f) in &metrics {
            let dts: Vec<f64> = pts.iter().map(|p| p.dt).collect();
            let errs: Vec<f64> = pts.iter().map(|p| f(p)).collect();
            // Finest three valid points (dts are in decreasing order).
            let valid: Vec<usize> = (0..dts.len())
                .filter(|&i| errs[i].is_finite() && errs[i] > 0.0)
                .collect();
            let tail = &valid[valid.len().saturating_sub(3)..];
            let fine = fit_order(
                &tail.iter().map(|&i| dts[i]).collect::<Vec<_>>(),
                &tail.iter().map(|&i| errs[i]).collect::<Vec<_>>(),
            );
            orders.push(Orders {
                rotator: k,
                metric: name,
                all: fit_order(&dts, &errs),
                fine,
            });
        }
    }
    orders
}
