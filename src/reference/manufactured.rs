//! A manufactured solution: an orientation given in closed form, and the
//! torque that makes it the exact motion of a given rigid body.
//!
//! `q(t) = exp(φ(t) u/2) ⊗ q₀ ⊗ exp(ψ(t) v/2)` (quaternion exponentials),
//! a rotation by `φ` about the world axis `u` after the start `q₀`, composed
//! with a rotation by `ψ` about the body axis `v`; `u` and `v` are unit and
//! in general oblique to each other and to the principal axes, and
//! `φ = a t + b sin(c t)`, `ψ = a′ t + b′ (1 − cos(c′ t))`.
//!
//! Differentiating, `q̇ = ½ φ̇ u ⊗ q + ½ ψ̇ q ⊗ v`, so the body angular velocity
//! `ω = 2 q* q̇` is `ω = φ̇ w + ψ̇ v` with `w = R_v(−ψ) u₀`, `u₀ = q₀* u q₀`
//! (the rotation about `u` leaves `u` fixed); `ẇ = −ψ̇ v × w`, so
//! `ω̇ = φ̈ w − φ̇ ψ̇ v × w + ψ̈ v`. Euler's equations (paper Eq. 4) then give the
//! body torque `τ_b = I ω̇ + ω × I ω`, and the prescribed world torque is
//! `τ = q τ_b q*`: a time-dependent torque in full 3-D with gyroscopic
//! coupling, under which every scheme's error is known exactly.

use crate::math::{exp_map, to_world};
use glam::{DQuat, DVec3};

/// `a t + b sin(c t)` (or, for `ψ`, `a t + b (1 − cos(c t))`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wave {
    /// Mean rate, rad/s.
    pub a: f64,
    /// Amplitude, rad.
    pub b: f64,
    /// Angular frequency, rad/s.
    pub c: f64,
}

impl Wave {
    /// `(f, ḟ, f̈)` of `a t + b sin(c t)`.
    fn sine(&self, t: f64) -> (f64, f64, f64) {
        let (s, co) = (self.c * t).sin_cos();
        (
            self.a * t + self.b * s,
            self.a + self.b * self.c * co,
            -self.b * self.c * self.c * s,
        )
    }

    /// `(f, ḟ, f̈)` of `a t + b (1 − cos(c t))`.
    fn versine(&self, t: f64) -> (f64, f64, f64) {
        let (s, co) = (self.c * t).sin_cos();
        (
            self.a * t + self.b * (1.0 - co),
            self.a + self.b * self.c * s,
            self.b * self.c * self.c * co,
        )
    }
}

/// The manufactured motion of one body (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Manufactured {
    /// Principal moments, kg m².
    pub inertia: DVec3,
    /// The start orientation.
    pub q0: DQuat,
    /// Unit world axis `u` of the first rotation.
    pub u: DVec3,
    /// Unit body axis `v` of the second.
    pub v: DVec3,
    /// `φ(t)`.
    pub phi: Wave,
    /// `ψ(t)`.
    pub psi: Wave,
}

impl Manufactured {
    /// The orientation `q(t)`.
    pub fn orientation(&self, t: f64) -> DQuat {
        let (phi, _, _) = self.phi.sine(t);
        let (psi, _, _) = self.psi.versine(t);
        exp_map(self.u * phi) * self.q0 * exp_map(self.v * psi)
    }

    /// `(ω, ω̇)` in the body frame at `t`.
    fn omega(&self, t: f64) -> (DVec3, DVec3) {
        let (_, dphi, ddphi) = self.phi.sine(t);
        let (psi, dpsi, ddpsi) = self.psi.versine(t);
        let u0 = to_world(self.q0.conjugate(), self.u);
        let w = to_world(exp_map(self.v * -psi), u0);
        let omega = dphi * w + dpsi * self.v;
        let omega_dot = ddphi * w - dphi * dpsi * self.v.cross(w) + ddpsi * self.v;
        (omega, omega_dot)
    }

    /// The body angular velocity `ω(t)`.
    pub fn omega_body(&self, t: f64) -> DVec3 {
        self.omega(t).0
    }

    /// The world torque that drives the motion, `q (I ω̇ + ω × I ω) q*`.
    pub fn torque(&self, t: f64) -> DVec3 {
        let (w, dw) = self.omega(t);
        let tau_b = self.inertia * dw + w.cross(self.inertia * w);
        to_world(self.orientation(t), tau_b)
    }
}
