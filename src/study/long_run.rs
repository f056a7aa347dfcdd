//! Long runs and time reversibility of every rotator: the
//! torque-free asymmetric top (10⁶ steps of 1e-4 s) and the precessing fibre
//! (10⁶ steps of 1e-5 s), each against its closed form.
//!
//! A long run samples, every `every` steps, the relative energy error
//! `E(t)/E₀ − 1` (`E = ½ ω_b·Iω_b`) and the relative world angular-momentum
//! error `|L(t) − L₀|/|L₀|` (`L = q Iω_b q*`; both conserved by the exact
//! flow). The energy drift rate is the least-squares slope of the energy
//! error on `t`; the run **drifts** when that trend over the run exceeds
//! twice the largest residual about it (the trend dominates the
//! oscillation), is **bounded** otherwise, and is at **rounding** when the
//! largest error stays below [`ROUNDING`]. The energy guard is lifted, so
//! first-order schemes are measured rather than stopped.
//!
//! Reversibility: forward `n` steps, ω flipped, `n` steps back; the distance
//! from the start is the geodesic angle plus the relative ω difference.
//!
//! The table is printed by
//! `cargo test --release --test suite free_flight::long_runs -- --ignored --nocapture`
//! (docs/validation.md, "Long runs and time reversibility").

use crate::integrate::rotate::RotatorKind;
use crate::math::{geodesic_angle, to_world};
use crate::scenario::{Scene, SimParams};
use glam::DVec3;

/// Below this largest relative energy error a run is at rounding.
pub const ROUNDING: f64 = 1e-10;

/// How the energy error behaves over a long run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Trend {
    /// Largest error below [`ROUNDING`].
    Rounding,
    /// No trend above the oscillation.
    Bounded,
    /// A linear trend above the oscillation.
    Drifting,
}

impl std::fmt::Display for Trend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Trend::Rounding => "rounding",
            Trend::Bounded => "bounded",
            Trend::Drifting => "drifting",
        })
    }
}

/// What one long run measured.
#[derive(Debug, Clone)]
pub struct LongRun {
    /// The rotator.
    pub kind: RotatorKind,
    /// Steps taken (fewer than asked if the run stopped).
    pub steps: u64,
    /// Why it stopped early, if it did.
    pub stopped: Option<String>,
    /// Largest `|E/E₀ − 1|`.
    pub energy_max: f64,
    /// Least-squares slope of `E/E₀ − 1` on `t`, 1/s.
    pub drift_per_s: f64,
    /// Bounded, drifting or rounding.
    pub trend: Trend,
    /// Largest `|L − L₀|/|L₀|`.
    pub momentum_max: f64,
    /// Orientation error at the end against the scene's closed form, rad.
    pub orientation_final: f64,
}

/// Least-squares line `a + b t` through `(t, e)`: `(a, b)`.
fn line(pts: &[(f64, f64)]) -> (f64, f64) {
    let n = pts.len() as f64;
    let mt = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let me = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let stt: f64 = pts.iter().map(|p| (p.0 - mt).powi(2)).sum();
    let ste: f64 = pts.iter().map(|p| (p.0 - mt) * (p.1 - me)).sum();
    let b = if stt > 0.0 { ste / stt } else { 0.0 };
    (me - b * mt, b)
}

/// The trend of samples `(t, e)` over a run of length `t_end` (module docs).
pub fn classify(pts: &[(f64, f64)], t_end: f64) -> (f64, Trend) {
    let (a, b) = line(pts);
    let largest = pts.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let residual = pts
        .iter()
        .map(|p| (p.1 - a - b * p.0).abs())
        .fold(0.0, f64::max);
    let trend = if largest < ROUNDING {
        Trend::Rounding
    } else if (b * t_end).abs() > 2.0 * residual {
        Trend::Drifting
    } else {
        Trend::Bounded
    };
    (b, trend)
}

