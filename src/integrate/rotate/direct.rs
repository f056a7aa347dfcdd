//! Direct multiplication, paper Eq. 49–50 (Whitmore; Karney; Betsch & Siebert).
//!
//! `q_{n+1} = exp(ω_n δt) q_n` with `exp` the unit quaternion
//! `[cos(‖ω‖δt/2), sin(‖ω‖δt/2) ω̂]` (Eq. 49; the paper's Eq. 48 misplaces δt) and
//! the world `ω_n = q_n ω_b q_n*`; `ω_b` by explicit Euler on Eq. 4 with the torque
//! at `(t_n, q_n)`. No renormalisation: the product of unit quaternions is unit up
//! to rounding. First order (the angular velocity is first order).

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{exp_map, to_world};
use glam::DVec3;

/// Direct multiplication by the exponential map, Eq. 49–50.
pub struct Direct;

impl Rotator for Direct {
    type Aux = ();

    const INFO: RotatorInfo = RotatorInfo {
        name: "direct",
        title:
            "Direct multiplication by the exponential map; explicit Euler for the angular velocity",
        equations: "Eq. 49-50",
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
        rot.q = exp_map(to_world(q, rot.omega_b) * dt) * q;
        rot.omega_b += dt * alpha;
        Ok(())
    }
}
