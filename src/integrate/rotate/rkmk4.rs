//! `rkmk4`: the classical fourth-order Runge–Kutta method lifted to the
//! rotation group by Munthe-Kaas (H. Munthe-Kaas, BIT 38 (1998) 92 and
//! Appl. Numer. Math. 29 (1999) 115; Hairer, Lubich & Wanner, *Geometric
//! Numerical Integration*, §IV.8.2).
//!
//! The orientation is written `q = q_n ⊗ exp(θ)` (rotation vector `θ` in the
//! body frame of `q_n`), so `θ̇ = dexp⁻¹_θ(ω_b)` with the right-trivialised
//! inverse differential
//! `dexp⁻¹_θ(v) = v + ½ θ × v + (1/|θ|² − (1 + cos|θ|)/(2|θ| sin|θ|)) θ × (θ × v)`,
//! and RK4's stages are taken on `(θ, ω_b)` from `(0, ω_n)`:
//! `K_i = (dexp⁻¹_{θ_i}(ω_i), I⁻¹(τ_b,i − ω_i × I ω_i))`, `τ_b,i` the torque at the
//! stage time in the frame `q_n ⊗ exp(θ_i)`; `q_{n+1} = q_n ⊗ exp(θ_{n+1})`.
//! Every orientation is exactly unit (no projection, unlike `rk4`). Fourth
//! order; four torque evaluations, all from the start-of-step contact
//! torque in contact scenes (first order there, like `rk4`).

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{exp_map, is_zero, to_body};
use glam::{DQuat, DVec3};

/// Runge–Kutta–Munthe-Kaas, order 4.
pub struct Rkmk4;

/// `dexp⁻¹_θ(v)` (module docs); the coefficient of `θ × (θ × v)` is
/// `1/12 + |θ|²/720 + |θ|⁴/30240 + …`, by series below `|θ| < 0.1`.
#[inline]
fn dexp_inv(theta: DVec3, v: DVec3) -> DVec3 {
    let a2 = theta.length_squared();
    let c = if a2 < 1e-2 {
        1.0 / 12.0 + a2 * (1.0 / 720.0 + a2 * (1.0 / 30240.0 + a2 / 1_209_600.0))
    } else {
        let a = a2.sqrt();
        1.0 / a2 - (1.0 + a.cos()) / (2.0 * a * a.sin())
    };
    let tv = theta.cross(v);
    v + 0.5 * tv + c * theta.cross(tv)
}

impl Rotator for Rkmk4 {
    type Aux = ();

    const INFO: RotatorInfo = RotatorInfo {
        name: "rkmk4",
        title: "Runge-Kutta-Munthe-Kaas of order 4: classical RK4 in the exponential coordinates of the rotation group",
        equations: "Munthe-Kaas 1998-99",
        order: 4,
        order_free: 4,
        symplectic: false,
        reversible: false,
        torque_evals: 4,
        torque_contract: "torque at t_n, t_n + dt/2 (twice), t_n + dt, at the stage orientations",
        contact_contract: "the start-of-step contact torque at every stage (forces are computed once per step), so first order with contacts",
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
        let (q, w) = (rot.q, rot.omega_b);
        let stage = |theta: DVec3, omega: DVec3, ts: f64| -> (DVec3, DVec3) {
            let tau = torque(ts);
            let tau_b = if is_zero(tau) {
                DVec3::ZERO
            } else {
                let qs: DQuat = if is_zero(theta) { q } else { q * exp_map(theta) };
                to_body(qs, tau)
            };
            (
                dexp_inv(theta, omega),
                inertia.angular_acceleration(omega, tau_b),
            )
        };
        let half = 0.5 * h;
        let (k1t, k1w) = stage(DVec3::ZERO, w, t);
        let (k2t, k2w) = stage(half * k1t, w + half * k1w, t + half);
        let (k3t, k3w) = stage(half * k2t, w + half * k2w, t + half);
        let (k4t, k4w) = stage(h * k3t, w + h * k3w, t + h);
        let s = h / 6.0;
        rot.q = q * exp_map(s * (k1t + 2.0 * k2t + 2.0 * k3t + k4t));
        rot.omega_b = w + s * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
        Ok(())
    }
}
