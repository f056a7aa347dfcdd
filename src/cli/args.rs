//! Command-line definitions (clap): the raw arguments, before any check.
//!
//! clap turns doc comments into `--help` text, so the types here are
//! documented by their help, not by rustdoc.
#![allow(missing_docs, rustdoc::invalid_html_tags)]

use crate::integrate::rotate::RotatorKind;
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// The exit-code table of `fibresim --help` (the README's "Exit codes").
pub const EXIT_CODES: &str = "\
Exit codes:
  0    success
  1    an output file could not be written mid-run (rows written so far are kept)
  2    bad input: malformed TOML, unknown key, wrong type, non-physical value,
       empty scene, missing file, unwritable output folder, dt > t_end; the
       message names the file (and line), the key and the fix
  3    the run was stopped as unstable: a named diagnosis on stderr and in
       summary.json (`stopped`); every row written before the stop is kept
  130  interrupted by Ctrl-C (SIGINT): the current step finishes, a checkpoint
       is written, outputs are flushed; continue with `run --resume`";

#[derive(Debug, Parser)]
#[command(
    name = "fibresim",
    version,
    about = "DEM of frictionless Hertzian cylindrical fibres, for comparing quaternion rotation integrators",
    after_help = "Exit codes: 0 success, 1 I/O failure mid-run, 2 bad input, 3 run stopped as unstable, 130 interrupted (Ctrl-C). More with --help.",
    after_long_help = EXIT_CODES
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    /// Worker threads [default: RAYON_NUM_THREADS, else the available cores]. Scenes of fewer than 256 bodies run on one thread; results are the same bytes whatever the count.
    #[arg(long, global = true, value_name = "N")]
    pub threads: Option<usize>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scenario and write energy.csv, orientation.csv (torque scenes) and summary.json.
    Run(RunArgs),
    /// Validate a scenario and print masses, contact and Rayleigh times, the recommended dt and what will run.
    Check(CheckArgs),
    /// List the rotators with their equations, order and torque contract.
    Rotators(RotatorsArgs),
    /// Run several rotators on one scene at one time step (in parallel) and plot their errors against time.
    Compare(CompareArgs),
    /// Error against time step for each rotator: observed orders, convergence and work-precision figures.
    Converge(ConvergeArgs),
    /// Plot a column of one or more of fibresim's CSV files (one series per file).
    Plot(PlotArgs),
    /// Stress suite: every stress case x rotator over dt = factor x the recommended dt, far past the limit; table and stability map.
    Stress(StressArgs),
    /// Draw fibres as a PNG (a VTK frame or series, a trajectory, a checkpoint or a scenario's start), or a whole run as a GIF.
    Render(RenderArgs),
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// What to draw: fibres.pvd or a vtk/fibres_<step>.vtp frame, trajectory.csv, checkpoint.json, or a scenario .toml (its start).
    pub input: PathBuf,
    /// Output file [default: beside the input, <stem>.png, or <stem>.gif with --gif].
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Animate every frame (a .pvd or a trajectory.csv) into a GIF.
    #[arg(long)]
    pub gif: bool,
    /// Colour by: speed, angle_z (axis against z), contacts, material, kinetic_energy, omega, z, id, or none.
    #[arg(long, default_value = "speed")]
    pub color: String,
    /// Colour range LO,HI in the field's unit [default: the data's, over every frame of a GIF].
    #[arg(long)]
    pub range: Option<String>,
    /// View direction, from the scene toward the camera: front, back, left, right, top, iso, or X,Y,Z.
    #[arg(long, default_value = "iso")]
    pub view: String,
    /// Zoom factor (1: the box, or the fibres, fill the picture).
    #[arg(long, default_value_t = 1.0)]
    pub zoom: f64,
    /// Picture size WxH in pixels.
    #[arg(long, default_value = "1000x800")]
    pub size: String,
    /// Fibres as flat-ended cylinders or as capsules.
    #[arg(long, default_value = "cylinder", value_parser = ["cylinder", "capsule"])]
    pub shape: String,
    /// Draw this step of a trajectory.csv or a .pvd [default: the last].
    #[arg(long)]
    pub step: Option<u64>,
    /// Scenario of a trajectory.csv (its fibre sizes and box) [default: the `scenario` of the summary.json beside it].
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// GIF frames per second.
    #[arg(long, default_value_t = 20.0)]
    pub fps: f64,
}

#[derive(Debug, Args)]
pub struct RotatorsArgs {
    /// Print the README's markdown table instead.
    #[arg(long)]
    pub markdown: bool,
}

