//! The step as a sequence of stages, the way LAMMPS's `Integrate` drives its
//! fixes: opening stages (half-kick and drift), force stages and closing
//! stages (half-kick). A rotator is the rotation part of the opening and
//! closing stages (`advance`, `finish`); translation is velocity Verlet in
//! each sub-step. Integrators never compute forces: only a [`Stage::Forces`]
//! does, and it moves nothing.
//!
//! A whole step of `δt` is [`VERLET`]: one sub-step. A composition (e.g. a
//! 4th-order Yoshida or Suzuki scheme, or a stage that exchanges ghost
//! bodies between ranks) lists several sub-steps, each opening at
//! `t_n + start·δt` for `h·δt` and closing at `t_n + end·δt`, each with its own
//! force evaluation.

/// One stage of a step. Times and lengths are in units of δt from `t_n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stage {
    /// Translation half-kick and drift, and the rotator's `advance`, over the
    /// sub-step `[t_n + start·δt, t_n + (start + h)·δt]`.
    Open {
        /// Start of the sub-step, in δt from `t_n`.
        start: f64,
        /// Its length, in δt.
        h: f64,
    },
    /// Contact forces and torques at the current configuration.
    Forces,
    /// Closing translation half-kick and the rotator's `finish`, at
    /// `t_n + end·δt`, of the sub-step of length `h·δt`. The last stage of a
    /// step is always a `Close`; it also measures the energy ledger.
    Close {
        /// End of the sub-step, in δt from `t_n`.
        end: f64,
        /// Its length, in δt.
        h: f64,
    },
}

/// Velocity Verlet with one force evaluation per step (paper §4; Allen &
/// Tildesley): open over δt, forces at `x_{n+1}`, close at `t_{n+1}`.
pub const VERLET: &[Stage] = &[
    Stage::Open { start: 0.0, h: 1.0 },
    Stage::Forces,
    Stage::Close { end: 1.0, h: 1.0 },
];

/// Whether `stages` is [`VERLET`] (so the step can run it without a loop).
pub const fn is_verlet(stages: &[Stage]) -> bool {
    matches!(
        stages,
        [
            Stage::Open { start: 0.0, h: 1.0 },
            Stage::Forces,
            Stage::Close { end: 1.0, h: 1.0 }
        ]
    )
}

/// Whether `stages` form a valid step: it ends with a `Close`, opens and
/// closes alternate, and every close follows a force evaluation.
pub const fn is_valid(stages: &[Stage]) -> bool {
    if stages.is_empty() {
        return false;
    }
    let (mut open, mut forced, mut i) = (false, false, 0);
    while i < stages.len() {
        match stages[i] {
            Stage::Open { .. } => {
                if open {
                    return false;
                }
                open = true;
                forced = false;
            }
            Stage::Forces => forced = true,
            Stage::Close { .. } => {
                if !open || !forced {
                    return false;
                }
                open = false;
            }
        }
        i += 1;
    }
    matches!(stages[stages.len() - 1], Stage::Close { .. })
}
