//! `orientation.csv`: the orientation per output row of the bodies that need
//! it — those with a prescribed torque, and the body of a closed-form
//! reference — or of every body when the scene asks (`[output] orientation =
//! "all"`); with a closed-form reference, the reference quaternion and the
//! geodesic angle to it (column names are a public contract). A scene with
//! neither writes no file: a bed's rows would be bodies × rows for nothing.

use super::file::CsvFile;
use crate::error::Result;
use crate::math::{geodesic_angle, wxyz};
use crate::output::Checkpoint;
use crate::run::observer::{Observer, RunEnd, View};
use crate::scenario::Scene;
use glam::{DQuat, DVec3};

/// The file name in the output folder, and the observer's name in checkpoints.
pub const ORIENTATION_FILE: &str = "orientation.csv";
const NAME: &str = ORIENTATION_FILE;

/// The `orientation.csv` observer.
pub struct OrientationCsv {
    file: CsvFile,
    every: u64,
    with_reference: bool,
    /// Storage indices of the bodies written, ascending.
    bodies: Vec<usize>,
}

impl OrientationCsv {
    /// `orientation.csv` in `dir` for `scene`, one row per body written
    /// every `every` steps; `None` when no body needs one.
    pub fn for_scene(dir: &std::path::Path, every: u64, scene: &Scene) -> Option<Self> {
        let bodies = bodies_written(scene);
        (!bodies.is_empty()).then(|| OrientationCsv {
            file: CsvFile::at(dir.join(NAME)),
            every,
            with_reference: scene.reference.is_some(),
            bodies,
        })
    }
}

/// The bodies `orientation.csv` holds, by storage index: every body if the
/// scene asks, else those with a prescribed torque and the one body of a
/// closed-form reference (the closed forms describe body 0).
pub fn bodies_written(scene: &Scene) -> Vec<usize> {
    if scene.output.orientation_all {
        return (0..scene.bodies.len()).collect();
    }
    let mut b: Vec<usize> = scene.torques.iter().map(|p| p.body).collect();
    if scene.reference.is_some() {
        b.push(0);
    }
    b.sort_unstable();
    b.dedup();
    b
}

/// `orientation.csv` when a body needs it (registered in
/// [`super::OUTPUTS`]; see [`OrientationCsv::for_scene`]).
pub fn open(o: &super::Opening) -> Option<Box<dyn Observer>> {
    OrientationCsv::for_scene(o.dir, o.every, o.scene).map(|c| Box::new(c) as Box<dyn Observer>)
}

impl Observer for OrientationCsv {
    fn every(&self) -> Option<u64> {
        Some(self.every)
    }

    fn start(&mut self, _v: &View) -> Result<()> {
        let mut cols = vec![
            "step", "t", "body", "qw", "qx", "qy", "qz", "ax", "ay", "az",
        ];
        if self.with_reference {
            cols.extend(["ref_qw", "ref_qx", "ref_qy", "ref_qz", "err_rad"]);
        }
        self.file.create(&cols)
    }

    fn row(&mut self, v: &View) -> Result<()> {
        let w = v.world;
        let scene = w.scene;
        let (step, t) = (w.step, w.time());
        let reference = scene.reference.as_ref().map(|r| r.orientation(t));
        let with_reference = self.with_reference;
        for &i in &self.bodies {
            let (q, id) = (w.states[i].rot.q, scene.ids.get(i));
            let a = q * DVec3::X;
            let mut row = self.file.row()?;
            row.u(step).f(t).u(id);
            for c in wxyz(q).into_iter().chain(a.to_array()) {
                row.f(c);
            }
            if with_reference {
                let r = reference.unwrap_or(DQuat::NAN);
                for c in wxyz(r) {
                    row.f(c);
                }
                row.f(geodesic_angle(q, r));
            }
            row.end();
        }
        self.file.rows_done()
    }

    fn checkpoint(&mut self, c: &mut Checkpoint) -> Result<()> {
        c.outputs.insert(self.file.name(), self.file.mark()?);
        Ok(())
    }

    fn resume(&mut self, c: &Checkpoint) -> Result<()> {
        self.file.reopen(c.output_len(NAME)?)
    }

    fn finish(&mut self, _v: &View, _end: &RunEnd) -> Result<()> {
        self.file.flush()
    }
}
