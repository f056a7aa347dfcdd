//! The progress bar of a run, drawn on stderr (never when it is not a
//! terminal: scripts and CI see nothing).

use crate::error::Result;
use crate::run::observer::{Observer, RunEnd, View};
use std::io::IsTerminal;

/// Moves a bar to the current step about 1000 times per run.
pub struct Progress {
    bar: indicatif::ProgressBar,
    tick: u64,
}

impl Progress {
    /// A bar of its own for a run of `steps` steps, if stderr is a terminal.
    pub fn terminal(steps: u64) -> Option<Self> {
        if !std::io::stderr().is_terminal() {
            return None;
        }
        let bar = indicatif::ProgressBar::new(steps);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {percent:>3}% step {pos}/{len} eta {eta}",
            )
            .expect("static template"),
        );
        Some(Self::on(bar, steps))
    }

    /// Drive `bar` (e.g. one line of a study's `MultiProgress`); its length
    /// is set to `steps`, and it is cleared when the run ends.
    pub fn on(bar: indicatif::ProgressBar, steps: u64) -> Self {
        bar.set_length(steps);
        Progress {
            bar,
            tick: (steps / 1000).max(1),
        }
    }
}

impl Observer for Progress {
    fn every(&self) -> Option<u64> {
        Some(self.tick)
    }

    fn row(&mut self, v: &View) -> Result<()> {
        self.bar.set_position(v.world.step);
        Ok(())
    }

    fn finish(&mut self, _v: &View, _end: &RunEnd) -> Result<()> {
        self.bar.finish_and_clear();
        Ok(())
    }
}
