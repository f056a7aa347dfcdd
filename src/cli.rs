//! Command-line definitions (clap) and their conversion into checked objects.

use crate::integrate::rotate::RotatorKind;
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

#[derive(Debug, Parser)]
#[command(
    name = "fibresim",
    version,
    about = "DEM of frictionless Hertzian cylindrical fibres, for comparing quaternion rotation integrators",
    after_help = "Exit codes: 0 success, 1 I/O failure, 2 bad input, 3 run stopped as unstable."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scenario and write energy.csv, orientation.csv (torque scenes) and summary.json.
    Run(RunArgs),
    /// Validate a scenario and print masses, contact and Rayleigh times, the recommended dt and what will run.
    Check(CheckArgs),
    /// List the rotators with their equations, order and torque contract.
    Rotators,
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
