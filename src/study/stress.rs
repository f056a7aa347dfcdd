//! `fibresim stress` (issue 5, SPEC §8): every stress case × rotator over a
//! sweep of `δt = factor × δt_rec`, on past the hard limit, with the default
//! guards. The library is called directly, so δt beyond `hard_limit_dt` runs.
//!
//! **Recommended δt.** Contact scenes: `advise(&scene).recommended_dt` (the
//! shortest Hertz collision / 50 and 0.2 × the Rayleigh time). Contact-free
//! scenes: `0.05 / ‖ω‖max`, a rotation of 0.05 rad per step, with `‖ω‖max`
//! the largest initial `‖ω‖` (constant in torque-free motion of a fibre, a
//! symmetric top).
//!
//! **Stable** means all of:
//! 1. the run reached `t_end` without a guard stop (a [`Diagnosis`]) or a panic;
//! 2. *energy*: the largest full-budget energy error over all steps (Eq. 65
//!    with the elastic energy of live contacts; nothing dissipates) is at most
//!    `energy_tol_pct`; in contact-free scenes also the error of the world
//!    angular momentum `L = Σ q I ω_b q*`, `‖L − L₀‖/‖L₀‖`, which torque-free
//!    motion conserves exactly — this is where a rotator's orientation error
//!    shows;
//! 3. *outcome*: the free-flight invariants at the end agree with the case's
//!    reference run (rk4 at half the smallest δt of the sweep): per body the
//!    velocity less the gravity drift, `v − g t`, and the angular momentum
//!    `L` (so runs that end at slightly different times still compare), as a
//!    rim speed: `‖Δv‖ + ‖ΔL‖ r / I_max`, over the largest such speed of the
//!    reference, at most `outcome_tol_pct`. It catches garbage that conserves
//!    energy (a wrong bounce, fibres passing through each other).
//!
//! The step count is `⌈t_end/δt⌉`, so every run covers the case's event and
//! δt is exactly the stated multiple.
//!
//! **Errors of stopped runs.** A guard checks the state after a step; the
//! energy error of that step is counted (it is the guard's value for an
//! energy stop), so a stopped run's largest error is not understated. The
//! scalar-pole guard fires before its step: every computed step is counted.

use super::{cell, fmt_e, write_csv, Progress};
use crate::advice::advise;
use crate::body::BodyState;
use crate::energy::error_pct;
use crate::error::{Diagnosis, Error, Result};
use crate::integrate::rotate::RotatorKind;
use crate::integrate::step::World;
use crate::plot::{render_map, CellMap, MapPanel};
use crate::scenario::{Scene, SimParams};
use crate::stop::StopKind;
use glam::DVec3;
use rayon::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Default δt factors (multiples of the recommended δt).
pub const DEFAULT_FACTORS: [f64; 10] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0];
/// Default energy (and angular momentum) tolerance, percent.
pub const ENERGY_TOL_PCT: f64 = 1.0;
/// Default outcome tolerance, percent of the reference's largest rim speed.
pub const OUTCOME_TOL_PCT: f64 = 5.0;
/// Rotation per step at the recommended δt of a contact-free scene, rad.
pub const SPIN_ANGLE_PER_STEP: f64 = 0.05;

/// One stress scene with its recommended δt.
#[derive(Debug, Clone)]
pub struct StressCase {
    pub name: String,
    pub scene: Scene,
    pub recommended_dt: f64,
    /// Where `recommended_dt` comes from.
    pub basis: &'static str,
    /// δt above which `fibresim run` refuses without `--allow-large-dt`.
    pub hard_limit_dt: Option<f64>,
}

