//! Run a scene to its end: the step loop with its observers, checkpoints and
//! the interrupt flag.

use crate::error::{Diagnosis, Error, Result};
use crate::integrate::rotate::Rotator;
use crate::integrate::step::World;
use crate::math::wxyz;
use crate::output::checkpoint::{self, bits, state_bits, unbits};
use crate::output::summary::finite;
use crate::output::{
    default_every, BodyFinal, Checkpoint, EnergyCsv, EnergyStats, OrientationCsv, Summary,
};
use crate::scenario::Scene;
use crate::with_rotator;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Set by the SIGINT handler (`main`); the run loop stops at the next step,
/// writes a checkpoint and flushes its outputs.
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// File name of the checkpoint inside the output folder.
pub const CHECKPOINT_FILE: &str = "checkpoint.json";

/// How to run: where to write and how often.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    pub out_dir: PathBuf,
    /// Output cadence; `None` = the scene's, else the default (≤ 2e4 rows).
    pub every: Option<u64>,
    /// Show a progress bar (only drawn when stderr is a terminal).
    pub progress: bool,
    /// Write `checkpoint.json` every this many steps.
    pub checkpoint_every: Option<u64>,
}

/// Outcome of a finished run. A run stopped by a guard returns
/// `Err(Error::Unstable)` after writing its outputs and summary.
pub struct RunOutcome {
    pub summary: Summary,
}

/// Run `scene` with its rotator (`scene.sim.rotator`).
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<RunOutcome> {
    run_from(scene, opts, None)
}

/// Continue a run from a checkpoint (`scene` rebuilt with [`scene_from_checkpoint`]).
pub fn run_from(
    scene: &Scene,
    opts: &RunOptions,
    resume: Option<&Checkpoint>,
) -> Result<RunOutcome> {
    run_inner(
        scene,
        opts,
        resume,
        progress_bar(scene.sim.steps, opts.progress),
    )
}

/// [`run`] drawing its progress on `bar` (e.g. one line of a study's
/// `MultiProgress`) instead of its own; `opts.progress` is ignored. The bar's
/// length is set to the step count, and it is cleared when the run ends.
pub fn run_with_bar(
    scene: &Scene,
    opts: &RunOptions,
    bar: Option<indicatif::ProgressBar>,
) -> Result<RunOutcome> {
    run_inner(scene, opts, None, bar)
}

fn run_inner(
    scene: &Scene,
    opts: &RunOptions,
    resume: Option<&Checkpoint>,
    bar: Option<indicatif::ProgressBar>,
) -> Result<RunOutcome> {
    crate::output::create_out_dir(&opts.out_dir)?;
    if let Some(b) = &bar {
        b.set_length(scene.sim.steps);
    }
    with_rotator!(scene.sim.rotator, R => run_with::<R>(scene, opts, resume, bar))
}

/// Rebuild the scene a checkpoint was taken from, with its δt, rotator, cadence
/// and guards; `t_end` overrides the original end time.
pub fn scene_from_checkpoint(c: &Checkpoint, t_end: Option<f64>) -> Result<Scene> {
    let mut scene = crate::scenario::parse_str(&c.scenario_text, &c.scenario_source)?;
    let rotator =
        crate::integrate::rotate::RotatorKind::from_name(&c.rotator).ok_or_else(|| {
            Error::bad(
                "checkpoint",
                "rotator",
                format!("unknown rotator `{}`", c.rotator),
            )
        })?;
    let dt = unbits(&c.dt, "dt")?;
    let t_end = t_end.unwrap_or(scene.sim.t_end());
    scene.sim =
        crate::scenario::SimParams::new(dt, t_end, rotator, Some(c.every), "command line", "--")?;
    if scene.sim.steps < c.step {
        return Err(Error::bad(
            "command line",
            "--t-end",
            format!(
                "the checkpoint is at step {} (t = {}), past t_end = {t_end}",
                c.step, c.t
            ),
        ));
    }
    scene.guards.energy_error_pct = unbits(&c.guards[0], "guards")?;
    scene.guards.overlap_ratio = unbits(&c.guards[1], "guards")?;
    Ok(scene)
}

