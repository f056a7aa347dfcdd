//! The contacts' records (friction's springs, `contact/history.rs`) across
//! ranks. A contact computed on two ranks (a pair whose bodies have two
//! owners) makes the same record on both from the same inputs, so between
//! rebuilds each rank keeps the records of its own candidates. At a
//! rebuild the records follow their contacts, as the pair memories do
//! (`memory.rs`): each rank sends those of the wall contacts of its bodies
//! and of the pairs whose first body it owns (each contact once), and
//! every rank keeps those of contacts that touch a body it now owns. At a
//! checkpoint rank 0 gathers them all.

use crate::contact::history::{record_from_raw, record_to_raw, ContactKey, History, RAW};

/// Doubles of one record on the wire: the key (`a`, `b` in one `f64`'s
/// bits, the slot in another's), then the record's numbers (its spring
/// and its point's place).
const WIRE: usize = 2 + RAW;

/// The entries of `h` that `mine` accepts (walls, then pairs) as wire
/// doubles: the counts of walls and of pairs, then each entry.
pub(super) fn encode(h: &History, mine: impl Fn(bool, &ContactKey) -> bool) -> Vec<f64> {
    let mut out = vec![0.0, 0.0];
    for (pair, store) in [(false, &h.walls), (true, &h.pairs)] {
        let mut count = 0;
        for (k, r) in store.iter().filter(|(k, _)| mine(pair, k)) {
            out.push(f64::from_bits(u64::from(k.a) << 32 | u64::from(k.b)));
            out.push(f64::from_bits(u64::from(k.slot)));
            out.extend(record_to_raw(r));
            count += 1;
        }
        out[pair as usize] = count as f64;
    }
    out
}

/// The store of the wire doubles of every rank (each an [`encode`], one
/// after the other), sorted by key (each rank's entries are sorted; their
/// union is not).
pub(super) fn decode(wire: &[f64]) -> History {
    let mut h = History::default();
    let mut at = 0;
    while at < wire.len() {
        let (walls, pairs) = (wire[at] as usize, wire[at + 1] as usize);
        at += 2;
        let part = &wire[at..at + WIRE * (walls + pairs)];
        at += part.len();
        for (k, d) in part.chunks_exact(WIRE).enumerate() {
            let (ab, slot) = (d[0].to_bits(), d[1].to_bits());
            let key = ContactKey {
                a: (ab >> 32) as u32,
                b: ab as u32,
                slot: slot as u8,
            };
            let raw = d[2..].try_into().expect("a record's numbers");
            let entry = (key, record_from_raw(raw));
            if k < walls {
                h.walls.push(entry);
            } else {
                h.pairs.push(entry);
            }
        }
    }
    h.walls.sort_unstable_by_key(|e| e.0);
    h.pairs.sort_unstable_by_key(|e| e.0);
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::law::Record;
    use glam::DVec3;

    /// Two ranks' records, each sending its own, give every record back
    /// to the bit, sorted, whatever the ranks' order.
    #[test]
    fn records_cross_ranks_to_the_bit() {
        let key = |a, b, slot| ContactKey { a, b, slot };
        let rec = |x: f64| Record {
            xi: DVec3::new(x, -0.0, f64::MIN_POSITIVE),
            place: DVec3::new(-x, 1e-300, f64::from_bits(x.to_bits() ^ 1)),
            weight: 0.25 - x,
        };
        let h = History {
            walls: vec![(key(1, 5, 1), rec(1e-7)), (key(4, 0, 0), rec(-3e-9))],
            pairs: vec![
                (key(1, 2, 0), rec(2e-8)),
                (key(1, 2, 1), rec(5.0)),
                (key(4, 9, 0), rec(-1.0)),
            ],
        };
        // Rank 0 owns bodies below 3, rank 1 the others.
        let r0 = encode(&h, |_, k| k.a < 3);
        let r1 = encode(&h, |_, k| k.a >= 3);
        let back = decode(&[r1, r0].concat());
        assert_eq!(back, h);
        assert_eq!(back.walls[0].1.xi.y.to_bits(), (-0.0f64).to_bits());
        assert_eq!(back.pairs[1].1.place.z.to_bits(), 5f64.to_bits() ^ 1);
        assert_eq!(back.pairs[1].1.weight, -4.75);
    }
}
