//! A run's output folder, so that two runs never mix: which of its files
//! are a run's outputs; the claim of a new run on a folder (refused when it
//! holds another run's outputs, unless `--force` or the default folder);
//! and the clearing of those outputs before a run writes (a resumed run
//! keeps only the files its checkpoint recorded). Files that are not a
//! run's outputs are never touched.

use super::checkpoint::{is_states_file_name, CHECKPOINT_FILE};
use super::energy::ENERGY_FILE;
use super::orientation::ORIENTATION_FILE;
use super::summary::SUMMARY_FILE;
use super::trajectory::TRAJECTORY_FILE;
use super::vtk::{BOX_FILE, FRAME_DIR, PVD_FILE};
use crate::error::{Error, Result};
use std::path::Path;

/// A run's files in its folder, besides the checkpoint's states files and
/// the frames in [`FRAME_DIR`].
const FILES: [&str; 7] = [
    ENERGY_FILE,
    ORIENTATION_FILE,
    TRAJECTORY_FILE,
    SUMMARY_FILE,
    CHECKPOINT_FILE,
    PVD_FILE,
    BOX_FILE,
];

/// Whether `name` (relative to the folder, `/`-separated) is a run's
/// output: one of [`FILES`], a checkpoint's states file
/// `checkpoint.<step>.states`, a frame `vtk/fibres_<step>.vtp`, or the
/// temporary name of one (`<name>.tmp`, left by a kill while it was written).
pub fn is_output(name: &str) -> bool {
    let name = name.strip_suffix(".tmp").unwrap_or(name);
    if FILES.contains(&name) || is_states_file_name(name) {
        return true;
    }
    name.strip_prefix(FRAME_DIR)
        .and_then(|n| n.strip_prefix("/fibres_"))
        .and_then(|n| n.strip_suffix(".vtp"))
        .is_some_and(|step| !step.is_empty() && step.bytes().all(|b| b.is_ascii_digit()))
}

/// The run outputs in `dir`, sorted by name (none if `dir` does not exist).
pub fn outputs_in(dir: &Path) -> Result<Vec<String>> {
    let mut found = vec![];
    for (sub, prefix) in [
        (dir.to_path_buf(), String::new()),
        (dir.join(FRAME_DIR), format!("{FRAME_DIR}/")),
    ] {
        let entries = match std::fs::read_dir(&sub) {
            Ok(e) => e,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
            Err(e) if e.kind() == std::io::ErrorKind::NotADirectory => continue,
            Err(e) => return Err(Error::io(&sub, e)),
        };
        for entry in entries {
            let entry = entry.map_err(|e| Error::io(&sub, e))?;
            let name = format!("{prefix}{}", entry.file_name().to_string_lossy());
            if is_output(&name) && entry.file_type().is_ok_and(|t| t.is_file()) {
                found.push(name);
            }
        }
    }
    found.sort();
    Ok(found)
}

/// Remove the outputs `names` from `dir`, and the frame folder once empty.
pub fn remove(dir: &Path, names: &[String]) -> Result<()> {
    for name in names {
        let path = dir.join(name);
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(Error::bad(
                    path.display().to_string(),
                    "--out",
                    format!("cannot remove this output of an earlier run: {e}; remove it yourself, or choose another folder with --out DIR"),
                ))
            }
            _ => {}
        }
    }
    // Only if empty: a user's own files in it stay.
    let _ = std::fs::remove_dir(dir.join(FRAME_DIR));
    Ok(())
}

/// Create `dir` for a new run, without any earlier run's outputs.
pub fn clear(dir: &Path) -> Result<()> {
    super::create_out_dir(dir)?;
    remove(dir, &outputs_in(dir)?)
}

/// How a new run came to its folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Claim {
    /// `--out DIR`: another run's outputs there are refused.
    Given,
    /// `--force`: they are replaced.
    Forced,
    /// The default folder of the scenario (and rotator): replaced, with a
    /// note, as a build tool replaces its previous build.
    Default,
}

/// A new run's claim on `dir` (checked before anything runs or is
/// written): an error for a given folder that holds another run's outputs,
/// the note to print when the default folder's are replaced, else nothing.
/// The outputs themselves are removed when the run starts ([`clear`]).
pub fn claim(dir: &Path, how: Claim) -> Result<Option<String>> {
    let found = outputs_in(dir)?;
    if found.is_empty() || how == Claim::Forced {
        return Ok(None);
    }
    let shown = listing(&found);
    let d = dir.display();
    if how == Claim::Default {
        return Ok(Some(format!(
            "replacing an earlier run's outputs in {d} ({shown}), the default folder of this scenario; give --out DIR to keep runs apart"
        )));
    }
    let resume = if found.iter().any(|f| f == CHECKPOINT_FILE) {
        format!(
            ", or continue that run with --resume {}",
            dir.join(CHECKPOINT_FILE).display()
        )
    } else {
        String::new()
    };
    Err(Error::bad(
        d.to_string(),
        "--out",
        format!("holds another run's outputs ({shown}), and two runs never share a folder: give --force to replace them, or another folder with --out DIR{resume}"),
    ))
}

/// `a, b, c and 12 VTK frames`.
fn listing(found: &[String]) -> String {
    let frames = found
        .iter()
        .filter(|f| f.starts_with(&format!("{FRAME_DIR}/")))
        .count();
    let mut parts: Vec<String> = found
        .iter()
        .filter(|f| !f.starts_with(&format!("{FRAME_DIR}/")))
        .cloned()
        .collect();
    if frames > 0 {
        parts.push(format!(
            "{frames} VTK frame{}",
            if frames == 1 { "" } else { "s" }
        ));
    }
    parts.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_are_known_by_name() {
        for yes in [
            "energy.csv",
            "checkpoint.1200.states",
            "checkpoint.json.tmp",
            "vtk/fibres_0.vtp",
            "vtk/fibres_000120.vtp",
            "vtk/fibres_7.vtp.tmp",
            "fibres.pvd",
        ] {
            assert!(is_output(yes), "{yes}");
        }
        for no in [
            "bed.toml",
            "bed_bodies.csv",
            "energy.png",
            "vtk/fibres_.vtp",
            "vtk/fibres_1a.vtp",
            "vtk/mine.vtp",
            "notes.txt",
            "checkpoint.states.bak",
        ] {
            assert!(!is_output(no), "{no}");
        }
    }

    /// Clearing removes a run's outputs and nothing else; the claims.
    #[test]
    fn clear_keeps_other_files_and_claims_name_the_way_out() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("vtk")).unwrap();
        for f in [
            "energy.csv",
            "checkpoint.json",
            "vtk/fibres_10.vtp",
            "notes.txt",
        ] {
            std::fs::write(d.join(f), "x").unwrap();
        }
        let err = claim(d, Claim::Given).unwrap_err().to_string();
        assert!(
            err.contains("--force")
                && err.contains("--out DIR")
                && err.contains("checkpoint.json, energy.csv, 1 VTK frame")
                && err.contains("--resume"),
            "{err}"
        );
        assert!(claim(d, Claim::Default)
            .unwrap()
            .unwrap()
            .contains("replacing"));
        assert_eq!(claim(d, Claim::Forced).unwrap(), None);
        clear(d).unwrap();
        assert_eq!(outputs_in(d).unwrap(), Vec::<String>::new());
        assert!(d.join("notes.txt").exists() && !d.join("vtk").exists());
        assert_eq!(claim(d, Claim::Given).unwrap(), None);
    }
}
