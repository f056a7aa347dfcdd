//! `fibresim stress` (docs/physics.md §8, docs/stress.md): every stress case × rotator over a
//! sweep of `δt = factor × δt_rec`, on past the hard limit, with the default
//! guards. The library is called directly, so δt beyond `hard_limit_dt` runs.
//!
//! **Recommended δt.** Contact scenes: `advise(&scene).recommended_dt` (the
//! shortest Hertz collision / 50 and 0.2 × the Rayleigh time). Contact-free
//! scenes: `0.05 / ‖ω‖max`, a rotation of 0.05 rad per step, with `‖ω‖max`
//! the largest initial `‖ω‖` (constant in torque-free motion of a fibre, a
//! symmetric top).
//!
//! **Stable** means all of:
//! 1. the run reached `t_end` without a guard stop (a [`Diagnosis`](crate::error::Diagnosis)) or a panic;
//! 2. *energy*: the largest full-budget energy error over all steps (Eq. 65
//!    with the elastic energy of live contacts; nothing dissipates) is at most
//!    `energy_tol_pct`; in contact-free scenes also the error of the world
//!    angular momentum `L = Σ q I ω_b q*`, `‖L − L₀‖/‖L₀‖`, which torque-free
//!    motion conserves exactly — this is where a rotator's orientation error
//!    shows;
//! 3. *outcome*: the free-flight invariants at the end agree with the case's
//!    reference run (rk4 at half the smallest δt of the sweep): per body the
//!    velocity less the gravity drift, `v − g t`, and the angular momentum
//!    `L` (so runs that end at slightly different times still compare), as a
//!    rim speed: `‖Δv‖ + ‖ΔL‖ r / I_max`, over the largest such speed of the
//!    reference, at most `outcome_tol_pct`. It catches garbage that conserves
//!    energy (a wrong bounce, fibres passing through each other).
//!
//! The step count is `⌈t_end/δt⌉`, so every run covers the case's event and
//! δt is exactly the stated multiple.
//!
//! **Errors of stopped runs.** A guard checks the state after a step; the
//! energy error of that step is counted (it is the guard's value for an
//! energy stop), so a stopped run's largest error is not understated. The
//! scalar-pole guard fires before its step: every computed step is counted.

mod case;
mod map;
mod summary;
mod sweep;
mod tables;
mod verdict;

pub use case::{load_cases, wildcard, StressCase};
pub use summary::StressSummary;
pub use sweep::StressRun;
pub use tables::print_report;
use verdict::Class;
pub use verdict::Verdict;

use crate::error::{Error, Result};
use crate::integrate::rotate::RotatorKind;
use std::path::PathBuf;

/// Default δt factors (multiples of the recommended δt).
pub const DEFAULT_FACTORS: [f64; 10] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0];
/// Default energy (and angular momentum) tolerance, percent.
pub const ENERGY_TOL_PCT: f64 = 1.0;
/// Default outcome tolerance, percent of the reference's largest rim speed.
pub const OUTCOME_TOL_PCT: f64 = 5.0;
/// Rotation per step at the recommended δt of a contact-free scene, rad.
pub(crate) const SPIN_ANGLE_PER_STEP: f64 = 0.05;

/// Options of the stress sweep.
#[derive(Debug, Clone)]
pub struct StressOptions {
    /// The rotators to sweep (rows of the map).
    pub rotators: Vec<RotatorKind>,
    /// Multiples of each case's recommended δt (columns of the map).
    pub factors: Vec<f64>,
    /// Energy (contact-free: also angular momentum) tolerance, percent.
    pub energy_tol_pct: f64,
    /// Outcome tolerance, percent of the reference's largest rim speed.
    pub outcome_tol_pct: f64,
    /// Folder of the tables and the map.
    pub out_dir: PathBuf,
    /// Draw progress bars (on a terminal only).
    pub progress: bool,
}

/// Everything the sweep found.
pub struct StressReport {
    /// The cases, as given.
    pub cases: Vec<StressCase>,
    /// Every run, in job order: per case and rotator, the factors then the
    /// scene's own δt.
    pub runs: Vec<StressRun>,
    /// One line per case × rotator.
    pub summary: Vec<StressSummary>,
}

/// Run the sweep and write `stress.csv`, `stress_runs.csv` and the map.
pub fn stress(cases: Vec<StressCase>, opts: &StressOptions) -> Result<StressReport> {
    if cases.is_empty() {
        return Err(Error::bad(
            "command line",
            "--cases",
            "no stress case matched",
        ));
    }
    if opts.factors.is_empty() || opts.factors.iter().any(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(Error::bad(
            "command line",
            "--factors",
            "give finite factors > 0, e.g. 0.25,1,4,16",
        ));
    }
    // Every case computes contacts: the compositions are left out.
    let opts = &match cases.iter().find(|c| c.scene.needs_contacts()) {
        Some(c) => StressOptions {
            rotators: super::runnable(&c.scene, &opts.rotators)?,
            ..opts.clone()
        },
        None => opts.clone(),
    };
    crate::output::create_out_dir(&opts.out_dir)?;
    let runs = sweep::sweep(&cases, opts)?;
    let summary = summary::summarise(&cases, &runs, opts);
    let report = StressReport {
        cases,
        runs,
        summary,
    };
    tables::write_outputs(&report, opts)?;
    Ok(report)
}
