//! `energy.csv` and `orientation.csv` (column names are a public contract).

use super::Row;
use crate::contact::stage::ContactStats;
use crate::energy::{error_pct, Ledger};
use crate::error::{Error, Result};
use crate::math::{geodesic_angle, wxyz};
use glam::{DQuat, DVec3};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

fn create(path: &Path) -> Result<csv::Writer<BufWriter<File>>> {
    let f = File::create(path).map_err(|e| Error::io(path, e))?;
    Ok(csv::Writer::from_writer(BufWriter::new(f)))
}

fn csv_err(path: &Path, e: csv::Error) -> Error {
    Error::io(path, std::io::Error::other(e.to_string()))
}

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

/// Energy ledger per output row, with Eq. 65 errors. `e_total` is Eq. 64
/// (no elastic term); the `full` error includes the elastic energy.
/// `energy_error_window_max_pct` is the largest Eq. 65 error over every step
/// since the previous row, so no spike between rows is hidden.
pub struct EnergyCsv {
    path: PathBuf,
    w: csv::Writer<BufWriter<File>>,
    with_contacts: bool,
    pub stats: EnergyStats,
}

/// The running statistics behind `energy.csv` (kept in checkpoints).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyStats {
    pub e0: f64,
    pub e0_full: f64,
    /// Largest Eq. 65 error, full-budget error and δ/D since the previous row.
    pub window_max: f64,
    pub window_max_full: f64,
    pub window_overlap: f64,
    /// Largest δ/D over the whole run (contact scenes).
    pub max_overlap_ratio: f64,
    /// Largest Eq. 65 and full-budget errors over the whole run (every step).
    pub max_error: f64,
    pub max_error_full: f64,
    pub last_error: f64,
    pub last_error_full: f64,
}

impl EnergyStats {
    pub fn new(initial: &Ledger) -> Self {
        EnergyStats {
            e0: initial.total(),
            e0_full: initial.total_full(),
            window_max: 0.0,
            window_max_full: 0.0,
            window_overlap: 0.0,
            max_overlap_ratio: 0.0,
            max_error: 0.0,
            max_error_full: 0.0,
            last_error: f64::NAN,
            last_error_full: f64::NAN,
        }
    }

    pub fn to_array(&self) -> [f64; 10] {
        [
            self.e0,
            self.e0_full,
            self.window_max,
            self.window_max_full,
            self.window_overlap,
            self.max_overlap_ratio,
            self.max_error,
            self.max_error_full,
            self.last_error,
            self.last_error_full,
        ]
    }

    pub fn from_array(a: [f64; 10]) -> Self {
        EnergyStats {
            e0: a[0],
            e0_full: a[1],
            window_max: a[2],
            window_max_full: a[3],
            window_overlap: a[4],
            max_overlap_ratio: a[5],
            max_error: a[6],
            max_error_full: a[7],
            last_error: a[8],
            last_error_full: a[9],
        }
    }
}

/// Open `path` for appending after cutting it to `len` bytes (resume).
fn reopen(path: &Path, len: u64) -> Result<csv::Writer<BufWriter<File>>> {
    use std::io::{Seek, SeekFrom};
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => Error::bad(
                path.display().to_string(),
                "--resume",
                format!("the output file the checkpoint continues is missing ({e}); resume from the checkpoint in its own folder"),
            ),
            _ => Error::io(path, e),
        })?;
    let have = f.metadata().map_err(|e| Error::io(path, e))?.len();
    if have < len {
        // set_len would pad with zero bytes: the file is not the one checkpointed.
        return Err(Error::bad(
            path.display().to_string(),
            "--resume",
            format!("is {have} bytes, shorter than the {len} the checkpoint recorded: it was changed after the checkpoint; rerun from the start"),
        ));
    }
    f.set_len(len).map_err(|e| Error::io(path, e))?;
    f.seek(SeekFrom::End(0)).map_err(|e| Error::io(path, e))?;
    Ok(csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(BufWriter::new(f)))
}

/// Flushed length of a writer's file, for checkpoints.
fn flushed_len(path: &Path, w: &mut csv::Writer<BufWriter<File>>) -> Result<u64> {
    w.flush().map_err(|e| Error::io(path, e))?;
    let f = w.get_ref().get_ref();
    Ok(f.metadata().map_err(|e| Error::io(path, e))?.len())
}

impl EnergyCsv {
    /// `with_contacts` adds the columns `contacts,max_overlap_ratio`: touching
    /// pairs at the row's step and the largest δ/D since the previous row.
    pub fn create(path: PathBuf, initial: &Ledger, with_contacts: bool) -> Result<Self> {
        let mut w = create(&path)?;
        let mut cols = ENERGY_COLUMNS.to_vec();
        if with_contacts {
            cols.extend(["contacts", "max_overlap_ratio"]);
        }
        w.write_record(&cols).map_err(|e| csv_err(&path, e))?;
        Ok(EnergyCsv {
            path,
            w,
            with_contacts,
            stats: EnergyStats::new(initial),
        })
    }

