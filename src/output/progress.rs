//! The progress of a run on stderr: the step, the simulated time, the
//! elapsed time, the rate in steps and body-steps per second, and the time
//! left. On a terminal a bar; otherwise (a batch job, a log file) a plain
//! line every [`LINE_SECONDS`], so a long run shows that it is alive. The
//! rate counts only the steps of this invocation, so after `--resume` the
//! bar starts at the checkpoint's step and its ETA is right.

use crate::error::Result;
use crate::output::Checkpoint;
use crate::run::observer::{Observer, RunEnd, View};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Seconds between two progress lines when stderr is not a terminal.
pub const LINE_SECONDS: f64 = 5.0;

/// How the progress is drawn.
enum Draw {
    /// A bar (a terminal).
    Bar(indicatif::ProgressBar),
    /// A line every `every`, the last one at `last`.
    Lines { every: Duration, last: Instant },
}

/// Follows a run about 1000 times over its steps (more often on long runs,
/// see [`tick`]), drawing a bar or lines.
pub struct Progress {
    draw: Draw,
    tick: u64,
    /// The step this invocation started from, and when.
    first: Option<(u64, Instant)>,
}

impl Progress {
    /// The progress of a run of `steps` steps: `lines` forces a line every
    /// that many seconds; else with `show`, a bar on a terminal and a line
    /// every [`LINE_SECONDS`] elsewhere; else none.
    pub fn of_run(steps: u64, show: bool, lines: Option<f64>) -> Option<Self> {
        let every = match lines {
            Some(s) => s,
            None if !show => return None,
            None if std::io::stderr().is_terminal() => return Self::terminal(steps),
            None => LINE_SECONDS,
        };
        Some(Progress {
            draw: Draw::Lines {
                every: Duration::from_secs_f64(every.max(0.0)),
                last: Instant::now(),
            },
            tick: tick(steps),
            first: None,
        })
    }

    /// A bar of its own for a run of `steps` steps, if stderr is a terminal.
    pub fn terminal(steps: u64) -> Option<Self> {
        if !std::io::stderr().is_terminal() {
            return None;
        }
        let bar = indicatif::ProgressBar::new(steps);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:30} {percent:>3}% {msg}")
                .expect("static template"),
        );
        Some(Self::on(bar, steps))
    }

    /// Drive `bar` (e.g. one line of a study's `MultiProgress`); its length
    /// is set to `steps`, and it is cleared when the run ends.
    pub fn on(bar: indicatif::ProgressBar, steps: u64) -> Self {
        bar.set_length(steps);
        Progress {
            draw: Draw::Bar(bar),
            tick: tick(steps),
            first: None,
        }
    }
}

/// The steps between two looks at the clock: about 1000 looks per run, but
/// never more than [`MAX_TICK`] steps apart, so that a long run of a large
/// scene (a bed steps about a hundred times a second) still draws a line
/// every few seconds.
fn tick(steps: u64) -> u64 {
    (steps / 1000).clamp(1, MAX_TICK)
}

/// See [`tick`]: a look costs one clock read, a few hundred steps of even
/// a one-body scene cost far more.
const MAX_TICK: u64 = 256;

/// `h:mm:ss`.
fn clock(seconds: f64) -> String {
    if !seconds.is_finite() {
        return "–".into();
    }
    let s = seconds.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

/// The bar's text at `step` of `steps`, `elapsed` seconds after this
/// invocation started at `first_step`, for `bodies` bodies stepped by `dt`.
pub fn status(
    first_step: u64,
    step: u64,
    steps: u64,
    elapsed: f64,
    dt: f64,
    bodies: usize,
) -> String {
    let done = step.saturating_sub(first_step) as f64;
    let rate = if elapsed > 0.0 && done > 0.0 {
        done / elapsed
    } else {
        f64::NAN
    };
    let eta = steps.saturating_sub(step) as f64 / rate;
    let (t, t_end) = (step as f64 * dt, steps as f64 * dt);
    format!(
        "step {step}/{steps}  t = {}/{} s  elapsed {}  {} steps/s  {} body-steps/s  eta {}",
        sig(t),
        sig(t_end),
        clock(elapsed),
        sig(rate),
        sig(rate * bodies as f64),
        if rate.is_finite() {
            clock(eta)
        } else {
            "–".into()
        }
    )
}

/// Three significant digits: `0.574`, `1.79e6`; `–` for NaN.
fn sig(x: f64) -> String {
    if !x.is_finite() {
        "–".into()
    } else if x == 0.0 || (1e-3..1e4).contains(&x.abs()) {
        format!("{}", format!("{x:.3e}").parse::<f64>().unwrap_or(x))
    } else {
        format!("{x:.2e}")
    }
}

impl Observer for Progress {
    fn every(&self) -> Option<u64> {
        Some(self.tick)
    }

    fn start(&mut self, _v: &View) -> Result<()> {
        self.first = Some((0, Instant::now()));
        Ok(())
    }

    fn reads_states(&self) -> bool {
        false
    }

    fn resume(&mut self, c: &Checkpoint) -> Result<()> {
        // The bar starts at the checkpoint's step; the rate counts from here.
        self.first = Some((c.step, Instant::now()));
        if let Draw::Bar(bar) = &self.draw {
            bar.set_position(c.step);
        }
        Ok(())
    }

    fn row(&mut self, v: &View) -> Result<()> {
        let w = v.world;
        let (first, at) = *self.first.get_or_insert((w.step, Instant::now()));
        let text = || {
            status(
                first,
                w.step,
                w.scene.sim.steps(),
                at.elapsed().as_secs_f64(),
                w.scene.sim.dt(),
                w.scene.bodies.len(),
            )
        };
        match &mut self.draw {
            Draw::Bar(bar) => {
                bar.set_position(w.step);
                bar.set_message(text());
            }
            // One clock read per tick.
            Draw::Lines { every, last } if last.elapsed() >= *every => {
                eprintln!("{}", text());
                *last = Instant::now();
            }
            Draw::Lines { .. } => {}
        }
        Ok(())
    }

    fn finish(&mut self, _v: &View, _end: &RunEnd) -> Result<()> {
        if let Draw::Bar(bar) = &self.draw {
            bar.finish_and_clear();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::status;

    /// After a resume at 92 %, the rate and the ETA count only this
    /// invocation's steps: 10 steps in 1 s leave 70 steps, 7 s.
    #[test]
    fn eta_after_a_resume_counts_from_the_checkpoint() {
        let s = status(920, 930, 1000, 1.0, 1e-3, 9);
        assert!(s.contains("step 930/1000"), "{s}");
        assert!(s.contains("t = 0.93/1 s"), "{s}");
        assert!(s.contains("elapsed 0:00:01"), "{s}");
        assert!(s.contains(" 10 steps/s"), "{s}");
        assert!(s.contains(" 90 body-steps/s"), "{s}");
        assert!(s.ends_with("eta 0:00:07"), "{s}");
    }

    /// A long run: rates in scientific notation, the ETA in h:mm:ss; no rate
    /// before the first step.
    #[test]
    fn long_runs_and_the_first_row() {
        let s = status(0, 5_740_000, 20_000_000, 3.0, 1e-7, 9);
        assert!(s.contains("t = 0.574/2 s"), "{s}");
        assert!(s.contains("1.91e6 steps/s"), "{s}");
        assert!(s.contains("1.72e7 body-steps/s"), "{s}");
        assert!(s.ends_with("eta 0:00:07"), "{s}");
        let first = status(0, 0, 100, 0.0, 1e-3, 1);
        assert!(
            first.contains("– steps/s") && first.ends_with("eta –"),
            "{first}"
        );
    }
}
