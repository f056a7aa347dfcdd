//! Whole-run statistics of the energy and the overlaps, accounted after every
//! step so that no spike between output rows is missed (kept in checkpoints).

use crate::contact::stage::ContactStats;
use crate::energy::{error_pct, Ledger};

/// Eq. 65 errors and overlaps over the whole run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunStats {
    /// Eq. 64 and full-budget energy at step 0.
    pub e0: f64,
    pub e0_full: f64,
    /// Largest δ/D over the whole run (contact scenes).
    pub max_overlap_ratio: f64,
    /// Largest Eq. 65 and full-budget errors over the whole run (every step).
    pub max_error: f64,
    pub max_error_full: f64,
    /// The errors and the largest δ/D of the last step accounted for.
    pub last_error: f64,
    pub last_error_full: f64,
    pub last_overlap_ratio: f64,
}

impl RunStats {
    pub fn new(initial: &Ledger) -> Self {
        RunStats {
            e0: initial.total(),
            e0_full: initial.total_full(),
            max_overlap_ratio: 0.0,
            max_error: 0.0,
            max_error_full: 0.0,
            last_error: f64::NAN,
            last_error_full: f64::NAN,
            last_overlap_ratio: 0.0,
        }
    }

    /// Account for one step.
    #[inline]
    pub fn account(&mut self, l: &Ledger, contacts: Option<ContactStats>) {
        let c = contacts.unwrap_or_default();
        self.last_overlap_ratio = c.max_overlap_ratio;
        self.max_overlap_ratio = self.max_overlap_ratio.max(c.max_overlap_ratio);
        let err = error_pct(l.total(), self.e0);
        let err_full = error_pct(l.total_full(), self.e0_full);
        // f64::max ignores NaN, so the maxima stay NaN-free for E_0 = 0 scenes.
        self.max_error = self.max_error.max(err);
        self.max_error_full = self.max_error_full.max(err_full);
        self.last_error = err;
        self.last_error_full = err_full;
    }

    pub fn to_array(&self) -> [f64; 8] {
        [
            self.e0,
            self.e0_full,
            self.max_overlap_ratio,
            self.max_error,
            self.max_error_full,
            self.last_error,
            self.last_error_full,
            self.last_overlap_ratio,
        ]
    }

    pub fn from_array(a: [f64; 8]) -> Self {
        RunStats {
            e0: a[0],
            e0_full: a[1],
            max_overlap_ratio: a[2],
            max_error: a[3],
            max_error_full: a[4],
            last_error: a[5],
            last_error_full: a[6],
            last_overlap_ratio: a[7],
        }
    }
}
