//! `pcdm-staggered`: the PCDM of Eq. 55–63 shifted by half a step, so that
//! its predicted orientation falls on the whole step where the forces are
//! computed: the "improved PCDM" of Seelen, Padding & Kuipers, Acta Mech.
//! 227 (2016) 3381, **as reconstructed here from the properties the paper
//! states** (its equations were not available to us): leap-frog staggered,
//! `q` and `ω_b` carried at half steps, whole-step values formed inside the
//! step; one torque evaluation per step, at the time and orientation the
//! forces are computed at; second order; no explicit renormalisation.
//!
//! Carried between steps ([`StaggeredAux`]): `q_{n+½}`, `ω_b,n+½` and the last
//! angular acceleration `ω̇_b,n`, with `α(ω_b, τ_b) = I⁻¹(τ_b − ω_b × I ω_b)`
//! (Eq. 4). The PCDM's predictor and corrector, each half a step later:
//! 1. predictor (`advance`, before forces), from `q_{n+½}` over δt/2 with the
//!    last acceleration: `ω_b,n+¾ = ω_b,n+½ + (δt/4) ω̇_b,n`,
//!    `q'_{n+1} = exp(ω_{n+¾} δt/2) q_{n+½}` (Eq. 58–59 shifted), and the
//!    whole-step angular velocity `ω'_b,n+1 = ω_b,n+½ + (δt/2) ω̇_b,n`;
//!    `(q'_{n+1}, ω'_b,n+1)` is the state the forces see;
//! 2. forces and torques at `(x_{n+1}, q'_{n+1})`, time `t_{n+1}`;
//! 3. corrector (`finish`): `ω̇_b,n+1 = α(ω'_b,n+1, q'* τ_{n+1} q')`,
//!    `q_{n+3/2} = exp(ω'_{n+1} δt) q_{n+½}` with `ω'_{n+1} = q' ω'_b,n+1 q'*`
//!    (Eq. 60–61 shifted), `ω_b,n+3/2 = ω_b,n+½ + δt ω̇_b,n+1` (Eq. 62 shifted);
//!    the whole-step angular velocity reported, `ω_b,n+1 = ω_b,n+½ + (δt/2)
//!    ω̇_b,n+1`, is the mean of the two half-step ones.
//!
//! The rotations about world axes are applied in `q_{n+½}`'s body frame, as
//! in `pcdm.rs`: `exp(q v q*) q = q exp(v)`.
//!
//! **Start.** The first step has whole-step values only; with the torque at
//! `(t_0, q_0)`, `ω̇_b,0 = α(ω_b,0, q_0* τ_0 q_0)`, `ω_b,½ = ω_b,0 + (δt/2) ω̇_b,0`
//! and `q_½ = exp(ω_¼ δt/2) q_0`, `ω_b,¼ = ω_b,0 + (δt/4) ω̇_b,0` (the PCDM
//! predictor over half a step). The start's `O(δt²)` error in `ω_b,½` is made
//! once, so the global order stays 2.
//!
//! **Order.** The predictor's lagged acceleration errs by `O(δt)` in
//! `ω̇`, so `ω'_b,n+1` and `ω_b,n+¾` err by `O(δt²)`, `q'_{n+1}` by `O(δt³)`
//! locally; the corrector is then the midpoint rule for both `q` and `ω_b`
//! over `[t_{n+½}, t_{n+3/2}]`: second order, with or without torque.
//! Neither symplectic nor time-reversible (the predictor extrapolates).
//!
//! **Torque.** One evaluation per step, at `(t_{n+1}, q'_{n+1})`: where and
//! when the forces are computed, so a contact torque is used at the
//! configuration it belongs to (the PCDM of `pcdm.rs` would need it at
//! `t_{n+½}`, where no forces are computed). The start adds one at `t_0`.
//!
//! No renormalisation: the increments are unit quaternions, and `q e` is
//! formed as `q + q (e − 1)` with `e − 1 = [−|s|²/(1 + c), s]` for
//! `e = [c, s]` (`c² + |s|² = 1`), accurate to relative rounding. A plain
//! product carries the rounding of `c` near 1, the same at every step under
//! a steady spin: `|q|` then drifts with a bias (`steady_spin_keeps_unit_norm`
//! below; docs/rotators-new.md gives the figures).

