//! Velocity Verlet for the centres of mass (paper §4; Allen & Tildesley).
//!
//! `v_{n+½} = v_n + (δt/2) a_n`, `x_{n+1} = x_n + δt v_{n+½}`, forces at `x_{n+1}`,
//! `v_{n+1} = v_{n+½} + (δt/2) a_{n+1}`. One force evaluation per step.

use glam::DVec3;

/// First half-kick and drift.
#[inline]
pub fn kick_drift(x: &mut DVec3, v: &mut DVec3, accel: DVec3, dt: f64) {
    *v += (0.5 * dt) * accel;
    *x += dt * *v;
}

/// Closing half-kick with the acceleration at the new positions.
#[inline]
pub fn kick(v: &mut DVec3, accel: DVec3, dt: f64) {
    *v += (0.5 * dt) * accel;
}
