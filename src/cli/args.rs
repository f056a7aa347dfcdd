//! Command-line definitions (clap): the raw arguments, before any check.
//!
//! clap turns doc comments into `--help` text, so the types here are
//! documented by their help, not by rustdoc.
#![allow(missing_docs, rustdoc::invalid_html_tags)]

use crate::integrate::rotate::RotatorKind;
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// The exit-code table of `fibresim --help` (docs/guide.md, "Exit codes").
pub const EXIT_CODES: &str = "\
Exit codes:
  0    success
  1    an output file could not be written mid-run (rows written so far are kept)
  2    bad input: malformed TOML, unknown key, wrong type, non-physical value,
       empty scene, missing file, unwritable output folder, an --out folder
       that holds another run's outputs (without --force), a checkpoint whose
       folder no longer holds what it recorded, dt > t_end; the message names
       the file (and line), the key and the fix
  3    the run was stopped as unstable: a named diagnosis on stderr and in
       summary.json (`stopped`); every row written before the stop is kept
  130  interrupted by Ctrl-C (SIGINT): the current step finishes, a checkpoint
       is written, outputs are flushed; the message gives the command that
       continues the run (`run --resume` or `settle --resume`)";

#[derive(Debug, Parser)]
#[command(
    name = "fibresim",
    version,
    about = "DEM of Hertzian cylindrical fibres (and spheres), frictionless or with Coulomb friction, for comparing quaternion rotation integrators",
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
    /// List every scenario key: its table, unit, default, allowed values and an example (docs/scenario.md has the full reference).
    Keys(KeysArgs),
    /// Run several rotators on one scene at one time step (in parallel) and plot their errors against time.
    Compare(CompareArgs),
    /// Error against time step for each rotator: observed orders, convergence and work-precision figures.
    Converge(ConvergeArgs),
    /// Plot a column of one or more of fibresim's CSV files (one series per file).
    Plot(PlotArgs),
    /// Stress suite: every stress case x rotator over dt = factor x the recommended dt, far past the limit; table and stability map.
    Stress(StressArgs),
    /// Write a scenario with N non-overlapping fibres in a box, and its body file (random sequential placement on a cell grid).
    Generate(GenerateArgs),
    /// Run a scenario with damping until its kinetic energy per body is below a threshold, then write the settled bed (an elastic scenario and its body file).
    Settle(SettleArgs),
    /// Copy a bed NX x NY x NZ times side by side in a box as many times larger (as LAMMPS's `replicate`), writing a scenario and its body file.
    Replicate(ReplicateArgs),
    /// Draw fibres as a PNG (a VTK frame or series, a trajectory, a checkpoint or a scenario's start), or a whole run as a GIF.
    Render(RenderArgs),
}

