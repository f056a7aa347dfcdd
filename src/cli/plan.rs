//! Raw arguments turned once into checked, ready-to-run plans (ripgrep's
//! "args → checked objects"): every flag check lives here, so the commands
//! only execute.

use super::args::{
    CheckArgs, CompareArgs, ConvergeArgs, GenerateArgs, RenderArgs, ReplicateArgs, RunArgs,
    SettleArgs, StressArgs,
};
use crate::advice::{advise_with, Advice};
use crate::contact::damping::Restitution;
use crate::contact::tangential::Friction;
use crate::error::{Error, Result};
use crate::generate::{
    place::{Fibres, Placement, Spheres},
    replicate::ReplicateOptions,
    sample::{Orientation, Size},
    GenerateOptions, Velocity,
};
use crate::output::Checkpoint;
use crate::run::RunOptions;
use crate::scenario::{self, Scene, SimParams};
use crate::study::compare::CompareOptions;
use crate::study::converge::ConvergeOptions;
use crate::study::stress::{load_cases, StressCase, StressOptions};
use glam::DVec3;
use std::path::{Path, PathBuf};

/// `fibresim run`, checked.
pub struct RunPlan {
    /// The scene, with the flags' overrides.
    pub scene: Scene,
    /// Where to write and how often to checkpoint.
    pub opts: RunOptions,
    /// The checkpoint to continue, and the folder it was found in.
    pub resume: Option<(Checkpoint, PathBuf)>,
    /// The time-step advice (its warnings are printed before the run).
    pub advice: Advice,
    /// No progress bar, no summary on stdout.
    pub quiet: bool,
    /// The scenario's warnings (values outside engineering practice).
    pub warnings: Vec<String>,
    /// What the run does to its folder that the user should know (the
    /// default folder's earlier outputs replaced).
    pub notes: Vec<String>,
}

/// `fibresim check`, checked.
pub struct CheckPlan {
    /// The scene, with `--dt` applied.
    pub scene: Scene,
    /// Its advice.
    pub advice: Advice,
    /// The scenario's warnings (values outside engineering practice).
    pub warnings: Vec<String>,
}

/// A flag that must be a finite number > 0.
pub fn positive_flag(flag: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::bad(
            "command line",
            flag,
            format!("must be a finite number > 0, got {v}; give a positive value"),
        ))
    }
}

/// The scene of `run`: the file (or the built-in default) with the flags'
/// overrides, and the stem that names its default output folder.
fn run_scene(args: &RunArgs) -> Result<(Scene, String, Vec<String>)> {
    let ((mut scene, warnings), stem) = match &args.scenario {
        Some(p) => (scenario::load_with_warnings(p)?, stem(p)),
        None => (
            scenario::parse_with_warnings(scenario::DEFAULT_SCENE.1, scenario::DEFAULT_SCENE.0)?,
            "default".to_string(),
        ),
    };
    if args.rotator.is_some() || args.dt.is_some() || args.t_end.is_some() || args.every.is_some() {
        let s = &scene.sim;
        scene.sim = SimParams::new(
            args.dt.unwrap_or(s.dt()),
            args.t_end.unwrap_or(s.t_end()),
            args.rotator.unwrap_or(s.rotator()),
            args.every.or(s.every()),
            "command line",
            "--",
        )?;
    }
    let o = &mut scene.output;
    o.vtk_every = crate::scenario::output::cadence("command line", "--vtk-every", args.vtk_every)?
        .or(o.vtk_every);
    o.trajectory_every = crate::scenario::output::cadence(
        "command line",
        "--trajectory-every",
        args.trajectory_every,
    )?
    .or(o.trajectory_every);
    if let Some(v) = args.max_energy_error {
        scene.guards.energy_error_pct = positive_flag("--max-energy-error", v)?;
    }
    if let Some(v) = args.max_overlap {
        scene.guards.overlap_ratio = positive_flag("--max-overlap", v)?;
    }
    Ok((scene, stem, warnings))
}

fn stem(p: &Path) -> String {
    p.file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
}

