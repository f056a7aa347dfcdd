//! The sweep: every case × rotator × factor (and the scene's own δt) run
//! with the default guards, each judged against its case's rk4 reference.

use super::{StressCase, StressOptions, Verdict};
use crate::body::BodyState;
use crate::energy::error_pct;
use crate::error::{Error, Result};
use crate::integrate::rotate::RotatorKind;
use crate::integrate::step::World;
use crate::scenario::{Scene, SimParams};
use crate::study::{Progress, StepBar};
use glam::DVec3;
use rayon::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

/// One run of the sweep.
#[derive(Debug, Clone)]
pub struct StressRun {
    /// Name of the case.
    pub case: String,
    /// The rotator run.
    pub rotator: RotatorKind,
    /// δt / δt_rec.
    pub factor: f64,
    /// True for the extra run at the scenario's own δt.
    pub scene_dt: bool,
    /// The step, s.
    pub dt: f64,
    /// Steps planned: `⌈t_end/δt⌉`.
    pub steps: u64,
    /// Steps completed (the stop's step for a stopped run).
    pub steps_done: u64,
    /// Largest full-budget energy error over the steps run, percent; for a
    /// stopped run the step that tripped the guard included.
    pub energy_err_pct: f64,
    /// Full-budget energy error at the stop (the last measured state),
    /// percent; NaN for a run that finished.
    pub energy_err_at_stop_pct: f64,
    /// Largest world angular momentum error, percent (contact-free scenes; else NaN).
    pub momentum_err_pct: f64,
    /// Final-state deviation from the reference, percent (NaN if not finished).
    pub outcome_err_pct: f64,
    /// How the run ended.
    pub verdict: Verdict,
    /// Wall time of the run, s (shared cores: for orientation only).
    pub wall_s: f64,
}

/// Free-flight invariants of a state: `v − g t` and `L` (world) per body.
fn invariants(scene: &Scene, states: &[BodyState], t: f64) -> Vec<(DVec3, DVec3)> {
    let g = scene.gravity.unwrap_or(DVec3::ZERO);
    scene
        .bodies
        .iter()
        .zip(states)
        .map(|(b, s)| (s.v - g * t, s.rot.q * (b.inertia.principal * s.rot.omega_b)))
        .collect()
}

/// Rim-speed scale of body `i`'s angular momentum: `r / I_max`.
fn l_to_speed(scene: &Scene, i: usize) -> f64 {
    let b = &scene.bodies[i];
    b.shape.bounding_radius() / b.inertia.principal.max_element()
}

/// Outcome error in percent: see the module docs, criterion 3.
fn outcome_error(scene: &Scene, got: &[(DVec3, DVec3)], reference: &[(DVec3, DVec3)]) -> f64 {
    let mut scale = 0.0f64;
    let mut worst = 0.0f64;
    for (i, (g, r)) in got.iter().zip(reference).enumerate() {
        let k = l_to_speed(scene, i);
        scale = scale.max(r.0.length() + r.1.length() * k);
        let d = (g.0 - r.0).length() + (g.1 - r.1).length() * k;
        worst = if d.is_nan() {
            f64::INFINITY
        } else {
            worst.max(d)
        };
    }
    100.0 * worst / scale.max(f64::MIN_POSITIVE)
}

/// `scene` with rotator `kind` and step `dt`, for `⌈t_end/δt⌉` steps.
fn sweep_scene(scene: &Scene, kind: RotatorKind, dt: f64) -> Scene {
    let mut s = scene.clone();
    let steps = (scene.sim.t_end() / dt * (1.0 - 1e-12)).ceil().max(1.0) as u64;
    s.sim = SimParams::with_steps(dt, steps, kind, None).expect("dt > 0, steps >= 1");
    s
}

struct Raw {
    steps_done: u64,
    energy: f64,
    energy_at_stop: f64,
    momentum: f64,
    end: std::result::Result<Vec<(DVec3, DVec3)>, Verdict>,
    wall_s: f64,
}

/// Run one scene, observing the energy and angular momentum at every step.
fn run_raw(s: &Scene, bar: StepBar) -> Raw {
    let contact_free = !s.needs_contacts();
    let l0: DVec3 = invariants(s, &s.initial, 0.0).iter().map(|x| x.1).sum();
    let (mut energy, mut momentum, mut done) = (0.0f64, 0.0f64, 0u64);
    let mut at_stop = f64::NAN;
    let worse = |acc: &mut f64, x: f64| {
        if x.is_nan() {
            *acc = f64::INFINITY;
        } else if x > *acc {
            *acc = x;
        }
    };
    let t0 = Instant::now();
    let momentum_err = |w: &World| {
        let l: DVec3 = invariants(s, &w.states, 0.0).iter().map(|x| x.1).sum();
        100.0 * (l - l0).length() / l0.length()
    };
    let r = catch_unwind(AssertUnwindSafe(|| {
        let crate::run::Finished {
            world: w,
            stopped: stop,
            ..
        } = crate::run::integrate_to_stop(s, |w| {
            done = w.step;
            worse(&mut energy, error_pct(w.ledger.total_full(), w.e0_full));
            if contact_free {
                worse(&mut momentum, momentum_err(w));
            }
            bar.at(w.step);
        });
        if let Some(d) = &stop {
            // The step that tripped the guard was not observed: count it.
            at_stop = error_pct(w.ledger.total_full(), w.e0_full);
            worse(&mut energy, at_stop);
            if contact_free && d.kind.after_step() {
                worse(&mut momentum, momentum_err(&w));
            }
        }
        match stop {
            None => Ok(invariants(s, &w.states, w.time())),
            Some(d) => Err(d),
        }
    }));
    bar.finish();
    let end = match r {
        Ok(Ok(inv)) => Ok(inv),
        Ok(Err(d)) => {
            done = d.step;
            Err(Verdict::Guard(d))
        }
        Err(p) => Err(Verdict::Panic(
            p.downcast_ref::<&str>()
                .map(|m| m.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(no message)".into()),
        )),
    };
    Raw {
        steps_done: done,
        energy,
        energy_at_stop: if at_stop.is_nan() && matches!(end, Err(Verdict::Guard(_))) {
            f64::INFINITY // non-finite state: the energy is undefined
        } else {
            at_stop
        },
        momentum: if contact_free { momentum } else { f64::NAN },
        end,
        wall_s: t0.elapsed().as_secs_f64(),
    }
}

struct Job<'c> {
    case: &'c StressCase,
    rotator: RotatorKind,
    factor: f64,
    scene_dt: bool,
    scene: Scene,
}

