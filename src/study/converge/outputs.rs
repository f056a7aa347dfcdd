//! The tables of a convergence study: points, fitted orders, reference.

use super::{figures, ConvergeOptions, ConvergeReport};
use crate::error::Result;
use crate::scenario::Scene;
use crate::study::fit::OrderFit;
use crate::study::{cell, write_csv};

/// Write `convergence.csv`, `orders.csv`, `reference.csv` and the figures.
pub(super) fn write_outputs(
    scene: &Scene,
    r: &ConvergeReport,
    opts: &ConvergeOptions,
) -> Result<()> {
    let dir = &opts.out_dir;
    let rows: Vec<Vec<String>> = r
        .points
        .iter()
        .map(|p| {
            vec![
                p.rotator.name().to_string(),
                cell(p.dt),
                p.steps.to_string(),
                cell(p.alpha_rad),
                cell(p.geodesic_rad),
                cell(p.x_error_pct),
                cell(p.position_m),
                cell(p.energy_full_max_pct),
                cell(p.energy_full_final_pct),
                cell(p.energy_max_pct),
                cell(p.energy_final_pct),
                cell(p.wall_s),
                p.timing_runs.to_string(),
                p.stopped.clone().unwrap_or_default(),
            ]
        })
        .collect();
    write_csv(
        &dir.join("convergence.csv"),
        &[
            "rotator",
            "dt",
            "steps",
            "alpha_rad",
            "geodesic_rad",
            "x_error_pct",
            "position_error_m",
            "energy_error_full_max_pct",
            "energy_error_full_final_pct",
            "energy_error_max_pct",
            "energy_error_final_pct",
            "wall_s",
            "timing_runs",
            "stopped",
        ],
        &rows,
    )?;
    let f = |o: &Option<OrderFit>, g: fn(&OrderFit) -> f64| o.as_ref().map_or(f64::NAN, g);
    let rows: Vec<Vec<String>> = r
        .orders
        .iter()
        .map(|o| {
            vec![
                o.rotator.name().to_string(),
                o.metric.to_string(),
                cell(f(&o.all, |x| x.order)),
                cell(f(&o.all, |x| x.r2)),
                o.all.map_or(0, |x| x.points).to_string(),
                cell(f(&o.fine, |x| x.order)),
                o.rotator.info().order.to_string(),
            ]
        })
        .collect();
    write_csv(
        &dir.join("orders.csv"),
        &[
            "rotator",
            "metric",
            "order",
            "r2",
            "points",
            "order_finest3",
            "nominal_order",
        ],
        &rows,
    )?;
    let rf = &r.reference;
    write_csv(
        &dir.join("reference.csv"),
        &[
            "kind",
            "dt",
            "steps",
            "wall_s",
            "richardson_alpha_rad",
            "richardson_geodesic_rad",
            "richardson_position_m",
        ],
        &[vec![
            rf.kind.to_string(),
            cell(rf.dt),
            rf.steps.to_string(),
            cell(rf.wall_s),
            cell(rf.alpha_err),
            cell(rf.geodesic_err),
            cell(rf.position_err),
        ]],
    )?;
    figures::figures(scene, r, opts)
}
