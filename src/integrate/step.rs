//! The time step as a fixed sequence of stages (LAMMPS-style hooks):
//! 1. translation half-kick and drift; 2. rotator `advance`;
//! 3. forces at the new configuration (contacts, if the scene has any);
//! 4. translation half-kick; rotator `finish`; 5. guards.
//!
//! Integrators never compute forces; the force stage never moves bodies.

use super::rotate::{Rotator, RotatorFault};
use super::verlet;
use crate::body::BodyState;
use crate::contact::stage::{ContactStage, ContactStats};
use crate::energy::{error_pct, Ledger};
use crate::error::Diagnosis;
use crate::scenario::Scene;
use crate::torque::PrescribedTorque;
use glam::DVec3;
use std::time::Instant;

/// Largest accepted drift of a quaternion's norm from 1 (rounding only: every
/// rotator keeps `‖q‖ = 1` by construction or by its own renormalisation).
pub const QUAT_NORM_TOLERANCE: f64 = 1e-9;

/// The evolving state of a scene, kept apart from the step logic.
#[derive(Debug, Clone)]
pub struct World<'s> {
    pub scene: &'s Scene,
    pub states: Vec<BodyState>,
    /// Latest contact force and torque per body (world frame), at `states`.
    pub force: Vec<DVec3>,
    pub torque: Vec<DVec3>,
    /// Elastic energy of the live contacts at `states`.
    pub elastic: f64,
    /// Number of completed steps; the time is `step · δt`.
    pub step: u64,
    /// The contact force stage; `None` when nothing can touch (SPEC §7).
    pub contacts: Option<ContactStage>,
    /// Energy ledger at `states` (updated every step: the energy guard reads it).
    pub ledger: Ledger,
    /// Full-budget energy at step 0.
    pub e0_full: f64,
    /// Whether the energy guard applies: prescribed torques do work, so
    /// energy is a conserved budget only without them.
    energy_guarded: bool,
    /// Stage timers (rapier-style), off unless a benchmark turns them on: two
    /// clock reads per stage per step are not free.
    pub timers: Option<StageTimes>,
}

/// Wall time spent in each stage of the step, summed over steps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    /// Verlet and rotators (stages 1, 2, 4).
    pub integrate: std::time::Duration,
    /// Broad phase, kernels, Hertz (stage 3).
    pub forces: std::time::Duration,
    /// Energy ledger and guards (stage 5).
    pub guards: std::time::Duration,
}

impl<'s> World<'s> {
    pub fn new(scene: &'s Scene) -> Self {
        let n = scene.bodies.len();
        let mut w = World {
            scene,
            states: scene.initial.clone(),
            force: vec![DVec3::ZERO; n],
            torque: vec![DVec3::ZERO; n],
            elastic: 0.0,
            step: 0,
            contacts: scene
                .needs_contacts()
                .then(|| ContactStage::new(&scene.bodies, scene.walls.as_ref())),
            ledger: Ledger::default(),
            e0_full: 0.0,
            energy_guarded: !scene.has_prescribed_torque(),
            timers: None,
        };
        w.compute_forces();
        w.ledger = w.measure();
        w.e0_full = w.ledger.total_full();
        w
    }

    /// Put the world at `step` with `states` (resuming from a checkpoint): the
    /// forces and the ledger are recomputed from the states, exactly as the
    /// step that produced them did.
    pub fn restore(&mut self, states: Vec<BodyState>, step: u64) {
        self.states = states;
        self.step = step;
        self.compute_forces();
        self.ledger = self.measure();
    }

    #[inline]
    fn measure(&self) -> Ledger {
        Ledger::measure(
            &self.scene.bodies,
            &self.states,
            self.scene.gravity,
            self.elastic,
        )
    }

    pub fn time(&self) -> f64 {
        self.step as f64 * self.scene.sim.dt
    }

    /// Stage 3: forces and torques at the current configuration. Without
    /// contacts there is nothing to compute (gravity enters as an acceleration).
    fn compute_forces(&mut self) {
        if let Some(c) = &mut self.contacts {
            c.compute(
                &self.scene.bodies,
                &self.states,
                &mut self.force,
                &mut self.torque,
            );
            self.elastic = c.stats.elastic;
        }
    }

