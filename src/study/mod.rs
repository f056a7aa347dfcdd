//! Studies over many runs: `compare` (rotators side by side at one δt),
//! `converge` (error against δt, observed orders, work–precision) and `plot`
//! (any of our CSV files). Runs go in parallel with rayon; each run is
//! deterministic, so outputs do not depend on the thread count.

pub mod compare;
pub mod converge;
pub mod csvplot;
pub mod fit;
pub mod order;
pub mod stress;

use crate::error::{Error, Result};
use crate::integrate::rotate::RotatorKind;
use crate::plot::{Chart, PlotError};
use crate::scenario::{Scene, SimParams};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::Path;

/// Parse `--rotators`: `all`, `paper`, or a comma-separated list of names.
pub fn parse_rotators(list: Option<&str>) -> Result<Vec<RotatorKind>> {
    let list = match list.map(str::trim) {
        None | Some("paper") => return Ok(RotatorKind::PAPER.to_vec()),
        Some("all") => return Ok(RotatorKind::ALL.to_vec()),
        Some(l) => l,
    };
    let mut out = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let k = RotatorKind::from_name(name).ok_or_else(|| {
            let known: Vec<_> = RotatorKind::ALL.iter().map(|k| k.name()).collect();
            Error::bad(
                "command line",
                "--rotators",
                format!(
                    "unknown rotator {name:?}; expected `all`, `paper` or names from: {}",
                    known.join(", ")
                ),
            )
        })?;
        if !out.contains(&k) {
            out.push(k);
        }
    }
    if out.is_empty() {
        return Err(Error::bad("command line", "--rotators", "no rotator given"));
    }
    Ok(out)
}

/// `scene` with rotator `kind`, step `dt` and end time `t_end` (checked).
pub fn with_params(scene: &Scene, kind: RotatorKind, dt: f64, t_end: f64) -> Result<Scene> {
    let mut s = scene.clone();
    s.sim = SimParams::new(dt, t_end, kind, scene.sim.every(), "command line", "--")?;
    Ok(s)
}

/// Render `chart` to `<stem>.png` and `<stem>.svg` in `dir`.
pub fn render_both(chart: &Chart, dir: &Path, stem: &str) -> Result<()> {
    for ext in ["png", "svg"] {
        let p = dir.join(format!("{stem}.{ext}"));
        crate::plot::render(chart, &p).map_err(plot_error)?;
    }
    Ok(())
}

pub fn plot_error(e: PlotError) -> Error {
    let path = match &e {
        PlotError::UnsupportedFormat { path }
        | PlotError::LengthMismatch { path, .. }
        | PlotError::Font { path }
        | PlotError::Draw { path, .. }
        | PlotError::Encode { path, .. }
        | PlotError::Io { path, .. } => path.clone(),
    };
    if let PlotError::UnsupportedFormat { .. } = e {
        return Error::bad("command line", "-o", e.to_string());
    }
    Error::io(path, std::io::Error::other(e.to_string()))
}

/// Progress of a study: one bar per run plus an overall bar with ETA, drawn
/// only when stderr is a terminal (all no-ops otherwise).
pub struct Progress {
    mp: Option<MultiProgress>,
    overall: Option<ProgressBar>,
}

impl Progress {
    /// `total` is the total work in body-steps (so the ETA weighs long runs).
    pub fn new(enabled: bool, total: u64, what: &str) -> Self {
        if !enabled || !std::io::stderr().is_terminal() {
            return Progress {
                mp: None,
                overall: None,
            };
        }
        let mp = MultiProgress::with_draw_target(ProgressDrawTarget::stderr());
        let overall = mp.add(ProgressBar::new(total));
        overall.set_style(
            ProgressStyle::with_template(&format!(
                "{what:<24} {{bar:30.cyan}} {{percent:>3}}% elapsed {{elapsed}} eta {{eta}}"
            ))
            .expect("static template"),
        );
        Progress {
            mp: Some(mp),
            overall: Some(overall),
        }
    }

    /// A bar for one run, labelled `label`, of `steps` steps.
    pub fn run_bar(&self, label: &str, steps: u64) -> Option<ProgressBar> {
        let mp = self.mp.as_ref()?;
        let pb = mp.add(ProgressBar::new(steps));
        pb.set_style(
            ProgressStyle::with_template(&format!(
                "  {label:<22} {{bar:30}} {{percent:>3}}% eta {{eta}}"
            ))
            .expect("static template"),
        );
        Some(pb)
    }

    /// Mark `work` body-steps done on the overall bar.
    pub fn done(&self, work: u64) {
        if let Some(o) = &self.overall {
            o.inc(work);
        }
    }

    pub fn finish(&self) {
        if let Some(o) = &self.overall {
            o.finish_and_clear();
        }
    }
}

/// Format an optional number for tables: `-` when missing or not finite.
pub fn fmt_e(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3e}")
    } else {
        "-".into()
    }
}

/// Shortest round-trip text of `x`, empty for NaN (CSV cells).
pub fn cell(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        crate::output::num(x)
    }
}

/// Write a CSV file from a header and rows of text cells.
pub fn write_csv(path: &Path, header: &[&str], rows: &[Vec<String>]) -> Result<()> {
    let io = |e: csv::Error| Error::io(path, std::io::Error::other(e.to_string()));
    let mut w = csv::Writer::from_path(path).map_err(io)?;
    w.write_record(header).map_err(io)?;
    for r in rows {
        w.write_record(r).map_err(io)?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// A tick interval for per-step progress updates (about 200 updates per run).
pub fn tick(steps: u64) -> u64 {
    (steps / 200).max(1)
}
