//! MPI domain decomposition (cargo feature `mpi`): `mpirun -np K fibresim
//! run SCENARIO` splits the bodies between K ranks and gives the bytes of
//! one process.
//!
//! - [`slabs`]: K slabs along the axis of largest centre spread, cut by
//!   fibre count; ghosts within L_max + D_max + skin of a slab.
//! - [`stepper`]: one rank's step (owned bodies, ghost exchange, migration
//!   at the one-process rebuilds, forces in the one-process order).
//! - [`tally`]: the scene sums (ledger, contact statistics) on rank 0 in
//!   the one-process order, broadcast to every rank.
//! - [`carry`]: what contacts keep (pair memories, contacts' records)
//!   sent between ranks at rebuilds and gathered for checkpoints.
//! - [`comm`]: the collectives (rsmpi), timed and counted.
//!
//! Outputs are written by rank 0, which gathers the states at every output
//! event, checkpoint and at the end (checkpoints are the one-process
//! format, so they resume with any number of ranks). MPI calls are made
//! only outside the rayon scopes of the force stage, so each rank still
//! runs its own threads (`--threads`).

mod carry;
mod comm;
mod slabs;
mod stepper;
mod tally;

use crate::error::{Error, Result};
use crate::output::checkpoint::Checkpoint;
use crate::output::Summary;
use crate::run::RunOptions;
use crate::scenario::Scene;
use comm::Comm;
use mpi::traits::*;
use std::path::PathBuf;
use stepper::{Clocks, RankStep};

/// Whether this process was started by an MPI launcher (OpenMPI's or
/// MPICH's `mpirun`/`mpiexec`, or a PMIx launcher such as `srun`).
pub fn launched() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
        .iter()
        .any(|k| std::env::var_os(k).is_some())
}

/// A run for the ranks, as its caller prepared it (every rank prepares
/// the same).
pub struct Job<'a> {
    /// The scene (its step-0 states move into the run).
    pub scene: Scene,
    /// Where to write and how often to checkpoint.
    pub opts: &'a RunOptions,
    /// The checkpoint to continue, and the folder it was found in.
    pub resume: Option<&'a (Checkpoint, PathBuf)>,
    /// Printed by rank 0 before the run.
    pub warnings: Vec<String>,
    /// Printed by rank 0 after the warnings.
    pub notes: Vec<String>,
    /// No per-rank table on stderr.
    pub quiet: bool,
}

/// `job` on the MPI ranks: every rank runs it; rank 0 writes, and hands
/// its outcome to `report` (what the caller prints of it). A stop (a
/// guard, Ctrl-C) ends every rank with the same diagnosis and exit code;
/// an error of rank 0 alone (an output it cannot write) aborts the job
/// with its exit code.
pub fn run(mut job: Job, report: impl FnOnce(&Scene, &Result<Summary>)) -> Result<()> {
    let Some((universe, _)) = mpi::initialize_with_threading(mpi::Threading::Funneled) else {
        return Err(Error::bad("mpirun", "MPI", "MPI could not be initialised"));
    };
    let world = universe.world();
    let root = world.rank() == 0;
    // The world takes the step-0 states; the scene keeps no copy.
    let initial = std::mem::take(&mut job.scene.initial);
    let result = run_ranked(&job, initial, &world, root, report);
    match &result {
        Err(e) if root && !matches!(e, Error::Unstable(_) | Error::Interrupted(_)) => {
            // Only rank 0 writes: the others wait in a collective.
            eprintln!("error: {e}");
            world.abort(e.exit_code());
        }
        _ => {}
    }
    drop(world);
    drop(universe);
    match result {
        Err(e) if !root => std::process::exit(e.exit_code()),
        r => r,
    }
}

