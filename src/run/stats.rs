//! Whole-run statistics of the energy and the overlaps, accounted after every
//! step so that no spike between output rows is missed (kept in checkpoints).
//!
//! Per step only the energies' absolute deviations `|E_n − E_0|` are kept
//! (their maxima, over the run and since the last event); the Eq. 65
//! percentages are formed when asked for. `d ↦ |d/E_0| · 100` is monotone
//! under rounding (one division and one product by constants), so the
//! percentage of the largest deviation is the largest percentage, to the bit:
//! the per-step path has no division (`cargo bench --bench run`).

use crate::contact::stage::ContactStats;
use crate::energy::Ledger;

/// Eq. 65 errors and overlaps over the whole run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunStats {
    /// Eq. 64 and full-budget energy at step 0.
    pub e0: f64,
    /// (See `e0`.)
    pub e0_full: f64,
    /// Largest δ/D over the whole run (contact scenes).
    pub max_overlap_ratio: f64,
    /// The largest δ/D of the last step accounted for.
    pub last_overlap_ratio: f64,
    /// `|E − E_0|` and `|E_full − E_0,full|` of the last step (NaN before
    /// the first).
    last_dev: [f64; 2],
    /// Their maxima over the steps accounted for by this process.
    max_dev: [f64; 2],
    /// Their maxima, and the largest δ/D, since the driver's last event.
    window_dev: [f64; 2],
    window_overlap: f64,
    /// What a checkpoint carried (percentages; zero for a fresh run): the
    /// maxima before the resume, and its last errors until the next step.
    carried_max: [f64; 2],
    carried_window: Window,
    carried_last: Option<[f64; 2]>,
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

/// Eq. 65 in percent of an absolute deviation `dev = |E − E_0|`: the same
/// bits as [`crate::energy::error_pct`]`(E, E_0)` (`|x/y| = |x|/|y|`
/// exactly); NaN when `E_0 = 0`.
#[inline]
fn pct(dev: f64, e0: f64) -> f64 {
    if e0 == 0.0 {
        f64::NAN
    } else {
        (dev / e0).abs() * 100.0
    }
}

/// `*m = max(*m, x)`, NaN ignored (as `f64::max`; a deviation is never
/// −0).
#[inline]
fn raise(m: &mut f64, x: f64) {
    if x > *m {
        *m = x;
    }
}

impl RunStats {
    /// Statistics of a run starting with the ledger `initial`.
    pub fn new(initial: &Ledger) -> Self {
        RunStats {
            e0: initial.total(),
            e0_full: initial.total_full(),
            max_overlap_ratio: 0.0,
            last_overlap_ratio: 0.0,
            last_dev: [f64::NAN; 2],
            max_dev: [0.0; 2],
            window_dev: [0.0; 2],
            window_overlap: 0.0,
            carried_max: [0.0; 2],
            carried_window: Window::default(),
            carried_last: None,
        }
    }

    /// Account for one step.
    #[inline]
    pub fn account(&mut self, l: &Ledger, contacts: Option<ContactStats>) {
        if let Some(c) = contacts {
            self.last_overlap_ratio = c.max_overlap_ratio;
            raise(&mut self.max_overlap_ratio, c.max_overlap_ratio);
            raise(&mut self.window_overlap, c.max_overlap_ratio);
        }
        let dev = [
            (l.total() - self.e0).abs(),
            (l.total_full() - self.e0_full).abs(),
        ];
        for ((m, w), d) in self.max_dev.iter_mut().zip(&mut self.window_dev).zip(dev) {
            raise(m, d);
            raise(w, d);
        }
        self.last_dev = dev;
        self.carried_last = None;
    }

    /// Eq. 65 and full-budget error (%) of the step last accounted for (NaN
    /// before the first step, and for E_0 = 0).
    #[inline]
    fn last(&self) -> [f64; 2] {
        self.carried_last.unwrap_or([
            pct(self.last_dev[0], self.e0),
            pct(self.last_dev[1], self.e0_full),
        ])
    }

    /// Eq. 65 error (%) of the step last accounted for.
    pub fn last_error(&self) -> f64 {
        self.last()[0]
    }

    /// Full-budget error (%) of the step last accounted for.
    pub fn last_error_full(&self) -> f64 {
        self.last()[1]
    }

