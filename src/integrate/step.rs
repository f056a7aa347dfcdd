//! One step: the rotator's stage sequence ([`crate::integrate::scheme`]) run
//! on the [`World`], then the guards.
//!
//! For [`VERLET`](crate::integrate::scheme::VERLET), the step of every shipped
//! rotator: 1. translation half-kick and drift, rotator `advance`; 2. forces
//! at the new configuration (contacts, if the scene has any); 3. one closing
//! pass: translation half-kick, rotator `finish`, the energy ledger and the
//! per-body guard; 4. the scene guards.
//!
//! The opening and closing stages are written once, body by body, and
//! walked on one thread, on the pool ([`crate::contact::stage::parallel`])
//! or over an MPI rank's own bodies (`walk.rs`): a body's arithmetic, the
//! rotator refusal reported and the ledger's sum do not depend on the
//! walker. docs/architecture.md.
//!
//! Integrators never compute forces; the force stage never moves bodies.

pub use super::world::{StageTimes, World};

use super::rotate::{AuxState, Rotator, RotatorFault};
use super::scheme::Stage;
use super::verlet;
use super::walk::{Input, Inputs, Pool, Serial, Walk};
use crate::body::{Body, BodyState};
use crate::energy::{error_pct, Ledger};
use crate::stop::{Diagnosis, StopKind};
use glam::DVec3;
use std::time::{Duration, Instant};

/// Largest accepted drift of a quaternion's norm from 1 (rounding only: every
/// rotator keeps `‖q‖ = 1` by construction or by its own renormalisation).
pub const QUAT_NORM_TOLERANCE: f64 = 1e-9;

impl<'s> World<'s> {
    /// Advance one step with rotator `R`: its stages walked on the thread
    /// pool for a scene that runs there, else on this thread.
    pub fn step<R: Rotator>(&mut self) -> Result<(), Box<Diagnosis>> {
        if crate::contact::stage::parallel(self.states.len()) {
            self.step_by::<R, Pool>(&Pool)
        } else {
            self.step_by::<R, Serial>(&Serial)
        }
    }

    /// [`World::step`] with the bodies walked by `walk`. The diagnosis is
    /// boxed: a stop is rare, and a one-word `Result` keeps a 100-byte
    /// copy out of every step (`benches/rotators.rs`).
    fn step_by<R: Rotator, W: Walk>(&mut self, walk: &W) -> Result<(), Box<Diagnosis>> {
        const { assert!(super::scheme::is_valid(R::STAGES)) };
        if R::Aux::LEN > 0 && self.aux.len() != R::Aux::LEN * self.states.len() {
            self.start_aux::<R>();
        }
        self.ledger_follows::<R>();
        let clock = self.timers.map(|_| Instant::now());
        let mut forces_time = Duration::ZERO;
        let mut forces = |w: &mut Self| match clock {
            None => w.compute_forces(),
            Some(_) => {
                let c = Instant::now();
                w.compute_forces();
                forces_time += c.elapsed();
            }
        };
        let sound = if const { super::scheme::is_verlet(R::STAGES) } {
            // The stages of VERLET, unrolled (no loop over the sequence).
            self.open_stage::<R, W>(walk, 0.0, 1.0)?;
            forces(self);
            self.close_stage::<R, W>(walk, 1.0, 1.0, true)
        } else {
            let last = R::STAGES.len() - 1;
            let mut sound = true;
            for (k, stage) in R::STAGES.iter().enumerate() {
                match *stage {
                    Stage::Open { start, h } => self.open_stage::<R, W>(walk, start, h)?,
                    Stage::Forces => forces(self),
                    Stage::Close { end, h } => {
                        sound = self.close_stage::<R, W>(walk, end, h, k == last)
                    }
                }
            }
            sound
        };
        self.step += 1;

        let clock_guards = clock.map(|_| Instant::now());
        let verdict = if sound && self.scene_is_sound() {
            Ok(())
        } else {
            self.diagnose_state().map_or(Ok(()), |d| Err(Box::new(d)))
        };
        if let (Some(t), Some(c0), Some(c1)) = (&mut self.timers, clock, clock_guards) {
            t.integrate += (c1 - c0) - forces_time;
            t.forces += forces_time;
            t.guards += c1.elapsed();
        }
        verdict
    }