/// Resuming into another folder than the checkpoint's (`--resume C --out NEW`):
/// copy the checkpoint folder's outputs, cut to the lengths the checkpoint
/// recorded, into `to`, where the resumed run then appends. Nothing happens
/// when `to` is the checkpoint's folder.
pub fn copy_resume_outputs(
    c: &Checkpoint,
    from: &std::path::Path,
    to: &std::path::Path,
) -> Result<()> {
    use std::io::Read;
    // Copying a folder onto itself would truncate the files it reads.
    let same = from == to
        || match (from.canonicalize(), to.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
    if same {
        return Ok(());
    }
    crate::output::create_out_dir(to)?;
    let files = [
        ("energy.csv", Some(c.energy_csv_len)),
        ("orientation.csv", c.orientation_csv_len),
    ];
    for (name, len) in files {
        let Some(len) = len else { continue };
        let src = from.join(name);
        let missing = |e: String| {
            Error::bad(
                src.display().to_string(),
                "--resume",
                format!(
                    "{e}; the checkpoint's folder must still hold the outputs it was written with"
                ),
            )
        };
        let f = std::fs::File::open(&src).map_err(|e| missing(format!("cannot read: {e}")))?;
        let have = f.metadata().map_err(|e| missing(e.to_string()))?.len();
        if have < len {
            return Err(missing(format!(
                "is {have} bytes, shorter than the {len} the checkpoint recorded"
            )));
        }
        let dst = to.join(name);
        let mut w = std::fs::File::create(&dst)
            .map_err(|e| crate::output::unwritable_at_start(Error::io(&dst, e)))?;
        std::io::copy(&mut f.take(len), &mut w).map_err(|e| Error::io(&dst, e))?;
    }
    Ok(())
}

fn progress_bar(steps: u64, enabled: bool) -> Option<indicatif::ProgressBar> {
    if !enabled || !std::io::stderr().is_terminal() {
        return None;
    }
    let pb = indicatif::ProgressBar::new(steps);
    pb.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {percent:>3}% step {pos}/{len} eta {eta}",
        )
        .expect("static template"),
    );
    Some(pb)
}

/// The observers of one run: energy and orientation files.
struct Outputs {
    energy: EnergyCsv,
    orient: Option<OrientationCsv>,
}

impl Outputs {
    fn write_orientation(&mut self, scene: &Scene, w: &World) -> Result<()> {
        if let Some(o) = &mut self.orient {
            let reference = scene
                .reference
                .as_ref()
                .map(|r| r.orientation(w.time(), scene.initial[0].rot.q));
            for (i, s) in w.states.iter().enumerate() {
                o.write(w.step, w.time(), i, s.rot.q, reference)?;
            }
        }
        Ok(())
    }

    fn write_row(&mut self, scene: &Scene, w: &World) -> Result<()> {
        self.energy
            .write_row(w.step, w.time(), &w.ledger, w.contact_stats())?;
        self.write_orientation(scene, w)
    }

    fn checkpoint(
        &mut self,
        scene: &Scene,
        w: &World,
        every: u64,
        path: &std::path::Path,
    ) -> Result<()> {
        Checkpoint {
            format: checkpoint::FORMAT.into(),
            scenario_source: scene.source.clone(),
            scenario_text: scene.text.clone(),
            rotator: scene.sim.rotator.name().into(),
            dt: bits(scene.sim.dt),
            every,
            guards: [
                bits(scene.guards.energy_error_pct),
                bits(scene.guards.overlap_ratio),
            ],
            step: w.step,
            t: w.time(),
            states: w.states.iter().map(state_bits).collect(),
            energy_stats: self.energy.stats.to_array().map(bits).to_vec(),
            energy_csv_len: self.energy.flushed_len()?,
            orientation_csv_len: match &mut self.orient {
                Some(o) => Some(o.flushed_len()?),
                None => None,
            },
        }
        .write(path)
    }
}