impl RunArgs {
    /// Check the flags, load the scene (or the checkpoint's), and apply the
    /// time-step advice's hard limit.
    pub fn plan(self) -> Result<RunPlan> {
        let checkpoint = self.resume.as_deref().map(Checkpoint::read).transpose()?;
        let (scene, stem, warnings) = match &checkpoint {
            Some(c) => {
                let mut scene = crate::run::scene_from_checkpoint(c, self.t_end)?;
                // The optional outputs the checkpointed run wrote, whether
                // its scenario or its flags asked for them.
                scene.output = crate::scenario::OutputRequest {
                    vtk_every: crate::output::vtk::cadence_in(c)?,
                    trajectory_every: crate::output::trajectory::cadence_in(c)?,
                    ..scene.output
                };
                (scene, "resumed".to_string(), vec![])
            }
            None => run_scene(&self)?,
        };
        checkpoint_every_flag(self.checkpoint_every)?;
        if checkpoint.as_ref().is_some_and(|c| c.settle.is_some()) {
            return Err(Error::bad(
                "command line",
                "--resume",
                "this checkpoint is of a `fibresim settle` run; continue it with `fibresim settle --resume CHECKPOINT --write BED.toml`",
            ));
        }
        let impact = self
            .impact_speed
            .map(|v| positive_flag("--impact-speed", v))
            .transpose()?;
        let advice = advise_with(&scene, impact);
        if let Some(limit) = advice.hard_limit_dt {
            let dt = scene.sim.dt();
            if dt > limit && !self.allow_large_dt {
                return Err(Error::bad(
                    &scene.source,
                    "simulation.dt",
                    format!(
                        "dt = {dt:e} s leaves fewer than 5 steps for {} ({:.3e} s); use dt <= {:.3e} s (see `fibresim check`), or --allow-large-dt to run anyway",
                        advice.limited_by(),
                        limit * 5.0,
                        advice.recommended_dt.unwrap_or(limit)
                    ),
                ));
            }
        }
        // The checkpoint's folder ("." for a bare `checkpoint.json`).
        let checkpoint_dir = self.resume.as_deref().map(checkpoint_dir);
        let default_out = match &checkpoint_dir {
            Some(d) => d.clone(),
            None => PathBuf::from("out")
                .join(&stem)
                .join(scene.sim.rotator().name()),
        };
        let given = self.out.is_some();
        let out_dir = self.out.unwrap_or(default_out);
        let note = out_claim(
            &out_dir,
            checkpoint.as_ref().zip(checkpoint_dir.as_deref()),
            given,
            self.force,
        )?;
        let mut flags = vec![];
        if self.allow_large_dt {
            flags.push(("--allow-large-dt", String::new()));
        }
        if let Some(v) = impact {
            flags.push(("--impact-speed", crate::output::num(v)));
        }
        let resume_command = crate::run::resume_command(
            "run",
            &out_dir.join(crate::output::checkpoint::CHECKPOINT_FILE),
            &flags,
        );
        Ok(RunPlan {
            opts: RunOptions {
                out_dir,
                progress: !self.quiet,
                progress_lines: self
                    .progress
                    .map(|s| positive_flag("--progress", s))
                    .transpose()?,
                checkpoint_every: self.checkpoint_every,
                resumed_from: checkpoint_dir.clone(),
                resume_command: Some(resume_command),
                ..Default::default()
            },
            resume: checkpoint.zip(checkpoint_dir),
            scene,
            advice,
            quiet: self.quiet,
            warnings,
            notes: note.into_iter().collect(),
        })
    }
}

impl CheckArgs {
    /// Load the scene and judge `--dt` instead of its own.
    pub fn plan(self) -> Result<CheckPlan> {
        let (mut scene, warnings) = scenario::load_with_warnings(&self.scenario)?;
        if let Some(dt) = self.dt {
            let s = &scene.sim;
            scene.sim =
                SimParams::new(dt, s.t_end(), s.rotator(), s.every(), "command line", "--")?;
        }
        let impact = self
            .impact_speed
            .map(|v| positive_flag("--impact-speed", v))
            .transpose()?;
        let advice = advise_with(&scene, impact);
        Ok(CheckPlan {
            scene,
            advice,
            warnings,
        })
    }
}

/// A study's scene and its default output folder `out/<stem>/<sub>`.
fn study_scene(path: &Path, sub: &str) -> Result<(Scene, PathBuf)> {
    let (scene, warnings) = scenario::load_with_warnings(path)?;
    for w in warnings {
        eprintln!("warning: {w}");
    }
    Ok((scene, PathBuf::from("out").join(stem(path)).join(sub)))
}

