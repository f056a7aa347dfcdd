//! Raw arguments turned once into checked, ready-to-run plans (ripgrep's
//! "args → checked objects"): every flag check lives here, so the commands
//! only execute.

use super::args::{CheckArgs, CompareArgs, ConvergeArgs, RenderArgs, RunArgs, StressArgs};
use crate::advice::{advise, Advice};
use crate::error::{Error, Result};
use crate::output::Checkpoint;
use crate::run::RunOptions;
use crate::scenario::{self, Scene, SimParams};
use crate::study::compare::CompareOptions;
use crate::study::converge::ConvergeOptions;
use crate::study::stress::{load_cases, StressCase, StressOptions};
use std::path::{Path, PathBuf};

/// The default scene of `fibresim run` with no scenario.
pub(crate) const DEFAULT_SCENE: (&str, &str) = (
    "<built-in nine_fibres>",
    include_str!("../../scenarios/nine_fibres.toml"),
);

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
}

/// `fibresim check`, checked.
pub struct CheckPlan {
    /// The scene, with `--dt` applied.
    pub scene: Scene,
    /// Its advice.
    pub advice: Advice,
}

/// A flag that must be a finite number > 0.
pub fn positive_flag(flag: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::bad(
            "command line",
            flag,
            format!("must be a finite number > 0, got {v}"),
        ))
    }
}

/// The scene of `run`: the file (or the built-in default) with the flags'
/// overrides, and the stem that names its default output folder.
fn run_scene(args: &RunArgs) -> Result<(Scene, String)> {
    let (mut scene, stem) = match &args.scenario {
        Some(p) => (scenario::load(p)?, stem(p)),
        None => (
            scenario::parse_str(DEFAULT_SCENE.1, DEFAULT_SCENE.0)?,
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
    Ok((scene, stem))
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
        let (scene, stem) = match &checkpoint {
            Some(c) => {
                let mut scene = crate::run::scene_from_checkpoint(c, self.t_end)?;
                // The optional outputs the checkpointed run wrote, whether
                // its scenario or its flags asked for them.
                scene.output = crate::scenario::OutputRequest {
                    vtk_every: crate::output::vtk::cadence_in(c)?,
                    trajectory_every: crate::output::trajectory::cadence_in(c)?,
                };
                (scene, "resumed".to_string())
            }
            None => run_scene(&self)?,
        };
        if self.checkpoint_every == Some(0) {
            return Err(Error::bad(
                "command line",
                "--checkpoint-every",
                "must be >= 1",
            ));
        }
        let advice = advise(&scene);
        if let Some(limit) = advice.hard_limit_dt {
            let dt = scene.sim.dt();
            if dt > limit && !self.allow_large_dt {
                return Err(Error::bad(
                    &scene.source,
                    "simulation.dt",
                    format!(
                        "dt = {dt:e} s leaves fewer than 5 steps for the shortest Hertz collision or face-tilt period ({:.3e} s); use dt <= {:.3e} s (see `fibresim check`), or --allow-large-dt to run anyway",
                        limit * 5.0,
                        advice.recommended_dt.unwrap_or(limit)
                    ),
                ));
            }
        }
        // The checkpoint's folder ("." for a bare `checkpoint.json`).
        let checkpoint_dir = self.resume.as_ref().map(|p| {
            p.parent()
                .filter(|d| !d.as_os_str().is_empty())
                .map_or_else(|| PathBuf::from("."), PathBuf::from)
        });
        let default_out = match &checkpoint_dir {
            Some(d) => d.clone(),
            None => PathBuf::from("out")
                .join(&stem)
                .join(scene.sim.rotator().name()),
        };
        Ok(RunPlan {
            opts: RunOptions {
                out_dir: self.out.unwrap_or(default_out),
                progress: !self.quiet,
                checkpoint_every: self.checkpoint_every,
            },
            resume: checkpoint.zip(checkpoint_dir),
            scene,
            advice,
            quiet: self.quiet,
        })
    }
}

impl CheckArgs {
    /// Load the scene and judge `--dt` instead of its own.
    pub fn plan(self) -> Result<CheckPlan> {
        let mut scene = scenario::load(&self.scenario)?;
        if let Some(dt) = self.dt {
            let s = &scene.sim;
            scene.sim =
                SimParams::new(dt, s.t_end(), s.rotator(), s.every(), "command line", "--")?;
        }
        let advice = advise(&scene);
        Ok(CheckPlan { scene, advice })
    }
}

/// A study's scene and its default output folder `out/<stem>/<sub>`.
fn study_scene(path: &Path, sub: &str) -> Result<(Scene, PathBuf)> {
    Ok((
        scenario::load(path)?,
        PathBuf::from("out").join(stem(path)).join(sub),
    ))
}

impl CompareArgs {
    /// The scene and the study's options.
    pub fn plan(self) -> Result<(Scene, CompareOptions)> {
        let (scene, default_out) = study_scene(&self.scenario, "compare")?;
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
        let opts = ConvergeOptions {
            rotators: crate::study::parse_rotators(Some(&self.rotators))?,
            dt_max: self.dt_max,
            dt_min: self.dt_min,
            points: self.points,
            t_end: self.t_end,
            ref_factor: self.ref_factor,
            out_dir: self.out.unwrap_or(default_out),
            progress: !self.quiet,
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
            .map(|s| {
                s.parse::<f64>().map_err(|_| {
                    Error::bad(
                        "command line",
                        "--factors",
                        format!("{s:?} is not a number; give e.g. 0.25,1,4,16"),
                    )
                })
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
        let output = self
            .output
            .unwrap_or_else(|| crate::render::default_output(&self.input, self.gif));
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
            gif: self.gif,
            step: self.step,
            scenario: self.scenario,
        })
    }
}
