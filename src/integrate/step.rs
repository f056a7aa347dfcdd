//! One step: the rotator's stage sequence ([`crate::integrate::scheme`]) run
//! on the [`World`], then the guards.
//!
//! For [`VERLET`](crate::integrate::scheme::VERLET), the step of every shipped
//! rotator: 1. translation half-kick and drift, rotator `advance`; 2. forces
//! at the new configuration (contacts, if the scene has any); 3. one closing
//! pass: translation half-kick, rotator `finish`, the energy ledger and the
//! per-body guard; 4. the scene guards.
//!
//! Integrators never compute forces; the force stage never moves bodies.

pub use super::world::{StageTimes, World};

use super::rotate::{AuxState, Rotator, RotatorFault};
use super::scheme::Stage;
use super::verlet;
use crate::body::BodyState;
use crate::energy::{error_pct, Ledger};
use crate::scenario::Prescribed;
use crate::stop::{Diagnosis, StopKind};
use crate::torque::PrescribedTorque;
use glam::DVec3;
use std::time::{Duration, Instant};

/// Largest accepted drift of a quaternion's norm from 1 (rounding only: every
/// rotator keeps `‖q‖ = 1` by construction or by its own renormalisation).
pub const QUAT_NORM_TOLERANCE: f64 = 1e-9;

/// The `len` doubles of body `i` in a flat per-body array.
#[inline]
fn slot(aux: &mut [f64], i: usize, len: usize) -> &mut [f64] {
    &mut aux[i * len..(i + 1) * len]
}

/// The prescribed torque of body `i`, if it has one: `next` walks the sparse,
/// ordered list alongside the bodies.
#[inline]
fn prescribed_at<'a>(
    next: &mut std::iter::Peekable<std::slice::Iter<'a, Prescribed>>,
    i: usize,
) -> Option<&'a PrescribedTorque> {
    next.next_if(|p| p.body == i).map(|p| &p.torque)
}