impl CompareArgs {
    /// The scene and the study's options.
    pub fn plan(self) -> Result<(Scene, CompareOptions)> {
        let (scene, default_out) = study_scene(&self.scenario, "compare")?;
        for (flag, v) in [("--dt", self.dt), ("--t-end", self.t_end)] {
            if let Some(v) = v {
                positive_flag(flag, v)?;
            }
        }
        let opts = CompareOptions {
            rotators: crate::study::parse_rotators(Some(&self.rotators))?,
            dt: self.dt,
            t_end: self.t_end,
            out_dir: self.out.unwrap_or(default_out),
            progress: !self.quiet,
        };
        Ok((scene, opts))
    }
}

impl ConvergeArgs {
    /// The scene and the study's options.
    pub fn plan(self) -> Result<(Scene, ConvergeOptions)> {
        let (scene, default_out) = study_scene(&self.scenario, "converge")?;
        for (flag, v) in [
            ("--dt-max", self.dt_max),
            ("--dt-min", self.dt_min),
            ("--t-end", self.t_end),
            ("--ref-factor", Some(self.ref_factor)),
        ] {
            if let Some(v) = v {
                positive_flag(flag, v)?;
            }
        }
        let opts = ConvergeOptions {
            rotators: crate::study::parse_rotators(Some(&self.rotators))?,
            dt_max: self.dt_max,
            dt_min: self.dt_min,
            points: self.points,
            t_end: self.t_end,
            ref_factor: self.ref_factor,
            out_dir: self.out.unwrap_or(default_out),
            progress: !self.quiet,
            trajectory: self.trajectory,
        };
        Ok((scene, opts))
    }
}

impl StressArgs {
    /// The stress cases and the sweep's options.
    pub fn plan(self) -> Result<(Vec<StressCase>, StressOptions)> {
        let factors = self
            .factors
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|s| match s.parse::<f64>() {
                Ok(f) if f.is_finite() && f > 0.0 => Ok(f),
                _ => Err(Error::bad(
                    "command line",
                    "--factors",
                    format!("{s:?} is not a number > 0; give e.g. 0.25,1,4,16"),
                )),
            })
            .collect::<Result<Vec<_>>>()?;
        let opts = StressOptions {
            rotators: crate::study::parse_rotators(Some(&self.rotators))?,
            factors,
            energy_tol_pct: positive_flag("--energy-tol", self.energy_tol)?,
            outcome_tol_pct: positive_flag("--outcome-tol", self.outcome_tol)?,
            out_dir: self.out,
            progress: !self.quiet,
        };
        Ok((load_cases(&self.dir, &self.cases)?, opts))
    }
}

/// `N` comma-separated finite numbers of flag `flag`.
fn numbers<const N: usize>(flag: &str, s: &str, what: &str) -> Result<[f64; N]> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .unwrap_or_default();
    match <[f64; N]>::try_from(v) {
        Ok(a) if a.iter().all(|x| x.is_finite()) => Ok(a),
        _ => Err(Error::bad(
            "command line",
            flag,
            format!("`{s}` is not {N} comma-separated numbers; give {what}"),
        )),
    }
}

/// A size flag: a number, `uniform:MIN:MAX` or `normal:MEAN:SD`.
fn size_flag(flag: &str, s: &str) -> Result<Size> {
    Size::parse(s).ok_or_else(|| {
        Error::bad(
            "command line",
            flag,
            format!("`{s}` is not a size; give a length in m (0.01), uniform:MIN:MAX (0 < MIN <= MAX) or normal:MEAN:SD (MEAN > 3 SD)"),
        )
    })
}

/// A restitution flag in (0, 1].
fn restitution_flag(flag: &str, e: f64) -> Result<f64> {
    if e.is_finite() && e > 0.0 && e <= 1.0 {
        Ok(e)
    } else {
        Err(Error::bad(
            "command line",
            flag,
            format!("a coefficient of restitution must lie in (0, 1], got {e}; give e.g. 0.3"),
        ))
    }
}

/// A friction flag: a finite number ≥ 0.
fn friction_flag(flag: &str, mu: f64) -> Result<f64> {
    if mu.is_finite() && mu >= 0.0 {
        Ok(mu)
    } else {
        Err(Error::bad(
            "command line",
            flag,
            format!("a Coulomb friction coefficient must be a finite number >= 0, got {mu}; give e.g. 0.3 (0 is frictionless)"),
        ))
    }
}

