//! `split4`: Yoshida's fourth-order symmetric composition of [`super::Split`]
//! (H. Yoshida, Phys. Lett. A 150 (1990) 262, Eq. 5.19 with `k = 1`):
//! `Φ_{w₁h} ∘ Φ_{w₀h} ∘ Φ_{w₁h}`, `w₁ = 1/(2 − 2^{1/3})`, `w₀ = 1 − 2w₁`.
//!
//! Each sub-step is a whole `split` step: its own half-kicks, exact free
//! flow and force evaluation (the step's stage sequence has three
//! open/forces/close sub-steps, so contact forces and torques are computed at
//! each sub-step's configuration, and a prescribed torque at its own time).
//! Symmetric and a composition of symplectic maps: symplectic,
//! time-reversible, exact in free flight, fourth order for smooth torques.
//! Three torque (and, with contacts, force) evaluations per step; the middle
//! sub-step goes backwards in time (`w₀ < 0`).
//!
//! Suzuki's five-stage composition (`w = 1/(4 − 4^{1/3})`, Phys. Lett. A 146
//! (1990) 319) has a 1/40 smaller error constant here but five evaluations;
//! on test case 4 Yoshida's three reach a given error in less time (README,
//! Rotators).

use super::split::SplitAux;
use super::Split;
use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::integrate::scheme::Stage;
use glam::DVec3;

/// `1/(2 − 2^{1/3})`.
const W1: f64 = 1.351_207_191_959_657_8;
/// `1 − 2 w₁ = −2^{1/3}/(2 − 2^{1/3})`.
const W0: f64 = -1.702_414_383_919_315_3;
/// Where the second sub-step ends, `w₁ + w₀`.
const MID: f64 = W1 + W0;

/// The three sub-steps of Yoshida's composition.
const YOSHIDA: &[Stage] = &[
    Stage::Open { start: 0.0, h: W1 },
    Stage::Forces,
    Stage::Close { end: W1, h: W1 },
    Stage::Open { start: W1, h: W0 },
    Stage::Forces,
    Stage::Close { end: MID, h: W0 },
    Stage::Open { start: MID, h: W1 },
    Stage::Forces,
    Stage::Close { end: 1.0, h: W1 },
];

/// Yoshida's fourth-order composition of `split`.
pub struct Split4;

impl Rotator for Split4 {
    type Aux = SplitAux;

    const INFO: RotatorInfo = RotatorInfo {
        name: "split4",
        title: "Yoshida's 4th-order symmetric composition of split: three split sub-steps, forces at each",
        equations: "Yoshida 1990 on split",
        order: 4,
        order_free: 0,
        symplectic: true,
        reversible: true,
        torque_evals: 3,
        torque_contract: "split's half-kicks at each sub-step's own time t_n + c dt, c = 0, w1, 1 - w1, 1 (w1 = 1.35)",
        contact_contract: "forces and torques computed at each of the three sub-step configurations",
        closing_kick: true,
        diagnostic: false,
    };

    const STAGES: &'static [Stage] = YOSHIDA;

    fn start(rot: &RotState, inertia: &Inertia) -> SplitAux {
        <Split as Rotator>::start(rot, inertia)
    }

    /// A whole `split` step over the sub-step.
    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut SplitAux,
        inertia: &Inertia,
        torque: T,
        t: f64,
        h: f64,
    ) -> Result<(), RotatorFault> {
        <Split as Rotator>::advance(rot, aux, inertia, torque, t, h)
    }

    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut SplitAux,
        inertia: &Inertia,
        torque: T,
        t_end: f64,
        h: f64,
    ) {
        <Split as Rotator>::finish(rot, aux, inertia, torque, t_end, h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients() {
        let cbrt2 = 2f64.cbrt();
        assert!((W1 - 1.0 / (2.0 - cbrt2)).abs() < 1e-15);
        assert!((W0 + cbrt2 / (2.0 - cbrt2)).abs() < 1e-15);
        assert!((2.0 * W1 + W0 - 1.0).abs() < 1e-15);
        assert!(crate::integrate::scheme::is_valid(YOSHIDA));
    }
}
