//! Checkpoints: everything needed to continue a run bit for bit.
//!
//! Floats are stored as their IEEE-754 bit patterns (hex), so a resumed run
//! continues from exactly the same numbers and NaN statistics survive. The
//! scenario text is embedded, so a later edit of the file cannot change a
//! resumed run. Each observer records its output files with their lengths
//! (cut back to them on resume) and its own state, by name.

use crate::body::{BodyState, RotState};
use crate::error::{Error, Result};
use crate::integrate::rotate::Rotator;
use crate::integrate::step::World;
use crate::run::observer::Observer;
use crate::run::stats::RunStats;
use crate::scenario::Scene;
use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The format this version writes and reads.
pub const FORMAT: &str = "fibresim-checkpoint-2";

#[derive(Debug, Clone, Serialize, Deserialize)]
/// A checkpoint (`checkpoint.json`).
pub struct Checkpoint {
    /// [`FORMAT`].
    pub format: String,
    /// Where the scenario came from.
    pub scenario_source: String,
    /// The scenario text, as read.
    pub scenario_text: String,
    /// The rotator's name.
    pub rotator: String,
    /// δt, bits.
    pub dt: String,
    /// Output cadence of the run's rows.
    pub every: u64,
    /// Guards (energy %, overlap ratio), bits.
    pub guards: [String; 2],
    /// Completed steps; the time is `step · δt` (informative copy in `t`).
    pub step: u64,
    /// The time of `step`, s (informative).
    pub t: f64,
    /// Global body ids, in the order of `states`.
    pub ids: Vec<u64>,
    /// Per body: x, v, q (w, x, y, z), ω_b, bits.
    pub states: Vec<Vec<String>>,
    /// The rotator's per-body auxiliary state, flat, bits.
    pub aux: Vec<String>,
    /// [`RunStats::to_array`], bits.
    pub run_stats: Vec<String>,
    /// Each output file by name, with its length at the checkpoint.
    pub outputs: BTreeMap<String, u64>,
    /// Each observer's own state by its name, bits.
    pub observers: BTreeMap<String, Vec<String>>,
}

/// A float as its 16-digit hex bit pattern.
pub fn bits(x: f64) -> String {
    format!("{:016x}", x.to_bits())
}

/// The float of a hex bit pattern; `what` names it in the error.
pub fn unbits(s: &str, what: &str) -> Result<f64> {
    u64::from_str_radix(s, 16).map(f64::from_bits).map_err(|_| {
        Error::bad(
            "checkpoint",
            what,
            format!("`{s}` is not a 16-digit hex float"),
        )
    })
}

fn unbits_all(v: &[String], what: &str) -> Result<Vec<f64>> {
    v.iter().map(|s| unbits(s, what)).collect()
}

/// A body's state as 13 bit patterns.
pub fn state_bits(s: &BodyState) -> Vec<String> {
    let q = s.rot.q;
    [s.x.to_array(), s.v.to_array()]
        .concat()
        .into_iter()
        .chain([q.w, q.x, q.y, q.z])
        .chain(s.rot.omega_b.to_array())
        .map(bits)
        .collect()
}

/// A body's state from its 13 bit patterns.
pub fn state_from_bits(v: &[String]) -> Result<BodyState> {
    if v.len() != 13 {
        return Err(Error::bad(
            "checkpoint",
            "states",
            "each body needs 13 numbers",
        ));
    }
    let f = unbits_all(v, "states")?;
    Ok(BodyState {
        x: DVec3::new(f[0], f[1], f[2]),
        v: DVec3::new(f[3], f[4], f[5]),
        rot: RotState {
            q: DQuat::from_xyzw(f[7], f[8], f[9], f[6]),
            omega_b: DVec3::new(f[10], f[11], f[12]),
        },
    })
}

impl Checkpoint {
    /// The driver's part of a checkpoint of `w` (observers add theirs).
    pub fn of<R: Rotator>(w: &World, stats: &RunStats) -> Self {
        let scene = w.scene;
        Checkpoint {
            format: FORMAT.into(),
            scenario_source: scene.source.clone(),
            scenario_text: scene.text.clone(),
            rotator: R::INFO.name.into(),
            dt: bits(scene.sim.dt()),
            every: scene.sim.every_or_default(),
            guards: [
                bits(scene.guards.energy_error_pct),
                bits(scene.guards.overlap_ratio),
            ],
            step: w.step,
            t: w.time(),
            ids: scene.ids.clone(),
            states: w.states.iter().map(state_bits).collect(),
            aux: w.aux.iter().copied().map(bits).collect(),
            run_stats: stats.to_array().map(bits).to_vec(),
            outputs: BTreeMap::new(),
            observers: BTreeMap::new(),
        }
    }