/// The Coulomb coefficients of `--friction` and `--wall-friction` over
/// `base` (the scene's, or none): `--friction` sets both unless
/// `--wall-friction` is given, `--wall-friction` alone keeps the body–body
/// one. `None` when both are 0, as `[contact]` reads them (build.rs).
fn friction_flags(
    body: Option<f64>,
    wall: Option<f64>,
    base: Option<Friction>,
) -> Result<Option<Friction>> {
    let body = body.map(|m| friction_flag("--friction", m)).transpose()?;
    let wall = wall
        .map(|m| friction_flag("--wall-friction", m))
        .transpose()?;
    if body.is_none() && wall.is_none() {
        return Ok(base);
    }
    // One of the two is given: a given --friction is the walls' default.
    let body = body.unwrap_or(base.map_or(0.0, |f| f.body));
    let wall = wall.unwrap_or(body);
    Ok((body > 0.0 || wall > 0.0).then_some(Friction { body, wall }))
}

/// A Poisson-ratio flag in (−1, 0.5).
fn poisson_flag(flag: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > -1.0 && v < 0.5 {
        Ok(v)
    } else {
        Err(Error::bad(
            "command line",
            flag,
            format!("Poisson's ratio must lie in (-1, 0.5), got {v}; give e.g. 0.35"),
        ))
    }
}

