//! Classical 4th-order Runge–Kutta on `(q, ω_b)`: the reference scheme of the
//! convergence studies (not one of the paper's methods).
//!
//! ODE: `dq/dt = ½ q ⊗ [0, ω_b]`, `dω_b/dt = I⁻¹(τ_b − ω_b × I ω_b)` with
//! `τ_b = q̂* τ(t, q̂) q̂`, `q̂ = q/‖q‖` at each stage. After the step `q` is
//! projected back to unit norm: RK4 leaves the sphere by `O(δt⁵)` per step, and
//! the projection keeps the global order 4 (Hairer, Lubich & Wanner, *Geometric
//! Numerical Integration*, §IV.4). Torque at `t_n`, `t_n + δt/2` (twice) and
//! `t_n + δt`.

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::pure;
use glam::{DQuat, DVec3};

/// Classical 4th-order Runge–Kutta on `(q, ω_b)`, projected.
pub struct Rk4;

#[inline]
fn rhs<T: Fn(f64) -> DVec3>(
    inertia: &Inertia,
    torque: &T,
    t: f64,
    q: DQuat,
    w: DVec3,
) -> (DQuat, DVec3) {
    let qn = q.normalize();
    let dq = q * pure(w) * 0.5;
    let dw = inertia.angular_acceleration_world(qn, w, torque(t));
    (dq, dw)
}

impl Rotator for Rk4 {
    type Aux = ();

    const INFO: RotatorInfo = RotatorInfo {
        name: "rk4",
        title: "Classical 4th-order Runge-Kutta on (q, omega_b), projected to unit norm: the reference for convergence studies",
        equations: "not in the paper",
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
        t_n: f64,
        dt: f64,
    ) -> Result<(), RotatorFault> {
        let (q, w) = (rot.q, rot.omega_b);
        let h = 0.5 * dt;
        let (k1q, k1w) = rhs(inertia, &torque, t_n, q, w);
        let (k2q, k2w) = rhs(inertia, &torque, t_n + h, q + k1q * h, w + h * k1w);
        let (k3q, k3w) = rhs(inertia, &torque, t_n + h, q + k2q * h, w + h * k2w);
        let (k4q, k4w) = rhs(inertia, &torque, t_n + dt, q + k3q * dt, w + dt * k3w);
        let s = dt / 6.0;
        // Projection to the unit sphere, see the module docs.
        rot.q = (q + (k1q + k2q * 2.0 + k3q * 2.0 + k4q) * s).normalize();
        rot.omega_b = w + s * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
        Ok(())
    }
}
