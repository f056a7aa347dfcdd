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

/// Facts about a scheme, read by `--help`, `fibresim rotators`, the README
/// table and the tests: the one place each is written.
#[derive(Debug, Clone, Copy)]
pub struct RotatorInfo {
    pub name: &'static str,
    /// One line saying what the scheme is.
    pub title: &'static str,
    /// The paper's equations this scheme implements.
    pub equations: &'static str,
    /// Global order of accuracy in δt for the orientation with a general
    /// (asymmetric inertia, time-dependent torque) load, as measured in
    /// `tests/rotator_order.rs`.
    pub order: u32,
    /// Torque evaluations per step.
    pub torque_evals: u32,
    /// When a prescribed torque is evaluated, and at which orientation it is
    /// taken into the body frame.
    pub torque_contract: &'static str,
    /// What a contact torque means to the scheme: contact torques are known
    /// only where forces were computed (SPEC §4).
    pub contact_contract: &'static str,
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
/// Each one's description lives in its [`RotatorInfo`].
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum RotatorKind {
    Euler,
    Leapfrog,
    Scalar,
    Direct,
    Pcdm,
    PcdmStart,
    Rk4,
    Frozen,
}

/// `--rotator` values, with help generated from [`RotatorInfo`].
impl clap::ValueEnum for RotatorKind {
    fn value_variants<'a>() -> &'a [Self] {
        &Self::SELECTABLE
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        let i = self.info();
        let source = match i.order {
            0 => String::new(),
            n => format!(" ({}, order {n})", i.equations),
        };
        Some(clap::builder::PossibleValue::new(i.name).help(format!(
            "{}{source}. Prescribed torque: {}. Contact torque: {}",
            i.title, i.torque_contract, i.contact_contract
        )))
    }
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

    /// Everything `--rotator` accepts: the schemes and the diagnostic.
    pub const SELECTABLE: [RotatorKind; 8] = [
        RotatorKind::Euler,
        RotatorKind::Leapfrog,
        RotatorKind::Scalar,
        RotatorKind::Direct,
        RotatorKind::Pcdm,
        RotatorKind::PcdmStart,
        RotatorKind::Rk4,
        RotatorKind::Frozen,
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
        Self::SELECTABLE.into_iter().find(|k| k.name() == s)
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