impl GenerateArgs {
    /// Check every flag into the generator's options.
    pub fn plan(self, command: String) -> Result<GenerateOptions> {
        if self.n == 0 && self.spheres == 0 {
            return Err(Error::bad(
                "command line",
                "--n",
                "give at least one fibre (--n) or sphere (--spheres)",
            ));
        }
        // A size flag that the bodies it sizes need.
        let needed =
            |flag: &str, value: &Option<String>, count: usize, what: &str| match (value, count) {
                (Some(v), _) => size_flag(flag, v).map(Some),
                (None, 0) => Ok(None),
                (None, _) => Err(Error::bad(
                    "command line",
                    flag,
                    format!("give {flag} for the {what}, e.g. {flag} 0.01"),
                )),
            };
        let diameter = needed("--diameter", &self.diameter, self.n, "fibres")?;
        let length = needed("--length", &self.length, self.n, "fibres")?;
        let sphere_diameter = needed(
            "--sphere-diameter",
            &self.sphere_diameter,
            self.spheres,
            "spheres",
        )?;
        let size = numbers::<3>("--box", &self.box_size, "LX,LY,LZ in m, e.g. 0.3,0.3,1.2")?;
        let size = DVec3::from_array(size);
        if size.min_element() <= 0.0 {
            return Err(Error::bad(
                "command line",
                "--box",
                format!("every side must be > 0, got {size}"),
            ));
        }
        let gap = match self.gap {
            Some(g) if g.is_finite() && g >= 0.0 => g,
            Some(g) => {
                return Err(Error::bad(
                    "command line",
                    "--gap",
                    format!("must be >= 0, got {g}"),
                ))
            }
            // The fibres' mean diameter, else the spheres'.
            None => diameter.or(sphere_diameter).map_or(0.0, |d| d.mean()) / 20.0,
        };
        // The bodies keep `gap` from the walls too.
        let (lo, hi) = match &self.region {
            None => (DVec3::ZERO, size),
            Some(r) => {
                let r = numbers::<6>("--region", r, "X0,Y0,Z0,X1,Y1,Z1 inside the box")?;
                let (lo, hi) = (DVec3::new(r[0], r[1], r[2]), DVec3::new(r[3], r[4], r[5]));
                if !(lo.cmpge(DVec3::ZERO).all() && hi.cmple(size).all() && lo.cmplt(hi).all()) {
                    return Err(Error::bad("command line", "--region", format!("{lo} .. {hi} must lie inside the box 0 .. {size}, lower corner below the upper")));
                }
                (lo, hi)
            }
        };
        let region = (lo + DVec3::splat(gap), hi - DVec3::splat(gap));
        let thickest = [diameter, sphere_diameter]
            .iter()
            .flatten()
            .map(|d| d.max())
            .fold(0.0, f64::max);
        if (region.1 - region.0).min_element() <= thickest {
            return Err(Error::bad(
                "command line",
                "--region",
                "the region is thinner than a body; enlarge it",
            ));
        }
        let axis = DVec3::from_array(numbers::<3>("--axis", &self.axis, "X,Y,Z, e.g. 0,0,1")?);
        if axis.length() < 1e-12 {
            return Err(Error::bad(
                "command line",
                "--axis",
                "must be a non-zero direction",
            ));
        }
        let axis = axis.normalize();
        let orientation = match self.orientation.as_str() {
            "isotropic" => Orientation::Isotropic,
            "aligned" => Orientation::Aligned(axis),
            "planar" => Orientation::Planar(axis),
            o => {
                return Err(Error::bad(
                    "command line",
                    "--orientation",
                    format!("unknown orientation `{o}`; choose isotropic, aligned or planar"),
                ))
            }
        };
        let velocity = match &self.velocity {
            Some(v) => Velocity::Fixed(DVec3::from_array(numbers::<3>(
                "--velocity",
                v,
                "VX,VY,VZ in m/s",
            )?)),
            None if self.speed.is_finite() && self.speed >= 0.0 => Velocity::Random(self.speed),
            None => {
                return Err(Error::bad(
                    "command line",
                    "--speed",
                    format!("must be >= 0, got {}", self.speed),
                ))
            }
        };
        if !(self.spin.is_finite() && self.spin >= 0.0) {
            return Err(Error::bad(
                "command line",
                "--spin",
                format!("must be >= 0, got {}", self.spin),
            ));
        }
        let gravity = match self.gravity.as_str() {
            "none" => None,
            g => Some(DVec3::from_array(numbers::<3>(
                "--gravity",
                g,
                "GX,GY,GZ in m/s^2 or `none`",
            )?)),
        };
        let young = positive_flag("--young", self.young)?;
        let poisson = poisson_flag("--poisson", self.poisson)?;
        let e = restitution_flag("--restitution", self.restitution)?;
        let sim = SimParams::new(
            self.dt,
            self.t_end,
            crate::integrate::rotate::RotatorKind::DEFAULT,
            None,
            "command line",
            "--",
        )?;
        Ok(GenerateOptions {
            placement: Placement {
                fibres: match (diameter, length) {
                    (Some(diameter), Some(length)) if self.n > 0 => Some(Fibres {
                        n: self.n,
                        diameter,
                        length,
                        orientation,
                    }),
                    _ => None,
                },
                spheres: match sphere_diameter {
                    Some(diameter) if self.spheres > 0 => Some(Spheres {
                        n: self.spheres,
                        diameter,
                    }),
                    _ => None,
                },
                region,
                gap,
                max_attempts: self.max_attempts.max(1),
            },
            walls: crate::contact::Walls {
                min: DVec3::ZERO,
                max: size,
                young: positive_flag("--wall-young", self.wall_young.unwrap_or(young))?,
                poisson: poisson_flag("--wall-poisson", self.wall_poisson.unwrap_or(poisson))?,
            },
            gravity,
            material: crate::body::Material {
                // (A bed of spheres only names its material for them.)
                name: if self.n == 0 { "sphere" } else { "fibre" }.into(),
                density: positive_flag("--density", self.density)?,
                young,
                poisson,
                friction: None,
            },
            velocity,
            spin: self.spin,
            seed: self.seed,
            dt: sim.dt(),
            // As given (checked by `sim`): steps·δt can print as 3.0000000000000004.
            t_end: self.t_end,
            restitution: (e < 1.0).then_some(Restitution { fibre: e, wall: e }),
            friction: friction_flags(self.friction, self.wall_friction, None)?,
            out: self.out,
            command,
        })
    }
}

/// `fibresim settle --check-every` unless given (or resumed).
pub const DEFAULT_CHECK_EVERY: u64 = 100;

/// `fibresim settle`, checked.
pub struct SettlePlan {
    /// The scene, with the settling restitution, δt and end time.
    pub scene: Scene,
    /// The run's options (with the settle test).
    pub opts: RunOptions,
    /// Its advice.
    pub advice: Advice,
    /// The settled scenario to write, and its δt and end time.
    pub write: PathBuf,
    /// (See `write`.)
    pub write_dt: f64,
    /// (See `write`.)
    pub write_t_end: f64,
    /// No progress bar, no summary.
    pub quiet: bool,
    /// The checkpoint to continue, and the folder it was found in.
    pub resume: Option<(Checkpoint, PathBuf)>,
    /// What the run does to its folder that the user should know.
    pub notes: Vec<String>,
}

