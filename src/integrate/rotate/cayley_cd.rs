//! `cayley-cd`: the explicit central-difference scheme on the unit
//! quaternions with the Cayley map, after the "central difference Cayley"
//! integrator (CDCay) of Li, Chen, Tian & Hu, Comput. Part. Mech. 12 (2025)
//! 81. **A reconstruction**: only the paper's abstract was available to us
//! (explicit, on the group of unit quaternions, the rotation update by the
//! Cayley map so that no transcendental function is evaluated, second
//! order); the equations below are derived from those properties, not
//! copied from the paper.
//!
//! With `Ω` the body angular velocity (`q̇ = ½ q ⊗ [0, Ω]`) and
//! `α(Ω, τ_b) = I⁻¹(τ_b − Ω × I Ω)` (Eq. 4), `Ω` is carried at half steps
//! ([`HalfStepVelocity`]) and `q` at whole steps:
//! 1. drift (`advance`): `q_{n+1} = q_n ⊗ cay(δt Ω_{n+½})`, with the Cayley map
//!    of the unit quaternions `cay(v) = (1 + v/4)(1 − v/4)⁻¹ =
//!    [(1 − |v|²/16) + v/2] / (1 + |v|²/16)` (`v/4` a pure quaternion): exactly
//!    unit, a turn by `4 atan(|v|/4) = |v| − |v|³/48 + …` about `v̂`. It is
//!    Eq. 35–37's Cayley factor (`leapfrog`) and Omelyan's, applied in the
//!    body frame;
//! 2. forces at `q_{n+1}`, time `t_{n+1}`;
//! 3. kick (`finish`), the central difference of Euler's equations at
//!    `t_{n+1}`: `Ω_{n+3/2} = Ω_{n+½} + δt α(Ω*_{n+1}, τ_b,n+1)`, with
//!    `τ_b,n+1 = q_{n+1}* τ(t_{n+1}) q_{n+1}` and the whole-step `Ω` of the
//!    gyroscopic term estimated explicitly by half a step,
//!    `Ω*_{n+1} = Ω_{n+½} + (δt/2) α(Ω_{n+½}, τ_b,n+1)`. The whole-step angular
//!    velocity reported is the mean `(Ω_{n+½} + Ω_{n+3/2})/2`.
//!
//! The estimate `Ω*` errs by `O(δt²)`, so the kick is the midpoint rule to
//! `O(δt³)` per step and the drift is the midpoint rule on the group (the
//! Cayley map differs from `exp` by `O(δt³)`): second order, with or
//! without torque. Taking `Ω_{n+½}` itself in the gyroscopic term (no
//! estimate) would make the scheme first order. Neither symplectic nor
//! time-reversible (the estimate extrapolates); Omelyan's scheme (`omelyan`)
//! is the implicit, reversible counterpart of the same central difference.
//!
//! **Start.** The first step starts the stagger with the torque at
//! `(t_0, q_0)`: `Ω_½ = Ω_0 + (δt/2) α(Ω_0, τ_b,0)`.
//!
//! **Torque.** One evaluation per step, at `(t_{n+1}, q_{n+1})`, after the
//! drift: the forces' configuration. The force stage sees `Ω_{n+½}`, as it
//! sees the translational `v_{n+½}`.
//!
//! No renormalisation: the Cayley factor `c` is unit by construction, and
//! `q c` is formed as `q + q (c − 1)` (`c − 1` is small and accurate to
//! relative rounding), so that the rounding of `c`'s scalar part near 1,
//! the same at every step under a steady spin, does not bias `|q|`.

