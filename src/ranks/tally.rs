//! The scene sums of a decomposed step, with the bits of one process.
//!
//! Floating-point sums depend on their order, so no rank-wise partial sum
//! can be combined into the one-process value. Each rank sends rank 0 its
//! terms instead: per owned body the three ledger terms of
//! [`Ledger::add_body`], per touching candidate its points' energies, the
//! energies of their friction springs and their overlap ratios. Rank 0
//! puts them in the one-process order (bodies by index; walls body-major,
//! then pairs sorted by global index, as the neighbour list orders them)
//! and sums exactly as the one-process step does; the result is
//! broadcast, so every rank's guards decide alike.

use crate::contact::stage::ContactStats;
use crate::energy::Ledger;

/// One touching candidate as a rank reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HitKey {
    /// A pair (after every wall in the one-process order) or a wall.
    pub pair: bool,
    /// Body A (the lower global index of a pair).
    pub a: u32,
    /// Body B of a pair, or the wall's index.
    pub b: u32,
}

/// Doubles per hit header: a, b (a wall `k` as `−1 − k`), number of
/// points `n`, as `−n` when as many springs' energies follow the points'
/// (a law that keeps records; a frictionless scene sends what it did).
const HEAD: usize = 3;

/// Append one hit to a rank's message: its key, its points' `weight·U`
/// and its springs' energies (the overlap ratios go into the rank's
/// [`Peak`] instead).
pub(crate) fn push_hit(
    out: &mut Vec<f64>,
    key: HitKey,
    energies: impl Iterator<Item = f64>,
    springs: &[f64],
) {
    let b = if key.pair {
        key.b as f64
    } else {
        -1.0 - key.b as f64
    };
    let at = out.len();
    out.extend([key.a as f64, b, 0.0]);
    out.extend(energies);
    let n = (out.len() - at - HEAD) as f64;
    assert!(
        springs.is_empty() || springs.len() as f64 == n,
        "a spring a point"
    );
    out[at + 2] = if springs.is_empty() { n } else { -n };
    out.extend_from_slice(springs);
}

/// The largest δ/D a rank saw, and where it comes first in the
/// one-process order (which decides ties: `note_overlap` keeps the first).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Peak {
    pub ratio: f64,
    /// (pair, a, b, point, side B): the one-process order of notes.
    pub at: [f64; 5],
    pub body: f64,
}

/// Doubles of a [`Peak`] on the wire.
pub(crate) const PEAK: usize = 7;

impl Default for Peak {
    fn default() -> Self {
        Peak {
            ratio: 0.0,
            at: [f64::INFINITY; 5],
            body: 0.0,
        }
    }
}

impl Peak {
    /// Note `ratio` on `body` at position `at` (notes come in the
    /// one-process order within a rank).
    #[inline]
    pub(crate) fn note(&mut self, ratio: f64, at: [f64; 5], body: u32) {
        if ratio > self.ratio {
            *self = Peak {
                ratio,
                at,
                body: body as f64,
            };
        }
    }

    pub(crate) fn to_array(self) -> [f64; PEAK] {
        let a = self.at;
        [self.ratio, a[0], a[1], a[2], a[3], a[4], self.body]
    }

    pub(crate) fn from_slice(d: &[f64]) -> Self {
        Peak {
            ratio: d[0],
            at: [d[1], d[2], d[3], d[4], d[5]],
            body: d[6],
        }
    }

    /// The one-process maximum of two ranks' peaks: the larger ratio, of
    /// equal ones the first in order.
    pub(crate) fn max(self, o: Peak) -> Peak {
        let earlier =
            o.at.iter()
                .zip(&self.at)
                .find(|(x, y)| x != y)
                .is_some_and(|(x, y)| x < y);
        if o.ratio > self.ratio || (o.ratio == self.ratio && o.ratio > 0.0 && earlier) {
            o
        } else {
            self
        }
    }
}

