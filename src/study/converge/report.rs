//! The report `fibresim converge` prints.

use super::reference::ReferenceKind;
use super::{ConvergeReport, Mode};
use crate::study::fit::OrderFit;
use crate::study::fmt_e;

/// The report as printed by `fibresim converge`.
pub fn print_report(r: &ConvergeReport) {
    let rf = &r.reference;
    match rf.kind {
        ReferenceKind::Rk4 => println!(
            "reference: rk4 at dt = {:.3e} s ({} steps, {:.2} s); its own error (Richardson, diff/15): alpha ~ {}, geodesic ~ {} rad",
            rf.dt, rf.steps, rf.wall_s, fmt_e(rf.alpha_err), fmt_e(rf.geodesic_err)
        ),
        ReferenceKind::ClosedForm => println!("reference: the scene's closed form"),
        ReferenceKind::Fine(k) => println!(
            "reference: {k} at dt = {:.3e} s ({} steps, {:.2} s), end state; its own error (distance to its twin at 2 dt): position ~ {} m, geodesic ~ {} rad",
            rf.dt, rf.steps, rf.wall_s, fmt_e(rf.position_err), fmt_e(rf.geodesic_err)
        ),
        ReferenceKind::None => println!(
            "reference: none (full-budget energy error: Eq. 65 with the elastic energy of live contacts)"
        ),
    }
    match r.mode {
        Mode::Orientation => println!(
            "{:<11} {:>10} {:>10} {:>12} {:>12} {:>10} {:>9}  stopped",
            "rotator", "dt", "steps", "alpha_rad", "geodesic", "x_err_%", "wall_s"
        ),
        Mode::Energy => println!(
            "{:<11} {:>10} {:>10} {:>12} {:>12} {:>12} {:>12} {:>9}  stopped",
            "rotator",
            "dt",
            "steps",
            "Efull_max_%",
            "Efull_fin_%",
            "position_m",
            "geodesic",
            "wall_s"
        ),
    }
    for p in &r.points {
        let stop = p.stopped.as_deref().unwrap_or("");
        match r.mode {
            Mode::Orientation => println!(
                "{:<11} {:>10.3e} {:>10} {:>12} {:>12} {:>10} {:>9.4}  {stop}",
                p.rotator.name(),
                p.dt,
                p.steps,
                fmt_e(p.alpha_rad),
                fmt_e(p.geodesic_rad),
                fmt_e(p.x_error_pct),
                p.wall_s
            ),
            Mode::Energy => println!(
                "{:<11} {:>10.3e} {:>10} {:>12} {:>12} {:>12} {:>12} {:>9.4}  {stop}",
                p.rotator.name(),
                p.dt,
                p.steps,
                fmt_e(p.energy_full_max_pct),
                fmt_e(p.energy_full_final_pct),
                fmt_e(p.position_m),
                fmt_e(p.geodesic_rad),
                p.wall_s
            ),
        }
    }
    println!(
        "\n{:<11} {:<24} {:>7} {:>6} {:>14} {:>8}",
        "rotator", "metric", "order", "r2", "order(fine 3)", "nominal"
    );
    for o in &r.orders {
        let f = |x: &Option<OrderFit>| x.map_or("-".into(), |x| format!("{:.3}", x.order));
        println!(
            "{:<11} {:<24} {:>7} {:>6} {:>14} {:>8}",
            o.rotator.name(),
            o.metric,
            f(&o.all),
            o.all.map_or("-".into(), |x| format!("{:.3}", x.r2)),
            f(&o.fine),
            o.rotator.info().order
        );
    }
    println!(
        "wall_s: median of sequential unobserved runs, none concurrent with another study run"
    );
    println!("total wall time {:.2} s", r.wall_s);
}
