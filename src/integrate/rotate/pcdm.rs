//! Predictor–corrector direct multiplication (PCDM), paper Eq. 55–63.
//!
//! With `α(ω_b, τ_b) = I⁻¹(τ_b − ω_b × I ω_b)` (Eq. 4):
//! 1. `α_n = α(ω_b,n, q_n* τ_n q_n)` (Eq. 56);
//!    `ω_b,n+¼ = ω_b,n + (δt/4) α_n`, `ω_b,n+½ = ω_b,n + (δt/2) α_n` (Eq. 57);
//! 2. predictor `q'_{n+½} = exp(ω_{n+¼} δt/2) q_n`, `ω_{n+¼} = q_n ω_b,n+¼ q_n*`
//!    (Eq. 58–59), evaluated as the equal `q_n e`, `e = exp(ω_b,n+¼ δt/2)`;
//! 3. `α_{n+½} = α(ω_b,n+½, q'* τ_{n+½} q')` at the predicted orientation;
//! 4. corrector `q_{n+1} = exp(ω_{n+½} δt) q_n`, `ω_{n+½} = q' ω_b,n+½ q'*`
//!    (Eq. 60–61), evaluated as the equal `q_n exp(e ω_b,n+½ e* δt)`;
//! 5. `ω_b,n+1 = ω_b,n + δt α_{n+½}` (Eq. 62).
//!
//! The paper does not say at which *time* the torque of step 3 is taken.
//! [`Pcdm`] takes it at `t_n + δt/2` (second order); [`super::PcdmStart`] takes it at
//! `t_n` (`pcdm_start.rs`; first order for time-dependent torques). A contact torque is the
//! latest computed world torque in both, rotated into the predicted frame `q'`.
//! No renormalisation: only unit quaternions are multiplied.

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{exp_map, is_zero, to_body, to_world};
use glam::DVec3;

/// PCDM with the mid-step torque at `t_n + δt/2`.
pub type Pcdm = PcdmScheme<true>;

pub struct PcdmScheme<const MID_STEP_TORQUE: bool>;

impl<const MID: bool> Rotator for PcdmScheme<MID> {
    type Aux = ();

    const INFO: RotatorInfo = if MID {
        RotatorInfo {
            name: "pcdm",
            title: "Predictor-corrector direct multiplication, mid-step torque at t_n + dt/2",
            equations: "Eq. 55-63",
            order: 2,
            order_free: 2,
            symplectic: false,
            reversible: false,
            torque_evals: 2,
            torque_contract: "torque at (t_n, q_n) and at (t_n + dt/2, q'_n+1/2)",
            contact_contract: "the start-of-step contact torque, taken into the frame of q_n and of the predicted q'_n+1/2",
            closing_kick: false,
        diagnostic: false,
        }
    } else {
        RotatorInfo {
            name: "pcdm-start",
            title: "PCDM with the mid-step torque taken at t_n: first order for time-dependent torques",
            equations: "Eq. 55-63",
            order: 1,
            order_free: 2,
            symplectic: false,
            reversible: false,
            torque_evals: 2,
            torque_contract: "torque at (t_n, q_n) and at (t_n, q'_n+1/2)",
            contact_contract: "the start-of-step contact torque, taken into the frame of q_n and of the predicted q'_n+1/2",
            closing_kick: false,
        diagnostic: false,
        }
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
        let w = rot.omega_b;
        let alpha_n = inertia.angular_acceleration_world(q, w, torque(t_n));
        let w_quarter = w + (0.25 * dt) * alpha_n;
        let w_half = w + (0.5 * dt) * alpha_n;
        // Eq. 58–59: `q' = exp(ω_{n+¼} δt/2) q_n` with `ω_{n+¼} = q_n ω_b,n+¼ q_n*`
        // is `q_n e`, `e = exp(ω_b,n+¼ δt/2)`, since exp(q v q*) = q exp(v) q*.
        let e = exp_map(w_quarter * (0.5 * dt));
        let t_half = if MID { t_n + 0.5 * dt } else { t_n };
        let tau_half = torque(t_half);
        // The torque in the predicted frame q'; q' itself is formed only when
        // there is a torque to rotate (as in `math::torque_to_body`).
        let tau_half_b = if is_zero(tau_half) {
            DVec3::ZERO
        } else {
            to_body(q * e, tau_half)
        };
        let alpha_half = inertia.angular_acceleration(w_half, tau_half_b);
        // Eq. 60–61: `exp(ω_{n+½} δt) q_n` with `ω_{n+½} = q' ω_b,n+½ q'*` is
        // `q_n exp(e ω_b,n+½ e* δt)` by the same identity.
        rot.q = q * exp_map(to_world(e, w_half) * dt);
        rot.omega_b = w + dt * alpha_half;
        Ok(())
    }
}
