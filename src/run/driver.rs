//! The one driver loop: step the world to the scene's end, account the run's
//! statistics, and call the observers on their cadences (LAMMPS's run loop
//! with its output and dump hooks). `fibresim run`, the studies and the
//! tests all run through it.

use super::observer::{Observer, RunEnd, View};
use super::stats::RunStats;
use crate::body::BodyState;
use crate::error::{Error, Result};
use crate::integrate::rotate::{AuxState, Rotator, RotatorVisitor};
use crate::integrate::step::World;
use crate::output::checkpoint::{self, Checkpoint};
use crate::scenario::Scene;
use crate::stop::{Diagnosis, StopKind};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// When the driver raises events besides rows.
#[derive(Debug, Clone, Default)]
pub struct Control {
    /// Take a checkpoint every this many steps.
    pub checkpoint_every: Option<u64>,
    /// Stop at the next step when its flag is set (SIGINT), after a
    /// checkpoint.
    pub interrupt: Option<Interrupt>,
    /// End the run (as if at its last step) once it has settled.
    pub settle: Option<Settle>,
}

/// What an interrupt (SIGINT) does.
#[derive(Debug, Clone)]
pub struct Interrupt {
    /// Set by the signal handler.
    pub flag: &'static AtomicBool,
    /// The checkpoint (written by the checkpoint observer).
    pub checkpoint: PathBuf,
    /// The command that continues the run from it, for the message.
    pub resume: String,
}

/// When a run has settled: its kinetic energy (translation and rotation)
/// per body at or below `ke_per_body`, tested every `every` steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settle {
    /// Threshold, J per body.
    pub ke_per_body: f64,
    /// Steps between two tests.
    pub every: u64,
}

impl Settle {
    /// Whether `w` has settled: its kinetic energy per body is at most the
    /// threshold and, under gravity, every body rests on something. Low
    /// kinetic energy alone is also the state of a bed released at rest,
    /// and of a body at the top of its bounce; a body at rest under gravity
    /// with nothing to touch is falling. The count of touching pairs (one
    /// pass of the kernels) is asked only once the energy is low.
    pub fn reached(&self, w: &World) -> bool {
        let ke = w.ledger.translation + w.ledger.rotation;
        if ke > self.ke_per_body * w.states.len() as f64 {
            return false;
        }
        match (&w.contacts, w.scene.gravity) {
            (Some(stage), Some(g)) if g != glam::DVec3::ZERO => stage
                .touching_per_body(&w.scene.bodies)
                .iter()
                .all(|&n| n > 0),
            _ => true,
        }
    }
}

/// The end of a drive: the final world, the run's statistics and the stop.
pub struct Finished<'s> {
    /// The world at the last step.
    pub world: World<'s>,
    /// The run's statistics.
    pub stats: RunStats,
    /// Why the run stopped early, if it did.
    pub stopped: Option<Diagnosis>,
    /// Wall time of the loop, s.
    pub wall_s: f64,
    /// The step the loop started from.
    pub first_step: u64,
    /// Whether the run ended because it settled ([`Control::settle`]).
    pub settled: bool,
}

/// Run `scene` with its rotator from the start (or from `resume`) to its
/// end, or to the first stop, calling `observers` in list order. An error is
/// an observer's (an output that cannot be written); every row written
/// before it is kept.
pub fn drive<'s>(
    scene: &'s Scene,
    observers: &mut [&mut dyn Observer],
    control: &Control,
    resume: Option<&Checkpoint>,
) -> Result<Finished<'s>> {
    let initial = scene.initial.clone();
    drive_by(scene, initial, observers, control, resume, OneProcess)
}

