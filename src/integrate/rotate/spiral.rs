//! `spiral`: SPIRAL, the synchronous (non-leap-frog) form of del Valle,
//! Angelidakis, Roy, Muñoz & Pöschel, Comput. Phys. Commun. 297 (2024) 109077.
//!
//! With the body-frame `ω_n`, `ω̇_n = I⁻¹(τ_b − ω_n × I ω_n)` (Eq. 4) and the
//! body torque `τ_b = q_n* τ(t_n) q_n` held for the whole step:
//! 1. `q_{n+1} = q_n ⊗ exp(h ω_n) ⊗ exp(h²/2 ω̇_n)` (rotation vectors; the
//!    paper's `e^{(h/2)ω} e^{(h²/4)ω̇}` in half-angle quaternion exponentials),
//!    the rotation to second order in `h` as two exact rotations;
//! 2. `ω_{n+1}` by the three-stage strong-stability-preserving Runge–Kutta
//!    method (SSPRK3): `k₁ = h ω̇(ω_n)`, `k₂ = h ω̇(ω_n + k₁)`,
//!    `k₃ = h ω̇(ω_n + (k₁ + k₂)/4)`, `ω_{n+1} = ω_n + (k₁ + k₂ + 4k₃)/6`.
//!
//! The paper calls SPIRAL third order: that holds for `ω` under a constant
//! body torque. The orientation update is exact only to `O(h³)` per step, and
//! the torque is taken once, at `(t_n, q_n)`: we measure second order in
//! torque-free motion and first order under a time-dependent or contact
//! torque, like every one-stage scheme here (docs/rotators.md).
//! Renormalised each step, to remove a rounding bias (see `advance`).

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{exp_map, torque_to_body};
use glam::DVec3;

/// SPIRAL, synchronous form.
pub struct Spiral;

/// SSPRK3 for `ω̇ = I⁻¹(τ_b − ω × Iω)` over `h` with `τ_b` held: the change of `ω`.
#[inline]
pub(super) fn ssprk3(inertia: &Inertia, w: DVec3, tau_b: DVec3, h: f64) -> DVec3 {
    let k1 = h * inertia.angular_acceleration(w, tau_b);
    let k2 = h * inertia.angular_acceleration(w + k1, tau_b);
    let k3 = h * inertia.angular_acceleration(w + 0.25 * (k1 + k2), tau_b);
    (k1 + k2 + 4.0 * k3) * (1.0 / 6.0)
}

impl Rotator for Spiral {
    type Aux = ();

    const INFO: RotatorInfo = RotatorInfo {
        name: "spiral",
        title: "SPIRAL (synchronous form): two exponential-map rotations by h omega and h^2/2 omega-dot, SSPRK3 for the angular velocity",
        equations: "del Valle et al. 2024, §3",
        order: 1,
        order_free: 2,
        symplectic: false,
        reversible: false,
        torque_evals: 1,
        torque_contract: "torque at (t_n, q_n), held for the step",
        contact_contract: "the contact torque of the start-of-step configuration",
        closing_kick: false,
        diagnostic: false,
    };

    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        _aux: &mut (),
        inertia: &Inertia,
        torque: T,
        t: f64,
        h: f64,
    ) -> Result<(), RotatorFault> {
        let w = rot.omega_b;
        let tau_b = torque_to_body(rot.q, torque(t));
        let w_dot = inertia.angular_acceleration(w, tau_b);
        // The second factor turns by only h²|ω̇|/2 (~1e-8 rad), so its
        // cosine rounds the same way step after step: |q| drifts by 4.5e-11
        // over 10⁶ steps (tests/suite/rotators.rs). Renormalised: this removes
        // only that rounding.
        rot.q = (rot.q * exp_map(h * w) * exp_map((0.5 * h * h) * w_dot)).normalize();
        rot.omega_b = w + ssprk3(inertia, w, tau_b, h);
        Ok(())
    }
}