/// `fibresim replicate`, checked.
pub struct ReplicatePlan {
    /// The bed to copy.
    pub scene: Scene,
    /// The copies and where to write them.
    pub opts: ReplicateOptions,
    /// Print nothing on success.
    pub quiet: bool,
}

impl ReplicateArgs {
    /// Load the bed and check the copy counts.
    pub fn plan(self, command: String) -> Result<ReplicatePlan> {
        let bad = || {
            Error::bad(
                "command line",
                "--times",
                format!(
                    "`{}` is not three whole numbers >= 1; give NX,NY,NZ, e.g. 3,3,1",
                    self.times
                ),
            )
        };
        let times: Vec<usize> = self
            .times
            .split(',')
            .map(|x| x.trim().parse::<usize>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad())?;
        let times = <[usize; 3]>::try_from(times).map_err(|_| bad())?;
        if times.contains(&0) {
            return Err(bad());
        }
        Ok(ReplicatePlan {
            scene: scenario::load(&self.scenario)?,
            opts: ReplicateOptions {
                times,
                out: self.out,
                command,
            },
            quiet: self.quiet,
        })
    }
}

/// `--checkpoint-every N`: N ≥ 1.
fn checkpoint_every_flag(n: Option<u64>) -> Result<Option<u64>> {
    match n {
        Some(0) => Err(Error::bad(
            "command line",
            "--checkpoint-every",
            "must be >= 1",
        )),
        n => Ok(n),
    }
}

/// The folder of a checkpoint file ("." for a bare `checkpoint.json`).
fn checkpoint_dir(p: &Path) -> PathBuf {
    p.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), PathBuf::from)
}

/// The claim of a run on its output folder `out` (`given` by `--out`):
/// a resumed run checks that its checkpoint's folder still holds what the
/// checkpoint recorded, and continues there freely; any other run
/// (`folder::claim`) refuses a given folder that holds another run's
/// outputs unless `force`, and replaces the default folder's with a note.
fn out_claim(
    out: &Path,
    resume: Option<(&Checkpoint, &Path)>,
    given: bool,
    force: bool,
) -> Result<Option<String>> {
    use crate::output::folder::{claim, Claim};
    if let Some((c, from)) = resume {
        crate::run::check_outputs(c, from)?;
        if crate::run::resume::same_folder(from, out) {
            return Ok(None);
        }
    }
    claim(
        out,
        match (force, given) {
            (true, _) => Claim::Forced,
            (false, true) => Claim::Given,
            (false, false) => Claim::Default,
        },
    )
}

