//! Whole-run statistics of the energy and the overlaps, accounted after every
//! step so that no spike between output rows is missed (kept in checkpoints).

use crate::contact::stage::ContactStats;
use crate::energy::{error_pct, Ledger};

/// Eq. 65 errors and overlaps over the whole run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunStats {
    /// Eq. 64 and full-budget energy at step 0.
    pub e0: f64,
    /// (See `e0`.)
    pub e0_full: f64,
    /// Largest δ/D over the whole run (contact scenes).
    pub max_overlap_ratio: f64,
    /// Largest Eq. 65 and full-budget errors over the whole run (every step).
    pub max_error: f64,
    /// (See `max_error`.)
    pub max_error_full: f64,
    /// The errors and the largest δ/D of the last step accounted for.
    pub last_error: f64,
    /// (See `last_error`.)
    pub last_error_full: f64,
    /// (See `last_error`.)
    pub last_overlap_ratio: f64,
    /// The largest errors and δ/D over the steps since the driver's last
    /// event (a row or a checkpoint of any observer): an observer that needs
    /// maxima between its rows folds this at every event
    /// ([`super::Observer::event`]) instead of looking at every step.
    pub since_event: Window,
}

/// Largest Eq. 65 error, full-budget error and δ/D over a span of steps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Window {
    /// Eq. 65 error, %.
    pub error: f64,
    /// Full-budget error, %.
    pub error_full: f64,
    /// δ/D.
    pub overlap: f64,
}

impl Window {
    /// The maxima of both spans. `f64::max` ignores NaN, so the maxima stay
    /// NaN-free for E_0 = 0 scenes.
    #[inline]
    pub fn max(self, o: Window) -> Window {
        Window {
            error: self.error.max(o.error),
            error_full: self.error_full.max(o.error_full),
            overlap: self.overlap.max(o.overlap),
        }
    }
}

impl RunStats {
    /// Statistics of a run starting with the ledger `initial`.
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
            since_event: Window::default(),
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
        self.since_event = self.since_event.max(Window {
            error: err,
            error_full: err_full,
            overlap: c.max_overlap_ratio,
        });
    }

    /// The statistics as numbers (checkpoints).
    pub fn to_array(&self) -> [f64; 11] {
        [
            self.e0,
            self.e0_full,
            self.max_overlap_ratio,
            self.max_error,
            self.max_error_full,
            self.last_error,
            self.last_error_full,
            self.last_overlap_ratio,
            self.since_event.error,
            self.since_event.error_full,
            self.since_event.overlap,
        ]
    }

    /// The statistics from [`RunStats::to_array`].
    pub fn from_array(a: [f64; 11]) -> Self {
        RunStats {
            e0: a[0],
            e0_full: a[1],
            max_overlap_ratio: a[2],
            max_error: a[3],
            max_error_full: a[4],
            last_error: a[5],
            last_error_full: a[6],
            last_overlap_ratio: a[7],
            since_event: Window {
                error: a[8],
                error_full: a[9],
                overlap: a[10],
            },
        }
    }
}
