//! `summary.json`: one object per run, for scripts.

use crate::error::Result;
use crate::math::wxyz;
use crate::output::Checkpoint;
use crate::run::observer::{Observer, RunEnd, View};
use crate::stop::Diagnosis;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The file name in the output folder.
pub const SUMMARY_FILE: &str = "summary.json";

/// One body's final state (`final` in summary.json).
#[derive(Debug, Clone, Serialize)]
pub struct BodyFinal {
    /// Global body id.
    pub body: u64,
    /// `[w, x, y, z]`.
    pub q: [f64; 4],
    /// Centre of mass, m.
    pub x: [f64; 3],
    /// Velocity, m/s.
    pub v: [f64; 3],
    /// Body-frame angular velocity, rad/s.
    pub omega_body: [f64; 3],
}

/// `summary.json` (key names are a public contract).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// The scenario file (or `<built-in …>`).
    pub scenario: String,
    /// The rotator's name.
    pub rotator: String,
    /// Time step, s.
    pub dt: f64,
    /// Steps actually taken (fewer than planned if the run stopped).
    pub steps: u64,
    /// Steps the run was to take.
    pub steps_planned: u64,
    /// The step this invocation started from (0, or the checkpoint's):
    /// its rates count `steps − first_step` (not written: `wall_s` and
    /// `ns_per_body_step` already count this invocation only).
    #[serde(skip)]
    pub first_step: u64,
    /// Planned end time `steps_planned · dt`, s.
    pub t_end: f64,
    /// Steps between two output rows.
    pub every: u64,
    /// Number of bodies.
    pub bodies: usize,
    /// Wall time of the stepping loop including output, s: this invocation
    /// only (after `--resume`, the resumed part).
    pub wall_s: f64,
    /// Wall time of every part of the run: before the checkpoint(s) resumed
    /// from, plus `wall_s`, s.
    pub wall_total_s: f64,
    /// `wall_s` per body and step, ns.
    pub ns_per_body_step: f64,
    /// Largest Eq. 65 error over every step, % (`null` when E₀ = 0).
    pub energy_error_max_pct: Option<f64>,
    /// Eq. 65 error at the last step, %.
    pub energy_error_final_pct: Option<f64>,
    /// Largest full-budget (with elastic energy) error over every step, %.
    pub energy_error_full_max_pct: Option<f64>,
    /// Full-budget error at the last step, %.
    pub energy_error_full_final_pct: Option<f64>,
    /// Kinetic energy (translation and rotation) at the last step, J
    /// (not written: `fibresim settle` reports it).
    #[serde(skip)]
    pub kinetic_final: f64,
    /// Damped scenes: energy dissipated by the contacts, J.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_dissipated: Option<f64>,
    /// Contact scenes: the largest overlap over the fibre diameter, δ/D.
    pub max_overlap_ratio: Option<f64>,
    /// Closed-form scenes: geodesic angle to the reference at the end, rad.
    pub reference_error_final_rad: Option<f64>,
    /// Closed-form scenes: relative error of the body-x vector's x-component at
    /// the end, percent (the paper's Table 2 "position error").
    pub reference_x_error_pct: Option<f64>,
    /// Why the run stopped early, if it did.
    pub stopped: Option<Diagnosis>,
    /// `fibresim settle`: whether the bed settled before `t_end`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settled: Option<bool>,
    /// The state of every `[[body]]` body at the last step (bodies of a body
    /// file are left out: `fibresim settle` writes them as a body file).
    #[serde(rename = "final")]
    pub final_state: Vec<BodyFinal>,
}

