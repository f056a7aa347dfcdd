//! Studies over many runs: `compare` (rotators side by side at one δt),
//! `converge` (error against δt, observed orders, work–precision) and `plot`
//! (any of our CSV files). Runs go in parallel with rayon; each run is
//! deterministic, so outputs do not depend on the thread count.

pub mod compare;
pub mod converge;
pub mod csvplot;
pub mod fit;
pub mod long_run;
pub mod order;
pub mod stress;
mod style;

pub(crate) use style::{rotator_slot, slot_of_label};

use crate::error::{Diagnosis, Error, Result};
use crate::integrate::rotate::RotatorKind;
use crate::plot::{Chart, PlotError};
use crate::run::integrate_observed;
use crate::scenario::{Scene, SimParams};
use glam::DQuat;
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

/// The rotators of `kinds` that can run `scene`: in a scene that computes
/// contacts the compositions (`split4`) are left out, with a note on stderr
/// ([`RotatorKind::contact_refusal`]); none left is bad input naming
/// `--rotators`.
pub(crate) fn runnable(scene: &Scene, kinds: &[RotatorKind]) -> Result<Vec<RotatorKind>> {
    if !scene.needs_contacts() {
        return Ok(kinds.to_vec());
    }
    let (ok, refused): (Vec<RotatorKind>, Vec<RotatorKind>) = kinds
        .iter()
        .copied()
        .partition(|k| k.contact_refusal().is_none());
    match (ok.is_empty(), refused.first()) {
        (true, Some(k)) => Err(Error::bad(
            "command line",
            "--rotators",
            k.contact_refusal().unwrap_or_default(),
        )),
        (_, Some(_)) => {
            let names: Vec<_> = refused.iter().map(|k| k.name()).collect();
            eprintln!(
                "note: {} left out: contact-free scenes only (one force evaluation per step here)",
                names.join(", ")
            );
            Ok(ok)
        }
        _ => Ok(ok),
    }
}

/// `scene` with rotator `kind`, step `dt` and end time `t_end` (checked).
pub(crate) fn with_params(scene: &Scene, kind: RotatorKind, dt: f64, t_end: f64) -> Result<Scene> {
    let mut s = scene.clone();
    s.sim = SimParams::new(dt, t_end, kind, scene.sim.every(), "command line", "--")?;
    Ok(s)
}

/// Render `chart` to `<stem>.png` and `<stem>.svg` in `dir`.
pub(crate) fn render_both(chart: &Chart, dir: &Path, stem: &str) -> Result<()> {
    for ext in ["png", "svg"] {
        let p = dir.join(format!("{stem}.{ext}"));
        crate::plot::render(chart, &p).map_err(plot_error)?;
    }
    Ok(())
}

/// A figure that could not be written: bad input for a format we do not
/// write (only `fibresim plot -o` chooses one), else an I/O error.
pub(crate) fn plot_error(e: PlotError) -> Error {
    if let PlotError::UnsupportedFormat { .. } = e {
        return Error::bad("command line", "--out", e.to_string());
    }
    Error::io(e.path(), std::io::Error::other(e.to_string()))
}

/// Progress of a study: one bar per run plus an overall bar with ETA, drawn
/// only when stderr is a terminal (all no-ops otherwise).
pub(crate) struct Progress {
    mp: Option<MultiProgress>,
    overall: Option<ProgressBar>,
}

impl Progress {
    /// `total` is the total work in body-steps (so the ETA weighs long runs).
    pub(crate) fn new(enabled: bool, total: u64, what: &str) -> Self {
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
    pub(crate) fn run_bar(&self, label: &str, steps: u64) -> Option<ProgressBar> {
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

    /// [`Progress::run_bar`], moved on by the step from a run's observer.
    pub(crate) fn step_bar(&self, label: &str, steps: u64) -> StepBar {
        StepBar {
            bar: self.run_bar(label, steps),
            every: (steps / 200).max(1),
        }
    }

    /// Mark `work` body-steps done on the overall bar.
    pub(crate) fn done(&self, work: u64) {
        if let Some(o) = &self.overall {
            o.inc(work);
        }
    }

    /// Clear the overall bar.
    pub(crate) fn finish(&self) {
        if let Some(o) = &self.overall {
            o.finish_and_clear();
        }
    }
}

/// One run's bar, updated about 200 times over the run (a redraw per step
/// would cost more than a short run's steps).
pub(crate) struct StepBar {
    bar: Option<ProgressBar>,
    every: u64,
}

impl StepBar {
    /// The run has completed `step` steps.
    pub(crate) fn at(&self, step: u64) {
        if let Some(b) = &self.bar {
            if step.is_multiple_of(self.every) {
                b.set_position(step);
            }
        }
    }

    /// The run is over: remove its bar.
    pub(crate) fn finish(self) {
        if let Some(b) = self.bar {
            b.finish_and_clear();
        }
    }
}

/// Run `s` and keep every body's orientation at step 0 and every `every`
/// steps: `q[k * bodies + i]` is body `i` at step `k * every`.
pub(crate) fn sample_orientations(
    s: &Scene,
    every: u64,
    progress: &Progress,
    label: &str,
) -> std::result::Result<Vec<DQuat>, Diagnosis> {
    let bar = progress.step_bar(label, s.sim.steps());
    let mut q: Vec<DQuat> = s.initial.iter().map(|b| b.rot.q).collect();
    let r = integrate_observed(s, |w| {
        if w.step.is_multiple_of(every) {
            q.extend(w.states.iter().map(|b| b.rot.q));
        }
        bar.at(w.step);
    });
    bar.finish();
    progress.done(s.sim.steps() * s.bodies.len() as u64);
    r.map(|_| q)
}

/// The file name of a scene's source, for figure titles.
pub(crate) fn scene_name(scene: &Scene) -> &str {
    scene.source.rsplit('/').next().unwrap_or(&scene.source)
}

/// Format an optional number for tables: `-` when missing or not finite.
pub(crate) fn fmt_e(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3e}")
    } else {
        "-".into()
    }
}

/// Shortest round-trip text of `x`, empty for NaN (CSV cells).
pub(crate) fn cell(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        crate::output::num(x)
    }
}

/// Write a CSV file from a header and rows of text cells.
pub(crate) fn write_csv(path: &Path, header: &[&str], rows: &[Vec<String>]) -> Result<()> {
    let io = |e: csv::Error| Error::io(path, std::io::Error::other(e.to_string()));
    let mut w = csv::Writer::from_path(path).map_err(io)?;
    w.write_record(header).map_err(io)?;
    for r in rows {
        w.write_record(r).map_err(io)?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}
