//! Continuing a run from its checkpoint: the scene it was taken from, the
//! check that its folder still holds the outputs it recorded, those outputs
//! continued in place or copied into another folder, and the command that
//! resumes a run.

use crate::error::{Error, Result};
use crate::output::checkpoint::unbits;
use crate::output::folder;
use crate::output::Checkpoint;
use crate::scenario::Scene;
use std::io::Read;
use std::path::Path;

/// Rebuild the scene a checkpoint was taken from, with its δt, rotator,
/// cadence, guards, restitution and planned steps; `t_end` overrides the
/// planned end.
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
    scene.sim = match t_end {
        Some(t) => {
            crate::scenario::SimParams::new(dt, t, rotator, Some(c.every), "command line", "--")?
        }
        None => {
            crate::scenario::SimParams::with_steps(dt, c.steps_planned, rotator, Some(c.every))?
        }
    };
    if scene.sim.steps() < c.step {
        return Err(Error::bad(
            "command line",
            "--t-end",
            format!(
                "the checkpoint is at step {} (t = {}), past t_end = {}",
                c.step,
                crate::fmt::short(c.t),
                crate::fmt::short(scene.sim.t_end())
            ),
        ));
    }
    // The restitution and friction the run used (`settle --restitution`
    // may have set them over the scenario's), as δt and the rotator are
    // the run's.
    if let Some(part) = &c.damping {
        scene.damping = part.restitution()?;
        if let Some(f) = part.friction()? {
            scene.friction = Some(f);
        }
    }
    scene.guards.energy_error_pct = unbits(&c.guards[0], "guards")?;
    scene.guards.overlap_ratio = unbits(&c.guards[1], "guards")?;
    Ok(scene)
}

/// Check, before anything runs, that the checkpoint's folder `dir` still
/// holds every output the checkpoint recorded, with the same bytes up to
/// its mark: another run written into the folder after the checkpoint is
/// refused (exit 2) naming the file, and nothing is touched.
pub fn check_outputs(c: &Checkpoint, dir: &Path) -> Result<()> {
    for (name, mark) in &c.outputs {
        let path = dir.join(name);
        if let Some(why) = mark.mismatch(&path) {
            return Err(Error::bad(
                path.display().to_string(),
                "--resume",
                format!("{why}: the folder no longer holds the outputs this checkpoint continues (another run wrote there after it, or the file was changed), so resuming would mix two runs; rerun from the start, with --force to replace these outputs"),
            ));
        }
    }
    Ok(())
}

/// Whether two paths name the same folder.
pub fn same_folder(a: &Path, b: &Path) -> bool {
    a == b
        || match (a.canonicalize(), b.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
}

/// Make `to` hold exactly the outputs the checkpoint `c` (found in `from`)
/// recorded, before the resumed run appends to them: in the checkpoint's
/// own folder, the outputs it did not record (frames written after it, the
/// summary of the run before, states files of other checkpoints) are removed; into another folder, its
/// earlier outputs are removed and the recorded ones copied, cut to the
/// recorded lengths (the checkpoint's folder is left as it is).
pub fn continue_in(c: &Checkpoint, from: &Path, to: &Path) -> Result<()> {
    use crate::output::checkpoint::CHECKPOINT_FILE;
    if same_folder(from, to) {
        let keep =
            |n: &String| c.outputs.contains_key(n) || *n == CHECKPOINT_FILE || *n == c.states_file;
        let stale: Vec<String> = folder::outputs_in(to)?
            .into_iter()
            .filter(|n| !keep(n))
            .collect();
        return folder::remove(to, &stale);
    }
    folder::clear(to)?;
    for (name, mark) in &c.outputs {
        let len = mark.bytes;
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

/// The command that resumes from `checkpoint` (`fibresim <command>
/// --resume <checkpoint>` and the `flags` it needs), for messages; words
/// are quoted for a POSIX shell where needed.
pub fn resume_command(command: &str, checkpoint: &Path, flags: &[(&str, String)]) -> String {
    let mut words = vec![
        "fibresim".to_string(),
        command.to_string(),
        "--resume".into(),
        shell_word(&checkpoint.display().to_string()),
    ];
    for (flag, value) in flags {
        words.push(flag.to_string());
        if !value.is_empty() {
            words.push(shell_word(value));
        }
    }
    words.join(" ")
}

/// `s` as one word of a POSIX shell.
fn shell_word(s: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_-./=:,+@%".contains(c);
    if !s.is_empty() && s.chars().all(plain) {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn resume_commands_quote_what_a_shell_would_split() {
        let c = super::resume_command(
            "settle",
            std::path::Path::new("out/my bed/checkpoint.json"),
            &[
                ("--write", "bed's.toml".into()),
                ("--allow-large-dt", String::new()),
            ],
        );
        assert_eq!(
            c,
            "fibresim settle --resume 'out/my bed/checkpoint.json' --write 'bed'\\''s.toml' --allow-large-dt"
        );
    }
}