/// `None` for NaN, so JSON stays valid (`null`).
pub fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl Summary {
    /// The summary of the run `v` ended as `end`, with rows every `every`
    /// steps, after `wall_before_s` of earlier parts (0 for a new run).
    pub fn of(v: &View, end: &RunEnd, every: u64, wall_before_s: f64) -> Self {
        let (world, stats) = (v.world, v.stats);
        let scene = world.scene;
        let sim = &scene.sim;
        let (ref_err, ref_x_err) = match scene.reference.as_ref() {
            Some(r) if end.stopped.is_none() => {
                let q_ref = r.orientation(world.time());
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
        let body_steps =
            ((world.step - end.first_step) as f64 * scene.bodies.len() as f64).max(1.0);
        Summary {
            scenario: scene.source.clone(),
            rotator: sim.rotator().name().to_string(),
            dt: sim.dt(),
            steps: world.step,
            steps_planned: sim.steps(),
            first_step: end.first_step,
            t_end: sim.t_end(),
            every,
            bodies: scene.bodies.len(),
            wall_s: end.wall_s,
            wall_total_s: wall_before_s + end.wall_s,
            ns_per_body_step: end.wall_s * 1e9 / body_steps,
            energy_error_max_pct: finite(stats.max_error())
                .filter(|_| stats.last_error().is_finite()),
            energy_error_final_pct: finite(stats.last_error()),
            energy_error_full_max_pct: finite(stats.max_error_full())
                .filter(|_| stats.last_error_full().is_finite()),
            energy_error_full_final_pct: finite(stats.last_error_full()),
            kinetic_final: world.ledger.translation + world.ledger.rotation,
            energy_dissipated: scene.damping.is_some().then_some(world.ledger.dissipated),
            max_overlap_ratio: world.contacts.is_some().then_some(stats.max_overlap_ratio),
            reference_error_final_rad: ref_err,
            reference_x_error_pct: ref_x_err,
            stopped: end.stopped.cloned(),
            settled: None,
            final_state: world.states[..scene.names.len()]
                .iter()
                .zip(scene.ids.iter())
                .map(|(s, id)| BodyFinal {
                    body: id,
                    q: wxyz(s.rot.q),
                    x: s.x.to_array(),
                    v: s.v.to_array(),
                    omega_body: s.rot.omega_b.to_array(),
                })
                .collect(),
        }
    }

    /// Write as pretty JSON (whole or absent).
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(self).expect("summary serialises");
        super::file::write_whole(path, (text + "\n").as_bytes())
    }

    /// Body-steps per second of this invocation (after a resume, of the
    /// steps it took).
    pub fn body_steps_per_s(&self) -> f64 {
        let steps = self.steps.saturating_sub(self.first_step) as f64;
        steps * self.bodies as f64 / self.wall_s.max(1e-9)
    }
}

/// The observer that writes `summary.json` when the run ends (also after a
/// stop), and keeps the summary for the caller.
pub struct SummaryJson {
    path: PathBuf,
    every: u64,
    settle: Option<crate::run::Settle>,
    /// Wall time of the parts before the checkpoint resumed from, s.
    wall_before_s: f64,
    /// When this invocation started.
    started: std::time::Instant,
    /// The summary, once the run has ended.
    pub summary: Option<Summary>,
}

/// Its name in checkpoints.
const NAME: &str = SUMMARY_FILE;

impl SummaryJson {
    /// `summary.json` in `dir`, for a run with rows every `every` steps.
    pub fn new(dir: &Path, every: u64) -> Self {
        SummaryJson {
            path: dir.join(SUMMARY_FILE),
            every,
            settle: None,
            wall_before_s: 0.0,
            started: std::time::Instant::now(),
            summary: None,
        }
    }

    /// Record whether the final state meets `settle` (`fibresim settle`).
    pub fn with_settle(mut self, settle: Option<crate::run::Settle>) -> Self {
        self.settle = settle;
        self
    }
}

impl Observer for SummaryJson {
    fn start(&mut self, _v: &View) -> Result<()> {
        self.started = std::time::Instant::now();
        Ok(())
    }

    fn checkpoint(&mut self, c: &mut Checkpoint) -> Result<()> {
        let total = self.wall_before_s + self.started.elapsed().as_secs_f64();
        c.observers
            .insert(NAME.into(), vec![super::checkpoint::bits(total)]);
        Ok(())
    }

    fn resume(&mut self, c: &Checkpoint) -> Result<()> {
        self.started = std::time::Instant::now();
        // Checkpoints written before wall_total_s existed carry no time:
        // their earlier parts count as 0 s.
        if c.observers.contains_key(NAME) {
            self.wall_before_s = c.observer_state(NAME)?.first().copied().unwrap_or(0.0);
        }
        Ok(())
    }

    fn finish(&mut self, v: &View, end: &RunEnd) -> Result<()> {
        let mut s = Summary::of(v, end, self.every, self.wall_before_s);
        s.settled = self.settle.map(|t| t.reached(v.world));
        s.write(&self.path)?;
        self.summary = Some(s);
        Ok(())
    }
}
