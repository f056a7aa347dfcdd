//! `trajectory.csv` (`--trajectory-every N`, `[output] trajectory_every`):
//! every body's pose and motion per row, world frame, for scripts and
//! pandas (column names are a public contract). The numbers are the
//! state's own f64 in shortest round-trip form, so the last row equals
//! `summary.json`'s `final` bit for bit (`omega` is the world-frame
//! `q ω_b q*`; the summary keeps the body frame).

use super::file::CsvFile;
use crate::error::Result;
use crate::math::{to_world, wxyz};
use crate::output::checkpoint::bits;
use crate::output::Checkpoint;
use crate::run::observer::{Observer, RunEnd, View};

/// The file name in the output folder, and the observer's checkpoint name.
pub const TRAJECTORY_FILE: &str = "trajectory.csv";

/// The columns of `trajectory.csv`.
pub const TRAJECTORY_COLUMNS: [&str; 16] = [
    "step", "t", "body", "x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz",
];

/// The `trajectory.csv` observer.
pub struct TrajectoryCsv {
    file: CsvFile,
    every: u64,
}

impl TrajectoryCsv {
    /// `trajectory.csv` in `dir`, one row per body every `every` steps.
    pub fn new(dir: &std::path::Path, every: u64) -> Self {
        TrajectoryCsv {
            file: CsvFile::at(dir.join(TRAJECTORY_FILE)),
            every,
        }
    }
}

/// The trajectory cadence a checkpoint's run used, if it wrote one.
pub fn cadence_in(c: &Checkpoint) -> Result<Option<u64>> {
    c.cadence(TRAJECTORY_FILE)
}

/// `trajectory.csv` when the scene asks for it (`output.trajectory_every`;
/// registered in [`super::OUTPUTS`]).
pub fn open(o: &super::Opening) -> Option<Box<dyn Observer>> {
    let n = o.scene.output.trajectory_every?;
    Some(Box::new(TrajectoryCsv::new(o.dir, n)))
}

impl Observer for TrajectoryCsv {
    fn every(&self) -> Option<u64> {
        Some(self.every)
    }

    fn start(&mut self, _v: &View) -> Result<()> {
        self.file.create(&TRAJECTORY_COLUMNS)
    }

    fn row(&mut self, v: &View) -> Result<()> {
        let w = v.world;
        let (step, t) = (w.step, w.time());
        for (s, id) in w.states.iter().zip(w.scene.ids.iter()) {
            let omega = to_world(s.rot.q, s.rot.omega_b);
            let mut row = self.file.row()?;
            row.u(step).f(t).u(id);
            let values = s.x.to_array().into_iter().chain(wxyz(s.rot.q));
            for c in values.chain(s.v.to_array()).chain(omega.to_array()) {
                row.f(c);
            }
            row.end();
        }
        self.file.rows_done()
    }

    fn checkpoint(&mut self, c: &mut Checkpoint) -> Result<()> {
        c.outputs.insert(self.file.name(), self.file.mark()?);
        c.observers
            .insert(TRAJECTORY_FILE.into(), vec![bits(self.every as f64)]);
        Ok(())
    }

    fn resume(&mut self, c: &Checkpoint) -> Result<()> {
        self.file.reopen(c.output_len(TRAJECTORY_FILE)?)
    }

    fn finish(&mut self, _v: &View, _end: &RunEnd) -> Result<()> {
        self.file.flush()
    }
}
