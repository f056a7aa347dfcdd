//! The VTK time series (`--vtk-every N`, `[output] vtk_every`): a frame
//! `vtk/fibres_<step>.vtp` every N steps, the step zero-padded to the digits
//! of the run's last step so that the names sort in time order
//! (`fibres_01500` before `fibres_10000`), the collection `fibres.pvd` with
//! each frame's physical time, and the box as a static `box.vtp` outline.
//! A resumed run whose last step has other digits (`--t-end` moved it)
//! renames the frames written so far and rewrites the `.pvd` to its width at
//! its first frame, so that it writes the names, and the bytes, of a run
//! straight to its end.
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
/// The checkpoint entry of the frame numbers' width (a checkpoint without
/// it is of a run that wrote them unpadded).
const WIDTH: &str = "vtk_width";

/// The frame file of `step`, relative to the output folder, its number
/// zero-padded to `width` digits.
pub fn frame_name(step: u64, width: usize) -> String {
    format!("{FRAME_DIR}/fibres_{step:0width$}.vtp")
}

/// The width of the frame numbers of a run whose last step is `last_step`:
/// its digits, so that every name of the run sorts by step.
pub fn frame_width(last_step: u64) -> usize {
    last_step.to_string().len()
}

/// The step of a frame file name (`vtk/fibres_<step>.vtp`), if it is one.
fn frame_step(name: &str) -> Option<u64> {
    name.strip_prefix(FRAME_DIR)?
        .strip_prefix("/fibres_")?
        .strip_suffix(".vtp")?
        .parse()
        .ok()
}

/// The VTK series observer.
pub struct VtkSeries {
    dir: PathBuf,
    every: u64,
    pvd: Pvd,
    /// Files written so far (relative name, mark), for checkpoints.
    written: Vec<(String, Mark)>,
    /// Digits of the frame numbers ([`frame_width`]): set at the start, or
    /// the checkpoint's on a resume until [`VtkSeries::renumber`].
    width: usize,
    /// A resumed series whose width is not yet checked against its run's.
    renumber_pending: bool,
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
            width: 1,
            renumber_pending: false,
            recount: false,
        }
    }

    /// Count the frames' contacts afresh from their states (see `recount`).
    pub fn recounting(self, recount: bool) -> Self {
        VtkSeries { recount, ..self }
    }

    /// Give the frames written so far (a resumed series) the width of this
    /// run's last step: rename them and their `.pvd` entries.
    fn renumber(&mut self, last_step: u64) -> Result<()> {
        self.renumber_pending = false;
        let width = frame_width(last_step);
        if width == self.width {
            return Ok(());
        }
        let old = self.width;
        let rename = |name: &str| -> String {
            match frame_step(name) {
                Some(step) if name == frame_name(step, old) => frame_name(step, width),
                _ => name.to_string(),
            }
        };
        for (name, _) in &mut self.written {
            let new = rename(name);
            if new != *name {
                let (from, to) = (self.dir.join(&*name), self.dir.join(&new));
                std::fs::rename(&from, &to).map_err(|e| Error::io(&from, e))?;
                *name = new;
            }
        }
        self.pvd.rewrite_files(rename)?;
        self.width = width;
        Ok(())
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

/// The VTK series when the scene asks for it (`output.vtk_every`;
/// registered in [`super::OUTPUTS`]).
pub fn open(o: &super::Opening) -> Option<Box<dyn Observer>> {
    let n = o.scene.output.vtk_every?;
    Some(Box::new(
        VtkSeries::new(o.dir, n).recounting(!o.whole_contact_stage),
    ))
}

impl Observer for VtkSeries {
    fn every(&self) -> Option<u64> {
        Some(self.every)
    }

    fn start(&mut self, v: &View) -> Result<()> {
        self.width = frame_width(v.world.scene.sim.steps());
        let frames = self.dir.join(FRAME_DIR);
        std::fs::create_dir_all(&frames).map_err(|e| Error::io(&frames, e))?;
        if let Some(w) = &v.world.scene.walls {
            self.write(BOX_FILE.into(), &outline::box_bytes(w))?;
        }
        self.pvd.create()
    }

    fn row(&mut self, v: &View) -> Result<()> {
        let w = v.world;
        if self.renumber_pending {
            self.renumber(w.scene.sim.steps())?;
        }
        let counts = match self.recount {
            true => super::contact_count::contacts_at(w.scene, &w.states),
            false => super::contact_count::contacts_of_world(w),
        };
        let name = frame_name(w.step, self.width);
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
        c.observers
            .insert(WIDTH.into(), vec![bits(self.width as f64)]);
        Ok(())
    }

    fn resume(&mut self, c: &Checkpoint) -> Result<()> {
        self.width = match c.observers.contains_key(WIDTH) {
            false => 1,
            true => match c.observer_state(WIDTH)?.as_slice() {
                [w] if *w >= 1.0 && w.fract() == 0.0 && *w <= 20.0 => *w as usize,
                _ => {
                    return Err(Error::bad(
                        "checkpoint",
                        "observers",
                        format!(
                        "`{WIDTH}` needs the frame numbers' width (1 whole number from 1 to 20)"
                    ),
                    ))
                }
            },
        };
        self.renumber_pending = true;
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

    fn finish(&mut self, v: &View, _end: &RunEnd) -> Result<()> {
        if self.renumber_pending {
            self.renumber(v.world.scene.sim.steps())?;
        }
        Ok(())
    }
}