    /// One step with the rotator `kind`, dispatched at every call (for tests
    /// and tools; a run dispatches once, see [`crate::run::drive`]).
    pub fn step_kind(&mut self, kind: super::rotate::RotatorKind) -> Result<(), Box<Diagnosis>> {
        struct One<'a, 'w, 's>(&'a mut World<'s>, std::marker::PhantomData<&'w ()>);
        impl super::rotate::RotatorVisitor for One<'_, '_, '_> {
            type Output = Result<(), Box<Diagnosis>>;
            fn visit<R: Rotator>(self) -> Self::Output {
                self.0.step::<R>()
            }
        }
        kind.visit(One(self, std::marker::PhantomData))
    }

    /// Tell the work ledger which angular velocity `R` hands the forces.
    #[inline]
    pub(crate) fn ledger_follows<R: Rotator>(&mut self) {
        if let Some(c) = &mut self.contacts {
            c.ledger_spin_at_midpoint(R::SPIN_AT_MIDPOINT);
        }
    }

    /// The rotator's auxiliary state at the start of a run.
    pub(crate) fn start_aux<R: Rotator>(&mut self) {
        let len = R::Aux::LEN;
        self.aux = vec![0.0; len * self.states.len()];
        for (i, (s, b)) in self.states.iter().zip(&self.scene.bodies).enumerate() {
            R::start(&s.rot, &b.inertia).write(&mut self.aux[i * len..(i + 1) * len]);
        }
    }

    /// An opening stage over `[t_n + start·δt, +h·δt]` of the bodies
    /// `walk` walks, each: translation half-kick and drift, rotator
    /// `advance`. The first refusal in body order, as its diagnosis.
    #[inline]
    fn open_stage<R: Rotator, W: Walk>(
        &mut self,
        walk: &W,
        start: f64,
        h: f64,
    ) -> Result<(), Box<Diagnosis>> {
        self.open::<R, W>(walk, start, h).map_err(|(i, fault)| {
            let t = (self.step as f64 + start) * self.scene.sim.dt();
            Box::new(fault_diagnosis(fault, self.scene.ids.get(i), self.step, t))
        })
    }

    /// A closing stage of the bodies `walk` walks ([`World::close`]); the
    /// step's last one also measures the ledger of the finished state and
    /// the per-body guard, and says whether every body passed it.
    #[inline]
    fn close_stage<R: Rotator, W: Walk>(&mut self, walk: &W, end: f64, h: f64, last: bool) -> bool {
        let g = self.scene.gravity.unwrap_or(DVec3::ZERO);
        let mut ledger = Ledger {
            elastic: self.elastic(),
            spring: self.spring_energy(),
            dissipated: self.dissipated(),
            ..Ledger::default()
        };
        let mut sound = true;
        self.close::<R, W>(walk, end, h, |_, body, s| {
            if last {
                ledger.add_body(body, s, g);
                sound &= body_is_sound(s);
            }
        });
        if last {
            self.ledger = ledger;
        }
        sound
    }

    /// The opening stage of the bodies `walk` walks, over `[t_n +
    /// start·δt, +h·δt]`: each body's half-kick and drift, then its
    /// rotator's `advance` under the body's torque. Every walked body is
    /// advanced; the first refusal in body order.
    #[inline]
    pub(crate) fn open<R: Rotator, W: Walk>(
        &mut self,
        walk: &W,
        start: f64,
        h: f64,
    ) -> Result<(), (usize, RotatorFault)> {
        let scene = self.scene;
        let dt = h * scene.sim.dt();
        let t = (self.step as f64 + start) * scene.sim.dt();
        let g = scene.gravity.unwrap_or(DVec3::ZERO);
        let inputs = Inputs {
            bodies: &scene.bodies,
            force: &self.force,
            torque: &self.torque,
            prescribed: &scene.torques,
        };
        walk.walk(
            &mut self.states,
            &mut self.aux,
            inputs,
            |s, a: &mut R::Aux, x| {
                let Input {
                    body,
                    force,
                    torque: contact,
                    prescribed,
                } = x;
                verlet::kick_drift(&mut s.x, &mut s.v, force * body.inv_mass + g, dt);
                // The torque the rotator asks for at a time `t`: the
                // prescribed torque there, if any, plus the latest contact
                // torque (docs/physics.md §4). (A closure of this stage
                // and walker: each walker's loop has its own `advance`.)
                let tau = move |t: f64| match prescribed {
                    Some(p) => p.at(t) + contact,
                    None => DVec3::ZERO + contact,
                };
                R::advance(&mut s.rot, a, &body.inertia, tau, t, dt)
            },
            |_, _, _| {},
        )
    }

    /// A closing stage at `t_n + end·δt` (of a sub-step of `h·δt`) of the
    /// bodies `walk` walks: each body's half-kick and its rotator's
    /// `finish`; then `then(i, body, state)` on each of them in body order.
    #[inline]
    pub(crate) fn close<R: Rotator, W: Walk>(
        &mut self,
        walk: &W,
        end: f64,
        h: f64,
        then: impl FnMut(usize, &Body, &BodyState),
    ) {
        let scene = self.scene;
        let dt = h * scene.sim.dt();
        let t_end = (self.step as f64 + end) * scene.sim.dt();
        let g = scene.gravity.unwrap_or(DVec3::ZERO);
        let inputs = Inputs {
            bodies: &scene.bodies,
            force: &self.force,
            torque: &self.torque,
            prescribed: &scene.torques,
        };
        let finished = walk.walk(
            &mut self.states,
            &mut self.aux,
            inputs,
            |s, a: &mut R::Aux, x| {
                let Input {
                    body,
                    force,
                    torque: contact,
                    prescribed,
                } = x;
                verlet::kick(&mut s.v, force * body.inv_mass + g, dt);
                let tau = move |t: f64| match prescribed {
                    Some(p) => p.at(t) + contact,
                    None => DVec3::ZERO + contact,
                };
                R::finish(&mut s.rot, a, &body.inertia, tau, t_end, dt);
                Ok::<(), std::convert::Infallible>(())
            },
            then,
        );
        let Ok(()) = finished;
    }

    /// The scene-wide guards (overlap, energy) of the fast path; the
    /// per-body ones are [`body_is_sound`]. Together as strict as
    /// [`Self::diagnose_state`].
    #[inline]
    pub(crate) fn scene_is_sound(&self) -> bool {
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
    pub(crate) fn diagnose_state(&self) -> Option<Diagnosis> {
        let guards = &self.scene.guards;
        let ids = &self.scene.ids;
        let diag = |kind: StopKind, body: Option<usize>, value: f64, limit: f64| Diagnosis {
            kind,
            step: self.step,
            t: self.time(),
            body: body.map(|i| ids.get(i)),
            value,
            limit,
        };
        for (i, s) in self.states.iter().enumerate() {
            let finite = s.x.is_finite()
                && s.v.is_finite()
                && s.rot.q.is_finite()
                && s.rot.omega_b.is_finite();
            if !finite {
                return Some(diag(StopKind::NonFiniteState, Some(i), f64::NAN, f64::MAX));
            }
        }
        // A state can be finite while its energy overflows (|ω| ~ 1e154): stop
        // there, before such rows reach the outputs.
        let energy = self.ledger.total_full();
        if !energy.is_finite() {
            return Some(diag(StopKind::NonFiniteEnergy, None, energy, f64::MAX));
        }
        if let Some(c) = self.contact_stats() {
            if c.max_overlap_ratio > guards.overlap_ratio {
                return Some(diag(
                    StopKind::Overlap,
                    Some(c.max_overlap_body),
                    c.max_overlap_ratio,
                    guards.overlap_ratio,
                ));
            }
        }
        let err = error_pct(energy, self.e0_full);
        if err > guards.energy_error_pct && self.energy_guarded {
            return Some(diag(
                StopKind::EnergyBlowUp,
                None,
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
                    StopKind::DegenerateOrientation,
                    Some(i),
                    (norm - 1.0).abs(),
                    QUAT_NORM_TOLERANCE,
                ));
            }
            let drift = (norm - 1.0).abs();
            if drift > QUAT_NORM_TOLERANCE {
                return Some(diag(
                    StopKind::QuatNormDrift,
                    Some(i),
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
pub(crate) fn body_is_sound(s: &BodyState) -> bool {
    const NORM2_LO: f64 = (1.0 - QUAT_NORM_TOLERANCE) * (1.0 - QUAT_NORM_TOLERANCE);
    const NORM2_HI: f64 = (1.0 + QUAT_NORM_TOLERANCE) * (1.0 + QUAT_NORM_TOLERANCE);
    (NORM2_LO..=NORM2_HI).contains(&s.rot.q.length_squared())
}

/// The diagnosis of a rotator's refusal of body `body` at `step`, time `t`.
pub(crate) fn fault_diagnosis(fault: RotatorFault, body: u64, step: u64, t: f64) -> Diagnosis {
    match fault {
        RotatorFault::ScalarSingularity { half_angle } => Diagnosis {
            kind: StopKind::ScalarSingularity,
            step,
            t,
            body: Some(body),
            value: half_angle,
            limit: std::f64::consts::FRAC_PI_2,
        },
    }
}