/// How the driver takes a step and makes the world whole for its observers:
/// [`OneProcess`] here; an MPI rank's decomposed step in `src/ranks/`.
pub trait Stepper<'s> {
    /// Before the first step (after `World::from_states` or a resume's
    /// restore).
    fn start(&mut self, _w: &mut World<'s>) {}
    /// One step of `w` with rotator `R`.
    fn step<R: Rotator>(&mut self, w: &mut World<'s>) -> std::result::Result<(), Box<Diagnosis>>;
    /// Before observers look at `w` (an event, a checkpoint, the end):
    /// every state in place where the observers run.
    fn sync(&mut self, _w: &mut World<'s>) {}
    /// Whether the world's contact stage holds every candidate pair of the
    /// scene (an MPI rank of several holds only its fibres' and ghosts').
    fn whole_contact_stage(&self) -> bool {
        true
    }
}

impl<'s, T: Stepper<'s>> Stepper<'s> for &mut T {
    fn start(&mut self, w: &mut World<'s>) {
        (**self).start(w)
    }
    fn step<R: Rotator>(&mut self, w: &mut World<'s>) -> std::result::Result<(), Box<Diagnosis>> {
        (**self).step::<R>(w)
    }
    fn sync(&mut self, w: &mut World<'s>) {
        (**self).sync(w)
    }
    fn whole_contact_stage(&self) -> bool {
        (**self).whole_contact_stage()
    }
}

/// The one-process step: [`World::step`].
pub struct OneProcess;

impl<'s> Stepper<'s> for OneProcess {
    fn step<R: Rotator>(&mut self, w: &mut World<'s>) -> std::result::Result<(), Box<Diagnosis>> {
        w.step::<R>()
    }
}

/// [`drive`] from the step-0 states `initial` (moved into the world; a
/// resumed run starts there too, then restores the checkpoint's), with the
/// steps taken by `stepper`.
pub fn drive_by<'s, S: Stepper<'s>>(
    scene: &'s Scene,
    initial: Vec<BodyState>,
    observers: &mut [&mut dyn Observer],
    control: &Control,
    resume: Option<&Checkpoint>,
    stepper: S,
) -> Result<Finished<'s>> {
    struct Drive<'a, 's, 'o, S> {
        scene: &'s Scene,
        initial: Vec<BodyState>,
        observers: &'a mut [&'o mut dyn Observer],
        control: &'a Control,
        resume: Option<&'a Checkpoint>,
        stepper: S,
    }
    impl<'s, S: Stepper<'s>> RotatorVisitor for Drive<'_, 's, '_, S> {
        type Output = Result<Finished<'s>>;
        fn visit<R: Rotator>(self) -> Self::Output {
            drive_with::<R, S>(
                self.scene,
                self.initial,
                self.observers,
                self.control,
                self.resume,
                self.stepper,
            )
        }
    }
    // A composition (several force stages) in a contact scene: exit 2.
    if let Some(why) = scene
        .needs_contacts()
        .then(|| scene.sim.rotator().contact_refusal())
        .flatten()
    {
        return Err(crate::error::Error::bad(
            scene.source.clone(),
            "simulation.rotator",
            why,
        ));
    }
    scene.sim.rotator().visit(Drive {
        scene,
        initial,
        observers,
        control,
        resume,
        stepper,
    })
}

/// The next multiple of `n` after `step`.
fn next_multiple(step: u64, n: u64) -> u64 {
    (step / n + 1) * n
}

