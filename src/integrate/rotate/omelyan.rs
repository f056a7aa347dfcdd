//! `omelyan`: Omelyan's leap-frog for rigid bodies with the norm-conserving
//! quaternion update (I. P. Omelyan, Comput. Phys. 12 (1998) 97, and Phys.
//! Rev. E 58 (1998) 1169), the scheme of Yade's
//! `leapfrogAsphericalRotateOmelyan_1998`.
//!
//! Omelyan's leap-frog advances the body-frame angular velocity by
//! `Ω_{n+½} = Ω_{n−½} + h I⁻¹ [τ_b,n + ½ (g(Ω_{n−½}) + g(Ω_{n+½}))]`,
//! `g(Ω) = (IΩ) × Ω` the gyroscopic term of Euler's equations (Eq. 4) averaged
//! over the two half steps, solved for `Ω_{n+½}` by fixed-point iteration,
//! and the quaternion by the Cayley form
//! `q_{n+1} = q_n ⊗ [(1 − h²Ω²/16) + (h/2) Ω] / (1 + h²Ω²/16)`, exactly unit.
//! Written kick–drift–kick, with `ω_n = Ω_{n−½} + (h/2) I⁻¹(τ_b,n + g(Ω_{n−½}))`
//! the whole-step angular velocity the energy is measured with, it is the same
//! sequence of `Ω_{n+½}` and `q_n`:
//! 1. solve `Ω = ω_n + (h/2) I⁻¹(τ_b(t_n, q_n) + g(Ω))` (implicit half-kick);
//! 2. `q_{n+1}` by the Cayley form with `Ω`;
//! 3. `ω_{n+1} = Ω + (h/2) I⁻¹(τ_b(t_{n+1}, q_{n+1}) + g(Ω))` (explicit half-kick).
//!
//! The implicit and explicit half-kicks are each other's adjoints and the
//! Cayley drift is symmetric, so the step is time-reversible; second order;
//! not symplectic (the body-frame trapezoid is not a Poisson map). One
//! torque evaluation per step ([`Fsal`]). Renormalised to remove the
//! Cayley factor's biased rounding (see `advance`).

use super::{Fsal, Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::torque_to_body;
use glam::{DQuat, DVec3};

/// Omelyan's leap-frog with the Cayley quaternion update.
pub struct Omelyan;

/// Iterations of the implicit half-kick are stopped when the update is below
/// this, relative (rounding), or after [`MAX_ITERATIONS`].
const ITERATION_TOL: f64 = 1e-15;
/// The iteration contracts by ~`h |ω|` per pass: 12 passes reach rounding
/// for `h |ω| < 0.05` rad.
const MAX_ITERATIONS: usize = 12;

/// The Cayley map of Omelyan's update for `v = h Ω`:
/// `[(1 − |v|²/16) + v/2] / (1 + |v|²/16)`.
#[inline]
fn cayley(v: DVec3) -> DQuat {
    let a = v.length_squared() / 16.0;
    let k = 1.0 / (1.0 + a);
    let b = 0.5 * k * v;
    DQuat::from_xyzw(b.x, b.y, b.z, (1.0 - a) * k)
}

impl Rotator for Omelyan {
    type Aux = Fsal;

    const INFO: RotatorInfo = RotatorInfo {
        name: "omelyan",
        title: "Omelyan's rigid-body leap-frog: implicit/explicit half-kicks of the body angular velocity, Cayley quaternion update (Yade)",
        equations: "Omelyan 1998 (Comput. Phys. 12, 97; PRE 58, 1169)",
        order: 2,
        order_free: 2,
        symplectic: false,
        reversible: true,
        torque_evals: 1,
        torque_contract: super::KDK_TORQUE_CONTRACT,
        contact_contract: super::KDK_CONTACT_CONTRACT,
        closing_kick: true,
        diagnostic: false,
    };

    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut Fsal,
        inertia: &Inertia,
        torque: T,
        t: f64,
        h: f64,
    ) -> Result<(), RotatorFault> {
        let (p, inv) = (inertia.principal, inertia.inverse);
        let tau_b = torque_to_body(rot.q, aux.at(t, &torque));
        let w = rot.omega_b;
        let half = 0.5 * h;
        let kick = |o: DVec3| w + half * inv * (tau_b + (p * o).cross(o));
        let mut omega = kick(w);
        for _ in 0..MAX_ITERATIONS {
            let next = kick(omega);
            let change = (next - omega).length_squared();
            omega = next;
            if change <= ITERATION_TOL * ITERATION_TOL * omega.length_squared() {
                break;
            }
        }
        // The Cayley factor is unit in exact arithmetic, but its rounding
        // is biased (|q|² falls by ~4e-17 a step: 9e-11 in |q| over 10⁶
        // steps, tests/suite/rotators.rs), so the product is renormalised; this
        // removes only rounding, as in `leapfrog`.
        rot.q = (rot.q * cayley(h * omega)).normalize();
        rot.omega_b = omega;
        Ok(())
    }

    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut Fsal,
        inertia: &Inertia,
        torque: T,
        t_end: f64,
        h: f64,
    ) {
        let tau_b = torque_to_body(rot.q, aux.take(t_end, &torque));
        let o = rot.omega_b;
        rot.omega_b = o + (0.5 * h) * inertia.inverse * (tau_b + (inertia.principal * o).cross(o));
    }
}
