//! The exact-work ledger of the non-conservative contact loads (the
//! restitution damping; a tangential law's force alike). The contact
//! law hands each point's non-conservative wrench back apart from its
//! total (`contact/law/`); the candidate loop sums those per body in the
//! order it sums the totals (`contact/blocks.rs`); this ledger turns the
//! per-body sums into work, whatever law produced them.
//!
//! **Work.** A force `D_k` computed at step k acts in two half-kicks
//! around `v_k`, so its exact translational work is `δt D_k·v_k`, `v_k =
//! v_{k−½} + (δt/2)(F_k/m + g)` (the two half-kicks use the same force).
//! Rotation alike: a torque `T_k` does `δt T_k·ω_k`, `ω_k` the world
//! angular velocity at the middle of the interval the torque drives. Most
//! rotators hand the forces an angular velocity half a kick before it (the
//! half-step `ω_{k−½}` of the kick–drift–kick schemes, the whole-step `ω_k`
//! of the start-of-step ones, whose torque drives `[t_k, t_{k+1}]`), so the
//! ledger adds the half kick of the total torque `τ_k`,
//! `ω_k = ω_{k−½} + (δt/2) q (I⁻¹ (q* τ_k q − ω_b × I ω_b))` (Euler's
//! equations, Eq. 4, over the half step; the rotators' own kicks agree to
//! higher order). A staggered scheme hands the forces its predicted middle
//! already (`Rotator::SPIN_AT_MIDPOINT`): the ledger takes it as it is, and
//! the half-step value half a kick before it. Taking the angular velocity
//! the forces see in either case would be off by `(δt/2) T_k·Δω` a step:
//! nothing for central loads on a sphere, but a steady first-order bias
//! wherever a non-conservative torque meets a spin it changes: friction's
//! torques spin the bodies up, and the normal damping acts at a fibre's
//! contact point off its axis, so its lever arm brakes the spin of every
//! landing fibre. The ledger at
//! step k holds every earlier stage's work and the closing half-kick's
//! share of stage k's; so `E + E_dissipated` closes as well as the
//! elastic budget does.
//!
//! **Checkpoint.** Between steps a stage with non-conservative loads
//! carries, beyond the states, its last total force and torque per body
//! (computed from `v_{k+½}`, which the full-step states cannot give back)
//! and the ledger's `done` and `dissipated` ([`WorkLedger::state`]); the
//! per-body loads are zeroed by every computation and `first` is false once
//! step 0's forces exist. `src/output/checkpoint.rs` stores exactly these.

use crate::body::{Bodies, Body, BodyState};
use glam::DVec3;

/// The non-conservative loads of a contact stage per body, and the energy
/// they dissipated.
#[derive(Debug, Clone)]
pub(crate) struct WorkLedger {
    dt: f64,
    gravity: DVec3,
    /// Non-conservative force and torque (world) of the last computation
    /// on each body.
    force: Vec<DVec3>,
    torque: Vec<DVec3>,
    /// Work done against the non-conservative loads of every earlier
    /// computation, J.
    done: f64,
    /// Whether the next computation is the first (step 0: full-step velocities).
    first: bool,
    /// Whether the forces see the angular velocity at the middle of their
    /// torque's interval (module docs), as the rotator stepping says.
    spin_at_midpoint: bool,
    /// Dissipated energy at the state of the last computation, J.
    pub(crate) dissipated: f64,
}

impl WorkLedger {
    /// The ledger of `n` bodies stepped by `dt` under `gravity`.
    pub(crate) fn new(n: usize, dt: f64, gravity: Option<DVec3>) -> Self {
        WorkLedger {
            dt,
            gravity: gravity.unwrap_or(DVec3::ZERO),
            force: vec![DVec3::ZERO; n],
            torque: vec![DVec3::ZERO; n],
            done: 0.0,
            first: true,
            spin_at_midpoint: false,
            dissipated: 0.0,
        }
    }

    /// Take the forces' angular velocity as the middle of their torque's
    /// interval (`Rotator::SPIN_AT_MIDPOINT` of the rotator stepping).
    pub(crate) fn set_spin_at_midpoint(&mut self, yes: bool) {
        self.spin_at_midpoint = yes;
    }

    /// The non-conservative force and torque per body (world), for the
    /// candidate loop to overwrite with this computation's.
    pub(crate) fn loads(&mut self) -> (&mut [DVec3], &mut [DVec3]) {
        (&mut self.force, &mut self.torque)
    }

