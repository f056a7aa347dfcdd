//! The summary of the sweep: one line per case × rotator.

use super::{Class, StressCase, StressOptions, StressRun};
use crate::integrate::rotate::RotatorKind;

/// One line of the summary table: a case and a rotator.
#[derive(Debug, Clone)]
pub struct StressSummary {
    /// Name of the case.
    pub case: String,
    /// The rotator.
    pub rotator: RotatorKind,
    /// The case's recommended δt, s.
    pub recommended_dt: f64,
    /// The hard δt limit over the recommended δt (NaN: no limit).
    pub hard_limit_factor: f64,
    /// Largest factor with every factor up to it stable (NaN: none).
    pub largest_stable_factor: f64,
    /// Stable factors above the first unstable one (non-monotone stability).
    pub stable_above_failure: Vec<f64>,
    /// Largest error (energy, or angular momentum if larger) of the run at
    /// the recommended δt, percent.
    pub err_at_recommended_pct: f64,
    /// How the run at the recommended δt ended, in a few words.
    pub at_recommended: String,
    /// The unstable runs, summarised: consecutive factors with the same
    /// detection grouped, e.g. `x0.25-0.5: energy/L error > tol`.
    pub detected_by: String,
    /// Largest error of the run at the scene's own δt, percent.
    pub err_at_scene_dt_pct: f64,
    /// The scene's own δt, s.
    pub scene_dt: f64,
    /// `x<factor>: <detection>` for every unstable run.
    pub detections: Vec<String>,
}

pub(super) fn summarise(
    cases: &[StressCase],
    runs: &[StressRun],
    opts: &StressOptions,
) -> Vec<StressSummary> {
    let mut out = vec![];
    for c in cases {
        for &k in &opts.rotators {
            let mut sweep: Vec<&StressRun> = runs
                .iter()
                .filter(|r| r.case == c.name && r.rotator == k && !r.scene_dt)
                .collect();
            sweep.sort_by(|a, b| a.factor.total_cmp(&b.factor));
            let first_bad = sweep.iter().position(|r| !r.verdict.is_stable());
            let largest = match first_bad {
                Some(0) => f64::NAN,
                Some(i) => sweep[i - 1].factor,
                None => sweep.last().map_or(f64::NAN, |r| r.factor),
            };
            let stable_above = first_bad.map_or(vec![], |i| {
                sweep[i..]
                    .iter()
                    .filter(|r| r.verdict.is_stable())
                    .map(|r| r.factor)
                    .collect()
            });
            let scene_run = runs
                .iter()
                .find(|r| r.case == c.name && r.rotator == k && r.scene_dt);
            let err = |r: &StressRun| r.energy_err_pct.max(r.momentum_err_pct);
            let at_rec = sweep.iter().find(|r| r.factor == 1.0);
            out.push(StressSummary {
                case: c.name.clone(),
                rotator: k,
                recommended_dt: c.recommended_dt,
                hard_limit_factor: c.hard_limit_dt.map_or(f64::NAN, |h| h / c.recommended_dt),
                largest_stable_factor: largest,
                stable_above_failure: stable_above,
                err_at_recommended_pct: at_rec.map_or(f64::NAN, |r| err(r)),
                at_recommended: at_rec.map_or("not run".into(), |r| r.verdict.short(opts)),
                detected_by: detected_by(&sweep, scene_run, opts),
                err_at_scene_dt_pct: scene_run.map_or(f64::NAN, err),
                scene_dt: c.scene.sim.dt(),
                detections: sweep
                    .iter()
                    .chain(scene_run.iter())
                    .filter(|r| !r.verdict.is_stable())
                    .map(|r| {
                        format!(
                            "{}{}: {}",
                            if r.scene_dt { "scene dt " } else { "x" },
                            if r.scene_dt {
                                format!("{:e}", r.dt)
                            } else {
                                format!("{}", r.factor)
                            },
                            r.verdict.detection(r, opts)
                        )
                    })
                    .collect(),
            });
        }
    }
    out
}

/// The unstable runs of one case × rotator, grouped: runs of consecutive
/// factors with the same detection become one `x<a>-<b>: <how>` item.
fn detected_by(sweep: &[&StressRun], scene_run: Option<&StressRun>, o: &StressOptions) -> String {
    let mut items: Vec<(f64, f64, Class)> = vec![];
    for r in sweep {
        let class = r.verdict.class();
        match items.last_mut() {
            Some(last) if class == last.2 && class != Class::Stable => last.1 = r.factor,
            _ => items.push((r.factor, r.factor, class)),
        }
    }
    let mut out: Vec<String> = items
        .into_iter()
        .filter(|i| i.2 != Class::Stable)
        .map(|(a, b, c)| {
            let range = if a == b {
                format!("x{a}")
            } else {
                format!("x{a}-{b}")
            };
            format!("{range}: {}", c.words(o))
        })
        .collect();
    if let Some(r) = scene_run.filter(|r| !r.verdict.is_stable()) {
        out.push(format!(
            "scene dt {:e}: {}",
            r.dt,
            r.verdict.class().words(o)
        ));
    }
    if out.is_empty() {
        "none unstable".into()
    } else {
        out.join("; ")
    }
}
