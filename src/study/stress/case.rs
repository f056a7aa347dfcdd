//! The stress cases: scenes with a recommended δt, loaded from a folder.

use super::SPIN_ANGLE_PER_STEP;
use crate::advice::advise;
use crate::error::{Error, Result};
use crate::scenario::Scene;
use std::path::{Path, PathBuf};

/// One stress scene with its recommended δt.
#[derive(Debug, Clone)]
pub struct StressCase {
    /// The case's name (its file stem).
    pub name: String,
    /// The scene as loaded; the sweep changes only its rotator and step.
    pub scene: Scene,
    /// The δt the factors multiply, s.
    pub recommended_dt: f64,
    /// Where `recommended_dt` comes from.
    pub basis: &'static str,
    /// δt above which `fibresim run` refuses without `--allow-large-dt`.
    pub hard_limit_dt: Option<f64>,
}

impl StressCase {
    /// A case named `name`, its recommended δt as in the module docs. A
    /// contact-free scene needs an initial spin and no prescribed torque.
    pub fn new(name: impl Into<String>, scene: Scene) -> Result<Self> {
        let name = name.into();
        let a = advise(&scene);
        let (recommended_dt, basis) = match a.recommended_dt {
            Some(r) => (r, "Hertz/50, 0.2 Rayleigh"),
            None => {
                let w = scene
                    .initial
                    .iter()
                    .map(|s| s.rot.omega_b.length())
                    .fold(0.0, f64::max);
                if w.is_nan() || w <= 0.0 || scene.has_prescribed_torque() {
                    return Err(Error::bad(
                        &scene.source,
                        "body",
                        "a stress case needs contacts or an initial spin (and no prescribed torque)",
                    ));
                }
                (SPIN_ANGLE_PER_STEP / w, "0.05 rad / |omega|")
            }
        };
        Ok(StressCase {
            name,
            scene,
            recommended_dt,
            basis,
            hard_limit_dt: a.hard_limit_dt,
        })
    }
}

/// Stress cases from the `*.toml` files of `dir` whose stem matches `glob`
/// (`*` and `?`), sorted by name.
pub fn load_cases(dir: &Path, glob: &str) -> Result<Vec<StressCase>> {
    let rd = std::fs::read_dir(dir).map_err(|e| {
        Error::bad(
            dir.display().to_string(),
            "--dir",
            format!("cannot read the stress case folder: {e}"),
        )
    })?;
    let mut paths: Vec<PathBuf> = rd
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter(|p| {
            p.file_stem()
                .and_then(|s| s.to_str())
                .is_some_and(|s| wildcard(glob.trim_end_matches(".toml"), s))
        })
        .collect();
    paths.sort();
    paths
        .iter()
        .map(|p| {
            let name = p.file_stem().and_then(|s| s.to_str()).unwrap_or("case");
            StressCase::new(name, crate::scenario::load(p)?)
        })
        .collect()
}

/// Shell-style match of `pat` (`*`, `?`) against the whole of `s`.
pub fn wildcard(pat: &str, s: &str) -> bool {
    let (p, t): (Vec<char>, Vec<char>) = (pat.chars().collect(), s.chars().collect());
    let (mut i, mut j, mut star, mut mark) = (0, 0, None, 0);
    while j < t.len() {
        if i < p.len() && (p[i] == '?' || p[i] == t[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if let Some(si) = star {
            i = si + 1;
            mark += 1;
            j = mark;
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}
