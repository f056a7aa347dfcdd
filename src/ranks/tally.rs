//! The scene sums of a decomposed step, with the bits of one process.
//!
//! Floating-point sums depend on their order, so no rank-wise partial sum
//! can be combined into the one-process value. Each rank sends rank 0 its
//! terms instead: per owned body the three ledger terms of
//! [`Ledger::add_body`], per touching candidate its points' energies and
//! overlap ratios. Rank 0 puts them in the one-process order (bodies by
//! index; walls body-major, then pairs sorted by global index, as the
//! neighbour list orders them) and sums exactly as the one-process step
//! does; the result is broadcast, so every rank's guards decide alike.

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

/// Doubles per hit header: pair flag, a, b, number of points.
const HEAD: usize = 4;
/// Doubles per point: weight·U, δ/D on A, δ/D on B.
pub(crate) const POINT: usize = 3;

/// Append one hit to a rank's message.
pub(crate) fn push_hit(out: &mut Vec<f64>, key: HitKey, points: &mut dyn Iterator<Item = [f64; 3]>) {
    let at = out.len();
    out.extend([key.pair as u8 as f64, key.a as f64, key.b as f64, 0.0]);
    let mut n = 0;
    for p in points {
        out.extend(p);
        n += 1;
    }
    out[at + 3] = n as f64;
}

/// The hits in `msg` (the concatenated messages of every rank), each with
/// the range of its points.
fn hits(msg: &[f64]) -> Vec<(HitKey, usize, usize)> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < msg.len() {
        let key = HitKey {
            pair: msg[k] != 0.0,
            a: msg[k + 1] as u32,
            b: msg[k + 2] as u32,
        };
        let n = msg[k + 3] as usize;
        out.push((key, k + HEAD, k + HEAD + n * POINT));
        k += HEAD + n * POINT;
    }
    out
}

/// The contact statistics of the hits in `msg`, summed in the one-process
/// order: the serial stage's walls loop, then its pairs loop (`apply` in
/// `contact/stage.rs`; `Slots::compute` reduces in the same order).
pub(crate) fn contact_stats(msg: &[f64]) -> ContactStats {
    let mut list = hits(msg);
    // Each rank's hits are already in order: a stable sort merges the runs.
    list.sort_by_key(|&(k, _, _)| (k.pair, k.a, k.b));
    let mut stats = ContactStats::default();
    for (key, from, to) in list {
        stats.touching += 1;
        for p in msg[from..to].chunks_exact(POINT) {
            stats.elastic += p[0];
            stats.note_overlap(p[1], key.a as usize);
            if key.pair {
                stats.note_overlap(p[2], key.b as usize);
            }
        }
    }
    stats
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
    /// ±1e16 and 1 depends on it.
    #[test]
    fn sums_in_the_one_process_order() {
        let mut r0 = Vec::new();
        let mut r1 = Vec::new();
        let pair = |a, b| HitKey { pair: true, a, b };
        push_hit(&mut r1, pair(0, 5), &mut [[1e16, 0.1, 0.2]].into_iter());
        push_hit(&mut r0, pair(3, 4), &mut [[1.0, 0.3, 0.3]].into_iter());
        push_hit(
            &mut r1,
            HitKey { pair: false, a: 7, b: 2 },
            &mut [[-1e16, 0.3, 0.0]].into_iter(),
        );
        let msg: Vec<f64> = r0.iter().chain(&r1).copied().collect();
        let s = contact_stats(&msg);
        // One-process order: wall (7), pair (0,5), pair (3,4):
        // (-1e16 + 1e16) + 1 = 1; in message order the 1 is rounded away.
        assert_eq!(s.elastic, 1.0);
        assert_eq!(s.touching, 3);
        // The first 0.3 in that order is the wall's, on body 7.
        assert_eq!((s.max_overlap_ratio, s.max_overlap_body), (0.3, 7));
    }
}
