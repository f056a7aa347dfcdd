//! Run a scene to its end: the observers of `fibresim run` wired to the one
//! driver loop ([`driver`]), and the in-memory runs of the studies and tests.

pub mod driver;
pub mod observer;
pub mod resume;
pub mod stats;

pub use driver::{drive, Control, Finished, Interrupt, Settle};
pub use observer::{EachStep, Observer, RunEnd, View};
pub use resume::{check_outputs, resume_command, scene_from_checkpoint};

use crate::body::BodyState;
use crate::error::{Diagnosis, Result};
use crate::integrate::rotate::RotatorKind;
use crate::integrate::step::World;
use crate::output::checkpoint::CHECKPOINT_FILE;
use crate::output::{Checkpoint, CheckpointFile, Progress, Summary, SummaryJson};
use crate::scenario::{Scene, SimParams};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// Set by the SIGINT handler (`main`); the run loop stops at the next step,
/// writes a checkpoint and flushes its outputs.
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// How to run: where to write, what to show, how often to checkpoint.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output folder.
    pub out_dir: PathBuf,
    /// Show the progress: a bar on a terminal, else a line every few
    /// seconds ([`Progress::of_run`]).
    pub progress: bool,
    /// A progress line every this many seconds, terminal or not (`--progress`).
    pub progress_lines: Option<f64>,
    /// Write `checkpoint.json` every this many steps.
    pub checkpoint_every: Option<u64>,
    /// End the run once it has settled (`fibresim settle`).
    pub settle: Option<Settle>,
    /// Write the final states of every body as a body file here, once the
    /// run has ended without a stop.
    pub write_bodies: Option<PathBuf>,
    /// A resumed run: the folder of its checkpoint, whose outputs it
    /// continues (copied first when `out_dir` is another folder).
    pub resumed_from: Option<PathBuf>,
    /// The command that continues this run after an interrupt [default:
    /// `fibresim run --resume <out_dir>/checkpoint.json`].
    pub resume_command: Option<String>,
}

/// Run `scene` with its rotator (`scene.sim.rotator()`), writing
/// `energy.csv`, `orientation.csv` (scenes with a prescribed torque or a
/// closed form), `summary.json`, and what `scene.output` asks for
/// (`trajectory.csv`, the VTK series) into `opts.out_dir`. A run stopped by a
/// guard returns `Err(Error::Unstable)` after writing its outputs.
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<Summary> {
    run_from(scene, scene.initial.clone(), opts, None)
}

/// [`run`] from the step-0 states `initial`, moved into the world
/// (`fibresim run` takes them out of its scene: a bed keeps one copy), or
/// continued from a checkpoint (`scene` rebuilt with
/// [`scene_from_checkpoint`]; `initial` is still its step 0).
pub fn run_from(
    scene: &Scene,
    initial: Vec<BodyState>,
    opts: &RunOptions,
    resume: Option<&Checkpoint>,
) -> Result<Summary> {
    let progress = Progress::of_run(scene.sim.steps(), opts.progress, opts.progress_lines);
    run_observed(scene, initial, opts, resume, progress)
}

/// [`run`] drawing its progress on `bar` (e.g. one line of a study's
/// `MultiProgress`) instead of its own; `opts.progress` is ignored.
pub fn run_with_bar(
    scene: &Scene,
    opts: &RunOptions,
    bar: Option<indicatif::ProgressBar>,
) -> Result<Summary> {
    let bar = bar.map(|b| Progress::on(b, scene.sim.steps()));
    run_observed(scene, scene.initial.clone(), opts, None, bar)
}

fn run_observed(
    scene: &Scene,
    initial: Vec<BodyState>,
    opts: &RunOptions,
    resume: Option<&Checkpoint>,
    progress: Option<Progress>,
) -> Result<Summary> {
    run_by(
        scene,
        initial,
        opts,
        resume,
        progress,
        driver::OneProcess,
        true,
    )
    .map(|s| s.expect("the writing process has a summary"))
}