use super::{AuxState, Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{exp_map, to_world, torque_to_body};
use glam::{DQuat, DVec3};

/// The half-step-staggered PCDM (module docs).
pub struct PcdmStaggered;

/// `q ⊗ exp(r)` (a turn by `|r|` about the body axis `r̂`), formed as
/// `q + q ⊗ (exp(r) − 1)` (module docs).
#[inline]
pub(crate) fn exp_turn(q: DQuat, r: DVec3) -> DQuat {
    let e = exp_map(r);
    let s = DVec3::new(e.x, e.y, e.z);
    q + q * DQuat::from_xyzw(e.x, e.y, e.z, -s.length_squared() / (1.0 + e.w))
}

/// What `pcdm-staggered` carries between steps: the staggered state.
#[derive(Debug, Clone, Copy)]
pub struct StaggeredAux {
    /// `q_{n+½}` (NaN before the first step: the start is still to be made).
    pub q_half: DQuat,
    /// `ω_b,n+½`, rad/s, body frame.
    pub omega_half: DVec3,
    /// `ω̇_b,n`, the angular acceleration of the last force evaluation, rad/s².
    pub accel: DVec3,
}

impl Default for StaggeredAux {
    fn default() -> Self {
        StaggeredAux {
            q_half: DQuat::from_xyzw(f64::NAN, f64::NAN, f64::NAN, f64::NAN),
            omega_half: DVec3::ZERO,
            accel: DVec3::ZERO,
        }
    }
}

impl AuxState for StaggeredAux {
    const LEN: usize = 10;
    #[inline]
    fn read(from: &[f64]) -> Self {
        StaggeredAux {
            q_half: DQuat::from_xyzw(from[0], from[1], from[2], from[3]),
            omega_half: DVec3::new(from[4], from[5], from[6]),
            accel: DVec3::new(from[7], from[8], from[9]),
        }
    }
    #[inline]
    fn write(&self, to: &mut [f64]) {
        to[..4].copy_from_slice(&self.q_half.to_array());
        to[4..7].copy_from_slice(&self.omega_half.to_array());
        to[7..10].copy_from_slice(&self.accel.to_array());
    }
}

impl Rotator for PcdmStaggered {
    type Aux = StaggeredAux;

    /// The forces see `ω'_b,n+1`, the middle of `[t_{n+½}, t_{n+3/2}]`
    /// over which their torque drives the corrector.
    const SPIN_AT_MIDPOINT: bool = true;

    const INFO: RotatorInfo = RotatorInfo {
        name: "pcdm-staggered",
        title: "PCDM shifted half a step (q, omega at half steps, one torque evaluation at the predicted whole-step orientation): Seelen et al.'s improved PCDM, reconstructed from its stated properties",
        equations: "Seelen et al. 2016 (reconstructed)",
        order: 2,
        order_free: 2,
        symplectic: false,
        reversible: false,
        torque_evals: 1,
        torque_contract: "torque at (t_n+1, q'_n+1), the predicted whole-step orientation the forces are computed at; the first step also takes it at (t_0, q_0)",
        contact_contract: "the contact torque of the new configuration (q'_n+1, with the predicted whole-step omega'_n+1 for velocity-dependent forces) drives the corrector over the whole step",
        closing_kick: true,
        diagnostic: false,
    };

    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut StaggeredAux,
        inertia: &Inertia,
        torque: T,
        t: f64,
        dt: f64,
    ) -> Result<(), RotatorFault> {
        if aux.q_half.w.is_nan() {
            // Start (module docs): the half-step state from the whole-step one.
            let a0 = inertia.angular_acceleration(rot.omega_b, torque_to_body(rot.q, torque(t)));
            let w_quarter = rot.omega_b + (0.25 * dt) * a0;
            *aux = StaggeredAux {
                q_half: exp_turn(rot.q, w_quarter * (0.5 * dt)),
                omega_half: rot.omega_b + (0.5 * dt) * a0,
                accel: a0,
            };
        }
        // Step 1: the predictor over [t_{n+½}, t_{n+1}].
        let w = aux.omega_half;
        let w_3q = w + (0.25 * dt) * aux.accel;
        rot.q = exp_turn(aux.q_half, w_3q * (0.5 * dt));
        rot.omega_b = w + (0.5 * dt) * aux.accel;
        Ok(())
    }

    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut StaggeredAux,
        inertia: &Inertia,
        torque: T,
        t_end: f64,
        dt: f64,
    ) {
        // Step 3: the corrector over [t_{n+½}, t_{n+3/2}] with the torque of
        // (t_{n+1}, q'_{n+1}); `rot` holds the predicted whole-step state.
        let (q_pred, w_pred) = (rot.q, rot.omega_b);
        let a = inertia.angular_acceleration(w_pred, torque_to_body(q_pred, torque(t_end)));
        // `e = q_{n+½}* q'_{n+1}` takes ω'_b,n+1 into q_{n+½}'s body frame.
        let e = aux.q_half.conjugate() * q_pred;
        let w = aux.omega_half;
        *aux = StaggeredAux {
            q_half: exp_turn(aux.q_half, to_world(e, w_pred) * dt),
            omega_half: w + dt * a,
            accel: a,
        };
        rot.omega_b = w + (0.5 * dt) * a;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::rotate::RotatorKind;
    use std::cell::RefCell;

    /// The stated order on every order case of `study::order` (the slow
    /// tier's `every_listed_rotator_has_its_stated_order`, for this scheme
    /// in the fast tier): exact references (manufactured solution, Jacobi's
    /// top) and rk4 ones (test case 4, the smooth torque).
    #[test]
    fn second_order_on_the_order_cases() {
        use crate::study::order::{cases, measure, reference};
        for case in cases() {
            let m = measure(&case, RotatorKind::PcdmStaggered, reference(&case));
            println!("{:<14} {m}", case.name);
            assert_eq!(m.window.len(), 4, "{}: {m}", case.name);
            assert!((m.order - 2.0).abs() < 0.2, "{}: {m}", case.name);
        }
    }

    /// One torque evaluation per step, at `t_{n+1}` in `finish` (where the
    /// forces are), and one more at `t_0` for the start.
    #[test]
    fn torque_asked_once_per_step_at_the_step_end() {
        let inertia = Inertia::new(DVec3::new(2e-3, 3e-3, 4e-3));
        let mut rot = RotState {
            q: DQuat::IDENTITY,
            omega_b: DVec3::new(5.0, 8.0, -6.0),
        };
        let mut aux = StaggeredAux::default();
        let asked = RefCell::new(vec![]);
        let torque = |t: f64| {
            asked.borrow_mut().push(t);
            DVec3::new(1e-3 * t, 0.0, 2e-3)
        };
        let dt = 1e-3;
        for n in 0..5 {
            let t = n as f64 * dt;
            PcdmStaggered::advance(&mut rot, &mut aux, &inertia, torque, t, dt).unwrap();
            PcdmStaggered::finish(&mut rot, &mut aux, &inertia, torque, t + dt, dt);
        }
        let want: Vec<f64> = (0..=5).map(|n| n as f64 * dt).collect();
        assert_eq!(*asked.borrow(), want);
    }

    /// `|q|` stays 1 to rounding over 10⁶ steps of a steady spin about a
    /// principal axis, the case where a plain product `q ⊗ exp(r)` drifts
    /// with a bias (module docs).
    #[test]
    fn steady_spin_keeps_unit_norm() {
        let inertia = Inertia::new(DVec3::new(1e-3, 5e-3, 5e-3));
        let mut rot = RotState {
            q: DQuat::IDENTITY,
            omega_b: DVec3::new(0.0, 0.0, 300.0),
        };
        let mut aux = StaggeredAux::default();
        let (dt, mut worst) = (1e-6, 0.0f64);
        for n in 0..1_000_000 {
            let t = n as f64 * dt;
            PcdmStaggered::advance(&mut rot, &mut aux, &inertia, |_| DVec3::ZERO, t, dt).unwrap();
            PcdmStaggered::finish(&mut rot, &mut aux, &inertia, |_| DVec3::ZERO, t + dt, dt);
            worst = worst.max((rot.q.length() - 1.0).abs());
        }
        println!("pcdm-staggered, 1e6 steps of a steady spin: max | |q| - 1 | = {worst:.2e}");
        assert!(worst < 1e-12, "{worst:e}");
    }
}
