//! The VTK time series (`--vtk-every N`, `[output] vtk_every`): a frame
//! `vtk/fibres_<step>.vtp` every N steps, the collection `fibres.pvd` with
//! each frame's physical time, and the box as a static `box.vtp` outline.
//! ParaView opens the `.pvd` as an animation; the Tube filter (radius
//! `diameter/2`, capped) draws each `VTK_LINE` as the exact cylinder.

mod frame;
mod outline;
mod pvd;
pub mod read;
mod xml;

pub use frame::{CELL_ARRAYS, QUATERNION_COMPONENTS};

use crate::error::{Error, Result};
use crate::output::checkpoint::bits;
use crate::output::mark::Mark;
use crate::output::Checkpoint;
use crate::run::observer::{Observer, RunEnd, View};
use pvd::Pvd;
use std::path::{Path, PathBuf};

/// The collection's file name in the output folder.
pub const PVD_FILE: &str = "fibres.pvd";
/// The box outline's file name in the output folder.
pub const BOX_FILE: &str = "box.vtp";
/// The folder of the frames, in the output folder.
pub const FRAME_DIR: &str = "vtk";
/// The observer's name in checkpoints (its state: the cadence).
const NAME: &str = "vtk";

/// The frame file of `step`, relative to the output folder.
pub fn frame_name(step: u64) -> String {
    format!("{FRAME_DIR}/fibres_{step}.vtp")
}

/// The VTK series observer.
pub struct VtkSeries {
    dir: PathBuf,
    every: u64,
    pvd: Pvd,
    /// Files written so far (relative name, mark), for checkpoints.
    written: Vec<(String, Mark)>,
    /// Count each frame's contacts from its states with a stage of its own,
    /// because the world's stage does not hold every candidate (an MPI
    /// rank's holds its own fibres' and its ghosts').
    recount: bool,
}

impl VtkSeries {
    /// A series in `dir`, one frame every `every` steps.
    pub fn new(dir: &Path, every: u64) -> Self {
        VtkSeries {
            dir: dir.to_path_buf(),
            every,
            pvd: Pvd::at(dir.join(PVD_FILE)),
            written: vec![],
            recount: false,
        }
    }

    /// Count the frames' contacts afresh from their states (see `recount`).
    pub fn recounting(self, recount: bool) -> Self {
        VtkSeries { recount, ..self }
    }

    /// Write a whole file (a frame is whole or absent after a kill or a
    /// full disk).
    fn write(&mut self, name: String, bytes: &[u8]) -> Result<()> {
        crate::output::file::write_whole(&self.dir.join(&name), bytes)?;
        self.written.push((name, Mark::of_bytes(bytes)));
        Ok(())
    }
}

/// The VTK cadence a checkpoint's run used, if it wrote a series.
pub fn cadence_in(c: &Checkpoint) -> Result<Option<u64>> {
    c.cadence(NAME)
}

impl Observer for VtkSeries {
    fn every(&self) -> Option<u64> {
        Some(self.every)
    }

    fn start(&mut self, v: &View) -> Result<()> {
        let frames = self.dir.join(FRAME_DIR);
        std::fs::create_dir_all(&frames).map_err(|e| Error::io(&frames, e))?;
        if let Some(w) = &v.world.scene.walls {
            self.write(BOX_FILE.into(), &outline::box_bytes(w))?;
        }
        self.pvd.create()
    }

    fn row(&mut self, v: &View) -> Result<()> {
        let w = v.world;
        let counts = match self.recount {
            true => super::contact_count::contacts_at(w.scene, &w.states),
            false => super::contact_count::contacts_of_world(w),
        };
        let name = frame_name(w.step);
        self.write(name.clone(), &frame::frame_bytes(w, &counts))?;
        self.pvd.push(w.time(), &name)
    }

    fn checkpoint(&mut self, c: &mut Checkpoint) -> Result<()> {
        for (name, mark) in &self.written {
            c.outputs.insert(name.clone(), mark.clone());
        }
        c.outputs.insert(PVD_FILE.into(), self.pvd.mark()?);
        c.observers
            .insert(NAME.into(), vec![bits(self.every as f64)]);
        Ok(())
    }

    fn resume(&mut self, c: &Checkpoint) -> Result<()> {
        self.pvd.reopen(c.output_len(PVD_FILE)?)?;
        let frames = self.dir.join(FRAME_DIR);
        std::fs::create_dir_all(&frames).map_err(|e| Error::io(&frames, e))?;
        self.written = c
            .outputs
            .iter()
            .filter(|(k, _)| k.starts_with(&format!("{FRAME_DIR}/")) || k.as_str() == BOX_FILE)
            .map(|(k, m)| (k.clone(), m.clone()))
            .collect();
        Ok(())
    }

    fn finish(&mut self, _v: &View, _end: &RunEnd) -> Result<()> {
        Ok(())
    }
}