fn open_outputs(
    scene: &Scene,
    opts: &RunOptions,
    world: &mut World,
    resume: Option<&Checkpoint>,
) -> Result<Outputs> {
    let with_orientation = scene.has_prescribed_torque() || scene.reference.is_some();
    let energy_path = opts.out_dir.join("energy.csv");
    let orient_path = opts.out_dir.join("orientation.csv");
    match resume {
        None => {
            let mut out = Outputs {
                energy: EnergyCsv::create(energy_path, &world.ledger, world.contacts.is_some())?,
                orient: if with_orientation {
                    Some(OrientationCsv::create(
                        orient_path,
                        scene.reference.is_some(),
                    )?)
                } else {
                    None
                },
            };
            out.energy.account(&world.ledger, world.contact_stats());
            out.write_row(scene, world)?;
            Ok(out)
        }
        Some(c) => {
            if c.states.len() != scene.bodies.len() || c.energy_stats.len() != 10 {
                return Err(Error::bad(
                    "checkpoint",
                    "states",
                    "does not match its own scenario",
                ));
            }
            let states = c
                .states
                .iter()
                .map(|s| checkpoint::state_from_bits(s))
                .collect::<Result<Vec<_>>>()?;
            world.restore(states, c.step);
            let mut a = [0.0; 10];
            for (x, s) in a.iter_mut().zip(&c.energy_stats) {
                *x = unbits(s, "energy_stats")?;
            }
            let orient = match (with_orientation, c.orientation_csv_len) {
                (true, Some(len)) => Some(OrientationCsv::resume(
                    orient_path,
                    len,
                    scene.reference.is_some(),
                )?),
                (false, None) => None,
                _ => {
                    return Err(Error::bad(
                        "checkpoint",
                        "orientation_csv_len",
                        "does not match its scenario",
                    ))
                }
            };
            Ok(Outputs {
                energy: EnergyCsv::resume(
                    energy_path,
                    c.energy_csv_len,
                    EnergyStats::from_array(a),
                    world.contacts.is_some(),
                )?,
                orient,
            })
        }
    }
}