    /// What the contact stage saw at the current configuration.
    pub fn contact_stats(&self) -> Option<ContactStats> {
        self.contacts.as_ref().map(|c| c.stats)
    }

    /// Advance one step with rotator `R`. The diagnosis is boxed: a stop is
    /// rare, and a one-word `Result` keeps a 100-byte copy out of every step
    /// (10 ns of a 35 ns single-body step, `benches/rotators.rs`).
    pub fn step<R: Rotator>(&mut self) -> Result<(), Box<Diagnosis>> {
        let dt = self.scene.sim.dt;
        let t_n = self.step as f64 * dt;
        let t_next = (self.step + 1) as f64 * dt;
        let scene = self.scene;
        let g = scene.gravity.unwrap_or(DVec3::ZERO);
        let clock = self.timers.map(|_| Instant::now());

        // Stages 1–2: half-kick and drift, rotator `advance`.
        let bodies = scene.bodies.iter().zip(&scene.torques);
        let loads = self.force.iter().zip(&self.torque);
        for (i, ((s, (body, prescribed)), (&f, &contact))) in
            self.states.iter_mut().zip(bodies).zip(loads).enumerate()
        {
            verlet::kick_drift(&mut s.x, &mut s.v, f * body.inv_mass + g, dt);
            R::advance(
                &mut s.rot,
                &body.inertia,
                torque_source(prescribed, contact),
                t_n,
                dt,
            )
            .map_err(|fault| Box::new(fault_diagnosis(fault, i, self.step, t_n)))?;
        }

        // Stage 3: forces at the new configuration.
        let clock_forces = clock.map(|_| Instant::now());
        self.compute_forces();
        let clock_after = clock.map(|_| Instant::now());

        // Stage 4, in one pass with the ledger of the finished state: closing
        // half-kick, rotator `finish`, energy terms, per-body soundness.
        let mut ledger = Ledger {
            elastic: self.elastic,
            ..Ledger::default()
        };
        let mut sound = true;
        let bodies = scene.bodies.iter().zip(&scene.torques);
        let loads = self.force.iter().zip(&self.torque);
        for ((s, (body, prescribed)), (&f, &contact)) in
            self.states.iter_mut().zip(bodies).zip(loads)
        {
            verlet::kick(&mut s.v, f * body.inv_mass + g, dt);
            if R::INFO.kick_drift_kick {
                let torque = torque_source(prescribed, contact);
                R::finish(&mut s.rot, &body.inertia, torque, t_next, dt);
            }
            ledger.add_body(body, s, g);
            sound &= body_is_sound(s);
        }
        self.step += 1;
        self.ledger = ledger;

        // Stage 5: guards.
        let clock_guards = clock.map(|_| Instant::now());
        let verdict = if sound && self.scene_is_sound() {
            Ok(())
        } else {
            self.diagnose_state().map_or(Ok(()), |d| Err(Box::new(d)))
        };
        if let (Some(t), Some(c0), Some(c1), Some(c2), Some(c3)) = (
            &mut self.timers,
            clock,
            clock_forces,
            clock_after,
            clock_guards,
        ) {
            t.integrate += (c1 - c0) + (c3 - c2);
            t.forces += c2 - c1;
            t.guards += c3.elapsed();
        }
        verdict
    }

    /// The scene-wide guards (overlap, energy) of the fast path; the
    /// per-body ones are [`body_is_sound`]. Together as strict as
    /// [`Self::diagnose_state`].
    #[inline]
    fn scene_is_sound(&self) -> bool {
        let guards = &self.scene.guards;
        let overlap_ok = self
            .contacts
            .as_ref()
            .is_none_or(|c| c.stats.max_overlap_ratio <= guards.overlap_ratio);
        let energy = self.ledger.total_full();
        overlap_ok
            && energy.is_finite()
            && !(self.energy_guarded && error_pct(energy, self.e0_full) > guards.energy_error_pct)
    }