impl StressCase {
    pub fn new(name: impl Into<String>, scene: Scene) -> Result<Self> {
        let name = name.into();
        let a = advise(&scene);
        let (recommended_dt, basis) = match a.recommended_dt {
            Some(r) => (r, "Hertz/50, 0.2 Rayleigh"),
            None => {
                let w = scene
                    .initial
                    .iter()
                    .map(|s| s.rot.omega_b.length())
                    .fold(0.0, f64::max);
                if w.is_nan() || w <= 0.0 || scene.has_prescribed_torque() {
                    return Err(Error::bad(
                        &scene.source,
                        "body",
                        "a stress case needs contacts or an initial spin (and no prescribed torque)",
                    ));
                }
                (SPIN_ANGLE_PER_STEP / w, "0.05 rad / |omega|")
            }
        };
        Ok(StressCase {
            name,
            scene,
            recommended_dt,
            basis,
            hard_limit_dt: a.hard_limit_dt,
        })
    }
}

#[derive(Debug, Clone)]
pub struct StressOptions {
    pub rotators: Vec<RotatorKind>,
    pub factors: Vec<f64>,
    pub energy_tol_pct: f64,
    pub outcome_tol_pct: f64,
    pub out_dir: PathBuf,
    pub progress: bool,
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    Stable,
    /// Stopped by a guard.
    Guard(Diagnosis),
    /// Finished, but the energy (or angular momentum) error is above tolerance.
    Energy,
    /// Finished, but the final invariants are off the reference.
    Outcome,
    /// The step panicked (a bug: never acceptable).
    Panic(String),
}

impl Verdict {
    pub fn is_stable(&self) -> bool {
        *self == Verdict::Stable
    }

    /// How the run ended, in a few words (tables).
    pub fn short(&self, o: &StressOptions) -> String {
        match self {
            Verdict::Stable => "stable".into(),
            Verdict::Energy => format!("finished, energy/L error > {} %", o.energy_tol_pct),
            Verdict::Outcome => format!("finished, final state off rk4 > {} %", o.outcome_tol_pct),
            Verdict::Guard(d) => {
                format!("stopped by guard `{}` at step {}", d.kind.short(), d.step)
            }
            Verdict::Panic(_) => "panic".into(),
        }
    }

    /// Map class (index into [`CLASSES`]) and the short cell text.
    fn class(&self) -> (usize, &'static str) {
        match self {
            Verdict::Stable => (0, ""),
            Verdict::Energy => (1, "E"),
            Verdict::Outcome => (2, "out"),
            Verdict::Guard(d) => match d.kind {
                StopKind::Overlap => (3, "ovl"),
                StopKind::EnergyBlowUp => (4, "E>10%"),
                StopKind::ScalarSingularity => (5, "tan"),
                StopKind::NonFiniteState | StopKind::NonFiniteEnergy => (6, "NaN"),
                StopKind::QuatNormDrift
                | StopKind::DegenerateOrientation
                | StopKind::Interrupted { .. } => (6, "|q|"),
            },
            Verdict::Panic(_) => (7, "PANIC"),
        }
    }

    /// How the instability was detected, for the tables.
    pub fn detection(&self, r: &StressRun, o: &StressOptions) -> String {
        match self {
            Verdict::Stable => String::new(),
            Verdict::Energy => format!(
                "accuracy threshold: {} error {:.3} % > {} %",
                if r.momentum_err_pct > r.energy_err_pct {
                    "angular momentum"
                } else {
                    "energy"
                },
                r.energy_err_pct.max(r.momentum_err_pct),
                o.energy_tol_pct
            ),
            Verdict::Outcome => format!(
                "accuracy threshold: final state off the reference by {:.3} % > {} %",
                r.outcome_err_pct, o.outcome_tol_pct
            ),
            Verdict::Guard(d) => format!(
                "guard `{}`: {} = {:.3e} > {:.3e} at t = {:.3e} s",
                d.kind.short(),
                d.quantity(),
                d.value,
                d.limit,
                d.t
            ),
            Verdict::Panic(m) => format!("PANIC: {m}"),
        }
    }
}