    /// Write atomically (temporary file, then rename), so an interrupt while
    /// writing never leaves a torn checkpoint.
    pub fn write(&self, path: &Path) -> Result<()> {
        let tmp = path.with_extension("json.tmp");
        let text = serde_json::to_string_pretty(self).expect("checkpoint serialises");
        std::fs::write(&tmp, text).map_err(|e| Error::io(&tmp, e))?;
        std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))
    }

    /// Read and check a checkpoint file.
    pub fn read(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::bad(
                &file,
                "--resume",
                format!("cannot read the checkpoint: {e}; give the checkpoint.json a run wrote (--checkpoint-every N, or Ctrl-C)"),
            )
        })?;
        // The format first, so an older checkpoint gets a message that says so.
        let format = serde_json::from_str::<serde_json::Value>(&text)
            .ok()
            .and_then(|v| v.get("format").and_then(|f| f.as_str()).map(str::to_string));
        if let Some(f) = format.filter(|f| f != FORMAT) {
            return Err(Error::bad(
                &file,
                "format",
                format!("expected `{FORMAT}`, found `{f}`: this checkpoint was written by another version of fibresim; rerun from the start"),
            ));
        }
        serde_json::from_str(&text).map_err(|e| {
            Error::bad(
                &file,
                "--resume",
                format!("not a fibresim checkpoint: {e}; give the checkpoint.json a run wrote"),
            )
        })
    }

    /// The recorded length of output `name`, or a bad-input error.
    pub fn output_len(&self, name: &str) -> Result<u64> {
        self.outputs.get(name).copied().ok_or_else(|| {
            Error::bad(
                "checkpoint",
                "outputs",
                format!(
                    "records no `{name}`, which this run writes: it does not match its scenario"
                ),
            )
        })
    }

    /// The cadence (steps) observer `name` saved as its state, if this
    /// checkpoint's run had that observer.
    pub fn cadence(&self, name: &str) -> Result<Option<u64>> {
        if !self.observers.contains_key(name) {
            return Ok(None);
        }
        match self.observer_state(name)?.as_slice() {
            [e] if *e >= 1.0 && e.fract() == 0.0 => Ok(Some(*e as u64)),
            _ => Err(Error::bad(
                "checkpoint",
                "observers",
                format!("`{name}` needs its cadence (1 whole number)"),
            )),
        }
    }

    /// Observer `name`'s saved state, as numbers.
    pub fn observer_state(&self, name: &str) -> Result<Vec<f64>> {
        let v = self.observers.get(name).ok_or_else(|| {
            Error::bad(
                "checkpoint",
                "observers",
                format!("has no state for `{name}`: it does not match its scenario"),
            )
        })?;
        unbits_all(v, "observers")
    }
}

/// The states (in storage order), the rotator's auxiliary state and the run
/// statistics of a checkpoint of `scene`, checked against it.
pub fn restore(
    c: &Checkpoint,
    scene: &Scene,
    aux_len: usize,
) -> Result<(Vec<BodyState>, Vec<f64>, RunStats)> {
    let n = scene.bodies.len();
    if c.states.len() != n || c.ids != scene.ids {
        return Err(Error::bad(
            "checkpoint",
            "states",
            "does not match its own scenario",
        ));
    }
    let states = c
        .states
        .iter()
        .map(|s| state_from_bits(s))
        .collect::<Result<Vec<_>>>()?;
    let aux = unbits_all(&c.aux, "aux")?;
    if aux.len() != aux_len * n {
        return Err(Error::bad(
            "checkpoint",
            "aux",
            format!(
                "has {} numbers; rotator `{}` keeps {aux_len} per body",
                aux.len(),
                c.rotator
            ),
        ));
    }
    let s = unbits_all(&c.run_stats, "run_stats")?;
    let stats: [f64; 11] = s
        .try_into()
        .map_err(|_| Error::bad("checkpoint", "run_stats", "needs 11 numbers"))?;
    Ok((states, aux, RunStats::from_array(stats)))
}

/// File name of the checkpoint inside the output folder.
pub const CHECKPOINT_FILE: &str = "checkpoint.json";

/// The observer that writes `checkpoint.json` (last in the observer list, so
/// the checkpoint holds every other observer's part).
pub struct CheckpointFile {
    /// `checkpoint.json` in the output folder.
    pub path: PathBuf,
}

impl Observer for CheckpointFile {
    fn checkpoint(&mut self, c: &mut Checkpoint) -> Result<()> {
        c.write(&self.path)
    }
}