/// Run every job of the sweep, the references first (each case's outcome
/// criterion needs its own).
pub(super) fn sweep(cases: &[StressCase], opts: &StressOptions) -> Result<Vec<StressRun>> {
    let fmin = opts.factors.iter().cloned().fold(f64::INFINITY, f64::min);
    let mut jobs = vec![];
    for c in cases {
        for &k in &opts.rotators {
            for &f in &opts.factors {
                jobs.push(Job {
                    case: c,
                    rotator: k,
                    factor: f,
                    scene_dt: false,
                    scene: sweep_scene(&c.scene, k, f * c.recommended_dt),
                });
            }
            let dt = c.scene.sim.dt();
            jobs.push(Job {
                case: c,
                rotator: k,
                factor: dt / c.recommended_dt,
                scene_dt: true,
                scene: sweep_scene(&c.scene, k, dt),
            });
        }
    }
    let refs: Vec<Scene> = cases
        .iter()
        .map(|c| {
            let dt = (fmin * c.recommended_dt).min(c.scene.sim.dt()) / 2.0;
            sweep_scene(&c.scene, RotatorKind::Rk4, dt)
        })
        .collect();
    let work = |s: &Scene| s.sim.steps() * s.bodies.len() as u64;
    let total =
        jobs.iter().map(|j| work(&j.scene)).sum::<u64>() + refs.iter().map(work).sum::<u64>();
    let progress = Progress::new(opts.progress, total, "stress");

    let references: Vec<Raw> = refs
        .par_iter()
        .zip(cases)
        .map(|(s, c)| {
            let r = run_raw(
                s,
                progress.step_bar(&format!("{} rk4 ref", c.name), s.sim.steps()),
            );
            progress.done(work(s));
            r
        })
        .collect();
    let mut ref_end = vec![];
    for (r, c) in references.iter().zip(cases) {
        match &r.end {
            Ok(inv) => ref_end.push(inv.clone()),
            Err(v) => {
                return Err(Error::bad(
                    &c.scene.source,
                    "reference",
                    format!(
                        "the rk4 reference at dt = {:e} s did not finish: {:?}",
                        refs[ref_end.len()].sim.dt(),
                        v
                    ),
                ))
            }
        }
    }

    let raws: Vec<Raw> = jobs
        .par_iter()
        .map(|j| {
            let label = format!("{} {} x{}", j.case.name, j.rotator, j.factor);
            let r = run_raw(&j.scene, progress.step_bar(&label, j.scene.sim.steps()));
            progress.done(work(&j.scene));
            r
        })
        .collect();
    progress.finish();

    let runs = jobs
        .iter()
        .zip(raws)
        .map(|(j, raw)| {
            let ci = cases
                .iter()
                .position(|c| c.name == j.case.name)
                .unwrap_or(0);
            let (verdict, outcome) = match raw.end {
                Err(v) => (v, f64::NAN),
                Ok(inv) => {
                    let o = outcome_error(&j.scene, &inv, &ref_end[ci]);
                    let e = raw.energy.max(if raw.momentum.is_nan() {
                        0.0
                    } else {
                        raw.momentum
                    });
                    let v = if e.is_nan() || e > opts.energy_tol_pct {
                        Verdict::Energy
                    } else if o.is_nan() || o > opts.outcome_tol_pct {
                        Verdict::Outcome
                    } else {
                        Verdict::Stable
                    };
                    (v, o)
                }
            };
            StressRun {
                case: j.case.name.clone(),
                rotator: j.rotator,
                factor: j.factor,
                scene_dt: j.scene_dt,
                dt: j.scene.sim.dt(),
                steps: j.scene.sim.steps(),
                steps_done: raw.steps_done,
                energy_err_pct: raw.energy,
                energy_err_at_stop_pct: raw.energy_at_stop,
                momentum_err_pct: raw.momentum,
                outcome_err_pct: outcome,
                verdict,
                wall_s: raw.wall_s,
            }
        })
        .collect();
    Ok(runs)
}
