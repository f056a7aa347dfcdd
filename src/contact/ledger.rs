//! The exact-work ledger of the non-conservative contact loads (the
//! restitution damping; a tangential law's force alike). The contact
//! law hands each point's non-conservative wrench back apart from its
//! total (`contact/law/`); the candidate loop sums those per body in the
//! order it sums the totals (`contact/blocks.rs`); this ledger turns the
//! per-body sums into work, whatever law produced them.
//!
//! **Work.** A force `D_k` computed at step k acts in two half-kicks
//! around `v_k`, so its exact translational work is `δt D_k·v_k`, `v_k =
//! v_{k−½} + (δt/2)(F_k/m + g)` (the two half-kicks use the same force;
//! rotation: `δt τ_k·ω`). The ledger at step k holds every earlier stage's
//! work and the closing half-kick's share of stage k's; so `E +
//! E_dissipated` closes as well as the elastic budget does for
//! translation.
//!
//! **Checkpoint.** Between steps a stage with non-conservative loads
//! carries, beyond the states, its last total force and torque per body
//! (computed from `v_{k+½}`, which the full-step states cannot give back)
//! and the ledger's `done` and `dissipated` ([`WorkLedger::state`]); the
//! per-body loads are zeroed by every computation and `first` is false once
//! step 0's forces exist. `src/output/checkpoint.rs` stores exactly these.

use crate::body::{Body, BodyState};
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
            dissipated: 0.0,
        }
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

    /// Close the computation: `force` holds the stage's total contact force
    /// per body. The ledger's share and the full work (module docs).
    pub(crate) fn account(&mut self, bodies: &[Body], states: &[BodyState], force: &[DVec3]) {
        let (dt, g) = (self.dt, self.gravity);
        let (mut closing, mut full) = (0.0, 0.0);
        for (((b, s), (&d, &dtau)), &f) in bodies
            .iter()
            .zip(states)
            .zip(self.force.iter().zip(&self.torque))
            .zip(force)
        {
            if d == DVec3::ZERO && dtau == DVec3::ZERO {
                continue;
            }
            let spin = dtau.dot(s.rot.q * s.rot.omega_b);
            let kick = 0.5 * dt * (f * b.inv_mass + g);
            if self.first {
                // Step 0: `v` is v₀; only the opening half-kick is to come.
                full += 0.25 * dt * d.dot(2.0 * s.v + kick) + 0.5 * dt * spin;
            } else {
                let v_full = s.v + kick;
                closing += 0.25 * dt * d.dot(s.v + v_full) + 0.5 * dt * spin;
                full += dt * (d.dot(v_full) + spin);
            }
        }
        // Work of the non-conservative loads is negative; the ledger keeps
        // it positive.
        self.dissipated = self.done - closing;
        self.done -= full;
        self.first = false;
    }
}
