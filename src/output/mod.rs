//! Observers of the driver loop that write files: the data outputs of
//! [`OUTPUTS`] (`energy.csv`, `orientation.csv`, and on request
//! `trajectory.csv` and the VTK series `fibres.pvd`, `vtk/`), and the run's
//! bookkeeping: `summary.json`, checkpoints, the progress.
//!
//! Numbers are written in their shortest round-trip form (ryu), so files are
//! exact, compact and identical for identical runs.

pub mod checkpoint;
pub mod contact_count;
pub mod energy;
pub mod file;
pub mod folder;
pub mod mark;
pub mod orientation;
pub mod progress;
pub mod summary;
pub mod trajectory;
pub mod vtk;

pub use checkpoint::{Checkpoint, CheckpointFile};
pub use energy::EnergyCsv;
pub use orientation::OrientationCsv;
pub use progress::Progress;
pub use summary::{BodyFinal, Summary, SummaryJson};
pub use trajectory::TrajectoryCsv;
pub use vtk::VtkSeries;

use crate::run::Observer;
use crate::scenario::Scene;

/// What a data output reads to decide whether a run writes it, and to open
/// it there.
pub struct Opening<'a> {
    /// The run's output folder.
    pub dir: &'a std::path::Path,
    /// The scene the run steps.
    pub scene: &'a Scene,
    /// The ledger's cadence: `simulation.every`, else [`default_every`].
    pub every: u64,
    /// Whether this process computes the whole contact stage (one process)
    /// or only its share of it (an MPI rank): a partial stage's contact
    /// counts are counted again where they are written.
    pub whole_contact_stage: bool,
}

/// Opens an output if the scene declares it (or, like `energy.csv`, always).
pub type Open = fn(&Opening) -> Option<Box<dyn Observer>>;

/// The data outputs of a run, in the order they write at an event. An
/// output is one file and one line here; the run's own bookkeeping (the
/// progress, `summary.json`, the checkpoint, which writes last what the
/// others recorded) is wired by [`crate::run`].
pub const OUTPUTS: &[Open] = &[energy::open, orientation::open, trajectory::open, vtk::open];
/// Create an output folder; failure is bad input naming `--out`.
pub fn create_out_dir(dir: &std::path::Path) -> crate::error::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| {
        crate::error::Error::bad(
            dir.display().to_string(),
            "--out",
            format!("cannot create the output folder: {e}; choose another folder with --out DIR"),
        )
    })
}

/// Create the folder a written file goes in (`generate -o new/bed.toml`, as
/// `run --out` creates its folder); failure is bad input naming `flag`.
pub fn create_parent_dir(file: &std::path::Path, flag: &str) -> crate::error::Result<()> {
    match file.parent().filter(|d| !d.as_os_str().is_empty()) {
        None => Ok(()),
        Some(dir) => std::fs::create_dir_all(dir).map_err(|e| {
            crate::error::Error::bad(
                dir.display().to_string(),
                flag,
                format!(
                    "cannot create the folder of {}: {e}; choose another path with {flag}",
                    file.display()
                ),
            )
        }),
    }
}

/// An output file that cannot be created when a run starts is bad input
/// naming `--out` (exit 2); the same failure mid-run stays an I/O error.
pub fn unwritable_at_start(e: crate::error::Error) -> crate::error::Error {
    match e {
        crate::error::Error::Io { path, source } => crate::error::Error::bad(
            path.display().to_string(),
            "--out",
            format!(
                "cannot write the output file: {source}; choose a folder you can write to with --out DIR"
            ),
        ),
        e => e,
    }
}

/// Default output cadence: at most 2e4 rows (well under the ~1e5 budget, so the
/// output costs less than the physics of a 1e6-step single-body run).
pub fn default_every(steps: u64) -> u64 {
    steps.div_ceil(20_000).max(1)
}

/// Shortest round-trip form, as a String (for cold paths).
pub fn num(x: f64) -> String {
    ryu::Buffer::new().format(x).to_string()
}

/// A CSV row builder that formats numbers without allocating: fields
/// separated by `,`, the row ended by `\n` (numbers and column names need no
/// quoting).
pub struct Row<'b> {
    out: &'b mut Vec<u8>,
    first: bool,
    buf: ryu::Buffer,
    ibuf: itoa_like::Buf,
}

impl<'b> Row<'b> {
    /// A row appended to `out`.
    pub fn new(out: &'b mut Vec<u8>) -> Self {
        Row {
            out,
            first: true,
            buf: ryu::Buffer::new(),
            ibuf: itoa_like::Buf::default(),
        }
    }

    /// The separator before every field but the first.
    #[inline]
    fn sep(&mut self) {
        if !self.first {
            self.out.push(b',');
        }
        self.first = false;
    }

    #[inline]
    /// Add a float field (shortest round-trip form).
    pub fn f(&mut self, x: f64) -> &mut Self {
        self.sep();
        self.out.extend_from_slice(self.buf.format(x).as_bytes());
        self
    }

    #[inline]
    /// Add an integer field.
    pub fn u(&mut self, x: u64) -> &mut Self {
        self.sep();
        self.out.extend_from_slice(self.ibuf.format(x));
        self
    }

    /// Add a text field (a column name).
    pub fn text(&mut self, s: &str) -> &mut Self {
        self.sep();
        self.out.extend_from_slice(s.as_bytes());
        self
    }

    /// End the row.
    pub fn end(&mut self) {
        self.out.push(b'\n');
    }
}

mod itoa_like {
    /// Formats a u64 into a stack buffer.
    #[derive(Default)]
    pub struct Buf([u8; 20]);

    impl Buf {
        pub fn format(&mut self, mut x: u64) -> &[u8] {
            let mut i = self.0.len();
            loop {
                i -= 1;
                self.0[i] = b'0' + (x % 10) as u8;
                x /= 10;
                if x == 0 {
                    return &self.0[i..];
                }
            }
        }
    }
}
