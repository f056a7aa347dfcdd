//! Scalar factor method (Kleppmann 2007), paper Eq. 40–45.
//!
//! `δq = (δt/2) ω_n q_n` (Eq. 44), then
//! `q_{n+1} = [q_n + tan(‖δq‖) δq/‖δq‖] cos(‖δq‖)` (Eq. 45, the renormalisation
//! folded in); `ω_b` by explicit Euler on Eq. 4 with the torque at `(t_n, q_n)`.
//! For unit `q_n` this equals the direct multiplication (Eq. 49–50) to rounding
//! while `‖ω‖δt < π`. At `‖δq‖ = π/2` the factor `tan` has a pole: the step is
//! refused with [`RotatorFault::ScalarSingularity`], never returned as a number.
//! First order.

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{pure, to_world};
use glam::DVec3;

/// Kleppmann's scalar factor method, Eq. 40–45.
pub struct Scalar;

/// Largest `‖δq‖` accepted; beyond it `tan` changes branch (the pole at π/2).
pub const SCALAR_HALF_ANGLE_LIMIT: f64 = std::f64::consts::FRAC_PI_2;

impl Rotator for Scalar {
    type Aux = ();

    const MAY_FAULT: bool = true;

    const INFO: RotatorInfo = RotatorInfo {
        name: "scalar",
        title: "Kleppmann's scalar factor; explicit Euler for the angular velocity",
        equations: "Eq. 40-45",
        order: 1,
        torque_evals: 1,
        torque_contract: "torque at (t_n, q_n); stops at ||omega|| dt / 2 >= pi/2",
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
        let dq = pure(to_world(q, rot.omega_b)) * q * (0.5 * dt); // Eq. 44
        let n = dq.length();
        if n >= SCALAR_HALF_ANGLE_LIMIT {
            return Err(RotatorFault::ScalarSingularity { half_angle: n });
        }
        let alpha = inertia.angular_acceleration_world(q, rot.omega_b, torque(t_n));
        // Eq. 45; tan(n)/n → 1 as n → 0.
        let f = if n > 0.0 { n.tan() / n } else { 1.0 };
        rot.q = (q + dq * f) * n.cos();
        rot.omega_b += dt * alpha;
        Ok(())
    }
}