#[derive(Debug, Args)]
pub struct StressArgs {
    /// Comma-separated rotator names, `paper` (pcdm,scalar,euler,leapfrog) or `all`.
    #[arg(long, default_value = "all")]
    pub rotators: String,
    /// Stress cases: a glob (`*`, `?`) on the file stems in --dir.
    #[arg(long, default_value = "*")]
    pub cases: String,
    /// Folder of the stress case files.
    #[arg(long, default_value = "scenarios/stress")]
    pub dir: PathBuf,
    /// Comma-separated multiples of each case's recommended dt.
    #[arg(long, default_value = "0.25,0.5,1,2,4,8,16,32,64,128")]
    pub factors: String,
    /// A finished run is inaccurate above this energy (contact-free: also angular momentum) error, percent.
    #[arg(long = "energy-tol", default_value_t = crate::study::stress::ENERGY_TOL_PCT)]
    pub energy_tol: f64,
    /// A finished run is inaccurate when its final velocities and angular momenta are off the rk4 reference by more than this percent of the largest rim speed.
    #[arg(long = "outcome-tol", default_value_t = crate::study::stress::OUTCOME_TOL_PCT)]
    pub outcome_tol: f64,
    /// Output folder.
    #[arg(long, default_value = "out/stress")]
    pub out: PathBuf,
    /// No progress bars and no table on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Scenario TOML file.
    pub scenario: PathBuf,
    /// Comma-separated rotator names, `paper` (pcdm,scalar,euler,leapfrog) or `all`.
    #[arg(long, default_value = "paper")]
    pub rotators: String,
    /// Time step, s [default: the scene's].
    #[arg(long)]
    pub dt: Option<f64>,
    /// End time, s [default: the scene's].
    #[arg(long = "t-end")]
    pub t_end: Option<f64>,
    /// Output folder [default: out/<scenario>/compare].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// No progress bars and no table on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// Scenario TOML file.
    pub scenario: PathBuf,
    /// Comma-separated rotator names, `paper` (pcdm,scalar,euler,leapfrog) or `all` [every scheme, so the work-precision figure shows each].
    #[arg(long, default_value = crate::study::converge::DEFAULT_ROTATORS)]
    pub rotators: String,
    /// Largest time step, s [default: 10x the scene's: 1e-5 for test case 4, the paper's range].
    #[arg(long = "dt-max")]
    pub dt_max: Option<f64>,
    /// Smallest time step, s [default: the scene's / 10; 1e-7 for test case 4].
    #[arg(long = "dt-min")]
    pub dt_min: Option<f64>,
    /// Number of time steps, geometric from dt-max to dt-min (each rounded to a whole multiple of the reference step).
    #[arg(long, default_value_t = 5)]
    pub points: usize,
    /// End time, s [default: the scene's].
    #[arg(long = "t-end")]
    pub t_end: Option<f64>,
    /// Scenes without a closed form: the rk4 reference step is dt-min / this.
    #[arg(long = "ref-factor", default_value_t = 10.0)]
    pub ref_factor: f64,
    /// Output folder [default: out/<scenario>/converge].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// No progress bars and no table on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct PlotArgs {
    /// CSV files (energy.csv, orientation.csv, convergence.csv, compare.csv, ...).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Output figure, .png or .svg [default: next to the first file].
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Column to plot [default: energy_error_pct, err_rad or alpha_rad, whichever exists].
    #[arg(long)]
    pub column: Option<String>,
    /// Column on the x axis [default: t, else dt].
    #[arg(long)]
    pub x: Option<String>,
    /// Force a logarithmic y axis. Without it an axis is logarithmic when its positive values span >= 2 decades and are spread over them; axes show units for known columns.
    #[arg(long = "log-y")]
    pub log_y: bool,
    /// Force a logarithmic x axis (see --log-y).
    #[arg(long = "log-x")]
    pub log_x: bool,
}

#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Scenario TOML file.
    pub scenario: PathBuf,
    /// Judge this time step instead of simulation.dt.
    #[arg(long)]
    pub dt: Option<f64>,
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// Scenario TOML file. Without one, runs the built-in default scene (the paper's test case 2, nine fibres).
    pub scenario: Option<PathBuf>,
    /// Rotation integrator (overrides simulation.rotator). Each one's torque contract is shown below.
    #[arg(long, value_enum)]
    pub rotator: Option<RotatorKind>,
    /// Time step, s (overrides simulation.dt).
    #[arg(long)]
    pub dt: Option<f64>,
    /// End time, s (overrides simulation.t_end).
    #[arg(long = "t-end")]
    pub t_end: Option<f64>,
    /// Output folder [default: out/<scenario>/<rotator>].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write one output row every N steps [default: at most 2e4 rows; every row also carries the largest error since the previous row].
    #[arg(long)]
    pub every: Option<u64>,
    /// Stop when the full-budget energy error exceeds this many percent [default: guards.energy_error_pct, else 10].
    #[arg(long)]
    pub max_energy_error: Option<f64>,
    /// Stop when a contact overlap exceeds this fraction of the diameter [default: guards.overlap_ratio, else 0.2].
    #[arg(long)]
    pub max_overlap: Option<f64>,
    /// Write a VTK frame every N steps: <out>/vtk/fibres_<step>.vtp, listed with its time in <out>/fibres.pvd (open it in ParaView), and the box in <out>/box.vtp [default: output.vtk_every, else none].
    #[arg(long, conflicts_with = "resume")]
    pub vtk_every: Option<u64>,
    /// Write every body's position, quaternion (w,x,y,z), velocity and world angular velocity to <out>/trajectory.csv every N steps [default: output.trajectory_every, else none].
    #[arg(long, conflicts_with = "resume")]
    pub trajectory_every: Option<u64>,
    /// Write <out>/checkpoint.json every N steps (Ctrl-C always writes one).
    #[arg(long)]
    pub checkpoint_every: Option<u64>,
    /// Continue from a checkpoint (its scenario, dt, rotator and cadence; --t-end may extend the run; outputs go to the checkpoint's folder unless --out).
    #[arg(long, conflicts_with_all = ["scenario", "rotator", "dt", "every"])]
    pub resume: Option<PathBuf>,
    /// Run even when dt leaves fewer than 5 steps per Hertz collision (normally refused as bad input).
    #[arg(long)]
    pub allow_large_dt: bool,
    /// No progress bar and no summary on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}