#[derive(Debug, Args)]
pub struct GenerateArgs {
    /// Number of fibres.
    #[arg(long, default_value_t = 0)]
    pub n: usize,
    /// Fibre diameter, m: a number, `uniform:MIN:MAX` or `normal:MEAN:SD` (cut at 3 SD) [needed with --n].
    #[arg(long)]
    pub diameter: Option<String>,
    /// Fibre length, m: a number, `uniform:MIN:MAX` or `normal:MEAN:SD` [needed with --n].
    #[arg(long)]
    pub length: Option<String>,
    /// Number of spheres, placed after the fibres in the room they leave.
    #[arg(long, default_value_t = 0)]
    pub spheres: usize,
    /// Sphere diameter, m: a number, `uniform:MIN:MAX` or `normal:MEAN:SD` [needed with --spheres].
    #[arg(long)]
    pub sphere_diameter: Option<String>,
    /// The box (its walls): LX,LY,LZ from the origin, m.
    #[arg(long = "box", value_name = "LX,LY,LZ")]
    pub box_size: String,
    /// Where the fibres go: X0,Y0,Z0,X1,Y1,Z1 inside the box [default: the whole box].
    #[arg(long)]
    pub region: Option<String>,
    /// Axis distribution: isotropic, aligned (along --axis) or planar (in the plane normal to --axis).
    #[arg(long, default_value = "isotropic")]
    pub orientation: String,
    /// The axis of `aligned`, the normal of `planar`.
    #[arg(long, default_value = "0,0,1", allow_hyphen_values = true)]
    pub axis: String,
    /// Initial speed, m/s, in a random direction per fibre.
    #[arg(long, default_value_t = 0.0)]
    pub speed: f64,
    /// Initial velocity VX,VY,VZ of every fibre, m/s (instead of --speed).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "speed")]
    pub velocity: Option<String>,
    /// Angular speed about a random axis normal to each fibre, rad/s.
    #[arg(long, default_value_t = 0.0)]
    pub spin: f64,
    /// Seed of the random draws (same seed, same bytes).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Smallest gap between two fibres' surfaces (and a fibre and a wall) [default: D/20].
    #[arg(long)]
    pub gap: Option<f64>,
    /// Candidates tried per fibre before the region counts as jammed.
    #[arg(long, default_value_t = 10_000)]
    pub max_attempts: u64,
    /// Fibre density, kg/m^3.
    #[arg(long, default_value_t = 1100.0)]
    pub density: f64,
    /// Fibre Young's modulus, Pa.
    #[arg(long, default_value_t = 5e7)]
    pub young: f64,
    /// Fibre Poisson ratio.
    #[arg(long, default_value_t = 0.35)]
    pub poisson: f64,
    /// Wall Young's modulus, Pa [default: the fibres'].
    #[arg(long)]
    pub wall_young: Option<f64>,
    /// Wall Poisson ratio [default: the fibres'].
    #[arg(long)]
    pub wall_poisson: Option<f64>,
    /// Gravity GX,GY,GZ, m/s^2, or `none`.
    #[arg(long, default_value = "0,0,-9.81", allow_hyphen_values = true)]
    pub gravity: String,
    /// Coefficient of restitution of the written scenario, in (0, 1] (1: elastic, no [contact] table).
    #[arg(long, default_value_t = 1.0)]
    pub restitution: f64,
    /// Coulomb friction coefficient of body-body contacts of the written scenario, >= 0 ([contact] friction; 0: frictionless).
    #[arg(long, allow_negative_numbers = true)]
    pub friction: Option<f64>,
    /// Coulomb friction coefficient of body-wall contacts, >= 0 ([contact] wall_friction) [default: --friction].
    #[arg(long, allow_negative_numbers = true)]
    pub wall_friction: Option<f64>,
    /// The scenario's time step, s.
    #[arg(long, default_value_t = 1e-6)]
    pub dt: f64,
    /// The scenario's end time, s.
    #[arg(long = "t-end", default_value_t = 0.01)]
    pub t_end: f64,
    /// The scenario to write (the body file goes beside it as <stem>_bodies.csv); its folder is created.
    #[arg(long, short, value_name = "FILE")]
    pub out: PathBuf,
    /// Print nothing on success.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct ReplicateArgs {
    /// Scenario TOML file of the bed to copy (it must have a [box]).
    pub scenario: PathBuf,
    /// Copies along x, y and z, e.g. 3,3,1.
    #[arg(long, value_name = "NX,NY,NZ")]
    pub times: String,
    /// The scenario to write (the body file goes beside it as <stem>_bodies.csv); its folder is created.
    #[arg(long, short, value_name = "FILE")]
    pub out: PathBuf,
    /// Print nothing on success.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct SettleArgs {
    /// Scenario TOML file (a generated bed, for example).
    #[arg(required_unless_present = "resume")]
    pub scenario: Option<PathBuf>,
    /// Coefficient of restitution while settling (fibre-fibre and fibre-wall) [default: the scenario's [contact]].
    #[arg(long)]
    pub restitution: Option<f64>,
    /// Coulomb friction coefficient of body-body contacts, >= 0, while settling and in the written bed [default: the scenario's [contact] friction].
    #[arg(long, conflicts_with = "resume", allow_negative_numbers = true)]
    pub friction: Option<f64>,
    /// Coulomb friction coefficient of body-wall contacts, >= 0 [default: --friction if given, else the scenario's wall_friction].
    #[arg(long, conflicts_with = "resume", allow_negative_numbers = true)]
    pub wall_friction: Option<f64>,
    /// Time step while settling, s [default: the scenario's].
    #[arg(long)]
    pub dt: Option<f64>,
    /// Give up after this simulated time, s [default: the scenario's t_end].
    #[arg(long = "t-end")]
    pub t_end: Option<f64>,
    /// Settled when the kinetic energy (translation + rotation) per body is at most this, J [default: 1e-4 x the mean m g D], and under gravity every body touches a body or a wall.
    #[arg(long = "ke-per-body", alias = "ke-per-fibre")]
    pub ke_per_body: Option<f64>,
    /// Test the threshold every N steps [default: 100, or the resumed checkpoint's].
    #[arg(long)]
    pub check_every: Option<u64>,
    /// The settled scenario to write (elastic; its body file goes beside it as <stem>_bodies.csv).
    #[arg(long)]
    pub write: PathBuf,
    /// Time step of the written scenario, s [default: the settling one].
    #[arg(long)]
    pub write_dt: Option<f64>,
    /// End time of the written scenario, s [default: 100 steps of --write-dt].
    #[arg(long)]
    pub write_t_end: Option<f64>,
    /// Output folder of the settling run (energy.csv, summary.json) [default: out/<scenario>/settle].
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write one output row every N steps.
    #[arg(long)]
    pub every: Option<u64>,
    /// Write <out>/checkpoint.json every N steps (Ctrl-C always writes one).
    #[arg(long, allow_negative_numbers = true)]
    pub checkpoint_every: Option<u64>,
    /// Continue a settle from its checkpoint (its scenario, restitution, dt, cadence, settle test and end time; --t-end may change the end; outputs go to the checkpoint's folder unless --out).
    #[arg(long, conflicts_with_all = ["scenario", "dt", "every"])]
    pub resume: Option<PathBuf>,
    /// Replace the outputs of another run in the --out folder (all of them) instead of refusing.
    #[arg(long)]
    pub force: bool,
    /// Print a progress line on stderr every SECONDS [default: 5], also on a terminal (without a terminal the lines are on unless -q).
    #[arg(long, value_name = "SECONDS", num_args = 0..=1, require_equals = true, default_missing_value = "5", conflicts_with = "quiet")]
    pub progress: Option<f64>,
    /// Run even when dt leaves fewer than 5 steps per Hertz collision.
    #[arg(long)]
    pub allow_large_dt: bool,
    /// Impact speed for the time-step advice, m/s (instead of the per-body energy bound).
    #[arg(long)]
    pub impact_speed: Option<f64>,
    /// No progress and no summary on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// What to draw: fibres.pvd or a vtk/fibres_<step>.vtp frame, trajectory.csv, checkpoint.json, or a scenario .toml (its start).
    pub input: PathBuf,
    /// The picture to write, its format from the extension: NAME.png (a still) or NAME.gif (every frame animated, as --gif); its folder is created [default: beside the input, <stem>.png, or <stem>.gif with --gif].
    #[arg(short = 'o', long = "out", alias = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Animate every frame (a .pvd or a trajectory.csv) into a GIF (the default with -o NAME.gif).
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
    /// Print docs/rotators.md's markdown table instead.
    #[arg(long)]
    pub markdown: bool,
}