/// [`run_observed`] with the steps taken by `stepper`; only the `writer`
/// writes outputs (an MPI rank other than 0 drives the same cadences with
/// silent observers, and gets no summary).
pub(crate) fn run_by<'s, S: driver::Stepper<'s>>(
    scene: &'s Scene,
    initial: Vec<BodyState>,
    opts: &RunOptions,
    resume: Option<&Checkpoint>,
    progress: Option<Progress>,
    stepper: S,
    writer: bool,
) -> Result<Option<Summary>> {
    let dir = &opts.out_dir;
    if writer {
        // No earlier run's output stays to be picked up (the command line
        // has already refused a given folder that holds any, unless forced).
        match resume {
            None => crate::output::folder::clear(dir)?,
            Some(c) => resume::continue_in(c, opts.resumed_from.as_deref().unwrap_or(dir), dir)?,
        }
    }
    let every = scene.sim.every_or_default();
    let opening = crate::output::Opening {
        dir,
        scene,
        every,
        whole_contact_stage: stepper.whole_contact_stage(),
    };
    let mut outputs: Vec<Box<dyn Observer>> = crate::output::OUTPUTS
        .iter()
        .filter_map(|open| open(&opening))
        .collect();
    let mut progress = progress;
    let mut summary = SummaryJson::new(dir, every).with_settle(opts.settle);
    let checkpoint_path = dir.join(CHECKPOINT_FILE);
    let mut checkpoint = CheckpointFile {
        path: checkpoint_path.clone(),
        states_file: None,
    };
    let mut observers: Vec<&mut dyn Observer> = outputs
        .iter_mut()
        .map(|o| &mut **o as &mut dyn Observer)
        .collect();
    if let Some(p) = &mut progress {
        observers.push(p);
    }
    observers.push(&mut summary);
    observers.push(&mut checkpoint); // last: it writes what the others added
    let mut silent: Vec<observer::Silent> = observers
        .iter()
        .map(|o| observer::Silent::of(&**o))
        .collect();
    let mut silent: Vec<&mut dyn Observer> =
        silent.iter_mut().map(|o| o as &mut dyn Observer).collect();
    let observers = if writer { &mut observers } else { &mut silent };
    let resume_command = opts
        .resume_command
        .clone()
        .unwrap_or_else(|| resume_command("run", &checkpoint_path, &[]));
    let control = Control {
        checkpoint_every: opts.checkpoint_every,
        interrupt: Some(Interrupt {
            flag: &INTERRUPTED,
            checkpoint: checkpoint_path,
            resume: resume_command,
        }),
        settle: opts.settle,
    };
    let finished = driver::drive_by(scene, initial, observers, &control, resume, stepper)?;
    if !writer {
        driver::outcome(finished.stopped)?;
        return Ok(None);
    }
    // A stopped run (a guard, an interrupt) writes no bodies: its states
    // are not an end.
    driver::outcome(finished.stopped)?;
    if let Some(path) = &opts.write_bodies {
        let names: Vec<String> = scene.materials.iter().map(|m| m.name.clone()).collect();
        let w = &finished.world;
        crate::scenario::body_file::write(path, &scene.ids, &scene.bodies, &w.states, &names)?;
    }
    Ok(Some(summary.summary.expect(
        "the summary observer has run at the end of the drive",
    )))
}

/// Integrate `scene` with its rotator, without writing anything, calling
/// `observe` after every step. Returns the final world, or the diagnosis of
/// the step that failed. Used by the studies and the tests.
pub fn integrate_observed<'s>(
    scene: &'s Scene,
    observe: impl FnMut(&World),
) -> std::result::Result<World<'s>, Diagnosis> {
    let f = integrate_to_stop(scene, observe);
    match f.stopped {
        None => Ok(f.world),
        Some(d) => Err(d),
    }
}

/// [`integrate_observed`], returning the world also when a guard stopped
/// the run (its ledger is that of the last measured state).
pub fn integrate_to_stop<'s>(scene: &'s Scene, observe: impl FnMut(&World)) -> Finished<'s> {
    let mut probe = EachStep(observe);
    drive(scene, &mut [&mut probe], &Control::default(), None)
        .expect("an in-memory observer writes nothing that can fail")
}

/// Integrate `scene` to its end with rotator `kind`, time step `dt`, and return
/// the final states.
pub fn integrate(
    scene: &Scene,
    kind: RotatorKind,
    dt: f64,
) -> std::result::Result<Vec<BodyState>, Diagnosis> {
    let mut s = scene.clone();
    let steps = (scene.sim.t_end() / dt).round() as u64;
    s.sim = SimParams::with_steps(dt, steps.max(1), kind, None)
        .expect("a positive dt and at least one step");
    integrate_observed(&s, |_| {}).map(|w| w.states)
}
