//! Checkpoints: everything needed to continue a run bit for bit.
//!
//! Floats are stored as their IEEE-754 bit patterns (hex), so a resumed run
//! continues from exactly the same numbers and NaN statistics survive. The
//! scenario text is embedded, so a later edit of the file cannot change a
//! resumed run. Output files are cut back to the lengths recorded here.

use crate::body::{BodyState, RotState};
use crate::error::{Error, Result};
use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};
use std::path::Path;

pub const FORMAT: &str = "fibresim-checkpoint-1";

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    pub format: String,
    pub scenario_source: String,
    pub scenario_text: String,
    pub rotator: String,
    /// δt, bits.
    pub dt: String,
    pub every: u64,
    /// Guards (energy %, overlap ratio), bits.
    pub guards: [String; 2],
    /// Completed steps; the time is `step · δt` (informative copy in `t`).
    pub step: u64,
    pub t: f64,
    /// Per body: x, v, q (w, x, y, z), ω_b, bits.
    pub states: Vec<Vec<String>>,
    /// `EnergyStats::to_array`, bits.
    pub energy_stats: Vec<String>,
    pub energy_csv_len: u64,
    pub orientation_csv_len: Option<u64>,
}

pub fn bits(x: f64) -> String {
    format!("{:016x}", x.to_bits())
}

pub fn unbits(s: &str, what: &str) -> Result<f64> {
    u64::from_str_radix(s, 16).map(f64::from_bits).map_err(|_| {
        Error::bad(
            "checkpoint",
            what,
            format!("`{s}` is not a 16-digit hex float"),
        )
    })
}

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

pub fn state_from_bits(v: &[String]) -> Result<BodyState> {
    if v.len() != 13 {
        return Err(Error::bad(
            "checkpoint",
            "states",
            "each body needs 13 numbers",
        ));
    }
    let f: Vec<f64> = v
        .iter()
        .map(|s| unbits(s, "states"))
        .collect::<Result<_>>()?;
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
    /// Write atomically (temporary file, then rename), so an interrupt while
    /// writing never leaves a torn checkpoint.
    pub fn write(&self, path: &Path) -> Result<()> {
        let tmp = path.with_extension("json.tmp");
        let text = serde_json::to_string_pretty(self).expect("checkpoint serialises");
        std::fs::write(&tmp, text).map_err(|e| Error::io(&tmp, e))?;
        std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))
    }

    pub fn read(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::bad(
                &file,
                "--resume",
                format!("cannot read the checkpoint: {e}; give the checkpoint.json a run wrote (--checkpoint-every N, or Ctrl-C)"),
            )
        })?;
        let c: Checkpoint = serde_json::from_str(&text).map_err(|e| {
            Error::bad(
                &file,
                "--resume",
                format!("not a fibresim checkpoint: {e}; give the checkpoint.json a run wrote"),
            )
        })?;
        if c.format != FORMAT {
            return Err(Error::bad(
                &file,
                "format",
                format!("expected `{FORMAT}`, found `{}`", c.format),
            ));
        }
        Ok(c)
    }
}