impl<'s> World<'s> {
    /// Advance one step with rotator `R`. The diagnosis is boxed: a stop is
    /// rare, and a one-word `Result` keeps a 100-byte copy out of every step
    /// (a large share of a single-body step: `benches/rotators.rs`).
    pub fn step<R: Rotator>(&mut self) -> Result<(), Box<Diagnosis>> {
        const { assert!(super::scheme::is_valid(R::STAGES)) };
        if R::Aux::LEN > 0 && self.aux.len() != R::Aux::LEN * self.states.len() {
            self.start_aux::<R>();
        }
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
            self.open::<R>(0.0, 1.0)?;
            forces(self);
            self.close::<R>(1.0, 1.0, true)
        } else {
            let last = R::STAGES.len() - 1;
            let mut sound = true;
            for (k, stage) in R::STAGES.iter().enumerate() {
                match *stage {
                    Stage::Open { start, h } => self.open::<R>(start, h)?,
                    Stage::Forces => forces(self),
                    Stage::Close { end, h } => sound = self.close::<R>(end, h, k == last),
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

    /// The rotator's auxiliary state at the start of a run.
    fn start_aux<R: Rotator>(&mut self) {
        let len = R::Aux::LEN;
        self.aux = vec![0.0; len * self.states.len()];
        for (i, (s, b)) in self.states.iter().zip(&self.scene.bodies).enumerate() {
            R::start(&s.rot, &b.inertia).write(slot(&mut self.aux, i, len));
        }
    }

    /// An opening stage: half-kick and drift, rotator `advance`, over
    /// `[t_n + start·δt, +h·δt]`.
    #[inline]
    fn open<R: Rotator>(&mut self, start: f64, h: f64) -> Result<(), Box<Diagnosis>> {
        if !R::MAY_FAULT && crate::contact::stage::parallel(self.states.len()) {
            self.open_par::<R>(start, h);
            return Ok(());
        }
        let scene = self.scene;
        let dt = h * scene.sim.dt();
        let t = (self.step as f64 + start) * scene.sim.dt();
        let g = scene.gravity.unwrap_or(DVec3::ZERO);
        let len = R::Aux::LEN;
        let has_torques = !scene.torques.is_empty();
        let mut prescribed = scene.torques.iter().peekable();
        let loads = self.force.iter().zip(&self.torque);
        for (i, ((s, body), (&f, &contact))) in self
            .states
            .iter_mut()
            .zip(&scene.bodies)
            .zip(loads)
            .enumerate()
        {
            verlet::kick_drift(&mut s.x, &mut s.v, f * body.inv_mass + g, dt);
            let p = if has_torques {
                prescribed_at(&mut prescribed, i)
            } else {
                None
            };
            let torque = torque_source(p, contact);
            let fault = |fault| Box::new(fault_diagnosis(fault, scene.ids.get(i), self.step, t));
            if const { R::Aux::LEN == 0 } {
                let mut a = R::Aux::default();
                R::advance(&mut s.rot, &mut a, &body.inertia, torque, t, dt).map_err(fault)?;
            } else {
                let aux = slot(&mut self.aux, i, len);
                let mut a = R::Aux::read(aux);
                R::advance(&mut s.rot, &mut a, &body.inertia, torque, t, dt).map_err(fault)?;
                a.write(aux);
            }
        }
        Ok(())
    }

    /// A closing stage at `t_n + end·δt`: half-kick, rotator `finish`. The
    /// step's last one also measures the ledger of the finished state and
    /// the per-body guard, in the same pass, and says whether every body
    /// passed it.
    #[inline]
    fn close<R: Rotator>(&mut self, end: f64, h: f64, last: bool) -> bool {
        if crate::contact::stage::parallel(self.states.len()) {
            return self.close_par::<R>(end, h, last);
        }
        let scene = self.scene;
        let dt = h * scene.sim.dt();
        let t_end = (self.step as f64 + end) * scene.sim.dt();
        let g = scene.gravity.unwrap_or(DVec3::ZERO);
        let len = R::Aux::LEN;
        let mut ledger = Ledger {
            elastic: self.elastic(),
            dissipated: self.dissipated(),
            ..Ledger::default()
        };
        let mut sound = true;
        let has_torques = !scene.torques.is_empty();
        let mut prescribed = scene.torques.iter().peekable();
        let loads = self.force.iter().zip(&self.torque);
        for (i, ((s, body), (&f, &contact))) in self
            .states
            .iter_mut()
            .zip(&scene.bodies)
            .zip(loads)
            .enumerate()
        {
            verlet::kick(&mut s.v, f * body.inv_mass + g, dt);
            let p = if has_torques {
                prescribed_at(&mut prescribed, i)
            } else {
                None
            };
            let torque = torque_source(p, contact);
            if const { R::Aux::LEN == 0 } {
                let mut a = R::Aux::default();
                R::finish(&mut s.rot, &mut a, &body.inertia, torque, t_end, dt);
            } else {
                let aux = slot(&mut self.aux, i, len);
                let mut a = R::Aux::read(aux);
                R::finish(&mut s.rot, &mut a, &body.inertia, torque, t_end, dt);
                a.write(aux);
            }
            if last {
                ledger.add_body(body, s, g);
                sound &= body_is_sound(s);
            }
        }
        if last {
            self.ledger = ledger;
        }
        sound
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
pub(super) fn body_is_sound(s: &BodyState) -> bool {
    const NORM2_LO: f64 = (1.0 - QUAT_NORM_TOLERANCE) * (1.0 - QUAT_NORM_TOLERANCE);
    const NORM2_HI: f64 = (1.0 + QUAT_NORM_TOLERANCE) * (1.0 + QUAT_NORM_TOLERANCE);
    (NORM2_LO..=NORM2_HI).contains(&s.rot.q.length_squared())
}

/// The torque a rotator asks for at time `t`: the body's prescribed torque,
/// if any, evaluated there, plus the latest computed contact torque
/// (docs/physics.md §4).
#[inline]
pub(super) fn torque_source(
    prescribed: Option<&PrescribedTorque>,
    contact: DVec3,
) -> impl Fn(f64) -> DVec3 + '_ {
    // Inlined by force: with codegen-units = 4, where this closure lands
    // follows the crate's layout, and a call per body-step is a measurable
    // share of the nine-fibre step (`cargo bench --bench contacts`).
    #[inline(always)]
    move |t| match prescribed {
        Some(p) => p.at(t) + contact,
        None => DVec3::ZERO + contact,
    }
}

fn fault_diagnosis(fault: RotatorFault, body: u64, step: u64, t: f64) -> Diagnosis {
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

/// The step's guards and diagnoses for an MPI rank's step (`src/ranks/`),
/// as wrappers: the originals stay private to this module, so the
/// one-process step inlines them as before (made crate-visible, LLVM
/// stopped inlining the torque closure into the one-process step).
#[cfg(feature = "mpi")]
pub(crate) mod for_ranks {
    use super::*;

    impl World<'_> {
        /// [`World::start_aux`].
        pub(crate) fn ranks_start_aux<R: Rotator>(&mut self) {
            self.start_aux::<R>()
        }
        /// [`World::scene_is_sound`].
        pub(crate) fn ranks_scene_is_sound(&self) -> bool {
            self.scene_is_sound()
        }
        /// [`World::diagnose_state`].
        pub(crate) fn ranks_diagnose_state(&self) -> Option<Diagnosis> {
            self.diagnose_state()
        }
    }

    /// [`body_is_sound`].
    pub(crate) fn ranks_body_is_sound(s: &BodyState) -> bool {
        body_is_sound(s)
    }

    /// [`fault_diagnosis`].
    pub(crate) fn ranks_fault_diagnosis(
        f: RotatorFault,
        body: u64,
        step: u64,
        t: f64,
    ) -> Diagnosis {
        fault_diagnosis(f, body, step, t)
    }
}