/// The contact statistics of the hits in `msg` (the concatenated
/// messages of every rank) and the ranks' peaks, and the springs' energy,
/// summed in the one-process order: the candidate loop's walls, then its
/// pairs, point by point (`Sums` in `contact/blocks.rs`: the elastic
/// energy and the springs' in two sums).
pub(crate) fn contact_stats(msg: &[f64], peaks: &[Peak]) -> (ContactStats, f64) {
    let mut list = Vec::new();
    let mut k = 0;
    while k < msg.len() {
        let (a, b) = (msg[k], msg[k + 1]);
        let n = msg[k + 2].abs() as usize;
        let m = if msg[k + 2] < 0.0 { n } else { 0 };
        // Walls (b < 0) first, body-major, walls in order; then pairs.
        let key = if b < 0.0 {
            (false, a, -1.0 - b)
        } else {
            (true, a, b)
        };
        list.push((key, k + HEAD, k + HEAD + n, k + HEAD + n + m));
        k += HEAD + n + m;
    }
    // Each rank's hits are already in order: a stable sort merges the runs.
    list.sort_by(|x, y| {
        (x.0 .0, x.0 .1, x.0 .2)
            .partial_cmp(&(y.0 .0, y.0 .1, y.0 .2))
            .expect("finite keys")
    });
    let mut stats = ContactStats::default();
    let mut spring = 0.0;
    for (_, from, to, end) in list {
        stats.touching += 1;
        for e in &msg[from..to] {
            stats.elastic += e;
        }
        for s in &msg[to..end] {
            spring += s;
        }
    }
    let peak = peaks.iter().copied().fold(Peak::default(), Peak::max);
    stats.max_overlap_ratio = peak.ratio;
    stats.max_overlap_body = peak.body as usize;
    (stats, spring)
}

/// The ledger of per-body terms `[m g·x, ½ m v², ½ ω·Iω]` (by body index),
/// summed as [`Ledger::add_body`] sums them, body after body.
pub(crate) fn ledger(terms: &[[f64; 3]], elastic: f64, dissipated: f64) -> Ledger {
    let mut l = Ledger {
        elastic,
        dissipated,
        ..Ledger::default()
    };
    for t in terms {
        l.gravity -= t[0];
        l.translation += t[1];
        l.rotation += t[2];
    }
    l
}

/// One body's ledger terms, as [`Ledger::add_body`] computes them.
#[inline]
pub(crate) fn body_terms(
    b: &crate::body::Body,
    s: &crate::body::BodyState,
    g: glam::DVec3,
) -> [f64; 3] {
    [
        b.mass * g.dot(s.x),
        0.5 * b.mass * s.v.length_squared(),
        b.inertia.kinetic_energy(s.rot.omega_b),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hits from two ranks, out of global order, are summed in the
    /// one-process order (walls first, then pairs by index): the sum of
    /// ±1e16 and 1 depends on it; so is the springs' energy, a hit with
    /// none (a frictionless wall) among them.
    #[test]
    fn sums_in_the_one_process_order() {
        let mut r0 = Vec::new();
        let mut r1 = Vec::new();
        let pair = |a, b| HitKey { pair: true, a, b };
        let wall = |a, b| HitKey { pair: false, a, b };
        push_hit(&mut r1, pair(0, 5), [1e16].into_iter(), &[-1e16]);
        push_hit(&mut r0, pair(3, 4), [1.0].into_iter(), &[1.0]);
        push_hit(&mut r1, wall(7, 2), [-1e16].into_iter(), &[1e16]);
        push_hit(&mut r0, wall(7, 3), [0.0].into_iter(), &[]);
        let msg: Vec<f64> = r0.iter().chain(&r1).copied().collect();
        let (mut p0, mut p1) = (Peak::default(), Peak::default());
        p0.note(0.3, [1.0, 3.0, 4.0, 0.0, 0.0], 3);
        p1.note(0.3, [0.0, 7.0, 2.0, 0.0, 0.0], 7);
        let (s, spring) = contact_stats(&msg, &[p0, p1]);
        // One-process order: walls (7, 2), (7, 3), pairs (0,5), (3,4):
        // (-1e16 + 1e16) + 1 = 1; in message order the 1 is rounded away.
        assert_eq!(s.elastic, 1.0);
        assert_eq!(spring, 1.0);
        assert_eq!(s.touching, 4);
        // The first 0.3 in that order is the wall's, on body 7.
        assert_eq!((s.max_overlap_ratio, s.max_overlap_body), (0.3, 7));
    }
}
