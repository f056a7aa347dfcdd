//! Euler method, paper Eq. 31–32.
//!
//! `q_{n+1} = normalise(q_n + ½ ω_n q_n δt)` with the world angular velocity
//! `ω_n = q_n ω_b q_n*`; `ω_b` by explicit Euler on Eq. 4 with the torque at
//! `(t_n, q_n)`. The renormalisation (Eq. 32) is part of the scheme as the paper
//! defines it: the Taylor step leaves the unit sphere by `O((‖ω‖δt)²)`.
//! First order.

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{pure, to_world};
use glam::DVec3;

/// Euler's method, Eq. 31–32.
pub struct Euler;

impl Rotator for Euler {
    type Aux = ();

    const INFO: RotatorInfo = RotatorInfo {
        name: "euler",
        title: "Euler: Taylor step of the quaternion, renormalised; explicit Euler for the angular velocity",
        equations: "Eq. 31-32",
        order: 1,
        order_free: 1,
        symplectic: false,
        reversible: false,
        torque_evals: 1,
        torque_contract: "torque at (t_n, q_n)",
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
        t_n: f64,
        dt: f64,
    ) -> Result<(), RotatorFault> {
        let q = rot.q;
        let alpha = inertia.angular_acceleration_world(q, rot.omega_b, torque(t_n));
        let omega_w = to_world(q, rot.omega_b);
        // Eq. 31, then Eq. 32 (the scheme's own renormalisation).
        rot.q = (q + pure(omega_w) * q * (0.5 * dt)).normalize();
        rot.omega_b += dt * alpha;
        Ok(())
    }
}