    /// Largest Eq. 65 error (%) over the whole run (every step).
    pub fn max_error(&self) -> f64 {
        self.carried_max[0].max(pct(self.max_dev[0], self.e0))
    }

    /// Largest full-budget error (%) over the whole run (every step).
    pub fn max_error_full(&self) -> f64 {
        self.carried_max[1].max(pct(self.max_dev[1], self.e0_full))
    }

    /// The largest errors and δ/D over the steps since the driver's last
    /// event (a row or a checkpoint of any observer): an observer that needs
    /// maxima between its rows folds this at every event
    /// ([`super::Observer::event`]) instead of looking at every step.
    pub fn since_event(&self) -> Window {
        self.carried_window.max(Window {
            error: pct(self.window_dev[0], self.e0),
            error_full: pct(self.window_dev[1], self.e0_full),
            overlap: self.window_overlap,
        })
    }

    /// Start a new window (the driver, after an event).
    #[inline]
    pub fn reset_window(&mut self) {
        self.window_dev = [0.0; 2];
        self.window_overlap = 0.0;
        self.carried_window = Window::default();
    }

    /// The statistics as numbers (checkpoints).
    pub fn to_array(&self) -> [f64; 11] {
        let w = self.since_event();
        [
            self.e0,
            self.e0_full,
            self.max_overlap_ratio,
            self.max_error(),
            self.max_error_full(),
            self.last_error(),
            self.last_error_full(),
            self.last_overlap_ratio,
            w.error,
            w.error_full,
            w.overlap,
        ]
    }

    /// The statistics from [`RunStats::to_array`].
    pub fn from_array(a: [f64; 11]) -> Self {
        RunStats {
            e0: a[0],
            e0_full: a[1],
            max_overlap_ratio: a[2],
            last_overlap_ratio: a[7],
            last_dev: [f64::NAN; 2],
            max_dev: [0.0; 2],
            window_dev: [0.0; 2],
            window_overlap: 0.0,
            carried_max: [a[3], a[4]],
            carried_window: Window {
                error: a[8],
                error_full: a[9],
                overlap: a[10],
            },
            carried_last: Some([a[5], a[6]]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::error_pct;

    fn ledger(translation: f64, elastic: f64) -> Ledger {
        Ledger {
            translation,
            elastic,
            ..Ledger::default()
        }
    }

    /// Reference: the per-step definition (every step's `error_pct`, its
    /// maxima by `f64::max`), evaluated alongside on energies spread over
    /// many binades and signs, a NaN, and E_0 = 0: the deferred percentages
    /// must be the same bits, and so must a checkpoint round trip.
    #[test]
    fn deferred_percentages_are_the_per_step_ones() {
        for e0 in [0.011489390574877214, -3.7, 0.0] {
            let start = ledger(e0, 0.0);
            let mut s = RunStats::new(&start);
            let (mut max, mut max_full, mut win) = (0.0f64, 0.0f64, 0.0f64);
            let mut x = 0.3f64;
            for i in 0..2000 {
                x = (x * 3.9 * (1.0 - x)).abs();
                let e = if i == 777 {
                    f64::NAN
                } else {
                    e0 + (x - 0.5) * 1e-3f64.powi(i % 7)
                };
                let el = x * 1e-6;
                let l = ledger(e, el);
                s.account(&l, None);
                let (err, err_full) = (error_pct(l.total(), e0), error_pct(l.total_full(), e0));
                (max, max_full, win) = (max.max(err), max_full.max(err_full), win.max(err));
                let (last, last_full) = (err, err_full);
                if i % 97 == 0 {
                    assert_eq!(s.since_event().error.to_bits(), win.to_bits(), "{e0} {i}");
                    s.reset_window();
                    win = 0.0;
                }
                if i % 301 == 0 {
                    s = RunStats::from_array(s.to_array());
                }
                assert_eq!(s.last_error().to_bits(), last.to_bits(), "{e0} {i}");
                assert_eq!(s.last_error_full().to_bits(), last_full.to_bits());
                assert_eq!(s.max_error().to_bits(), max.to_bits(), "{e0} {i}");
                assert_eq!(s.max_error_full().to_bits(), max_full.to_bits());
            }
        }
    }
}
