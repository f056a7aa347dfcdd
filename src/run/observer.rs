//! What watches a run: every output (CSV files, the summary, checkpoints, the
//! progress bar, a study's in-memory probe) is an [`Observer`] of the one
//! driver loop ([`super::driver`]). Observers read the state; they never
//! change it.

use super::stats::RunStats;
use crate::error::Result;
use crate::integrate::step::World;
use crate::output::Checkpoint;
use crate::stop::Diagnosis;

/// What an observer sees: the world after a step, and the run's statistics.
pub struct View<'a, 's> {
    /// The world after the step.
    pub world: &'a World<'s>,
    /// The run's statistics after the step.
    pub stats: &'a RunStats,
}

/// How a run ended, for [`Observer::finish`].
pub struct RunEnd<'a> {
    /// The stop, if the run did not reach its end.
    pub stopped: Option<&'a Diagnosis>,
    /// Wall time of the stepping loop, outputs included, s.
    pub wall_s: f64,
    /// The step the loop started from (0, or a checkpoint's).
    pub first_step: u64,
}

/// An observer of the driver loop. Every hook has a default that does nothing.
///
/// Order of calls: `start` and `row` at step 0 (a new run), or `resume` (a
/// resumed one); at each event `event`, then
/// then after each step `after_step` (if [`Observer::every_step`]), `row` on
/// the observer's cadence, `checkpoint` on the checkpoint cadence, `row` at
/// the last step if it was not on cadence; `finish` once at the end, also
/// after a stop.
pub trait Observer {
    /// Steps between two rows; `None` for an observer that writes no rows.
    fn every(&self) -> Option<u64> {
        None
    }

    /// Whether [`Observer::after_step`] must see every step (asked once).
    fn every_step(&self) -> bool {
        false
    }

    /// Whether its rows read the bodies' states (not only the ledger and
    /// the contact statistics). Under MPI the states are gathered to rank
    /// 0 only for the events that need them (`src/ranks/`).
    fn reads_states(&self) -> bool {
        true
    }

    /// A new run starts (not a resumed one): create the output files.
    fn start(&mut self, _v: &View) -> Result<()> {
        Ok(())
    }

    /// At every event of the driver (a step where any observer writes a row,
    /// or a checkpoint), before its rows: `v.stats.since_event()` holds the
    /// maxima over the steps since the previous event.
    fn event(&mut self, _v: &View) {}

    /// After every step, when [`Observer::every_step`] says so.
    fn after_step(&mut self, _v: &View) {}

    /// A row of output at the current step.
    fn row(&mut self, _v: &View) -> Result<()> {
        Ok(())
    }

    /// Add this observer's output files (flushed, with their lengths) and its
    /// state to the checkpoint being written. Observers are asked in list
    /// order; the checkpoint file's writer is the last.
    fn checkpoint(&mut self, _c: &mut Checkpoint) -> Result<()> {
        Ok(())
    }

    /// Continue from a checkpoint: reopen the files cut to the recorded
    /// lengths and restore the state saved by [`Observer::checkpoint`].
    fn resume(&mut self, _c: &Checkpoint) -> Result<()> {
        Ok(())
    }

    /// The run is over (finished or stopped): flush and write what is final.
    fn finish(&mut self, _v: &View, _end: &RunEnd) -> Result<()> {
        Ok(())
    }
}

/// An in-memory observer: calls `f` after every step (studies and tests).
pub struct EachStep<F>(pub F);

impl<F: FnMut(&World)> Observer for EachStep<F> {
    fn every_step(&self) -> bool {
        true
    }

    fn after_step(&mut self, v: &View) {
        (self.0)(v.world)
    }
}

/// An observer that writes nothing but keeps another's cadences: an MPI
/// rank other than 0 drives its loop through the same events (the
/// collective gathers of `src/ranks/` happen at them) without writing.
pub(crate) struct Silent {
    every: Option<u64>,
    every_step: bool,
    reads_states: bool,
}

impl Silent {
    /// The cadences of `o`.
    pub(crate) fn of(o: &dyn Observer) -> Self {
        Silent {
            every: o.every(),
            every_step: o.every_step(),
            reads_states: o.reads_states(),
        }
    }
}

impl Observer for Silent {
    fn every(&self) -> Option<u64> {
        self.every
    }
    fn every_step(&self) -> bool {
        self.every_step
    }
    fn reads_states(&self) -> bool {
        self.reads_states
    }
}