/// The map classes: label and colour (Okabe–Ito where it fits).
pub const CLASSES: [(&str, [u8; 3]); 8] = [
    ("stable", [0x00, 0x9E, 0x73]),
    ("finished, energy/L error > tol (E)", [0xE6, 0x9F, 0x00]),
    ("finished, final state wrong (out)", [0xF0, 0xE4, 0x42]),
    ("guard: overlap > 0.2 D (ovl)", [0xD5, 0x5E, 0x00]),
    ("guard: energy error > 10 % (E>10%)", [0xCC, 0x79, 0xA7]),
    ("guard: scalar tan pole (tan)", [0x56, 0xB4, 0xE9]),
    ("guard: non-finite / |q| drift", [0x00, 0x72, 0xB2]),
    ("panic", [0x00, 0x00, 0x00]),
];

/// Few-word name of map class `c`, for the summarised detections.
fn class_words(c: usize, o: &StressOptions) -> String {
    match c {
        0 => "stable".into(),
        1 => format!("energy/L error > {} %", o.energy_tol_pct),
        2 => format!("final state off rk4 > {} %", o.outcome_tol_pct),
        3 => "overlap guard".into(),
        4 => "energy guard".into(),
        5 => "scalar tan-pole guard".into(),
        6 => "non-finite / |q| guard".into(),
        _ => "PANIC".into(),
    }
}

/// One run of the sweep.
#[derive(Debug, Clone)]
pub struct StressRun {
    pub case: String,
    pub rotator: RotatorKind,
    /// δt / δt_rec.
    pub factor: f64,
    /// True for the extra run at the scenario's own δt.
    pub scene_dt: bool,
    pub dt: f64,
    pub steps: u64,
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
    pub verdict: Verdict,
    pub wall_s: f64,
}

/// One line of the summary table: a case and a rotator.
#[derive(Debug, Clone)]
pub struct StressSummary {
    pub case: String,
    pub rotator: RotatorKind,
    pub recommended_dt: f64,
    pub hard_limit_factor: f64,
    /// Largest factor with every factor up to it stable (NaN: none).
    pub largest_stable_factor: f64,
    /// Stable factors above the first unstable one (non-monotone stability).
    pub stable_above_failure: Vec<f64>,
    pub err_at_recommended_pct: f64,
    /// How the run at the recommended δt ended ([`Verdict::short`]).
    pub at_recommended: String,
    /// The unstable runs, summarised: consecutive factors with the same
    /// detection grouped, e.g. `x0.25-0.5: energy/L error > tol`.
    pub detected_by: String,
    pub err_at_scene_dt_pct: f64,
    pub scene_dt: f64,
    /// `x<factor>: <detection>` for every unstable run.
    pub detections: Vec<String>,
}

