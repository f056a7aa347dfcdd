//! Continuing a run from its checkpoint: the scene it was taken from, and its
//! outputs when the resumed run writes into another folder.

use crate::error::{Error, Result};
use crate::output::checkpoint::unbits;
use crate::output::Checkpoint;
use crate::scenario::Scene;

/// Rebuild the scene a checkpoint was taken from, with its δt, rotator, cadence,
/// guards and restitution; `t_end` overrides the original end time.
pub fn scene_from_checkpoint(c: &Checkpoint, t_end: Option<f64>) -> Result<Scene> {
    let mut scene = crate::scenario::parse_str(&c.scenario_text, &c.scenario_source)?;
    let rotator =
        crate::integrate::rotate::RotatorKind::from_name(&c.rotator).ok_or_else(|| {
            Error::bad(
                "checkpoint",
                "rotator",
                format!("unknown rotator `{}`", c.rotator),
            )
        })?;
    let dt = unbits(&c.dt, "dt")?;
    let t_end = t_end.unwrap_or(scene.sim.t_end());
    scene.sim =
        crate::scenario::SimParams::new(dt, t_end, rotator, Some(c.every), "command line", "--")?;
    if scene.sim.steps() < c.step {
        return Err(Error::bad(
            "command line",
            "--t-end",
            format!(
                "the checkpoint is at step {} (t = {}), past t_end = {t_end}",
                c.step, c.t
            ),
        ));
    }
    // The restitution the run used (`settle --restitution` may have set it
    // over the scenario's), as δt and the rotator are the run's.
    if let Some(part) = &c.damping {
        scene.damping = Some(part.restitution()?);
    }
    scene.guards.energy_error_pct = unbits(&c.guards[0], "guards")?;
    scene.guards.overlap_ratio = unbits(&c.guards[1], "guards")?;
    Ok(scene)
}

/// Resuming into another folder than the checkpoint's (`--resume C --out NEW`):
/// copy the checkpoint folder's outputs, cut to the lengths the checkpoint
/// recorded, into `to`, where the resumed run then appends. Nothing happens
/// when `to` is the checkpoint's folder.
pub fn copy_resume_outputs(
    c: &Checkpoint,
    from: &std::path::Path,
    to: &std::path::Path,
) -> Result<()> {
    use std::io::Read;
    // Copying a folder onto itself would truncate the files it reads.
    let same = from == to
        || match (from.canonicalize(), to.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
    if same {
        return Ok(());
    }
    crate::output::create_out_dir(to)?;
    for (name, &len) in &c.outputs {
        let src = from.join(name);
        let missing = |e: String| {
            Error::bad(
                src.display().to_string(),
                "--resume",
                format!(
                    "{e}; the checkpoint's folder must still hold the outputs it was written with"
                ),
            )
        };
        let f = std::fs::File::open(&src).map_err(|e| missing(format!("cannot read: {e}")))?;
        let have = f.metadata().map_err(|e| missing(e.to_string()))?.len();
        if have < len {
            return Err(missing(format!(
                "is {have} bytes, shorter than the {len} the checkpoint recorded"
            )));
        }
        let dst = to.join(name);
        // Outputs in subfolders (`vtk/fibres_<step>.vtp`).
        if let Some(parent) = dst.parent() {
            crate::output::create_out_dir(parent)?;
        }
        let mut w = std::fs::File::create(&dst)
            .map_err(|e| crate::output::unwritable_at_start(Error::io(&dst, e)))?;
        std::io::copy(&mut f.take(len), &mut w).map_err(|e| Error::io(&dst, e))?;
    }
    Ok(())
}
