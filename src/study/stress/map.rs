//! The stability map: rotator × δt factor, one panel per case, each cell
//! coloured by its run's [`Class`].

use super::{Class, StressOptions, StressReport};
use crate::plot::{CellMap, MapPanel};

/// Rotator × δt-factor map, one panel per case.
pub(super) fn stability_map(r: &StressReport, opts: &StressOptions) -> CellMap {
    let mut factors = opts.factors.clone();
    factors.sort_by(f64::total_cmp);
    factors.dedup();
    let panels = r
        .cases
        .iter()
        .map(|c| {
            let cells = opts
                .rotators
                .iter()
                .map(|&k| {
                    factors
                        .iter()
                        .map(|&f| {
                            r.runs
                                .iter()
                                .find(|x| {
                                    x.case == c.name
                                        && x.rotator == k
                                        && !x.scene_dt
                                        && x.factor == f
                                })
                                .map(|x| {
                                    (x.verdict.class().index(), x.verdict.cell_text().to_string())
                                })
                        })
                        .collect()
                })
                .collect();
            // Fractional column of a factor (log-interpolated between columns).
            let column = |f: f64| -> f64 {
                if factors.len() < 2 {
                    return f64::NAN;
                }
                let lf = f.ln();
                for (i, w) in factors.windows(2).enumerate() {
                    let (a, b) = (w[0].ln(), w[1].ln());
                    if lf >= a && lf <= b {
                        return i as f64 + 0.5 + (lf - a) / (b - a);
                    }
                }
                f64::NAN
            };
            let marks = c
                .hard_limit_dt
                .map(|h| {
                    let f = h / c.recommended_dt;
                    (
                        column(f),
                        format!("hard limit (5 steps/collision) = x{f:.1}"),
                    )
                })
                .into_iter()
                .collect();
            MapPanel {
                title: format!(
                    "{}  (δt_rec = {:.2e} s, {})",
                    c.name, c.recommended_dt, c.basis
                ),
                x_ticks: factors
                    .iter()
                    .map(|&f| {
                        if f == 1.0 {
                            "1 (rec)".into()
                        } else {
                            format!("{f}")
                        }
                    })
                    .collect(),
                rows: opts.rotators.iter().map(|k| k.name().to_string()).collect(),
                row_slots: opts
                    .rotators
                    .iter()
                    .map(|&k| Some(crate::study::rotator_slot(k)))
                    .collect(),
                cells,
                marks,
            }
        })
        .collect();
    CellMap {
        title: format!(
            "Stability map: δt = factor × δt_rec (stable: no guard stop, energy/L error ≤ {} %, final state within {} % of rk4)",
            opts.energy_tol_pct, opts.outcome_tol_pct
        ),
        x_label: "δt / δt_rec".into(),
        classes: Class::ALL
            .iter()
            .map(|c| (c.label().to_string(), c.colour()))
            .collect(),
        panels,
        columns: 2,
    }
}
