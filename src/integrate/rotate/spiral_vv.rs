//! `spiral-vv`: SPIRAL's leap-frog form (del Valle et al., Comput. Phys.
//! Commun. 297 (2024) 109077), written as velocity Verlet as in its authors'
//! JaxDEM: half-kick – rotation – half-kick in the body frame.
//!
//! 1. `ω_{n+½} = ω_n + SSPRK3_{h/2}(ω_n; τ_b(t_n, q_n))` (the three-stage
//!    Runge–Kutta of [`super::spiral`], the body torque held);
//! 2. `q_{n+1} = q_n ⊗ exp(h ω_{n+½})`;
//! 3. after forces, `ω_{n+1} = ω_{n+½} + SSPRK3_{h/2}(ω_{n+½}; τ_b(t_{n+1}, q_{n+1}))`.
//!
//! A Strang splitting of the body-frame Euler equations (the kicks) and the
//! kinematics (the rotation with `ω` frozen): second order, with the contact
//! torque at both ends of the step. The SSPRK3 half-kicks are not each
//! other's adjoints, so the step is not exactly symmetric. One torque
//! evaluation per step ([`Fsal`]). No renormalisation.

use super::spiral::ssprk3;
use super::{Fsal, Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{exp_map, torque_to_body};
use glam::DVec3;

/// SPIRAL, leap-frog (velocity-Verlet) form.
pub struct SpiralVv;

impl Rotator for SpiralVv {
    type Aux = Fsal;

    const INFO: RotatorInfo = RotatorInfo {
        name: "spiral-vv",
        title: "SPIRAL (leap-frog form): SSPRK3 half-kicks of the body angular velocity around one exponential-map rotation",
        equations: "del Valle et al. 2024, §3 (leap-frog)",
        order: 2,
        order_free: 2,
        symplectic: false,
        reversible: false,
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
        let tau_b = torque_to_body(rot.q, aux.at(t, &torque));
        let w = rot.omega_b + ssprk3(inertia, rot.omega_b, tau_b, 0.5 * h);
        rot.q *= exp_map(h * w);
        rot.omega_b = w;
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
        rot.omega_b += ssprk3(inertia, rot.omega_b, tau_b, 0.5 * h);
    }
}