use super::{AuxState, Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::torque_to_body;
use glam::{DQuat, DVec3};

/// The central difference with the Cayley map (module docs).
pub struct CayleyCd;

/// What `cayley-cd` carries between steps: `Ω_{n+½}`.
#[derive(Debug, Clone, Copy)]
pub struct HalfStepVelocity {
    /// `Ω_{n+½}`, rad/s, body frame (NaN before the first step).
    pub omega_half: DVec3,
}

impl Default for HalfStepVelocity {
    fn default() -> Self {
        HalfStepVelocity {
            omega_half: DVec3::splat(f64::NAN),
        }
    }
}

impl AuxState for HalfStepVelocity {
    const LEN: usize = 3;
    #[inline]
    fn read(from: &[f64]) -> Self {
        HalfStepVelocity {
            omega_half: DVec3::new(from[0], from[1], from[2]),
        }
    }
    #[inline]
    fn write(&self, to: &mut [f64]) {
        to[..3].copy_from_slice(&self.omega_half.to_array());
    }
}

/// `q ⊗ cay(v)`, formed as `q + q ⊗ (cay(v) − 1)` with
/// `cay(v) − 1 = [−2s, v/2] / (1 + s)`, `s = |v|²/16` (module docs).
#[inline]
pub(crate) fn cayley_turn(q: DQuat, v: DVec3) -> DQuat {
    let s = v.length_squared() * (1.0 / 16.0);
    let k = 1.0 / (1.0 + s);
    let b = (0.5 * k) * v;
    q + q * DQuat::from_xyzw(b.x, b.y, b.z, -2.0 * s * k)
}

impl Rotator for CayleyCd {
    type Aux = HalfStepVelocity;

    const INFO: RotatorInfo = RotatorInfo {
        name: "cayley-cd",
        title: "Explicit central difference on the unit quaternions with the Cayley map (body omega at half steps): Li et al.'s CDCay, reconstructed from its stated properties",
        equations: "Li et al. 2025, CDCay (reconstructed)",
        order: 2,
        order_free: 2,
        symplectic: false,
        reversible: false,
        torque_evals: 1,
        torque_contract: "torque at (t_n+1, q_n+1), after the Cayley drift, for the kick omega_n+1/2 -> omega_n+3/2; the first step also takes it at (t_0, q_0)",
        contact_contract: "the contact torque of the new configuration drives the whole kick omega_n+1/2 -> omega_n+3/2; the force stage sees the half-step omega_n+1/2",
        closing_kick: true,
        diagnostic: false,
    };

    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut HalfStepVelocity,
        inertia: &Inertia,
        torque: T,
        t: f64,
        dt: f64,
    ) -> Result<(), RotatorFault> {
        if aux.omega_half.x.is_nan() {
            // Start (module docs).
            let tau_b = torque_to_body(rot.q, torque(t));
            aux.omega_half = rot.omega_b + (0.5 * dt) * inertia.angular_acceleration(rot.omega_b, tau_b);
        }
        let w = aux.omega_half;
        rot.q = cayley_turn(rot.q, dt * w);
        rot.omega_b = w;
        Ok(())
    }

    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut HalfStepVelocity,
        inertia: &Inertia,
        torque: T,
        t_end: f64,
        dt: f64,
    ) {
        let tau_b = torque_to_body(rot.q, torque(t_end));
        let w = aux.omega_half;
        let w_whole = w + (0.5 * dt) * inertia.angular_acceleration(w, tau_b);
        let a = inertia.angular_acceleration(w_whole, tau_b);
        aux.omega_half = w + dt * a;
        rot.omega_b = w + (0.5 * dt) * a;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::rotate::RotatorKind;
    use crate::math::{exp_map, geodesic_angle};
    use std::cell::RefCell;

    /// The stated order on every order case of `study::order` (the slow
    /// tier's `every_listed_rotator_has_its_stated_order`, for this scheme
    /// in the fast tier).
    #[test]
    fn second_order_on_the_order_cases() {
        use crate::study::order::{cases, measure, reference};
        for case in cases() {
            let m = measure(&case, RotatorKind::CayleyCd, reference(&case));
            println!("{:<14} {m}", case.name);
            assert_eq!(m.window.len(), 4, "{}: {m}", case.name);
            assert!((m.order - 2.0).abs() < 0.2, "{}: {m}", case.name);
        }
    }

    /// `cay(v)` is the turn by `4 atan(|v|/4)` about `v̂` (closed form of the
    /// Cayley map of the unit quaternions), unit to rounding.
    #[test]
    fn cayley_map_is_the_closed_form_turn() {
        let q0 = DQuat::from_xyzw(0.3, -0.2, 0.2449489742783178, 0.9);
        for v in [
            DVec3::new(1e-6, -2e-6, 3e-6),
            DVec3::new(0.02, 0.01, -0.03),
            DVec3::new(1.5, -0.7, 0.4),
        ] {
            let angle = 4.0 * (0.25 * v.length()).atan();
            let want = q0 * exp_map(v.normalize() * angle);
            let got = cayley_turn(q0, v);
            assert!(geodesic_angle(got, want) < 1e-15, "{v}: {:e}", geodesic_angle(got, want));
            assert!((got.length() - 1.0).abs() < 4e-16, "{v}");
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
        let mut aux = HalfStepVelocity::default();
        let asked = RefCell::new(vec![]);
        let torque = |t: f64| {
            asked.borrow_mut().push(t);
            DVec3::new(1e-3 * t, 0.0, 2e-3)
        };
        let dt = 1e-3;
        for n in 0..5 {
            let t = n as f64 * dt;
            CayleyCd::advance(&mut rot, &mut aux, &inertia, torque, t, dt).unwrap();
            CayleyCd::finish(&mut rot, &mut aux, &inertia, torque, t + dt, dt);
        }
        let want: Vec<f64> = (0..=5).map(|n| n as f64 * dt).collect();
        assert_eq!(*asked.borrow(), want);
    }

    /// `|q|` stays 1 to rounding over 10⁶ steps of a steady spin about a
    /// principal axis, where a plain product `q ⊗ cay(v)` drifts with a
    /// bias (module docs).
    #[test]
    fn steady_spin_keeps_unit_norm() {
        let inertia = Inertia::new(DVec3::new(1e-3, 5e-3, 5e-3));
        let mut rot = RotState {
            q: DQuat::IDENTITY,
            omega_b: DVec3::new(0.0, 0.0, 300.0),
        };
        let mut aux = HalfStepVelocity::default();
        let (dt, mut worst) = (1e-6, 0.0f64);
        for n in 0..1_000_000 {
            let t = n as f64 * dt;
            CayleyCd::advance(&mut rot, &mut aux, &inertia, |_| DVec3::ZERO, t, dt).unwrap();
            CayleyCd::finish(&mut rot, &mut aux, &inertia, |_| DVec3::ZERO, t + dt, dt);
            worst = worst.max((rot.q.length() - 1.0).abs());
        }
        println!("cayley-cd, 1e6 steps of a steady spin: max | |q| - 1 | = {worst:.2e}");
        assert!(worst < 1e-12, "{worst:e}");
    }
}