/// Run `scene` (one contact-free body with a closed form) with `kind` for
/// `steps` steps of `dt`, sampling every `every` steps.
pub fn long_run(scene: &Scene, kind: RotatorKind, dt: f64, steps: u64, every: u64) -> LongRun {
    let mut s = scene.clone();
    s.sim = SimParams::with_steps(dt, steps, kind, None).expect("a positive dt");
    s.guards.energy_error_pct = f64::INFINITY;
    let inertia = scene.bodies[0].inertia.principal;
    let energy = |w: DVec3| 0.5 * (inertia * w).dot(w);
    let momentum = |st: &crate::body::BodyState| to_world(st.rot.q, inertia * st.rot.omega_b);
    let (e0, l0) = (
        energy(scene.initial[0].rot.omega_b),
        momentum(&scene.initial[0]),
    );
    let mut pts = Vec::new();
    let mut momentum_max = 0.0f64;
    let f = crate::run::integrate_to_stop(&s, |w| {
        if w.step.is_multiple_of(every) {
            let st = &w.states[0];
            pts.push((w.time(), energy(st.rot.omega_b) / e0 - 1.0));
            momentum_max = momentum_max.max((momentum(st) - l0).length() / l0.length());
        }
    });
    let t_end = f.world.time();
    let (drift_per_s, trend) = classify(&pts, t_end);
    let orientation_final = scene.reference.as_ref().map_or(f64::NAN, |r| {
        geodesic_angle(f.world.states[0].rot.q, r.orientation(t_end))
    });
    LongRun {
        kind,
        steps: f.world.step,
        stopped: f.stopped.map(|d| d.to_string()),
        energy_max: pts.iter().map(|p| p.1.abs()).fold(0.0, f64::max),
        drift_per_s,
        trend,
        momentum_max,
        orientation_final,
    }
}

/// Forward `n` steps of `dt`, ω flipped, `n` steps back: the distance from
/// the start (module docs). The scene's reference and energy guard are
/// dropped.
pub fn round_trip(scene: &Scene, kind: RotatorKind, dt: f64, n: u64) -> f64 {
    let mut s = scene.clone();
    s.reference = None;
    s.sim = SimParams::with_steps(dt, n, kind, None).expect("a positive dt");
    s.guards.energy_error_pct = f64::INFINITY;
    let start = s.initial[0].rot;
    let there = crate::run::integrate_to_stop(&s, |_| {}).world.states[0].rot;
    s.initial[0].rot.q = there.q;
    s.initial[0].rot.omega_b = -there.omega_b;
    let back = crate::run::integrate_to_stop(&s, |_| {}).world.states[0].rot;
    geodesic_angle(back.q, start.q)
        + (back.omega_b + start.omega_b).length() / start.omega_b.length()
}

/// One scene's long runs as a markdown table.
pub fn markdown(title: &str, runs: &[(LongRun, f64)]) -> String {
    use std::fmt::Write;
    let mut s = format!(
        "{title}\n\n| rotator | max \\|ΔE/E\\| | energy drift, 1/s | energy | max \\|ΔL\\|/\\|L\\| | orientation error at end, rad | reversibility distance |\n|---|---|---|---|---|---|---|\n"
    );
    for (r, rev) in runs {
        let stop = match &r.stopped {
            Some(_) => format!(" (stopped at step {})", r.steps),
            None => String::new(),
        };
        let _ = writeln!(
            s,
            "| `{}` | {:.1e} | {:+.1e} | {}{stop} | {:.1e} | {:.1e} | {:.1e} |",
            r.kind.name(),
            r.energy_max,
            r.drift_per_s,
            r.trend,
            r.momentum_max,
            r.orientation_final,
            rev
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The classification can tell a trend from an oscillation and from
    /// rounding.
    #[test]
    fn classify_tells_drift_from_oscillation() {
        let t: Vec<f64> = (0..=100).map(|i| i as f64).collect();
        let drift: Vec<_> = t.iter().map(|&t| (t, 1e-6 * t + 1e-6 * t.sin())).collect();
        let wave: Vec<_> = t.iter().map(|&t| (t, 1e-6 * (0.3 * t).sin())).collect();
        let tiny: Vec<_> = t.iter().map(|&t| (t, 1e-13 * t)).collect();
        assert_eq!(classify(&drift, 100.0).1, Trend::Drifting);
        assert!((classify(&drift, 100.0).0 - 1e-6).abs() < 5e-8);
        assert_eq!(classify(&wave, 100.0).1, Trend::Bounded);
        assert_eq!(classify(&tiny, 100.0).1, Trend::Rounding);
    }
}
