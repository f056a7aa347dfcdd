//! The tables of the sweep: `stress.csv`, `stress_runs.csv`, the markdown
//! tables and the summary printed on stdout.

use super::map::stability_map;
use super::{StressOptions, StressReport, StressSummary, Verdict};
use crate::error::{Error, Result};
use crate::plot::render_map;
use crate::study::{cell, fmt_e, plot_error, write_csv};

/// Header of `stress.csv`.
const SUMMARY_HEADER: [&str; 13] = [
    "case",
    "rotator",
    "recommended_dt",
    "hard_limit_factor",
    "largest_stable_dt",
    "largest_stable_factor",
    "energy_error_full_at_recommended_pct",
    "run_at_recommended",
    "scene_dt",
    "energy_error_full_at_scene_dt_pct",
    "stable_above_first_failure",
    "detected_by",
    "unstable_runs",
];

/// Header of `stress_runs.csv`.
const RUNS_HEADER: [&str; 16] = [
    "case",
    "rotator",
    "factor",
    "scene_dt",
    "dt",
    "steps",
    "steps_done",
    "stable",
    "energy_error_full_max_pct",
    "energy_error_full_at_stop_pct",
    "momentum_error_max_pct",
    "outcome_error_pct",
    "detection",
    "quantity",
    "value",
    "limit",
];

/// Write `stress.csv`, `stress_runs.csv`, the markdown tables and the map.
pub(super) fn write_outputs(r: &StressReport, opts: &StressOptions) -> Result<()> {
    let dir = &opts.out_dir;
    let rows: Vec<Vec<String>> = r
        .summary
        .iter()
        .map(|s| {
            vec![
                s.case.clone(),
                s.rotator.name().into(),
                cell(s.recommended_dt),
                cell(s.hard_limit_factor),
                cell(s.largest_stable_factor * s.recommended_dt),
                cell(s.largest_stable_factor),
                cell(s.err_at_recommended_pct),
                s.at_recommended.clone(),
                cell(s.scene_dt),
                cell(s.err_at_scene_dt_pct),
                s.stable_above_failure
                    .iter()
                    .map(|f| crate::output::num(*f))
                    .collect::<Vec<_>>()
                    .join(" "),
                s.detected_by.clone(),
                s.detections.join("; "),
            ]
        })
        .collect();
    write_csv(&dir.join("stress.csv"), &SUMMARY_HEADER, &rows)?;
    let rows: Vec<Vec<String>> = r
        .runs
        .iter()
        .map(|x| {
            let (kind, q, v, l) = match &x.verdict {
                Verdict::Guard(d) => (
                    d.kind.short().to_string(),
                    d.quantity().to_string(),
                    cell(d.value),
                    cell(d.limit),
                ),
                Verdict::Stable => (String::new(), String::new(), String::new(), String::new()),
                v => (
                    v.detection(x, opts),
                    String::new(),
                    String::new(),
                    String::new(),
                ),
            };
            vec![
                x.case.clone(),
                x.rotator.name().into(),
                cell(x.factor),
                x.scene_dt.to_string(),
                cell(x.dt),
                x.steps.to_string(),
                x.steps_done.to_string(),
                x.verdict.is_stable().to_string(),
                cell(x.energy_err_pct),
                cell(x.energy_err_at_stop_pct),
                cell(x.momentum_err_pct),
                cell(x.outcome_err_pct),
                kind,
                q,
                v,
                l,
            ]
        })
        .collect();
    write_csv(&dir.join("stress_runs.csv"), &RUNS_HEADER, &rows)?;
    let (compact, full) = markdown(r);
    for (name, text) in [("stress_table.md", compact), ("stress_full.md", full)] {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(&p, e))?;
    }
    let map = stability_map(r, opts);
    for ext in ["png", "svg"] {
        let p = dir.join(format!("stability_map.{ext}"));
        render_map(&map, &p).map_err(plot_error)?;
    }
    Ok(())
}