fn drive_with<'s, R: Rotator, S: Stepper<'s>>(
    scene: &'s Scene,
    initial: Vec<BodyState>,
    observers: &mut [&mut dyn Observer],
    control: &Control,
    resume: Option<&Checkpoint>,
    mut stepper: S,
) -> Result<Finished<'s>> {
    let steps = scene.sim.steps();
    // A resumed world is measured at step 0 first: its energy guard's E₀.
    let mut world = World::from_states(scene, initial);
    let mut stats = RunStats::new(&world.ledger);
    // An output that cannot be opened when the run starts is bad input
    // naming `--out` (exit 2); the same failure mid-run stays an I/O error.
    let opening = (|| -> Result<()> {
        match resume {
            None => {
                stats.account(&world.ledger, world.contact_stats());
                let v = View {
                    world: &world,
                    stats: &stats,
                };
                for o in observers.iter_mut() {
                    o.start(&v)?;
                    if o.every().is_some() {
                        o.row(&v)?;
                    }
                }
                stats.reset_window();
            }
            Some(c) => {
                let (states, aux, restored) = checkpoint::restore(c, scene, R::Aux::LEN)?;
                let damped = checkpoint::restore_damping(c, scene)?;
                world.restore(states, aux, c.step, c.memory.clone());
                if let Some(d) = damped {
                    world.restore_damping(d);
                }
                stats = restored;
                for o in observers.iter_mut() {
                    o.resume(c)?;
                }
            }
        }
        Ok(())
    })();
    opening.map_err(crate::output::unwritable_at_start)?;
    stepper.start(&mut world);
    let first_step = world.step;

    // Per observer, the next step that writes its row; the driver's next
    // event is the nearest of those, the next checkpoint and the last step,
    // so a step without events costs one comparison.
    let cadence: Vec<Option<u64>> = observers.iter().map(|o| o.every()).collect();
    let mut next_row: Vec<u64> = cadence
        .iter()
        .map(|e| e.map_or(u64::MAX, |n| next_multiple(world.step, n)))
        .collect();
    let per_step: Vec<usize> = (0..observers.len())
        .filter(|&i| observers[i].every_step())
        .collect();
    let checkpoint_every = control.checkpoint_every.unwrap_or(u64::MAX);
    let mut next_checkpoint = next_multiple(world.step, checkpoint_every);
    let next_event = |rows: &[u64], ck: u64| rows.iter().copied().fold(ck.min(steps), u64::min);
    let mut next = next_event(&next_row, next_checkpoint);
    let interrupt = control.interrupt.as_ref();

    let start = Instant::now();
    let mut stopped: Option<Diagnosis> = None;
    let mut settled = false;
    while world.step < steps {
        if let Err(d) = stepper.step::<R>(&mut world) {
            stopped = Some(*d);
            break;
        }
        stats.account(&world.ledger, world.contact_stats());
        if !per_step.is_empty() {
            let v = View {
                world: &world,
                stats: &stats,
            };
            for &i in &per_step {
                observers[i].after_step(&v);
            }
        }
        let interrupted = interrupt.is_some_and(|i| i.flag.load(Ordering::Relaxed));
        settled = control
            .settle
            .is_some_and(|s| world.step.is_multiple_of(s.every) && s.reached(&world));
        if world.step < next && !interrupted && !settled {
            continue;
        }
        let last = world.step == steps || settled;
        let states_read = last
            || interrupted
            || world.step == next_checkpoint
            || (0..observers.len())
                .any(|i| world.step == next_row[i] && observers[i].reads_states());
        if states_read {
            stepper.sync(&mut world);
        }
        let v = View {
            world: &world,
            stats: &stats,
        };
        for o in observers.iter_mut() {
            o.event(&v);
        }
        let mut on_cadence = vec![false; observers.len()];
        for (i, o) in observers.iter_mut().enumerate() {
            if world.step == next_row[i] {
                o.row(&v)?;
                on_cadence[i] = true;
                next_row[i] += cadence[i].unwrap_or(u64::MAX);
            }
        }
        // A checkpoint sees every on-cadence row of its step, never the
        // off-cadence final row, so a longer resumed run writes the same bytes.
        let periodic = world.step == next_checkpoint;
        if periodic {
            next_checkpoint = next_checkpoint.saturating_add(checkpoint_every);
        }
        if interrupted || periodic {
            // Every observer has folded this event's window: the resumed
            // run starts a new one, as the whole run does after the event.
            let mut after_event = stats;
            after_event.reset_window();
            let mut c = Checkpoint::of::<R>(&world, &after_event);
            c.settle = control.settle.map(checkpoint::SettlePart::of);
            for o in observers.iter_mut() {
                o.checkpoint(&mut c)?;
            }
        }
        if last {
            for (i, o) in observers.iter_mut().enumerate() {
                if cadence[i].is_some() && !on_cadence[i] {
                    o.row(&v)?;
                }
            }
        }
        if interrupted && !last {
            let (checkpoint, resume) = interrupt
                .map(|i| (i.checkpoint.clone(), i.resume.clone()))
                .unwrap_or_default();
            stopped = Some(Diagnosis {
                kind: StopKind::Interrupted { checkpoint, resume },
                step: world.step,
                t: world.time(),
                body: None,
                value: 2.0,
                limit: 0.0,
            });
            break;
        }
        if settled {
            break;
        }
        next = next_event(&next_row, next_checkpoint);
        stats.reset_window();
    }
    let wall_s = start.elapsed().as_secs_f64();
    stepper.sync(&mut world);
    let end = RunEnd {
        stopped: stopped.as_ref(),
        wall_s,
        first_step,
    };
    let v = View {
        world: &world,
        stats: &stats,
    };
    for o in observers.iter_mut() {
        o.finish(&v, &end)?;
    }
    Ok(Finished {
        world,
        stats,
        stopped,
        wall_s,
        first_step,
        settled,
    })
}

/// Map a finished run to the CLI's result: a stop is an error (exit 3, or
/// 130 for an interrupt) after every output was written.
pub fn outcome(stopped: Option<Diagnosis>) -> Result<()> {
    match stopped {
        Some(d) if matches!(d.kind, StopKind::Interrupted { .. }) => Err(Error::Interrupted(d)),
        Some(d) => Err(Error::Unstable(d)),
        None => Ok(()),
    }
}
