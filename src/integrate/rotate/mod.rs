//! Quaternion rotators: the schemes compared by fibresim.
//!
//! A rotator advances one body's `(q, ω_b)`. Two hooks cover both families
//! (SPEC §4, ARCHITECTURE "The rotator contract"):
//! - [`Rotator::advance`] runs before forces are computed: one-stage schemes do
//!   their whole step here; kick–drift–kick schemes do the first half-kick and
//!   the drift.
//! - [`Rotator::finish`] runs after forces at the new positions: the closing
//!   half-kick (a no-op for one-stage schemes).
//!
//! Torque is asked for through a closure `torque(t) -> τ_world`: a prescribed
//! torque evaluates its function of time exactly at `t`; a contact torque
//! answers with the latest computed world torque, whatever `t` is asked. The
//! orientation half of a rotator's torque contract is the frame it rotates
//! that world torque into (`q_n`, a predicted `q'`, a stage orientation).
//! Each rotator states its contract as data in [`RotatorInfo`].
//!
//! Dispatch on [`RotatorKind`] happens once per run (see `crate::run`), so each
//! scheme compiles to its own tight loop.

mod direct;
mod euler;
mod frozen;
mod leapfrog;
mod pcdm;
mod rk4;
mod scalar;

pub use direct::Direct;
pub use euler::Euler;
pub use frozen::Frozen;
pub use leapfrog::Leapfrog;
pub use pcdm::{Pcdm, PcdmStart};
pub use rk4::Rk4;
pub use scalar::Scalar;

use crate::body::{Inertia, RotState};
use glam::DVec3;

/// Why a rotator could not take a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RotatorFault {
    /// The scalar factor `tan(‖δq‖)` of Eq. 41–45 reached its pole:
    /// `‖δq‖ = ‖ω‖δt/2 ≥ π/2`.
    ScalarSingularity { half_angle: f64 },
}

/// Facts about a scheme, read by `--help`, the README table and the tests.
#[derive(Debug, Clone, Copy)]
pub struct RotatorInfo {
    pub name: &'static str,
    /// The paper's equations this scheme implements.
    pub equations: &'static str,
    /// Global order of accuracy in δt for the orientation with a general
    /// (asymmetric inertia, time-dependent torque) load, as measured in
    /// `tests/rotator_order.rs`.
    pub order: u32,
    /// Torque evaluations per step.
    pub torque_evals: u32,
    /// When and at which orientation torque is asked for.
    pub torque_contract: &'static str,
    /// Whether the scheme has a closing half-kick after forces.
    pub kick_drift_kick: bool,
}

/// One quaternion integration scheme. Stateless: all state is in [`RotState`].
pub trait Rotator {
    const INFO: RotatorInfo;

    /// Advance `(q, ω_b)` from `t_n` towards `t_n + δt`, before forces are computed.
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        inertia: &Inertia,
        torque: T,
        t_n: f64,
        dt: f64,
    ) -> Result<(), RotatorFault>;

    /// Close the step at `t_next = t_n + δt`, after forces at the new positions.
    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        _rot: &mut RotState,
        _inertia: &Inertia,
        _torque: T,
        _t_next: f64,
        _dt: f64,
    ) {
    }
}

/// The selectable rotators (`--rotator`, scenario key `simulation.rotator`).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    clap::ValueEnum,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
#[clap(rename_all = "kebab-case")]
pub enum RotatorKind {
    /// Euler (Eq. 31–32). Torque at (t_n, q_n).
    Euler,
    /// Leap-frog with the Cayley factor (Eq. 33–39), kick–drift–kick on the world angular momentum. Torque at (t_n, q_n) and (t_n+1, q_n+1).
    Leapfrog,
    /// Kleppmann's scalar factor (Eq. 40–45). Torque at (t_n, q_n). Stops with a diagnosis at the tan pole.
    Scalar,
    /// Direct multiplication by the exponential map (Eq. 49–50). Torque at (t_n, q_n).
    Direct,
    /// PCDM (Eq. 55–63), torque at (t_n, q_n) and at mid-step (t_n+½, q'_n+½).
    Pcdm,
    /// PCDM with both torque evaluations at t_n (the timing that reproduces the paper's Table 2); orientations q_n and q'_n+½.
    PcdmStart,
    /// Classical 4th-order Runge–Kutta on (q, ω_b), projected to unit norm: the reference scheme for convergence studies.
    Rk4,
    /// Diagnostic: no rotation at all (q and ω_b frozen, torque ignored), to separate the contact model's energy error from the rotators'.
    Frozen,
}

impl RotatorKind {
    /// Every integration scheme (the `frozen` diagnostic is not one).
    pub const ALL: [RotatorKind; 7] = [
        RotatorKind::Euler,
        RotatorKind::Leapfrog,
        RotatorKind::Scalar,
        RotatorKind::Direct,
        RotatorKind::Pcdm,
        RotatorKind::PcdmStart,
        RotatorKind::Rk4,
    ];

    /// The paper's four rotators (Figs. 2–4).
    pub const PAPER: [RotatorKind; 4] = [
        RotatorKind::Pcdm,
        RotatorKind::Scalar,
        RotatorKind::Euler,
        RotatorKind::Leapfrog,
    ];

    pub fn info(self) -> RotatorInfo {
        match self {
            RotatorKind::Euler => Euler::INFO,
            RotatorKind::Leapfrog => Leapfrog::INFO,
            RotatorKind::Scalar => Scalar::INFO,
            RotatorKind::Direct => Direct::INFO,
            RotatorKind::Pcdm => Pcdm::INFO,
            RotatorKind::PcdmStart => PcdmStart::INFO,
            RotatorKind::Rk4 => Rk4::INFO,
            RotatorKind::Frozen => Frozen::INFO,
        }
    }

    pub fn name(self) -> &'static str {
        self.info().name
    }

    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .chain([RotatorKind::Frozen])
            .find(|k| k.name() == s)
    }
}

impl std::fmt::Display for RotatorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Call `$body` with the type `$R` bound to the rotator chosen by `$kind`.
/// This is the one place a run dispatches on the enum.
#[macro_export]
macro_rules! with_rotator {
    ($kind:expr, $R:ident => $body:expr) => {{
        use $crate::integrate::rotate::*;
        match $kind {
            RotatorKind::Euler => {
                type $R = Euler;
                $body
            }
            RotatorKind::Leapfrog => {
                type $R = Leapfrog;
                $body
            }
            RotatorKind::Scalar => {
                type $R = Scalar;
                $body
            }
            RotatorKind::Direct => {
                type $R = Direct;
                $body
            }
            RotatorKind::Pcdm => {
                type $R = Pcdm;
                $body
            }
            RotatorKind::PcdmStart => {
                type $R = PcdmStart;
                $body
            }
            RotatorKind::Rk4 => {
                type $R = Rk4;
                $body
            }
            RotatorKind::Frozen => {
                type $R = Frozen;
                $body
            }
        }
    }};
}