    /// The first guard that fires, with its named diagnosis; the most
    /// specific first (a NaN state also has a NaN energy).
    #[cold]
    #[inline(never)]
    fn diagnose_state(&self) -> Option<Diagnosis> {
        let guards = &self.scene.guards;
        let diag =
            |kind: &str, body: Option<usize>, quantity: &str, value: f64, limit: f64| Diagnosis {
                kind: kind.into(),
                step: self.step,
                t: self.time(),
                body,
                quantity: quantity.into(),
                value,
                limit,
            };
        for (i, s) in self.states.iter().enumerate() {
            let finite = s.x.is_finite()
                && s.v.is_finite()
                && s.rot.q.is_finite()
                && s.rot.omega_b.is_finite();
            if !finite {
                return Some(diag(
                    "non-finite state (position, velocity, orientation or spin is NaN or infinite)",
                    Some(i),
                    "state",
                    f64::NAN,
                    f64::MAX,
                ));
            }
        }
        // A state can be finite while its energy overflows (|ω| ~ 1e154): stop
        // there, before such rows reach the outputs.
        let energy = self.ledger.total_full();
        if !energy.is_finite() {
            return Some(diag(
                "non-finite energy (the state has overflowed)",
                None,
                "energy",
                energy,
                f64::MAX,
            ));
        }
        if let Some(c) = self.contact_stats() {
            if c.max_overlap_ratio > guards.overlap_ratio {
                return Some(diag(
                    "overlap beyond the Hertz range (impact too fast or dt too large)",
                    Some(c.max_overlap_body),
                    "overlap / D",
                    c.max_overlap_ratio,
                    guards.overlap_ratio,
                ));
            }
        }
        let err = error_pct(energy, self.e0_full);
        if err > guards.energy_error_pct && self.energy_guarded {
            return Some(diag(
                "energy blow-up (full-budget energy error above the limit)",
                None,
                "energy error %",
                err,
                guards.energy_error_pct,
            ));
        }
        for (i, s) in self.states.iter().enumerate() {
            let norm = s.rot.q.length();
            if norm < 0.5 {
                // A renormalising scheme whose update overflowed (Euler's
                // `normalize` of an infinite quaternion gives 0).
                return Some(diag(
                    "degenerate orientation (the rotation update overflowed)",
                    Some(i),
                    "| ||q|| - 1 |",
                    (norm - 1.0).abs(),
                    QUAT_NORM_TOLERANCE,
                ));
            }
            let drift = (norm - 1.0).abs();
            if drift > QUAT_NORM_TOLERANCE {
                return Some(diag(
                    "quaternion norm drift",
                    Some(i),
                    "| ||q|| - 1 |",
                    drift,
                    QUAT_NORM_TOLERANCE,
                ));
            }
        }
        None
    }
}

/// The per-body part of the fast guard path: `|‖q‖ − 1| ≤ tol`, tested as
/// bounds on `‖q‖²` (no square root; false for a NaN). A non-finite `x`, `v`
/// or `ω` needs no test of its own here: it makes the ledger's total
/// non-finite (`g·x` is computed even for `g = 0`, and `0·∞` is NaN), which
/// [`World::scene_is_sound`] rejects; the slow path then names the body.
#[inline]
fn body_is_sound(s: &BodyState) -> bool {
    const NORM2_LO: f64 = (1.0 - QUAT_NORM_TOLERANCE) * (1.0 - QUAT_NORM_TOLERANCE);
    const NORM2_HI: f64 = (1.0 + QUAT_NORM_TOLERANCE) * (1.0 + QUAT_NORM_TOLERANCE);
    (NORM2_LO..=NORM2_HI).contains(&s.rot.q.length_squared())
}

/// The torque a rotator asks for at time `t`: the body's prescribed torque,
/// if any, evaluated there, plus the latest computed contact torque (SPEC §4).
#[inline]
fn torque_source(
    prescribed: &Option<PrescribedTorque>,
    contact: DVec3,
) -> impl Fn(f64) -> DVec3 + '_ {
    move |t| prescribed.as_ref().map_or(DVec3::ZERO, |p| p.at(t)) + contact
}

fn fault_diagnosis(fault: RotatorFault, body: usize, step: u64, t: f64) -> Diagnosis {
    match fault {
        RotatorFault::ScalarSingularity { half_angle } => Diagnosis {
            kind: "scalar-factor singularity (tan pole of Eq. 41); reduce dt or use pcdm".into(),
            step,
            t,
            body: Some(body),
            quantity: "|omega| dt / 2".into(),
            value: half_angle,
            limit: std::f64::consts::FRAC_PI_2,
        },
    }
}