pub struct StressReport {
    pub cases: Vec<StressCase>,
    pub runs: Vec<StressRun>,
    pub summary: Vec<StressSummary>,
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
fn run_raw(s: &Scene, bar: Option<indicatif::ProgressBar>) -> Raw {
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
    let tick = super::tick(s.sim.steps());
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
            if let Some(b) = &bar {
                if w.step % tick == 0 {
                    b.set_position(w.step);
                }
            }
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
    if let Some(b) = bar {
        b.finish_and_clear();
    }
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

/// Run the sweep and write `stress.csv`, `stress_runs.csv` and the map.
pub fn stress(cases: Vec<StressCase>, opts: &StressOptions) -> Result<StressReport> {
    if cases.is_empty() {
        return Err(Error::bad(
            "command line",
            "--cases",
            "no stress case matched",
        ));
    }
    if opts.factors.is_empty() || opts.factors.iter().any(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(Error::bad(
            "command line",
            "--factors",
            "give finite factors > 0, e.g. 0.25,1,4,16",
        ));
    }
    std::fs::create_dir_all(&opts.out_dir).map_err(|e| {
        Error::bad(
            opts.out_dir.display().to_string(),
            "--out",
            format!("cannot create the output folder: {e}"),
        )
    })?;
    let fmin = opts.factors.iter().cloned().fold(f64::INFINITY, f64::min);
    let mut jobs = vec![];
    for c in &cases {
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

    // References first (each case's outcome criterion needs its own).
    let references: Vec<Raw> = refs
        .par_iter()
        .zip(&cases)
        .map(|(s, c)| {
            let r = run_raw(
                s,
                progress.run_bar(&format!("{} rk4 ref", c.name), s.sim.steps()),
            );
            progress.done(work(s));
            r
        })
        .collect();
    let mut ref_end = vec![];
    for (r, c) in references.iter().zip(&cases) {
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
            let r = run_raw(&j.scene, progress.run_bar(&label, j.scene.sim.steps()));
            progress.done(work(&j.scene));
            r
        })
        .collect();
    progress.finish();

    let runs: Vec<StressRun> = jobs
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
    let summary = summarise(&cases, &runs, opts);
    let report = StressReport {
        cases,
        runs,
        summary,
    };
    write_outputs(&report, opts)?;
    Ok(report)
}

fn summarise(cases: &[StressCase], runs: &[StressRun], opts: &StressOptions) -> Vec<StressSummary> {
    let mut out = vec![];
    for c in cases {
        for &k in &opts.rotators {
            let mut sweep: Vec<&StressRun> = runs
                .iter()
                .filter(|r| r.case == c.name && r.rotator == k && !r.scene_dt)
                .collect();
            sweep.sort_by(|a, b| a.factor.total_cmp(&b.factor));
            let first_bad = sweep.iter().position(|r| !r.verdict.is_stable());
            let largest = match first_bad {
                Some(0) => f64::NAN,
                Some(i) => sweep[i - 1].factor,
                None => sweep.last().map_or(f64::NAN, |r| r.factor),
            };
            let stable_above = first_bad.map_or(vec![], |i| {
                sweep[i..]
                    .iter()
                    .filter(|r| r.verdict.is_stable())
                    .map(|r| r.factor)
                    .collect()
            });
            let scene_run = runs
                .iter()
                .find(|r| r.case == c.name && r.rotator == k && r.scene_dt);
            let err = |r: &StressRun| r.energy_err_pct.max(r.momentum_err_pct);
            let at_rec = sweep.iter().find(|r| r.factor == 1.0);
            out.push(StressSummary {
                case: c.name.clone(),
                rotator: k,
                recommended_dt: c.recommended_dt,
                hard_limit_factor: c.hard_limit_dt.map_or(f64::NAN, |h| h / c.recommended_dt),
                largest_stable_factor: largest,
                stable_above_failure: stable_above,
                err_at_recommended_pct: at_rec.map_or(f64::NAN, |r| err(r)),
                at_recommended: at_rec.map_or("not run".into(), |r| r.verdict.short(opts)),
                detected_by: detected_by(&sweep, scene_run, opts),
                err_at_scene_dt_pct: scene_run.map_or(f64::NAN, err),
                scene_dt: c.scene.sim.dt(),
                detections: sweep
                    .iter()
                    .chain(scene_run.iter())
                    .filter(|r| !r.verdict.is_stable())
                    .map(|r| {
                        format!(
                            "{}{}: {}",
                            if r.scene_dt { "scene dt " } else { "x" },
                            if r.scene_dt {
                                format!("{:e}", r.dt)
                            } else {
                                format!("{}", r.factor)
                            },
                            r.verdict.detection(r, opts)
                        )
                    })
                    .collect(),
            });
        }
    }
    out
}

/// The unstable runs of one case × rotator, grouped: runs of consecutive
/// factors with the same detection become one `x<a>-<b>: <how>` item.
fn detected_by(sweep: &[&StressRun], scene_run: Option<&StressRun>, o: &StressOptions) -> String {
    let mut items: Vec<(f64, f64, usize)> = vec![];
    for r in sweep {
        let class = r.verdict.class().0;
        match items.last_mut() {
            Some(last) if class == last.2 && class != 0 => last.1 = r.factor,
            _ => items.push((r.factor, r.factor, class)),
        }
    }
    let mut out: Vec<String> = items
        .into_iter()
        .filter(|i| i.2 != 0)
        .map(|(a, b, c)| {
            let range = if a == b {
                format!("x{a}")
            } else {
                format!("x{a}-{b}")
            };
            format!("{range}: {}", class_words(c, o))
        })
        .collect();
    if let Some(r) = scene_run.filter(|r| !r.verdict.is_stable()) {
        out.push(format!(
            "scene dt {:e}: {}",
            r.dt,
            class_words(r.verdict.class().0, o)
        ));
    }
    if out.is_empty() {
        "none unstable".into()
    } else {
        out.join("; ")
    }
}

/// Header of `stress.csv`.
pub const SUMMARY_HEADER: [&str; 13] = [
    "case",
    "rotator",
    "recommended_dt",
    "hard_limit_factor",
    "largest_stable_dt",
    "largest_stable_factor",
    "energy_error_full_at_recommended_pct",
    "run_at_recommended",
    "scene_dt",
    "energy_error_full_at_scene_dt_pct",
    "stable_above_first_failure",
    "detected_by",
    "unstable_runs",
];

/// Header of `stress_runs.csv`.
pub const RUNS_HEADER: [&str; 16] = [
    "case",
    "rotator",
    "factor",
    "scene_dt",
    "dt",
    "steps",
    "steps_done",
    "stable",
    "energy_error_full_max_pct",
    "energy_error_full_at_stop_pct",
    "momentum_error_max_pct",
    "outcome_error_pct",
    "detection",
    "quantity",
    "value",
    "limit",
];

fn write_outputs(r: &StressReport, opts: &StressOptions) -> Result<()> {
    let dir = &opts.out_dir;
    let rows: Vec<Vec<String>> = r
        .summary
        .iter()
        .map(|s| {
            vec![
                s.case.clone(),
                s.rotator.name().into(),
                cell(s.recommended_dt),
                cell(s.hard_limit_factor),
                cell(s.largest_stable_factor * s.recommended_dt),
                cell(s.largest_stable_factor),
                cell(s.err_at_recommended_pct),
                s.at_recommended.clone(),
                cell(s.scene_dt),
                cell(s.err_at_scene_dt_pct),
                s.stable_above_failure
                    .iter()
                    .map(|f| crate::output::num(*f))
                    .collect::<Vec<_>>()
                    .join(" "),
                s.detected_by.clone(),
                s.detections.join("; "),
            ]
        })
        .collect();
    write_csv(&dir.join("stress.csv"), &SUMMARY_HEADER, &rows)?;
    let rows: Vec<Vec<String>> = r
        .runs
        .iter()
        .map(|x| {
            let (kind, q, v, l) = match &x.verdict {
                Verdict::Guard(d) => (
                    d.kind.short().to_string(),
                    d.quantity().to_string(),
                    cell(d.value),
                    cell(d.limit),
                ),
                Verdict::Stable => (String::new(), String::new(), String::new(), String::new()),
                v => (
                    v.detection(x, opts),
                    String::new(),
                    String::new(),
                    String::new(),
                ),
            };
            vec![
                x.case.clone(),
                x.rotator.name().into(),
                cell(x.factor),
                x.scene_dt.to_string(),
                cell(x.dt),
                x.steps.to_string(),
                x.steps_done.to_string(),
                x.verdict.is_stable().to_string(),
                cell(x.energy_err_pct),
                cell(x.energy_err_at_stop_pct),
                cell(x.momentum_err_pct),
                cell(x.outcome_err_pct),
                kind,
                q,
                v,
                l,
            ]
        })
        .collect();
    write_csv(&dir.join("stress_runs.csv"), &RUNS_HEADER, &rows)?;
    let (compact, full) = markdown(r);
    for (name, text) in [("stress_table.md", compact), ("stress_full.md", full)] {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(&p, e))?;
    }
    let map = stability_map(r, opts);
    for ext in ["png", "svg"] {
        let p = dir.join(format!("stability_map.{ext}"));
        render_map(&map, &p).map_err(super::plot_error)?;
    }
    Ok(())
}

/// Rotator × δt-factor map, one panel per case.
pub(crate) fn stability_map(r: &StressReport, opts: &StressOptions) -> CellMap {
    let mut factors = opts.factors.clone();
    factors.sort_by(f64::total_cmp);
    factors.dedup();
    let panels = r
        .cases
        .iter()
        .map(|c| {
            let cells = opts
                .rotators
                .iter()
                .map(|&k| {
                    factors
                        .iter()
                        .map(|&f| {
                            r.runs
                                .iter()
                                .find(|x| {
                                    x.case == c.name
                                        && x.rotator == k
                                        && !x.scene_dt
                                        && x.factor == f
                                })
                                .map(|x| {
                                    let (class, text) = x.verdict.class();
                                    (class, text.to_string())
                                })
                        })
                        .collect()
                })
                .collect();
            // Fractional column of a factor (log-interpolated between columns).
            let column = |f: f64| -> f64 {
                if factors.len() < 2 {
                    return f64::NAN;
                }
                let lf = f.ln();
                for (i, w) in factors.windows(2).enumerate() {
                    let (a, b) = (w[0].ln(), w[1].ln());
                    if lf >= a && lf <= b {
                        return i as f64 + 0.5 + (lf - a) / (b - a);
                    }
                }
                f64::NAN
            };
            let marks = c
                .hard_limit_dt
                .map(|h| {
                    let f = h / c.recommended_dt;
                    (
                        column(f),
                        format!("hard limit (5 steps/collision) = x{f:.1}"),
                    )
                })
                .into_iter()
                .collect();
            MapPanel {
                title: format!(
                    "{}  (δt_rec = {:.2e} s, {})",
                    c.name, c.recommended_dt, c.basis
                ),
                x_ticks: factors
                    .iter()
                    .map(|&f| {
                        if f == 1.0 {
                            "1 (rec)".into()
                        } else {
                            format!("{f}")
                        }
                    })
                    .collect(),
                rows: opts.rotators.iter().map(|k| k.name().to_string()).collect(),
                cells,
                marks,
            }
        })
        .collect();
    CellMap {
        title: format!(
            "Stability map: δt = factor × δt_rec (stable: no guard stop, energy/L error ≤ {} %, final state within {} % of rk4)",
            opts.energy_tol_pct, opts.outcome_tol_pct
        ),
        x_label: "δt / δt_rec".into(),
        classes: CLASSES
            .iter()
            .map(|(l, c)| (l.to_string(), *c))
            .collect(),
        panels,
        columns: 2,
    }
}

/// Print the summary table on stdout.
pub fn print_report(r: &StressReport) {
    println!(
        "{:<14} {:<10} {:>10} {:>8} {:>11} {:>8} {:>12}  first unstable run",
        "case", "rotator", "dt_rec", "limit x", "stable dt", "x rec", "E err @rec %"
    );
    for s in &r.summary {
        println!(
            "{:<14} {:<10} {:>10} {:>8} {:>11} {:>8} {:>12}  {}",
            s.case,
            s.rotator.name(),
            fmt_e(s.recommended_dt),
            fmt_e(s.hard_limit_factor),
            fmt_e(s.largest_stable_factor * s.recommended_dt),
            if s.largest_stable_factor.is_finite() {
                crate::output::num(s.largest_stable_factor)
            } else {
                "none".into()
            },
            fmt_e(s.err_at_recommended_pct),
            s.detections.first().map_or("-", String::as_str)
        );
    }
}

/// Stress cases from the `*.toml` files of `dir` whose stem matches `glob`
/// (`*` and `?`), sorted by name.
pub fn load_cases(dir: &Path, glob: &str) -> Result<Vec<StressCase>> {
    let rd = std::fs::read_dir(dir).map_err(|e| {
        Error::bad(
            dir.display().to_string(),
            "--dir",
            format!("cannot read the stress case folder: {e}"),
        )
    })?;
    let mut paths: Vec<PathBuf> = rd
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter(|p| {
            p.file_stem()
                .and_then(|s| s.to_str())
                .is_some_and(|s| wildcard(glob.trim_end_matches(".toml"), s))
        })
        .collect();
    paths.sort();
    paths
        .iter()
        .map(|p| {
            let name = p.file_stem().and_then(|s| s.to_str()).unwrap_or("case");
            StressCase::new(name, crate::scenario::load(p)?)
        })
        .collect()
}

/// Shell-style match of `pat` (`*`, `?`) against the whole of `s`.
pub fn wildcard(pat: &str, s: &str) -> bool {
    let (p, t): (Vec<char>, Vec<char>) = (pat.chars().collect(), s.chars().collect());
    let (mut i, mut j, mut star, mut mark) = (0, 0, None, 0);
    while j < t.len() {
        if i < p.len() && (p[i] == '?' || p[i] == t[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if let Some(si) = star {
            i = si + 1;
            mark += 1;
            j = mark;
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}

/// `x` to 3 significant digits: fixed in [1e-3, 1e4), else scientific.
fn sig3(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "–".into()
        } else {
            "∞".into()
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..4).contains(&e) {
        format!("{:.*}", (2 - e).max(0) as usize, x)
    } else {
        format!("{x:.2e}")
    }
}

impl StressSummary {
    /// Largest stable δt cell: `4.81e-5 (x4)`, `none`, plus non-monotone notes.
    fn stable_cell(&self) -> String {
        let mut c = if self.largest_stable_factor.is_finite() {
            format!(
                "{:.2e} (×{})",
                self.largest_stable_factor * self.recommended_dt,
                self.largest_stable_factor
            )
        } else {
            "none".into()
        };
        if !self.stable_above_failure.is_empty() {
            let f: Vec<String> = self
                .stable_above_failure
                .iter()
                .map(|f| format!("×{f}"))
                .collect();
            c += &format!(", stable again at {}", f.join(", "));
        }
        c
    }

    /// Error at δt_rec with how that run ended, e.g. `10.1 % (stopped by …)`.
    fn err_cell(&self) -> String {
        let e = format!("{} %", sig3(self.err_at_recommended_pct));
        if self.at_recommended == "stable" {
            e
        } else {
            format!("{e} ({})", self.at_recommended)
        }
    }
}

/// Markdown tables of the result: a compact one (rotators with the same
/// result share a row; for the README) and one line per case × rotator.
pub fn markdown(r: &StressReport) -> (String, String) {
    let mut compact = String::from(
        "| case | δt_rec (s) | rotators | largest stable δt (s) | energy error at δt_rec (max over the run; spin: also L) | how the unstable runs were detected |\n|---|---|---|---|---|---|\n",
    );
    for c in &r.cases {
        let rows: Vec<&StressSummary> = r.summary.iter().filter(|s| s.case == c.name).collect();
        let mut groups: Vec<(Vec<&str>, [String; 3])> = vec![];
        for s in &rows {
            let key = [s.stable_cell(), s.err_cell(), s.detected_by.clone()];
            match groups.iter_mut().find(|g| g.1 == key) {
                Some(g) => g.0.push(s.rotator.name()),
                None => groups.push((vec![s.rotator.name()], key)),
            }
        }
        for (names, [stable, err, det]) in groups {
            let who = if names.len() == rows.len() && rows.len() > 1 {
                format!("all {}", names.len())
            } else {
                names.join(", ")
            };
            compact += &format!(
                "| {} | {:.2e} | {who} | {stable} | {err} | {det} |\n",
                c.name, c.recommended_dt
            );
        }
    }
    let mut full = String::from(
        "| case | rotator | δt_rec (s) | hard limit (× rec) | largest stable δt (s) | energy error at δt_rec (%) | run at δt_rec | scene δt (s) | energy error at scene δt (%) | how the unstable runs were detected | first unstable run, in detail |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for s in &r.summary {
        full += &format!(
            "| {} | {} | {:.2e} | {} | {} | {} | {} | {:e} | {} | {} | {} |\n",
            s.case,
            s.rotator.name(),
            s.recommended_dt,
            if s.hard_limit_factor.is_finite() {
                format!("{:.1}", s.hard_limit_factor)
            } else {
                "–".into()
            },
            s.stable_cell(),
            sig3(s.err_at_recommended_pct),
            s.at_recommended,
            s.scene_dt,
            sig3(s.err_at_scene_dt_pct),
            s.detected_by,
            s.detections.first().map_or("–", String::as_str),
        );
    }
    (compact, full)
}