impl SettleArgs {
    /// Load the scene (or the checkpoint's) and check the flags.
    pub fn plan(self) -> Result<SettlePlan> {
        let checkpoint_every = checkpoint_every_flag(self.checkpoint_every)?;
        let checkpoint = self.resume.as_deref().map(Checkpoint::read).transpose()?;
        let mut scene = match &checkpoint {
            Some(c) => crate::run::scene_from_checkpoint(c, self.t_end)?,
            None => scenario::load(
                self.scenario
                    .as_deref()
                    .expect("clap: a scenario or --resume"),
            )?,
        };
        // A resumed settle keeps its restitution, and its settle test unless
        // the flags give another (the test only decides where it stops).
        let saved = checkpoint.as_ref().and_then(|c| c.settle.clone());
        if let (Some(c), Some(e)) = (&checkpoint, self.restitution) {
            let kept = c
                .damping
                .as_ref()
                .map(|d| d.restitution())
                .transpose()?
                .flatten();
            if kept.is_none_or(|k| k.fibre != e || k.wall != e) {
                let was = kept.map_or("none (elastic)".to_string(), |k| {
                    format!("{} (walls {})", k.fibre, k.wall)
                });
                return Err(Error::bad(
                    "command line",
                    "--restitution",
                    format!("{e} differs from the checkpoint's restitution {was}: a resumed settle keeps its restitution; drop --restitution, or settle again from the start"),
                ));
            }
        }
        if scene.has_prescribed_torque() {
            return Err(Error::bad(
                &scene.source,
                "body.torque",
                "a scene with prescribed torques cannot settle; remove the torques",
            ));
        }
        if let Some(e) = self.restitution.filter(|_| checkpoint.is_none()) {
            let e = restitution_flag("--restitution", e)?;
            scene.damping = (e < 1.0).then_some(Restitution { fibre: e, wall: e });
        }
        scene.friction = friction_flags(self.friction, self.wall_friction, scene.friction)?;
        if scene.damping.is_none() {
            return Err(Error::bad(&scene.source, "contact.restitution", "nothing dissipates, so the bed can never settle; give --restitution E (e.g. 0.3) or [contact] restitution"));
        }
        if self.dt.is_some() || self.t_end.is_some() || self.every.is_some() {
            let s = &scene.sim;
            scene.sim = SimParams::new(
                self.dt.unwrap_or(s.dt()),
                self.t_end.unwrap_or(s.t_end()),
                s.rotator(),
                self.every.or(s.every()),
                "command line",
                "--",
            )?;
        }
        let ke = match self.ke_per_body {
            Some(k) => positive_flag("--ke-per-body", k)?,
            None if saved.is_some() => saved.as_ref().expect("checked").ke_per_fibre()?,
            None => {
                // 1e-4 of the mean m g D (g = 9.81 m/s² without gravity).
                let g = scene.gravity.map_or(9.81, |g| g.length());
                let sum: f64 = scene
                    .bodies
                    .iter()
                    .map(|b| b.mass * g * b.shape.diameter())
                    .sum();
                1e-4 * sum / scene.bodies.len() as f64
            }
        };
        let check_every = match (self.check_every, &saved) {
            (None, Some(s)) => s.check_every,
            (n, _) => n.unwrap_or(DEFAULT_CHECK_EVERY),
        };
        if check_every == 0 {
            return Err(Error::bad("command line", "--check-every", "must be >= 1"));
        }
        let impact = self
            .impact_speed
            .map(|v| positive_flag("--impact-speed", v))
            .transpose()?;
        let advice = advise_with(&scene, impact);
        if let Some(limit) = advice.hard_limit_dt {
            if scene.sim.dt() > limit && !self.allow_large_dt {
                return Err(Error::bad(&scene.source, "--dt", format!("dt = {:e} s leaves fewer than 5 steps for {}; use dt <= {limit:.3e} s, --impact-speed V, or --allow-large-dt", scene.sim.dt(), advice.limited_by())));
            }
        }
        let write_dt = positive_flag("--write-dt", self.write_dt.unwrap_or(scene.sim.dt()))?;
        let write_t_end = positive_flag(
            "--write-t-end",
            self.write_t_end.unwrap_or(100.0 * write_dt),
        )?;
        SimParams::new(
            write_dt,
            write_t_end,
            scene.sim.rotator(),
            None,
            "command line",
            "--write-",
        )?;
        let dir = self.resume.as_deref().map(checkpoint_dir);
        let given = self.out.is_some();
        let out = self.out.or_else(|| dir.clone()).unwrap_or_else(|| {
            let scenario = self
                .scenario
                .as_deref()
                .expect("clap: a scenario or --resume");
            PathBuf::from("out").join(stem(scenario)).join("settle")
        });
        let note = out_claim(
            &out,
            checkpoint.as_ref().zip(dir.as_deref()),
            given,
            self.force,
        )?;
        // What the resumed settle needs that its checkpoint does not keep.
        let mut flags = vec![("--write", self.write.display().to_string())];
        for (flag, v) in [
            ("--write-dt", self.write_dt),
            ("--write-t-end", self.write_t_end),
            ("--impact-speed", impact),
        ] {
            if let Some(v) = v {
                flags.push((flag, crate::output::num(v)));
            }
        }
        if self.allow_large_dt {
            flags.push(("--allow-large-dt", String::new()));
        }
        let resume_command = crate::run::resume_command(
            "settle",
            &out.join(crate::output::checkpoint::CHECKPOINT_FILE),
            &flags,
        );
        Ok(SettlePlan {
            resume: checkpoint.zip(dir.clone()),
            opts: RunOptions {
                out_dir: out.clone(),
                progress: !self.quiet,
                progress_lines: self
                    .progress
                    .map(|s| positive_flag("--progress", s))
                    .transpose()?,
                checkpoint_every,
                settle: Some(crate::run::Settle {
                    ke_per_body: ke,
                    every: check_every,
                }),
                // Under a temporary name: `settle` renames it with the
                // scenario that names it, so neither is left without the other.
                write_bodies: Some(crate::output::file::temporary(
                    &crate::generate::body_file_of(&self.write),
                )),
                resumed_from: dir,
                resume_command: Some(resume_command),
            },
            scene,
            advice,
            write: self.write,
            write_dt,
            write_t_end,
            quiet: self.quiet,
            notes: note.into_iter().collect(),
        })
    }
}

