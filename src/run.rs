//! Run a scene to its end: the step loop with its observers.

use crate::energy::Ledger;
use crate::error::{Error, Result};
use crate::integrate::rotate::Rotator;
use crate::integrate::step::World;
use crate::math::wxyz;
use crate::output::summary::finite;
use crate::output::{default_every, BodyFinal, EnergyCsv, OrientationCsv, Summary};
use crate::scenario::Scene;
use crate::with_rotator;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

/// How to run: where to write and how often.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub out_dir: PathBuf,
    /// Output cadence; `None` = the scene's, else the default (≤ ~1e5 rows).
    pub every: Option<u64>,
    /// Show a progress bar (only drawn when stderr is a terminal).
    pub progress: bool,
}

/// Outcome of a finished run. A run stopped by a guard returns
/// `Err(Error::Unstable)` after writing its outputs and summary.
pub struct RunOutcome {
    pub summary: Summary,
}

/// Run `scene` with its rotator (`scene.sim.rotator`).
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<RunOutcome> {
    run_with_bar(scene, opts, progress_bar(scene.sim.steps, opts.progress))
}

/// [`run`] drawing its progress on `bar` (e.g. one line of a study's
/// `MultiProgress`) instead of its own; `opts.progress` is ignored. The bar's
/// length is set to the step count, and it is cleared when the run ends.
pub fn run_with_bar(
    scene: &Scene,
    opts: &RunOptions,
    bar: Option<indicatif::ProgressBar>,
) -> Result<RunOutcome> {
    std::fs::create_dir_all(&opts.out_dir).map_err(|e| {
        Error::bad(
            opts.out_dir.display().to_string(),
            "--out",
            format!("cannot create the output folder: {e}"),
        )
    })?;
    if let Some(b) = &bar {
        b.set_length(scene.sim.steps);
    }
    with_rotator!(scene.sim.rotator, R => run_with::<R>(scene, opts, bar))
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

fn run_with<R: Rotator>(
    scene: &Scene,
    opts: &RunOptions,
    pb: Option<indicatif::ProgressBar>,
) -> Result<RunOutcome> {
    let sim = &scene.sim;
    let every = opts
        .every
        .or(sim.every)
        .unwrap_or_else(|| default_every(sim.steps));
    let mut world = World::new(scene);
    let ledger = |w: &World| Ledger::measure(&scene.bodies, &w.states, scene.gravity, w.elastic);

    let mut energy = EnergyCsv::create(opts.out_dir.join("energy.csv"), &ledger(&world))?;
    let mut orient = if scene.has_prescribed_torque() || scene.reference.is_some() {
        Some(OrientationCsv::create(
            opts.out_dir.join("orientation.csv"),
            scene.reference.is_some(),
        )?)
    } else {
        None
    };
    let reference_at = |w: &World| {
        scene
            .reference
            .as_ref()
            .map(|r| r.orientation(w.time(), scene.initial[0].rot.q))
    };
    let write_orientation = |o: &mut Option<OrientationCsv>, w: &World| -> Result<()> {
        if let Some(o) = o {
            for (i, s) in w.states.iter().enumerate() {
                o.write(w.step, w.time(), i, s.rot.q, reference_at(w))?;
            }
        }
        Ok(())
    };

    energy.observe(0, 0.0, &ledger(&world), true)?;
    write_orientation(&mut orient, &world)?;

    let tick = (sim.steps / 1000).max(1);
    let start = Instant::now();
    let mut stopped = None;
    while world.step < sim.steps {
        if let Err(d) = world.step::<R>() {
            stopped = Some(d);
            break;
        }
        let write = world.step % every == 0 || world.step == sim.steps;
        energy.observe(world.step, world.time(), &ledger(&world), write)?;
        if write {
            write_orientation(&mut orient, &world)?;
        }
        if let Some(pb) = &pb {
            if world.step % tick == 0 {
                pb.set_position(world.step);
            }
        }
    }
    let wall = start.elapsed().as_secs_f64();
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    energy.flush()?;
    if let Some(o) = &mut orient {
        o.flush()?;
    }

    let (ref_err, ref_x_err) = match reference_at(&world) {
        Some(r) if stopped.is_none() => {
            let q = world.states[0].rot.q;
            let ax = (q * glam::DVec3::X).x;
            let rx = (r * glam::DVec3::X).x;
            (
                Some(crate::math::geodesic_angle(q, r)),
                Some(((ax - rx) / rx).abs() * 100.0),
            )
        }
        _ => (None, None),
    };
    let steps_done = world.step;
    let body_steps = (steps_done as f64 * scene.bodies.len() as f64).max(1.0);
    let summary = Summary {
        scenario: scene.source.clone(),
        rotator: R::INFO.name.to_string(),
        dt: sim.dt,
        steps: steps_done,
        steps_planned: sim.steps,
        t_end: sim.t_end(),
        every,
        bodies: scene.bodies.len(),
        wall_s: wall,
        ns_per_body_step: wall * 1e9 / body_steps,
        energy_error_max_pct: finite(energy.max_error).filter(|_| energy.last_error.is_finite()),
        energy_error_final_pct: finite(energy.last_error),
        energy_error_full_max_pct: finite(energy.max_error_full)
            .filter(|_| energy.last_error_full.is_finite()),
        energy_error_full_final_pct: finite(energy.last_error_full),
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
) -> std::result::Result<World<'s>, crate::error::Diagnosis> {
    fn go<'s, R: Rotator>(
        scene: &'s Scene,
        observe: &mut dyn FnMut(&World<'s>),
    ) -> std::result::Result<World<'s>, crate::error::Diagnosis> {
        let mut world = World::new(scene);
        while world.step < scene.sim.steps {
            world.step::<R>()?;
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
) -> std::result::Result<Vec<crate::body::BodyState>, crate::error::Diagnosis> {
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