    /// Continue a file written up to `len` bytes, with the statistics it had then.
    pub fn resume(
        path: PathBuf,
        len: u64,
        stats: EnergyStats,
        with_contacts: bool,
    ) -> Result<Self> {
        Ok(EnergyCsv {
            w: reopen(&path, len)?,
            path,
            with_contacts,
            stats,
        })
    }

    pub fn flushed_len(&mut self) -> Result<u64> {
        flushed_len(&self.path, &mut self.w)
    }

    /// Account for one step (every step, so the maxima see everything).
    pub fn account(&mut self, l: &Ledger, contacts: Option<ContactStats>) {
        let c = contacts.unwrap_or_default();
        let s = &mut self.stats;
        s.window_overlap = s.window_overlap.max(c.max_overlap_ratio);
        s.max_overlap_ratio = s.max_overlap_ratio.max(c.max_overlap_ratio);
        let err = error_pct(l.total(), s.e0);
        let err_full = error_pct(l.total_full(), s.e0_full);
        // f64::max ignores NaN, so the maxima stay NaN-free for E_0 = 0 scenes.
        s.window_max = s.window_max.max(err);
        s.window_max_full = s.window_max_full.max(err_full);
        s.max_error = s.max_error.max(err);
        s.max_error_full = s.max_error_full.max(err_full);
        s.last_error = err;
        s.last_error_full = err_full;
    }

    /// Write the row of the step last accounted for, and start a new window.
    pub fn write_row(
        &mut self,
        step: u64,
        t: f64,
        l: &Ledger,
        contacts: Option<ContactStats>,
    ) -> Result<()> {
        let s = self.stats;
        let window = if s.last_error.is_nan() {
            f64::NAN
        } else {
            s.window_max
        };
        let window_full = if s.last_error_full.is_nan() {
            f64::NAN
        } else {
            s.window_max_full
        };
        let touching = contacts.unwrap_or_default().touching as u64;
        let with_contacts = self.with_contacts;
        Row::new(&mut self.w)
            .u(step)
            .and_then(|r| r.f(t))
            .and_then(|r| r.f(l.gravity))
            .and_then(|r| r.f(l.translation))
            .and_then(|r| r.f(l.rotation))
            .and_then(|r| r.f(l.elastic))
            .and_then(|r| r.f(l.total()))
            .and_then(|r| r.f(s.last_error))
            .and_then(|r| r.f(s.last_error_full))
            .and_then(|r| r.f(window))
            .and_then(|r| r.f(window_full))
            .and_then(|r| {
                if with_contacts {
                    r.u(touching)?.f(s.window_overlap)?;
                }
                r.end()
            })
            .map_err(|e| csv_err(&self.path, e))?;
        self.stats.window_max = 0.0;
        self.stats.window_max_full = 0.0;
        self.stats.window_overlap = 0.0;
        Ok(())
    }

    pub fn flush(&mut self) -> Result<()> {
        self.w.flush().map_err(|e| Error::io(&self.path, e))
    }
}

/// Orientation of every body per output row; with a closed-form reference, the
/// reference quaternion and the geodesic angle to it.
pub struct OrientationCsv {
    path: PathBuf,
    w: csv::Writer<BufWriter<File>>,
    with_reference: bool,
}

impl OrientationCsv {
    pub fn create(path: PathBuf, with_reference: bool) -> Result<Self> {
        let mut w = create(&path)?;
        let mut cols = vec![
            "step", "t", "body", "qw", "qx", "qy", "qz", "ax", "ay", "az",
        ];
        if with_reference {
            cols.extend(["ref_qw", "ref_qx", "ref_qy", "ref_qz", "err_rad"]);
        }
        w.write_record(&cols).map_err(|e| csv_err(&path, e))?;
        Ok(OrientationCsv {
            path,
            w,
            with_reference,
        })
    }

    /// Continue a file written up to `len` bytes.
    pub fn resume(path: PathBuf, len: u64, with_reference: bool) -> Result<Self> {
        Ok(OrientationCsv {
            w: reopen(&path, len)?,
            path,
            with_reference,
        })
    }

    pub fn flushed_len(&mut self) -> Result<u64> {
        flushed_len(&self.path, &mut self.w)
    }

    pub fn write(
        &mut self,
        step: u64,
        t: f64,
        body: usize,
        q: DQuat,
        reference: Option<DQuat>,
    ) -> Result<()> {
        let a = q * DVec3::X;
        let write = |w: &mut csv::Writer<_>| -> csv::Result<()> {
            let mut row = Row::new(w);
            row.u(step)?.f(t)?.u(body as u64)?;
            for c in wxyz(q).into_iter().chain(a.to_array()) {
                row.f(c)?;
            }
            if self.with_reference {
                let r = reference.unwrap_or(DQuat::NAN);
                for c in wxyz(r) {
                    row.f(c)?;
                }
                row.f(geodesic_angle(q, r))?;
            }
            row.end()
        };
        write(&mut self.w).map_err(|e| csv_err(&self.path, e))
    }

    pub fn flush(&mut self) -> Result<()> {
        self.w.flush().map_err(|e| Error::io(&self.path, e))
    }
}