/// `fibresim render`, checked.
pub struct RenderPlan {
    /// The input file.
    pub input: PathBuf,
    /// The picture or animation to write.
    pub output: PathBuf,
    /// Animate every frame.
    pub gif: bool,
    /// The step of a still.
    pub step: Option<u64>,
    /// A trajectory's scenario.
    pub scenario: Option<PathBuf>,
    /// How to draw.
    pub opts: crate::render::RenderOptions,
    /// GIF frames per second.
    pub fps: f64,
}

/// Two numbers `A<sep>B` of a flag.
fn pair(flag: &str, s: &str, sep: char, example: &str) -> Result<(f64, f64)> {
    let bad = || {
        Error::bad(
            "command line",
            flag,
            format!("`{s}` is not two numbers separated by `{sep}`; give e.g. {example}"),
        )
    };
    let (a, b) = s.split_once(sep).ok_or_else(bad)?;
    let a: f64 = a.trim().parse().map_err(|_| bad())?;
    let b: f64 = b.trim().parse().map_err(|_| bad())?;
    if a.is_finite() && b.is_finite() {
        Ok((a, b))
    } else {
        Err(bad())
    }
}

impl RenderArgs {
    /// Check the flags.
    pub fn plan(self) -> Result<RenderPlan> {
        let field = crate::render::Field::from_name(&self.color)?;
        let range = match &self.range {
            Some(r) => {
                let (lo, hi) = pair("--range", r, ',', "0,2")?;
                if hi <= lo {
                    return Err(Error::bad(
                        "command line",
                        "--range",
                        format!("needs LO < HI, got {r}"),
                    ));
                }
                Some((lo, hi))
            }
            None => None,
        };
        let (w, h) = pair("--size", &self.size, 'x', "1000x800")?;
        if !(16.0..=8192.0).contains(&w)
            || !(16.0..=8192.0).contains(&h)
            || w.fract() != 0.0
            || h.fract() != 0.0
        {
            return Err(Error::bad(
                "command line",
                "--size",
                format!(
                    "`{}`: width and height must be whole numbers from 16 to 8192",
                    self.size
                ),
            ));
        }
        // The format is the extension's: a still PNG or an animated GIF.
        let (output, gif) = match self.output {
            None => (
                crate::render::default_output(&self.input, self.gif),
                self.gif,
            ),
            Some(o) => {
                let ext = o
                    .extension()
                    .and_then(|e| e.to_str())
                    .map(str::to_ascii_lowercase);
                match ext.as_deref() {
                    Some("png") if self.gif => {
                        return Err(Error::bad(
                            "command line",
                            "--gif",
                            format!("--gif writes an animation, but `{}` names a PNG; give -o NAME.gif, or drop --gif for a still", o.display()),
                        ))
                    }
                    Some("png") => (o, false),
                    Some("gif") => (o, true),
                    _ => {
                        return Err(Error::bad(
                            "command line",
                            "--out",
                            format!("`{}`: render writes PNG (a still) or GIF (an animation), chosen by the extension; give -o NAME.png or -o NAME.gif", o.display()),
                        ))
                    }
                }
            }
        };
        Ok(RenderPlan {
            opts: crate::render::RenderOptions {
                field,
                range,
                view: crate::render::view_direction(&self.view)?,
                zoom: positive_flag("--zoom", self.zoom)?,
                width: w as u32,
                height: h as u32,
                capsule: self.shape == "capsule",
            },
            fps: positive_flag("--fps", self.fps)?,
            input: self.input,
            output,
            gif,
            step: self.step,
            scenario: self.scenario,
        })
    }
}
