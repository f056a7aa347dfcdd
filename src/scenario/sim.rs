//! The numerical parameters of a run and the guards that stop it early.

use super::check::Ctx;
use crate::error::{Error, Result};
use crate::fmt::short;
use crate::integrate::rotate::RotatorKind;

/// Largest relative distance of `t_end / dt` from a whole number that is
/// taken as rounding of the inputs (their quotient is exact to ~1e-16).
pub const WHOLE_STEPS_TOL: f64 = 1e-9;

/// Numerical parameters of a run, checked: made only by [`SimParams::new`]
/// or [`SimParams::with_steps`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimParams {
    dt: f64,
    steps: u64,
    rotator: RotatorKind,
    every: Option<u64>,
}

impl SimParams {
    /// Check `dt`, `t_end` and `every`; `prefix` names where they came from in
    /// messages (`"simulation."` for the file, `"--"` for flags).
    pub fn new(
        dt: f64,
        t_end: f64,
        rotator: RotatorKind,
        every: Option<u64>,
        src: &str,
        prefix: &str,
    ) -> Result<Self> {
        let cx = Ctx { src };
        let dt = cx.positive(&format!("{prefix}dt"), dt)?;
        // Flags are spelled with a hyphen, file keys with an underscore.
        let key_t = if prefix == "--" {
            "--t-end".to_string()
        } else {
            format!("{prefix}t_end")
        };
        let t_end = cx.positive(&key_t, t_end)?;
        if dt > t_end {
            return Err(cx.err(
                &format!("{prefix}dt"),
                format!(
                    "dt = {} s is larger than t_end = {} s; choose dt <= t_end",
                    short(dt),
                    short(t_end)
                ),
            ));
        }
        let ratio = t_end / dt;
        let steps = ratio.round();
        // Only the rounding of the two decimals and of their quotient (a few
        // ulp) is forgiven: a t_end between two steps is never silently moved.
        if (ratio - steps).abs() > WHOLE_STEPS_TOL * ratio.max(1.0) {
            let (lo, hi) = (ratio.floor().max(1.0), ratio.ceil().max(1.0));
            return Err(cx.err(
                &key_t,
                format!(
                    "t_end = {} s is {ratio:.3} steps of dt = {} s, not a whole number; use t_end = {} s ({lo} steps) or {} s ({hi} steps), or change dt",
                    short(t_end),
                    short(dt),
                    short(lo * dt),
                    short(hi * dt)
                ),
            ));
        }
        if steps > 1e12 {
            return Err(cx.err(
                &key_t,
                format!(
                    "{} steps is more than fibresim will run; increase dt or reduce t_end",
                    short(steps)
                ),
            ));
        }
        if every == Some(0) {
            return Err(cx.err(&format!("{prefix}every"), super::check::EVERY_ZERO));
        }
        Ok(SimParams {
            dt,
            steps: steps as u64,
            rotator,
            every,
        })
    }

    /// `steps` steps of `dt` (the studies' sweeps, which round a t_end up
    /// to whole steps themselves).
    pub fn with_steps(
        dt: f64,
        steps: u64,
        rotator: RotatorKind,
        every: Option<u64>,
    ) -> Result<Self> {
        if !(dt.is_finite() && dt > 0.0) || steps == 0 || every == Some(0) {
            return Err(Error::bad(
                "parameters",
                "dt",
                format!(
                    "need dt > 0, at least one step and every >= 1 (dt = {}, {steps} steps)",
                    short(dt)
                ),
            ));
        }
        Ok(SimParams {
            dt,
            steps,
            rotator,
            every,
        })
    }

    /// The same parameters with another rotator.
    pub fn with_rotator(&self, rotator: RotatorKind) -> Self {
        SimParams {
            rotator,
            ..self.clone()
        }
    }

    /// Time step δt, s.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Steps to run.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The rotator.
    pub fn rotator(&self) -> RotatorKind {
        self.rotator
    }

    /// Output cadence as given; `None` = the default.
    pub fn every(&self) -> Option<u64> {
        self.every
    }

    /// Output cadence: as given, else at most 2e4 rows
    /// ([`crate::output::default_every`]).
    pub fn every_or_default(&self) -> u64 {
        self.every
            .unwrap_or_else(|| crate::output::default_every(self.steps))
    }

    /// End time `steps · δt`, s.
    pub fn t_end(&self) -> f64 {
        self.steps as f64 * self.dt
    }
}

/// Limits that stop a run early with a named diagnosis (docs/physics.md §8).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Guards {
    /// Largest full-budget energy error (Eq. 65 with the elastic term), percent.
    /// Default 10 %: far above any trustworthy run (the paper's worst is ~2 %),
    /// low enough to stop a blow-up within a few steps of its start.
    pub energy_error_pct: f64,
    /// Largest overlap as a fraction of the fibre diameter. Default 0.2: Hertz
    /// theory assumes small strains; beyond δ = D/5 the contact model is fiction.
    pub overlap_ratio: f64,
}

impl Default for Guards {
    fn default() -> Self {
        Guards {
            energy_error_pct: 10.0,
            overlap_ratio: 0.2,
        }
    }
}
