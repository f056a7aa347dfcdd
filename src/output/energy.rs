//! `energy.csv`: the energy ledger per output row, with Eq. 65 errors (column
//! names are a public contract).

use super::file::CsvFile;
use crate::error::Result;
use crate::output::Checkpoint;
use crate::run::observer::{Observer, RunEnd, View};
use crate::run::stats::Window;

/// The columns every energy.csv has (contact scenes add two).
pub const ENERGY_COLUMNS: [&str; 11] = [
    "step",
    "t",
    "e_grav",
    "e_trans",
    "e_rot",
    "e_elastic",
    "e_total",
    "energy_error_pct",
    "energy_error_full_pct",
    "energy_error_window_max_pct",
    "energy_error_full_window_max_pct",
];

/// Energy ledger per output row. `e_total` is Eq. 64 (no elastic term); the
/// `full` error includes the elastic energy. The `*_window_max_pct` columns
/// are the largest error over every step since the previous row, so no spike
/// between rows is hidden; in contact scenes `contacts,max_overlap_ratio`
/// are the touching pairs at the row's step and the largest δ/D since the
/// previous row.
pub struct EnergyCsv {
    file: CsvFile,
    every: u64,
    with_contacts: bool,
    with_dissipation: bool,
    with_spring: bool,
    window: Window,
}

/// The file name in the output folder, and the observer's name in checkpoints.
pub const ENERGY_FILE: &str = "energy.csv";
const NAME: &str = ENERGY_FILE;

impl EnergyCsv {
    /// `energy.csv` in `dir`, one row per `every` steps; opened when the run
    /// starts ([`Observer::start`]) or resumes.
    pub fn new(dir: &std::path::Path, every: u64, with_contacts: bool) -> Self {
        EnergyCsv {
            file: CsvFile::at(dir.join(NAME)),
            every,
            with_contacts,
            with_dissipation: false,
            with_spring: false,
            window: Window::default(),
        }
    }

    /// Add the column `e_dissipated` (the ledger's dissipated energy, J),
    /// after the contacts' columns, for scenes that declare damping or
    /// friction.
    pub fn with_dissipation(mut self, yes: bool) -> Self {
        self.with_dissipation = yes;
        self
    }

    /// Add the column `e_spring` (the energy the friction springs hold,
    /// J), last, for scenes that declare friction.
    pub fn with_spring(mut self, yes: bool) -> Self {
        self.with_spring = yes;
        self
    }
}

/// Every run writes `energy.csv` (registered in [`super::OUTPUTS`]).
pub fn open(o: &super::Opening) -> Option<Box<dyn Observer>> {
    let csv = EnergyCsv::new(o.dir, o.every, o.scene.needs_contacts())
        .with_dissipation(o.scene.damping.is_some() || o.scene.friction.is_some())
        .with_spring(o.scene.friction.is_some());
    Some(Box::new(csv))
}

impl Observer for EnergyCsv {
    fn every(&self) -> Option<u64> {
        Some(self.every)
    }

    fn start(&mut self, _v: &View) -> Result<()> {
        let mut cols = ENERGY_COLUMNS.to_vec();
        if self.with_contacts {
            cols.extend(["contacts", "max_overlap_ratio"]);
        }
        if self.with_dissipation {
            cols.push("e_dissipated");
        }
        if self.with_spring {
            cols.push("e_spring");
        }
        self.file.create(&cols)
    }

    fn reads_states(&self) -> bool {
        false
    }

    fn event(&mut self, v: &View) {
        self.window = self.window.max(v.stats.since_event());
    }

    /// The row of the step last accounted for; starts a new window.
    fn row(&mut self, v: &View) -> Result<()> {
        let (s, l, w) = (v.stats, &v.world.ledger, self.window);
        let window = if s.last_error().is_nan() {
            f64::NAN
        } else {
            w.error
        };
        let window_full = if s.last_error_full().is_nan() {
            f64::NAN
        } else {
            w.error_full
        };
        let touching = v.world.contact_stats().unwrap_or_default().touching as u64;
        let with_contacts = self.with_contacts;
        let dissipated = self.with_dissipation.then_some(l.dissipated);
        let spring = self.with_spring.then_some(l.spring);
        let mut r = self.file.row()?;
        r.u(v.world.step)
            .f(v.world.time())
            .f(l.gravity)
            .f(l.translation)
            .f(l.rotation)
            .f(l.elastic)
            .f(l.total())
            .f(s.last_error())
            .f(s.last_error_full())
            .f(window)
            .f(window_full);
        if with_contacts {
            r.u(touching).f(w.overlap);
        }
        if let Some(d) = dissipated {
            r.f(d);
        }
        if let Some(s) = spring {
            r.f(s);
        }
        r.end();
        self.file.rows_done()?;
        self.window = Window::default();
        Ok(())
    }

    fn checkpoint(&mut self, c: &mut Checkpoint) -> Result<()> {
        c.outputs.insert(self.file.name(), self.file.mark()?);
        let w = self.window;
        c.observers.insert(
            NAME.into(),
            [w.error, w.error_full, w.overlap]
                .map(super::checkpoint::bits)
                .to_vec(),
        );
        Ok(())
    }

    fn resume(&mut self, c: &Checkpoint) -> Result<()> {
        self.file.reopen(c.output_len(NAME)?)?;
        let s = c.observer_state(NAME)?;
        if s.len() != 3 {
            return Err(crate::error::Error::bad(
                "checkpoint",
                "observers",
                "energy.csv needs 3 numbers",
            ));
        }
        self.window = Window {
            error: s[0],
            error_full: s[1],
            overlap: s[2],
        };
        Ok(())
    }

    fn finish(&mut self, _v: &View, _end: &RunEnd) -> Result<()> {
        self.file.flush()
    }
}
