//! A rotator that exists only in the library's unit tests: the explicit
//! midpoint rule (RK2) on `(q, ω_b)`, projected to unit norm. It is added to
//! the list by one line and nothing else, so the tests in
//! `integrate/rotate/list_tests.rs` show that such a rotator is run, listed,
//! documented and order-checked.

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::pure;
use glam::DVec3;

/// The explicit midpoint rule (test fixture).
pub struct MidpointDemo;

impl Rotator for MidpointDemo {
    type Aux = ();

    const INFO: RotatorInfo = RotatorInfo {
        name: "midpoint-demo",
        title: "Test fixture: explicit midpoint rule on (q, omega_b), projected to unit norm",
        equations: "not in the paper",
        order: 2,
        order_free: 2,
        symplectic: false,
        reversible: false,
        torque_evals: 2,
        torque_contract: "torque at (t_n, q_n) and (t_n + dt/2, q_n+1/2)",
        contact_contract: "the start-of-step contact torque at both stages",
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
        let dw = inertia.angular_acceleration_world(q, w, torque(t));
        let q_mid = (q + q * pure(w) * (0.25 * h)).normalize();
        let w_mid = w + (0.5 * h) * dw;
        let dw_mid = inertia.angular_acceleration_world(q_mid, w_mid, torque(t + 0.5 * h));
        // Projection to the unit sphere: RK2 leaves it by O(h³) per step.
        rot.q = (q + q_mid * pure(w_mid) * (0.5 * h)).normalize();
        rot.omega_b = w + h * dw_mid;
        Ok(())
    }
}