/// Print the summary table on stdout.
pub fn print_report(r: &StressReport) {
    println!(
        "{:<14} {:<10} {:>10} {:>8} {:>11} {:>8} {:>12}  first unstable run",
        "case", "rotator", "dt_rec", "limit x", "stable dt", "x rec", "E err @rec %"
    );
    for s in &r.summary {
        println!(
            "{:<14} {:<10} {:>10} {:>8} {:>11} {:>8} {:>12}  {}",
            s.case,
            s.rotator.name(),
            fmt_e(s.recommended_dt),
            fmt_e(s.hard_limit_factor),
            fmt_e(s.largest_stable_factor * s.recommended_dt),
            if s.largest_stable_factor.is_finite() {
                crate::output::num(s.largest_stable_factor)
            } else {
                "none".into()
            },
            fmt_e(s.err_at_recommended_pct),
            s.detections.first().map_or("-", String::as_str)
        );
    }
}

/// `x` to 3 significant digits: fixed in [1e-3, 1e4), else scientific.
fn sig3(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "–".into()
        } else {
            "∞".into()
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..4).contains(&e) {
        format!("{:.*}", (2 - e).max(0) as usize, x)
    } else {
        format!("{x:.2e}")
    }
}

impl StressSummary {
    /// Largest stable δt cell: `4.81e-5 (x4)`, `none`, plus non-monotone notes.
    fn stable_cell(&self) -> String {
        let mut c = if self.largest_stable_factor.is_finite() {
            format!(
                "{:.2e} (×{})",
                self.largest_stable_factor * self.recommended_dt,
                self.largest_stable_factor
            )
        } else {
            "none".into()
        };
        if !self.stable_above_failure.is_empty() {
            let f: Vec<String> = self
                .stable_above_failure
                .iter()
                .map(|f| format!("×{f}"))
                .collect();
            c += &format!(", stable again at {}", f.join(", "));
        }
        c
    }

    /// Error at δt_rec with how that run ended, e.g. `10.1 % (stopped by …)`.
    fn err_cell(&self) -> String {
        let e = format!("{} %", sig3(self.err_at_recommended_pct));
        if self.at_recommended == "stable" {
            e
        } else {
            format!("{e} ({})", self.at_recommended)
        }
    }
}

/// Markdown tables of the result: a compact one (rotators with the same
/// result share a row) and one line per case × rotator, both for docs/stress.md.
fn markdown(r: &StressReport) -> (String, String) {
    let mut compact = String::from(
        "| case | δt_rec (s) | rotators | largest stable δt (s) | energy error at δt_rec (max over the run; spin: also L) | how the unstable runs were detected |\n|---|---|---|---|---|---|\n",
    );
    for c in &r.cases {
        let rows: Vec<&StressSummary> = r.summary.iter().filter(|s| s.case == c.name).collect();
        let mut groups: Vec<(Vec<&str>, [String; 3])> = vec![];
        for s in &rows {
            let key = [s.stable_cell(), s.err_cell(), s.detected_by.clone()];
            match groups.iter_mut().find(|g| g.1 == key) {
                Some(g) => g.0.push(s.rotator.name()),
                None => groups.push((vec![s.rotator.name()], key)),
            }
        }
        for (names, [stable, err, det]) in groups {
            let who = if names.len() == rows.len() && rows.len() > 1 {
                format!("all {}", names.len())
            } else {
                names.join(", ")
            };
            compact += &format!(
                "| {} | {:.2e} | {who} | {stable} | {err} | {det} |\n",
                c.name, c.recommended_dt
            );
        }
    }
    let mut full = String::from(
        "| case | rotator | δt_rec (s) | hard limit (× rec) | largest stable δt (s) | energy error at δt_rec (%) | run at δt_rec | scene δt (s) | energy error at scene δt (%) | how the unstable runs were detected | first unstable run, in detail |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for s in &r.summary {
        full += &format!(
            "| {} | {} | {:.2e} | {} | {} | {} | {} | {:e} | {} | {} | {} |\n",
            s.case,
            s.rotator.name(),
            s.recommended_dt,
            if s.hard_limit_factor.is_finite() {
                format!("{:.1}", s.hard_limit_factor)
            } else {
                "–".into()
            },
            s.stable_cell(),
            sig3(s.err_at_recommended_pct),
            s.at_recommended,
            s.scene_dt,
            sig3(s.err_at_scene_dt_pct),
            s.detected_by,
            s.detections.first().map_or("–", String::as_str),
        );
    }
    (compact, full)
}
