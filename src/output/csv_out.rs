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

pub const ENERGY_COLUMNS: [&str; 10] = [
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
];

/// Energy ledger per output row, with Eq. 65 errors. `e_total` is Eq. 64
/// (no elastic term); the `full` error includes the elastic energy.
/// `energy_error_window_max_pct` is the largest Eq. 65 error over every step
/// since the previous row, so no spike between rows is hidden.
pub struct EnergyCsv {
    path: PathBuf,
    w: csv::Writer<BufWriter<File>>,
    e0: f64,
    e0_full: f64,
    window_max: f64,
    with_contacts: bool,
    window_overlap: f64,
    /// Largest δ/D over the whole run (contact scenes).
    pub max_overlap_ratio: f64,
    /// Largest Eq. 65 and full-budget errors over the whole run (every step).
    pub max_error: f64,
    pub max_error_full: f64,
    pub last_error: f64,
    pub last_error_full: f64,
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
            e0: initial.total(),
            e0_full: initial.total_full(),
            window_max: 0.0,
            with_contacts,
            window_overlap: 0.0,
            max_overlap_ratio: 0.0,
            max_error: 0.0,
            max_error_full: 0.0,
            last_error: f64::NAN,
            last_error_full: f64::NAN,
        })
    }

    /// Account for one step; `write` says whether this step gets a row.
    pub fn observe(
        &mut self,
        step: u64,
        t: f64,
        l: &Ledger,
        contacts: Option<ContactStats>,
        write: bool,
    ) -> Result<()> {
        let c = contacts.unwrap_or_default();
        self.window_overlap = self.window_overlap.max(c.max_overlap_ratio);
        self.max_overlap_ratio = self.max_overlap_ratio.max(c.max_overlap_ratio);
        let err = error_pct(l.total(), self.e0);
        let err_full = error_pct(l.total_full(), self.e0_full);
        // f64::max ignores NaN, so the maxima stay NaN-free for E_0 = 0 scenes.
        self.window_max = self.window_max.max(err);
        self.max_error = self.max_error.max(err);
        self.max_error_full = self.max_error_full.max(err_full);
        self.last_error = err;
        self.last_error_full = err_full;
        if write {
            let window = if err.is_nan() {
                f64::NAN
            } else {
                self.window_max
            };
            let with_contacts = self.with_contacts;
            let overlap = self.window_overlap;
            Row::new(&mut self.w)
                .u(step)
                .and_then(|r| r.f(t))
                .and_then(|r| r.f(l.gravity))
                .and_then(|r| r.f(l.translation))
                .and_then(|r| r.f(l.rotation))
                .and_then(|r| r.f(l.elastic))
                .and_then(|r| r.f(l.total()))
                .and_then(|r| r.f(err))
                .and_then(|r| r.f(err_full))
                .and_then(|r| r.f(window))
                .and_then(|r| {
                    if with_contacts {
                        r.u(c.touching as u64)?.f(overlap)?;
                    }
                    r.end()
                })
                .map_err(|e| csv_err(&self.path, e))?;
            self.window_max = 0.0;
            self.window_overlap = 0.0;
        }
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