#[derive(Debug, Args)]
pub struct KeysArgs {
    /// Print docs/scenario.md's markdown tables instead.
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
    #[arg(
        long,
        default_value = "0.25,0.5,1,2,4,8,16,32,64,128",
        allow_hyphen_values = true
    )]
    pub factors: String,
    /// A finished run is inaccurate above this energy (contact-free: also angular momentum) error, percent.
    #[arg(long = "energy-tol", default_value_t = crate::study::stress::ENERGY_TOL_PCT, allow_hyphen_values = true)]
    pub energy_tol: f64,
    /// A finished run is inaccurate when its final velocities and angular momenta are off the rk4 reference by more than this percent of the largest rim speed.
    #[arg(long = "outcome-tol", default_value_t = crate::study::stress::OUTCOME_TOL_PCT, allow_hyphen_values = true)]
    pub outcome_tol: f64,
    /// Output folder.
    #[arg(long, short, default_value = "out/stress", value_name = "DIR")]
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
    #[arg(long, allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// End time, s [default: the scene's].
    #[arg(long = "t-end", allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Output folder [default: out/<scenario>/compare].
    #[arg(long, short, value_name = "DIR")]
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
    #[arg(long = "dt-max", allow_hyphen_values = true)]
    pub dt_max: Option<f64>,
    /// Smallest time step, s [default: the scene's / 10; 1e-7 for test case 4].
    #[arg(long = "dt-min", allow_hyphen_values = true)]
    pub dt_min: Option<f64>,
    /// Number of time steps, geometric from dt-max to dt-min (each rounded to a whole multiple of the reference step).
    #[arg(long, default_value_t = 5, allow_negative_numbers = true)]
    pub points: usize,
    /// End time, s [default: the scene's].
    #[arg(long = "t-end", allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Scenes without a closed form: the rk4 reference step is dt-min / this.
    #[arg(
        long = "ref-factor",
        default_value_t = 10.0,
        allow_hyphen_values = true
    )]
    pub ref_factor: f64,
    /// Output folder [default: out/<scenario>/converge].
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Scenes without prescribed torques: also measure each run's trajectory error at T (largest distance and geodesic angle of a body) against this rotator at dt-min / ref-factor [default rotator: nosquish].
    #[arg(long, value_enum, num_args = 0..=1, default_missing_value = "nosquish", value_name = "ROTATOR")]
    pub trajectory: Option<RotatorKind>,
    /// No progress bars and no table on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct PlotArgs {
    /// CSV files: energy.csv, orientation.csv (run); compare.csv (compare); convergence.csv, orders.csv, reference.csv (converge); stress.csv, stress_runs.csv (stress).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// The figure to write, its format from the extension: NAME.png or NAME.svg (others are refused); its folder is created [default: next to the first file].
    #[arg(short = 'o', long = "out", alias = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Column to plot [default: the first with data of energy_error_full_pct (the conserved full budget), err_rad, alpha_rad, energy_error_full_max_pct, max_error, order, richardson_alpha_rad, largest_stable_factor, ax].
    #[arg(long)]
    pub column: Option<String>,
    /// Column on the x axis [default: the first of t, dt, factor, wall_s, nominal_order, recommended_dt].
    #[arg(long)]
    pub x: Option<String>,
    /// Plot an energy error with its sign, (E - E0)/|E0| (energy_error_pct, energy_error_full_pct of energy.csv); the files hold |E - E0|/|E0|.
    #[arg(long)]
    pub signed: bool,
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
    #[arg(long, allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// Time collisions at this impact speed, m/s, instead of the per-body energy bound.
    #[arg(long)]
    pub impact_speed: Option<f64>,
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// Scenario TOML file. Without one, runs the built-in default scene (the paper's test case 2, nine fibres).
    pub scenario: Option<PathBuf>,
    /// Rotation integrator (overrides simulation.rotator). Each one's torque contract is shown below.
    #[arg(long, value_enum)]
    pub rotator: Option<RotatorKind>,
    /// Time step, s (overrides simulation.dt).
    #[arg(long, allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// End time, s (overrides simulation.t_end).
    #[arg(long = "t-end", allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Output folder [default: out/<scenario>/<rotator>].
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write one output row every N steps [default: at most 2e4 rows; every row also carries the largest error since the previous row].
    #[arg(long, allow_negative_numbers = true)]
    pub every: Option<u64>,
    /// Stop when the full-budget energy error exceeds this many percent [default: guards.energy_error_pct, else 10].
    #[arg(long, allow_hyphen_values = true, conflicts_with = "resume")]
    pub max_energy_error: Option<f64>,
    /// Stop when a contact overlap exceeds this fraction of the diameter [default: guards.overlap_ratio, else 0.2].
    #[arg(long, allow_hyphen_values = true, conflicts_with = "resume")]
    pub max_overlap: Option<f64>,
    /// Write a VTK frame every N steps: <out>/vtk/fibres_<step>.vtp, listed with its time in <out>/fibres.pvd (open it in ParaView), and the box in <out>/box.vtp [default: output.vtk_every, else none].
    #[arg(long, conflicts_with = "resume")]
    pub vtk_every: Option<u64>,
    /// Write every body's position, quaternion (w,x,y,z), velocity and world angular velocity to <out>/trajectory.csv every N steps [default: output.trajectory_every, else none].
    #[arg(long, conflicts_with = "resume")]
    pub trajectory_every: Option<u64>,
    /// Write <out>/checkpoint.json every N steps (Ctrl-C always writes one).
    #[arg(long, allow_negative_numbers = true)]
    pub checkpoint_every: Option<u64>,
    /// Continue from a checkpoint (its scenario, dt, rotator, cadences, guards and end time; --t-end may change the end; outputs go to the checkpoint's folder unless --out).
    #[arg(long, conflicts_with_all = ["scenario", "rotator", "dt", "every"])]
    pub resume: Option<PathBuf>,
    /// Replace the outputs of another run in the --out folder (all of them, VTK frames included) instead of refusing.
    #[arg(long)]
    pub force: bool,
    /// Print a progress line on stderr every SECONDS [default: 5], also on a terminal (without a terminal the lines are on unless -q).
    #[arg(long, value_name = "SECONDS", num_args = 0..=1, require_equals = true, default_missing_value = "5", conflicts_with = "quiet")]
    pub progress: Option<f64>,
    /// Run even when dt leaves fewer than 5 steps per Hertz collision (normally refused as bad input).
    #[arg(long)]
    pub allow_large_dt: bool,
    /// Time collisions at this impact speed, m/s, for the advice (instead of the per-body energy bound).
    #[arg(long)]
    pub impact_speed: Option<f64>,
    /// No progress and no summary on stdout.
    #[arg(long, short)]
    pub quiet: bool,
}
