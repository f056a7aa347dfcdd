//! The δt grid: a fine reference step and the whole multiples of it that
//! the rotators run at, so the reference is sampled exactly at their times.

use crate::error::{Error, Result};

/// The fine grid of a study and the multiples run on it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Grid {
    /// Fine steps over `t_end` (even).
    pub(super) n_ref: u64,
    /// The fine step, `t_end / n_ref`.
    pub(super) dt_ref: f64,
    /// The multiples `m` of `dt_ref` run, largest first; each divides `n_ref`.
    pub(super) ms: Vec<u64>,
    /// The fine steps between stored reference samples: the gcd of `ms`.
    pub(super) stride: u64,
}

impl Grid {
    /// `points` multiples closest in log to the geometric sequence from
    /// `dt_max` to `dt_min`, on a fine grid `factor`× finer than `dt_min`.
    pub(super) fn new(
        t_end: f64,
        dt_max: f64,
        dt_min: f64,
        points: usize,
        factor: f64,
    ) -> Result<Grid> {
        let bad = |k: &str, m: String| Error::bad("command line", k, m);
        if !(dt_min > 0.0 && dt_max >= dt_min) {
            return Err(bad(
                "--dt-min",
                format!("need 0 < dt-min <= dt-max (got {dt_min:e}, {dt_max:e})"),
            ));
        }
        if dt_max > t_end {
            return Err(bad(
                "--dt-max",
                format!("dt-max = {dt_max:e} s exceeds t_end = {t_end:e} s"),
            ));
        }
        if points < 2 || dt_max == dt_min {
            return Err(bad(
                "--points",
                "need at least 2 points and dt-max > dt-min to fit an order".into(),
            ));
        }
        if factor.is_nan() || factor < 1.0 {
            return Err(bad("--ref-factor", "must be >= 1".into()));
        }
        // Even, so the Richardson run at twice the step lands on the same end time.
        let mut n_ref = (t_end / (dt_min / factor)).round().max(2.0) as u64;
        n_ref += n_ref % 2;
        if n_ref > 2_000_000_000 {
            return Err(bad(
                "--dt-min",
                format!("the reference would take {n_ref} steps; raise dt-min or lower --ref-factor / --t-end"),
            ));
        }
        let dt_ref = t_end / n_ref as f64;
        let divs = divisors(n_ref);
        let mut ms: Vec<u64> = (0..points)
            .map(|k| {
                let target = dt_max * (dt_min / dt_max).powf(k as f64 / (points - 1) as f64);
                *divs
                    .iter()
                    .min_by(|a, b| {
                        let da = ((**a as f64 * dt_ref) / target).ln().abs();
                        let db = ((**b as f64 * dt_ref) / target).ln().abs();
                        da.total_cmp(&db)
                    })
                    .expect("n_ref has divisors")
            })
            .collect();
        ms.sort_unstable_by(|a, b| b.cmp(a));
        ms.dedup();
        let stride = ms.iter().fold(0, |g, &m| gcd(g, m));
        Ok(Grid {
            n_ref,
            dt_ref,
            ms,
            stride,
        })
    }
}

fn divisors(n: u64) -> Vec<u64> {
    let mut d = Vec::new();
    let mut i = 1;
    while i * i <= n {
        if n.is_multiple_of(i) {
            d.push(i);
            if i * i != n {
                d.push(n / i);
            }
        }
        i += 1;
    }
    d.sort_unstable();
    d
}

pub(super) fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Expected values by hand: 0.1 s at 1e-7 / 10 is n = 10⁷ = 2⁷·5⁷ fine
    /// steps; the targets 1e-5 … 1e-7 s are m = 1000, 316.2, 100, 31.62, 10,
    /// and the divisors of 10⁷ nearest in log to 316.2 and 31.62 are 320
    /// (2⁶·5) and 32 (2⁵), as 250, 400, 25 and 40 are farther.
    #[test]
    fn grid_is_whole_multiples() {
        let g = Grid::new(0.1, 1e-5, 1e-7, 5, 10.0).unwrap();
        assert_eq!(g.n_ref, 10_000_000);
        assert_eq!(g.ms, vec![1000, 320, 100, 32, 10]);
        assert_eq!(g.stride, 2);
        for m in g.ms {
            assert_eq!(g.n_ref % m, 0);
        }
    }
}