fn run_with<R: Rotator>(
    scene: &Scene,
    opts: &RunOptions,
    resume: Option<&Checkpoint>,
    pb: Option<indicatif::ProgressBar>,
) -> Result<RunOutcome> {
    let sim = &scene.sim;
    let every = opts
        .every
        .or(sim.every)
        .unwrap_or_else(|| default_every(sim.steps));
    let mut world = World::new(scene);
    let mut out = open_outputs(scene, opts, &mut world, resume)
        .map_err(crate::output::unwritable_at_start)?;
    let checkpoint_path = opts.out_dir.join(CHECKPOINT_FILE);
    let first_step = world.step;

    // The next step that writes a row, a checkpoint or a progress tick:
    // comparisons per step instead of three integer divisions.
    let next_multiple = |n: u64| (world.step / n + 1) * n;
    let tick = (sim.steps / 1000).max(1);
    let mut next_row = next_multiple(every);
    let checkpoint_every = opts.checkpoint_every.unwrap_or(u64::MAX); // MAX: never
    let mut next_checkpoint = next_multiple(checkpoint_every);
    let mut next_tick = next_multiple(tick);
    let start = Instant::now();
    let mut stopped: Option<Diagnosis> = None;
    while world.step < sim.steps {
        if let Err(d) = world.step::<R>() {
            stopped = Some(*d);
            break;
        }
        let cadence = world.step == next_row;
        let last = world.step == sim.steps;
        out.energy.account(&world.ledger, world.contact_stats());
        if cadence {
            out.write_row(scene, &world)?;
            next_row += every;
        }
        // A checkpoint sees every on-cadence row of its step, never the
        // off-cadence final row, so a longer resumed run writes the same bytes.
        let interrupted = INTERRUPTED.load(Ordering::Relaxed);
        let periodic = world.step == next_checkpoint;
        if periodic {
            next_checkpoint += checkpoint_every;
        }
        if interrupted || periodic {
            out.checkpoint(scene, &world, every, &checkpoint_path)?;
        }
        if last && !cadence {
            out.write_row(scene, &world)?;
        }
        if interrupted && !last {
            stopped = Some(Diagnosis {
                kind: format!(
                    "interrupted (SIGINT); resume with `fibresim run --resume {}`",
                    checkpoint_path.display()
                ),
                step: world.step,
                t: world.time(),
                body: None,
                quantity: "signal".into(),
                value: 2.0,
                limit: 0.0,
            });
            break;
        }
        if world.step == next_tick {
            next_tick += tick;
            if let Some(pb) = &pb {
                pb.set_position(world.step);
            }
        }
    }
    let wall = start.elapsed().as_secs_f64();
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    out.energy.flush()?;
    if let Some(o) = &mut out.orient {
        o.flush()?;
    }

    let stats = out.energy.stats;
    let (ref_err, ref_x_err) = match scene.reference.as_ref() {
        Some(r) if stopped.is_none() => {
            let q_ref = r.orientation(world.time(), scene.initial[0].rot.q);
            let q = world.states[0].rot.q;
            let ax = (q * glam::DVec3::X).x;
            let rx = (q_ref * glam::DVec3::X).x;
            (
                Some(crate::math::geodesic_angle(q, q_ref)),
                Some(((ax - rx) / rx).abs() * 100.0),
            )
        }
        _ => (None, None),
    };
    let body_steps = ((world.step - first_step) as f64 * scene.bodies.len() as f64).max(1.0);
    let summary = Summary {
        scenario: scene.source.clone(),
        rotator: R::INFO.name.to_string(),
        dt: sim.dt,
        steps: world.step,
        steps_planned: sim.steps,
        t_end: sim.t_end(),
        every,
        bodies: scene.bodies.len(),
        wall_s: wall,
        ns_per_body_step: wall * 1e9 / body_steps,
        energy_error_max_pct: finite(stats.max_error).filter(|_| stats.last_error.is_finite()),
        energy_error_final_pct: finite(stats.last_error),
        energy_error_full_max_pct: finite(stats.max_error_full)
            .filter(|_| stats.last_error_full.is_finite()),
        energy_error_full_final_pct: finite(stats.last_error_full),
        max_overlap_ratio: world.contacts.is_some().then_some(stats.max_overlap_ratio),
        reference_error_final_rad: ref_err,
        reference_x_error_pct: ref_x_err,
        stopped: stopped.clone(),
        final_state: world
            .states
            .iter()
            .enumerate()
            .map(|(i, s)| BodyFinal {
                body: i,
                q: wxyz(s.rot.q),
                x: s.x.to_array(),
                v: s.v.to_array(),
                omega_body: s.rot.omega_b.to_array(),
            })
            .collect(),
    };
    summary.write(&opts.out_dir.join("summary.json"))?;
    match stopped {
        Some(d) if d.quantity == "signal" => Err(Error::Interrupted(d)),
        Some(d) => Err(Error::Unstable(d)),
        None => Ok(RunOutcome { summary }),
    }
}

/// Integrate `scene` with its rotator, without writing anything, calling
/// `observe` after every step. Returns the final world, or the diagnosis of
/// the step that failed. Used by the studies and the tests.
pub fn integrate_observed<'s>(
    scene: &'s Scene,
    mut observe: impl FnMut(&World<'s>),
) -> std::result::Result<World<'s>, Diagnosis> {
    fn go<'s, R: Rotator>(
        scene: &'s Scene,
        observe: &mut dyn FnMut(&World<'s>),
    ) -> std::result::Result<World<'s>, Diagnosis> {
        let mut world = World::new(scene);
        while world.step < scene.sim.steps {
            world.step::<R>().map_err(|d| *d)?;
            observe(&world);
        }
        Ok(world)
    }
    with_rotator!(scene.sim.rotator, R => go::<R>(scene, &mut observe))
}

/// Integrate `scene` to its end with rotator `kind`, time step `dt`, and return
/// the final states.
pub fn integrate(
    scene: &Scene,
    kind: crate::integrate::rotate::RotatorKind,
    dt: f64,
) -> std::result::Result<Vec<crate::body::BodyState>, Diagnosis> {
    let mut s = scene.clone();
    let steps = (scene.sim.t_end() / dt).round() as u64;
    s.sim = crate::scenario::SimParams {
        dt,
        steps,
        rotator: kind,
        every: None,
    };
    integrate_observed(&s, |_| {}).map(|w| w.states)
}