fn run_ranked(
    job: &Job,
    initial: Vec<crate::body::BodyState>,
    world: &mpi::topology::SimpleCommunicator,
    root: bool,
    report_outcome: impl FnOnce(&Scene, &Result<Summary>),
) -> Result<()> {
    let scene = &job.scene;
    let out_dir = &job.opts.out_dir;
    if root {
        for w in &job.warnings {
            eprintln!("warning: {w}");
        }
        for n in &job.notes {
            eprintln!("note: {n}");
        }
    }
    let _ = ctrlc::set_handler(|| {
        crate::run::INTERRUPTED.store(true, std::sync::atomic::Ordering::Relaxed)
    });
    let progress = root
        .then(|| {
            crate::output::Progress::of_run(
                scene.sim.steps(),
                job.opts.progress,
                job.opts.progress_lines,
            )
        })
        .flatten();
    let mut stepper = RankStep::new(Comm::new(world));
    let outcome = crate::run::run_by(
        scene,
        initial,
        job.opts,
        job.resume.map(|r| &r.0),
        progress,
        &mut stepper,
        root,
    );
    if let Err(e) = &outcome {
        if root && !matches!(e, Error::Unstable(_) | Error::Interrupted(_)) {
            return outcome.map(|_| ());
        }
    }
    let ranks = report(&mut stepper);
    if let (Some(ranks), Ok(Some(_))) = (&ranks, &outcome) {
        if !job.quiet {
            eprint!("{}", ranks.table());
        }
        if stepper.comm.size > 1 {
            ranks.splice_into(&out_dir.join("summary.json"))?;
        }
    }
    if root {
        let o = outcome.map(|s| s.expect("rank 0 writes the summary"));
        report_outcome(scene, &o);
        o.map(|_| ())
    } else {
        outcome.map(|_| ())
    }
}

/// The per-rank report, on rank 0.
struct Report {
    rows: Vec<[f64; ROW]>,
}

const ROW: usize = 10;

/// Every rank's clocks and traffic, on rank 0.
fn report(s: &mut RankStep) -> Option<Report> {
    let c: Clocks = s.clocks;
    let steps = c.steps.max(1) as f64;
    let row = [
        c.owned as f64 / steps,
        c.ghosts as f64 / steps,
        c.forces.as_secs_f64(),
        c.integrate.as_secs_f64(),
        s.comm.time.as_secs_f64(),
        s.comm.waiting.as_secs_f64(),
        s.comm.bytes as f64,
        c.steps as f64,
        c.rebuilds as f64,
        c.migrated as f64,
    ];
    let (all, _) = s.comm.gather(&row)?;
    Some(Report {
        rows: all
            .chunks_exact(ROW)
            .map(|r| r.try_into().expect("rows of ROW"))
            .collect(),
    })
}

impl Report {
    fn table(&self) -> String {
        let mut t = String::from(
            "rank  bodies  ghosts  force_s  integrate_s  comm_s  wait_s  bytes/step  bytes/body-step  rebuilds  migrated\n",
        );
        for (r, row) in self.rows.iter().enumerate() {
            let per_step = row[6] / row[7].max(1.0);
            t += &format!(
                "{r:>4}  {:>6.0}  {:>6.0}  {:>7.3}  {:>11.3}  {:>6.3}  {:>6.3}  {:>10.0}  {:>15.1}  {:>8.0}  {:>8.0}\n",
                row[0],
                row[1],
                row[2],
                row[3],
                row[4],
                row[5],
                per_step,
                per_step / row[0].max(1.0),
                row[8],
                row[9]
            );
        }
        t
    }

    /// Add the report to `summary.json` under `ranks` (only for K > 1, so
    /// a one-process summary keeps its bytes).
    fn splice_into(&self, path: &std::path::Path) -> Result<()> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let rows: Vec<serde_json::Value> = self
            .rows
            .iter()
            .enumerate()
            .map(|(r, row)| {
                let per_step = row[6] / row[7].max(1.0);
                serde_json::json!({
                    "rank": r,
                    "bodies": row[0],
                    "ghosts": row[1],
                    "force_s": row[2],
                    "integrate_s": row[3],
                    "comm_s": row[4],
                    "wait_s": row[5],
                    "bytes_per_step": per_step,
                    "bytes_per_body_step": per_step / row[0].max(1.0),
                    "rebuilds": row[8],
                    "migrated": row[9],
                })
            })
            .collect();
        let ranks = serde_json::to_string_pretty(&rows).expect("rows serialise");
        let body = text.trim_end().strip_suffix('}').ok_or_else(|| {
            Error::bad(
                path.display().to_string(),
                "summary",
                "is not a JSON object",
            )
        })?;
        let ranks = ranks.replace('\n', "\n  ");
        let out = format!("{},\n  \"ranks\": {ranks}\n}}\n", body.trim_end());
        // Whole or not at all: a kill here leaves the one-process summary.
        crate::output::file::write_whole(path, out.as_bytes())
    }
}