    /// What the ledger carries from one step to the next: `[done,
    /// dissipated]`, J. With the stage's last total force and torque per
    /// body (the step's open reads them) this is all such a step keeps
    /// between steps: the loads are zeroed by every computation, and
    /// `first` is false after the computation of step 0
    /// (`World::from_states`).
    pub(crate) fn state(&self) -> [f64; 2] {
        [self.done, self.dissipated]
    }

    /// Put back a [`WorkLedger::state`] (resuming from a checkpoint).
    pub(crate) fn set_state(&mut self, [done, dissipated]: [f64; 2]) {
        self.done = done;
        self.dissipated = dissipated;
        self.first = false;
    }

    /// Close the computation: `force` and `torque` hold the stage's total
    /// contact force and torque (world) per body. The ledger's share and
    /// the full work (module docs).
    pub(crate) fn account(
        &mut self,
        bodies: &Bodies,
        states: &[BodyState],
        loads: (&[DVec3], &[DVec3]),
    ) {
        let (closing, full) = self.work(bodies, states, loads);
        self.close(closing, full);
    }

    /// The ledger after a computation whose bodies' shares sum to
    /// `closing` and `full`.
    pub(crate) fn close(&mut self, closing: f64, full: f64) {
        // Work of the non-conservative loads is negative; the ledger keeps
        // it positive.
        self.dissipated = self.done - closing;
        self.done -= full;
        self.first = false;
    }

    /// The closing half-kick's share and the full work of this
    /// computation's loads (module docs).
    #[inline(always)]
    fn work(
        &self,
        bodies: &Bodies,
        states: &[BodyState],
        (force, torque): (&[DVec3], &[DVec3]),
    ) -> (f64, f64) {
        let (mut closing, mut full) = (0.0, 0.0);
        for ((((b, s), (&d, &dtau)), &f), &tau) in bodies
            .iter()
            .zip(states)
            .zip(self.force.iter().zip(&self.torque))
            .zip(force)
            .zip(torque)
        {
            if let Some([c, w]) = self.share(b, s, (d, dtau), (f, tau)) {
                closing += c;
                full += w;
            }
        }
        (closing, full)
    }

    /// Body `i`'s share of [`WorkLedger::account`]'s two sums, `[closing,
    /// full]` (`loads` its total contact force and torque), or `None` when
    /// the last computation left no non-conservative load on it (the sums
    /// skip it). An MPI rank sends its bodies' shares for rank 0 to sum in
    /// the one-process order.
    #[cfg(feature = "mpi")]
    pub(crate) fn body_work(
        &self,
        i: usize,
        b: &Body,
        s: &BodyState,
        loads: (DVec3, DVec3),
    ) -> Option<[f64; 2]> {
        self.share(b, s, (self.force[i], self.torque[i]), loads)
    }

    /// One body's shares of [`WorkLedger::work`]: its non-conservative
    /// force and torque `(d, dtau)` under its total `(f, tau)`. At step 0
    /// only the opening half-kick is to come: no closing share (adding 0
    /// to a sum that starts at +0 leaves it as it is).
    #[inline(always)]
    fn share(
        &self,
        b: &Body,
        s: &BodyState,
        (d, dtau): (DVec3, DVec3),
        (f, tau): (DVec3, DVec3),
    ) -> Option<[f64; 2]> {
        if d == DVec3::ZERO && dtau == DVec3::ZERO {
            return None;
        }
        let (dt, g) = (self.dt, self.gravity);
        let kick = 0.5 * dt * (f * b.inv_mass + g);
        let (q, omega_b) = (s.rot.q, s.rot.omega_b);
        // The torque's power at `ω_{k−½}` (`spin`) and at `ω_k`
        // (`spin_full`), half a kick apart.
        let seen = dtau.dot(q * omega_b);
        let dw = 0.5 * dt * b.inertia.angular_acceleration_world(q, omega_b, tau);
        let half_kick = dtau.dot(q * dw);
        let (spin, spin_full) = if self.spin_at_midpoint && !self.first {
            (seen - half_kick, seen)
        } else {
            (seen, seen + half_kick)
        };
        Some(if self.first {
            // Step 0: `v` and `ω` are v₀ and ω₀; only the opening
            // half-kick is to come.
            [
                0.0,
                0.25 * dt * (d.dot(2.0 * s.v + kick) + spin + spin_full),
            ]
        } else {
            let v_full = s.v + kick;
            [
                0.25 * dt * (d.dot(s.v + v_full) + spin + spin_full),
                dt * (d.dot(v_full) + spin_full),
            ]
        })
    }
}
