//! `[output]`: which optional outputs a scene writes, and how often. A
//! command-line flag (`--vtk-every`, `--trajectory-every`) overrides its key.

use super::check::Ctx;
use super::file::OutputSection;
use crate::error::Result;

/// Optional outputs and their cadences, in steps; `None`: not written.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OutputRequest {
    /// A VTK frame every this many steps (`fibres.pvd`, `vtk/`).
    pub vtk_every: Option<u64>,
    /// A `trajectory.csv` row per body every this many steps.
    pub trajectory_every: Option<u64>,
    /// `orientation.csv` holds every body (`[output] orientation = "all"`),
    /// not only those that need it (a prescribed torque, a closed form).
    pub orientation_all: bool,
}

/// A cadence: at least one step; `key` names it in the message.
pub(crate) fn cadence(src: &str, key: &str, v: Option<u64>) -> Result<Option<u64>> {
    match v {
        Some(0) => Err(Ctx { src }.err(
            key,
            "must be >= 1 (steps between two outputs); remove it to write none",
        )),
        v => Ok(v),
    }
}

pub(super) fn build_output(src: &str, raw: Option<&OutputSection>) -> Result<OutputRequest> {
    let Some(o) = raw else {
        return Ok(OutputRequest::default());
    };
    let orientation_all = match o.orientation.as_deref() {
        None | Some("needed") => false,
        Some("all") => true,
        // The pre-check refuses it first, with the others in its report.
        Some(other) => {
            return Err(Ctx { src }.err(
                "output.orientation",
                super::check::unknown_name(super::keys::Kind::OrientationBodies, other),
            ))
        }
    };
    Ok(OutputRequest {
        vtk_every: cadence(src, "output.vtk_every", o.vtk_every)?,
        trajectory_every: cadence(src, "output.trajectory_every", o.trajectory_every)?,
        orientation_all,
    })
}
