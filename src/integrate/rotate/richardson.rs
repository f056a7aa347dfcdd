//! `richardson`: the Richardson-iteration update of LAMMPS `fix nve/asphere`
//! (`MathExtra::richardson`, described in the LAMMPS manual), as a
//! kick–drift–kick on the world angular momentum.
//!
//! 1. `L ← L + (h/2) τ(t_n)` (world frame);
//! 2. `ω = q I⁻¹(q* L q) q*` with `q = q_n`, and the quaternion ODE
//!    `q̇ = ½ ω ⊗ q` is stepped over `h` with `L` held fixed by one explicit
//!    Euler step, `q_full = N(q + (h/2) ω ⊗ q)`, and by two half steps, the
//!    second with `ω` recomputed at the half-step quaternion,
//!    `q_½ = N(q + (h/4) ω ⊗ q)`, `q_h = N(q_½ + (h/4) ω(q_½) ⊗ q_½)`;
//! 3. Richardson's extrapolation `q_{n+1} = N(2 q_h − q_full)` cancels the
//!    first-order error of Euler's method;
//! 4. after forces, `L ← L + (h/2) τ(t_{n+1})`.
//!
//! `N` is normalisation, part of the scheme as LAMMPS defines it: Euler
//! steps leave the unit sphere by `O(h²)`. The extrapolated drift is second
//! order, so the step is second order; it is neither symplectic nor
//! symmetric. One torque evaluation per step ([`Fsal`]).

use super::{Fsal, Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{pure, to_body, torque_to_body};
use glam::{DQuat, DVec3};

/// LAMMPS's Richardson-iteration quaternion update.
pub struct Richardson;

/// `q̇/… = q ⊗ ω_b` with `ω_b = I⁻¹ q̂* L q̂` at the normalised `q`:
/// `ω ⊗ q` for the world `ω`, computed in the body frame.
#[inline]
fn omega_q(q: DQuat, l_w: DVec3, inertia: &Inertia) -> DQuat {
    q * pure(inertia.inverse * to_body(q, l_w))
}

impl Rotator for Richardson {
    type Aux = Fsal;

    const INFO: RotatorInfo = RotatorInfo {
        name: "richardson",
        title: "Richardson-extrapolated Euler drift of the quaternion between half-kicks of the world angular momentum (LAMMPS fix nve/asphere)",
        equations: "LAMMPS MathExtra::richardson",
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
        let q = rot.q;
        let tau = aux.at(t, &torque);
        // Step 1 in q_n's body frame: q_n* L_{n+½} q_n = I ω_b + (h/2) q_n* τ q_n.
        let l_b = inertia.principal * rot.omega_b + (0.5 * h) * torque_to_body(q, tau);
        let l_w = crate::math::to_world(q, l_b);
        let wq = q * pure(inertia.inverse * l_b);
        let q_full = (q + wq * (0.5 * h)).normalize();
        let q_half = (q + wq * (0.25 * h)).normalize();
        let q_h = (q_half + omega_q(q_half, l_w, inertia) * (0.25 * h)).normalize();
        let q_new = (q_h * 2.0 - q_full).normalize();
        rot.q = q_new;
        // Hold L_{n+½} in the new body frame until `finish`.
        rot.omega_b = inertia.inverse * to_body(q_new, l_w);
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
        aux.closing_half_kick(rot, inertia, &torque, t_end, h);
    }
}
