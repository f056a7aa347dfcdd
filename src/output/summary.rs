//! `summary.json`: one object per run, for scripts.

use crate::error::{Diagnosis, Error, Result};
use serde::Serialize;
use std::path::Path;

#[derive(Debug, Clone, Serialize)]
pub struct BodyFinal {
    pub body: usize,
    /// `[w, x, y, z]`.
    pub q: [f64; 4],
    pub x: [f64; 3],
    pub v: [f64; 3],
    pub omega_body: [f64; 3],
}

#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub scenario: String,
    pub rotator: String,
    pub dt: f64,
    /// Steps actually taken (fewer than planned if the run stopped).
    pub steps: u64,
    pub steps_planned: u64,
    pub t_end: f64,
    pub every: u64,
    pub bodies: usize,
    /// Wall time of the stepping loop including output, s.
    pub wall_s: f64,
    pub ns_per_body_step: f64,
    pub energy_error_max_pct: Option<f64>,
    pub energy_error_final_pct: Option<f64>,
    pub energy_error_full_max_pct: Option<f64>,
    pub energy_error_full_final_pct: Option<f64>,
    /// Contact scenes: the largest overlap over the fibre diameter, δ/D.
    pub max_overlap_ratio: Option<f64>,
    /// Closed-form scenes: geodesic angle to the reference at the end, rad.
    pub reference_error_final_rad: Option<f64>,
    /// Closed-form scenes: relative error of the body-x vector's x-component at
    /// the end, percent (the paper's Table 2 "position error").
    pub reference_x_error_pct: Option<f64>,
    /// Why the run stopped early, if it did.
    pub stopped: Option<Diagnosis>,
    #[serde(rename = "final")]
    pub final_state: Vec<BodyFinal>,
}

/// `None` for NaN, so JSON stays valid (`null`).
pub fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl Summary {
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(self).expect("summary serialises");
        std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))
    }
}
