//! The evolving state of a scene, kept apart from the step logic
//! (rapier's bodies and pipeline): per-body states, the latest forces and
//! torques, the contact stage's caches, the energy ledger and the step count.

use crate::body::BodyState;
use crate::contact::stage::{ContactStage, ContactStats};
use crate::energy::Ledger;
use crate::scenario::Scene;
use glam::DVec3;

/// The evolving state of a scene.
#[derive(Debug, Clone)]
pub struct World<'s> {
    /// The scene being run.
    pub scene: &'s Scene,
    /// Kinematic state per body, by storage index (a compact 104-byte
    /// record; per-body constants are in `scene.bodies`).
    pub states: Vec<BodyState>,
    /// Per-body auxiliary state of the rotator, `Aux::LEN` doubles per body
    /// (see [`crate::integrate::rotate::AuxState`]); empty for schemes that
    /// keep none.
    pub aux: Vec<f64>,
    /// Latest contact force and torque per body (world frame), at `states`.
    pub force: Vec<DVec3>,
    /// (See `force`.)
    pub torque: Vec<DVec3>,
    /// Number of completed steps; the time is `step · δt`.
    pub step: u64,
    /// The contact force stage; `None` when nothing can touch
    /// (docs/physics.md §7).
    pub contacts: Option<ContactStage>,
    /// Energy ledger at `states` (updated every step: the energy guard reads
    /// it). Its `elastic` term is the contact stage's.
    pub ledger: Ledger,
    /// Full-budget energy at step 0.
    pub e0_full: f64,
    /// Whether the energy guard applies: prescribed torques do work, so
    /// energy is a conserved budget only without them.
    pub(crate) energy_guarded: bool,
    /// Stage timers (rapier-style), off unless a benchmark turns them on: two
    /// clock reads per stage per step are not free.
    pub timers: Option<StageTimes>,
}

/// What a damped or frictional world needs besides its states to continue
/// bit for bit ([`World::restore_damping`]; a checkpoint stores it).
#[derive(Debug, Clone)]
pub struct DampedState {
    /// The last force stage's total contact force and torque per body.
    pub loads: Vec<[DVec3; 2]>,
    /// The ledger of the non-conservative loads (`done`, `dissipated`), J.
    pub ledger: [f64; 2],
    /// A frictional world's contacts' records (their springs) after the
    /// last force stage.
    pub(crate) history: Option<crate::contact::history::History>,
    /// The energy those springs held, J.
    pub spring: f64,
}

/// Wall time spent in each stage of the step, summed over steps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    /// Opening and closing stages: Verlet and the rotators.
    pub integrate: std::time::Duration,
    /// Force stages: broad phase, kernels, Hertz.
    pub forces: std::time::Duration,
    /// Guards.
    pub guards: std::time::Duration,
}

impl<'s> World<'s> {
    /// The scene at step 0 (a copy of `scene.initial`: the scene can be run
    /// again), with its forces and ledger computed.
    pub fn new(scene: &'s Scene) -> Self {
        Self::from_states(scene, scene.initial.clone())
    }

    /// [`World::new`] from the step-0 states `states`, moved in: `fibresim
    /// run` takes them out of its scene rather than keep two copies
    /// (104 B per body).
    pub fn from_states(scene: &'s Scene, states: Vec<BodyState>) -> Self {
        let n = scene.bodies.len();
        assert_eq!(states.len(), n, "one step-0 state per body");
        let mut w = World {
            scene,
            states,
            aux: vec![],
            force: vec![DVec3::ZERO; n],
            torque: vec![DVec3::ZERO; n],
            step: 0,
            contacts: scene.needs_contacts().then(|| {
                ContactStage::new(&scene.bodies, &scene.materials, scene.walls.as_ref())
                    .with_friction(scene.friction, scene.sim.dt())
                    .with_damping(scene.damping, n, scene.sim.dt(), scene.gravity)
            }),
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

    /// Put the world at `step` with `states` and the rotator's `aux`
    /// (resuming from a checkpoint) and the pairs' `memory` of their scans:
    /// the forces and the ledger are recomputed from the states, exactly
    /// as the step that produced them did.
    pub fn restore(
        &mut self,
        states: Vec<BodyState>,
        aux: Vec<f64>,
        step: u64,
        memory: Vec<crate::contact::memory::Entry>,
    ) {
        self.states = states;
        self.aux = aux;
        self.step = step;
        if let Some(c) = &mut self.contacts {
            c.restore_memory(memory, &self.scene.bodies, &self.states);
        }
        self.compute_forces();
        self.ledger = self.measure();
    }

    /// The rest of a damped or frictional world's checkpoint, after
    /// [`World::restore`]: its forces came from half-step velocities, so
    /// the recomputed ones are replaced by the stored ones, the ledger of
    /// the non-conservative loads is put back, and so are the contacts'
    /// records, which the recomputation advanced (its positions-only
    /// statistics, elastic energy and overlaps, are the step's).
    pub fn restore_damping(&mut self, d: DampedState) {
        if let Some(c) = &mut self.contacts {
            assert!(c.set_damping_state(d.ledger), "the law reads velocities");
            if let Some(h) = d.history {
                assert!(c.set_history(h, d.spring), "the law keeps records");
            }
        }
        for ((f, t), [df, dt]) in self.force.iter_mut().zip(&mut self.torque).zip(d.loads) {
            (*f, *t) = (df, dt);
        }
        self.ledger = self.measure();
    }

    /// The ledger of the current states.
    pub(crate) fn measure(&self) -> Ledger {
        Ledger {
            dissipated: self.dissipated(),
            spring: self.spring_energy(),
            ..Ledger::measure(
                &self.scene.bodies,
                &self.states,
                self.scene.gravity,
                self.elastic(),
            )
        }
    }

    /// Elastic energy of the live contacts at `states`, J.
    #[inline]
    pub fn elastic(&self) -> f64 {
        self.contacts.as_ref().map_or(0.0, |c| c.stats.elastic)
    }

    /// Energy dissipated by contact damping up to `states`, J (0 when the
    /// scene declares none).
    #[inline]
    pub fn dissipated(&self) -> f64 {
        self.contacts.as_ref().map_or(0.0, |c| c.dissipated())
    }

    /// Energy stored in the contacts' friction springs at `states`, J (0
    /// without friction).
    #[inline]
    pub fn spring_energy(&self) -> f64 {
        self.contacts.as_ref().map_or(0.0, |c| c.spring_energy())
    }

    /// The time of the current step, `step · δt`, s.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.scene.sim.dt()
    }

    /// The force stage: forces and torques at the current configuration.
    /// Without contacts there is nothing to compute (gravity enters as an
    /// acceleration).
    pub(crate) fn compute_forces(&mut self) {
        if let Some(c) = &mut self.contacts {
            c.compute(
                &self.scene.bodies,
                &self.states,
                &mut self.force,
                &mut self.torque,
            );
        }
    }

    /// What the contact stage saw at the current configuration.
    pub fn contact_stats(&self) -> Option<ContactStats> {
        self.contacts.as_ref().map(|c| c.stats)
    }
}
