//! `fincham`: Fincham's leap-frog rotational algorithm (D. Fincham, Mol.
//! Simul. 8 (1992) 165; Allen & Tildesley, *Computer Simulation of
//! Liquids*, §3.3) as Yade codes it (`NewtonIntegrator::leapfrogAsphericalRotate`),
//! and `fincham-mid`, the form Fincham describes.
//!
//! With the world angular momentum `L` (kick–drift–kick form of the
//! leap-frog, `L_n = L_{n−½} + (h/2) τ_n`):
//! 1. `ω_b,n = I⁻¹ q_n* L_n q_n`, `q_{n+½} = q_n + (h/2) ½ q_n ⊗ ω_b,n`
//!    (an explicit Euler predictor);
//! 2. `L_{n+½} = L_n + (h/2) τ(t_n)`;
//! 3. `ω_b,n+½ = I⁻¹ A* L_{n+½} A`, with `A = q_n` in Yade (`fincham`) and
//!    `A = q_{n+½}/‖q_{n+½}‖` in Fincham's paper (`fincham-mid`);
//! 4. `q_{n+1} = N(q_n + h ½ q_{n+½} ⊗ ω_b,n+½)`, `N` the normalisation both
//!    apply (part of the scheme: Euler-type steps leave the unit sphere);
//! 5. after forces, `L_{n+1} = L_{n+½} + (h/2) τ(t_{n+1})`.
//!
//! Converting the half-step momentum with the old orientation makes Yade's
//! form first order: `ω_b,n+½` is off by `O(h)` (the body has turned by
//! `h/2 · ω` since `q_n`). With the predicted half-step orientation the
//! drift is the midpoint rule, second order. Neither is symplectic or
//! symmetric. One torque evaluation per step ([`Fsal`]).

use super::{Fsal, Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{pure, to_body, to_world, torque_to_body};
use glam::DVec3;

/// Fincham's leap-frog as Yade codes it (half-step momentum converted with `q_n`).
pub type Fincham = FinchamScheme<false>;

/// Fincham's leap-frog; `MID`: the half-step momentum is converted with the
/// predicted half-step orientation (Fincham's paper) instead of `q_n` (Yade).
pub struct FinchamScheme<const MID: bool>;

impl<const MID: bool> Rotator for FinchamScheme<MID> {
    type Aux = Fsal;

    const INFO: RotatorInfo = if MID {
        RotatorInfo {
            name: "fincham-mid",
            title: "Fincham's leap-frog with the half-step momentum taken into the predicted half-step frame (Fincham 1992)",
            equations: "Fincham 1992; Allen & Tildesley §3.3",
            order: 2,
            order_free: 2,
            symplectic: false,
            reversible: false,
            torque_evals: 1,
            torque_contract: super::KDK_TORQUE_CONTRACT,
            contact_contract: super::KDK_CONTACT_CONTRACT,
            closing_kick: true,
            diagnostic: false,
        }
    } else {
        RotatorInfo {
            name: "fincham",
            title: "Fincham's leap-frog as Yade codes it: the half-step momentum taken into the old frame q_n, so first order",
            equations: "Fincham 1992 as in Yade",
            order: 1,
            order_free: 1,
            symplectic: false,
            reversible: false,
            torque_evals: 1,
            torque_contract: super::KDK_TORQUE_CONTRACT,
            contact_contract: super::KDK_CONTACT_CONTRACT,
            closing_kick: true,
            diagnostic: false,
        }
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
        let q_half = q + q * pure(rot.omega_b) * (0.25 * h);
        // L_{n+½}, world: q_n (I ω_b,n + (h/2) q_n* τ q_n) q_n*.
        let l_half = to_world(
            q,
            inertia.principal * rot.omega_b + (0.5 * h) * torque_to_body(q, tau),
        );
        let frame = if MID { q_half.normalize() } else { q };
        let w_half = inertia.inverse * to_body(frame, l_half);
        // Normalisation: part of the scheme (module docs).
        let q_new = (q + q_half * pure(w_half) * (0.5 * h)).normalize();
        rot.q = q_new;
        // Hold L_{n+½} in the new body frame until `finish`.
        rot.omega_b = inertia.inverse * to_body(q_new, l_half);
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
