//! Leap-frog (Walton & Braun 1993) in the paper's Cayley form, Eq. 33–39.
//!
//! The paper leaves the half-step angular velocity to "the leap-frog method". We
//! use the standard DEM choice, kick–drift–kick on the world angular momentum
//! `L = q (I ω_b) q*`, which needs no gyroscopic term in the world frame:
//! 1. `L_{n+½} = L_n + (δt/2) τ(t_n, q_n)`;
//! 2. `ω_{n+½} = q_n I⁻¹ (q_n* L_{n+½} q_n) q_n*` — converted with `q_n`, the
//!    time-level mixing the paper criticises in §3.3;
//! 3. `β = [1, (δt/4) ω_{n+½}]` (Eq. 35–36), `q̃ = ββ/‖β‖²` (Eq. 37 corrected as in
//!    docs/physics.md §1: the paper's `‖β‖²/A` is not unit), `q_{n+1} = q̃ q_n` (Eq. 39); the
//!    rotation angle is `4 atan(‖ω‖δt/4) = ‖ω‖δt + O(δt³)`;
//! 4. after forces: `L_{n+1} = L_{n+½} + (δt/2) τ(t_{n+1}, q_{n+1})`.
//!
//! The paper renormalises `q_{n+1}` every step (§3.1.2); with the exact Cayley
//! factor that removes only rounding, and we keep it to follow the paper.
//! Second order for a sphere (ω does not depend on q), first order otherwise
//! because of step 2.

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{to_body, to_world, torque_to_body};
use glam::{DQuat, DVec3};

/// Leap-frog in the paper's Cayley form, Eq. 33–39.
pub struct Leapfrog;

impl Rotator for Leapfrog {
    type Aux = ();

    const INFO: RotatorInfo = RotatorInfo {
        name: "leapfrog",
        title: "Leap-frog in Cayley form, kick-drift-kick on the world angular momentum",
        equations: "Eq. 33-39",
        order: 1,
        order_free: 1,
        symplectic: false,
        reversible: false,
        torque_evals: 2,
        torque_contract:
            "half-kick with torque at (t_n, q_n); closing half-kick with torque at (t_n+1, q_n+1)",
        contact_contract: "first half-kick with the start-of-step contact torque, closing half-kick with the torque of the new configuration",
        closing_kick: true,
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
        // Steps 1–2 in q_n's body frame, where `q_n* L q_n = I ω_b + (δt/2) q_n* τ q_n`.
        let l_half_b =
            inertia.principal * rot.omega_b + (0.5 * dt) * torque_to_body(q, torque(t_n));
        let omega_half = to_world(q, inertia.inverse * l_half_b);
        let b = (0.25 * dt) * omega_half;
        let beta = DQuat::from_xyzw(b.x, b.y, b.z, 1.0);
        let cayley = (beta * beta) * (1.0 / beta.length_squared());
        // Renormalised as the paper does (removes rounding only, see above).
        let q_new = (cayley * q).normalize();
        rot.q = q_new;
        // Hold L_{n+½} in the new body frame until `finish`.
        rot.omega_b = inertia.inverse * to_body(q_new, to_world(q, l_half_b));
        Ok(())
    }

    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        _aux: &mut (),
        inertia: &Inertia,
        torque: T,
        t_next: f64,
        dt: f64,
    ) {
        let q = rot.q;
        let tau_b = torque_to_body(q, torque(t_next));
        rot.omega_b += (0.5 * dt) * inertia.inverse * tau_b;
    }
}
