//! What contacts keep (`contact/carry.rs`: the fibre pairs' memories,
//! the contacts' records) across ranks, for every client alike. A record
//! changes what its contact computes, so it must be the one-process
//! record whichever rank computes that contact. Between rebuilds each
//! rank keeps those of its own candidates (a contact computed on two
//! ranks, its bodies having two owners, makes the same record on both
//! from the same inputs). At a rebuild every rank sends the entries whose
//! key's first body it owns (each record once) and every rank takes those
//! of its new candidates; at a checkpoint rank 0 gathers them. The
//! message is the states file's bytes of the entries (`carry::encode`),
//! eight to a word, copied and never computed with.

use crate::contact::carry::{decode, encode, Carried, Entry, Key};

/// One rank's message of `stores` (each sorted by key, the entries whose
/// first body `mine` accepts): the byte count, then the bytes.
pub(super) fn pack<R: Carried>(
    stores: impl IntoIterator<Item = impl IntoIterator<Item = Entry<R>>>,
    mine: impl Fn(u32) -> bool,
) -> Vec<f64> {
    let mut bytes = vec![];
    for store in stores {
        encode(
            store.into_iter().filter(|(k, _)| mine(k.first())),
            &mut bytes,
        );
    }
    let mut words = vec![f64::from_bits(bytes.len() as u64)];
    words.extend(bytes.chunks(8).map(|c| {
        let mut w = [0u8; 8];
        w[..c.len()].copy_from_slice(c);
        f64::from_bits(u64::from_le_bytes(w))
    }));
    words
}

/// The `K` stores of every rank's message ([`pack`], one after the
/// other), each sorted by key (each rank's entries are sorted; their
/// union is not).
pub(super) fn unpack<R: Carried, const K: usize>(words: &[f64]) -> [Vec<Entry<R>>; K] {
    let mut stores: [Vec<Entry<R>>; K] = std::array::from_fn(|_| vec![]);
    let mut rest = words;
    while let Some((len, tail)) = rest.split_first() {
        let len = len.to_bits() as usize;
        let (part, after) = tail.split_at(len.div_ceil(8));
        rest = after;
        let bytes: Vec<u8> = part
            .iter()
            .flat_map(|w| w.to_bits().to_le_bytes())
            .take(len)
            .collect();
        let mut at = 0;
        for store in &mut stores {
            let (entries, used) =
                decode::<R>(&bytes[at..], "sent", |_| true).expect("a rank sends what it keeps");
            store.extend(entries);
            at += used;
        }
    }
    for store in &mut stores {
        store.sort_unstable_by_key(|e| e.0);
    }
    stores
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::fibre_fibre::PairMemory;
    use crate::contact::history::{ContactKey, History};
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
        let stores = || [h.walls.iter().copied(), h.pairs.iter().copied()];
        let r0 = pack(stores(), |a| a < 3);
        let r1 = pack(stores(), |a| a >= 3);
        let [walls, pairs] = unpack::<Record, 2>(&[r1, r0].concat());
        let back = History { walls, pairs };
        assert_eq!(back, h);
        assert_eq!(back.walls[0].1.xi.y.to_bits(), (-0.0f64).to_bits());
        assert_eq!(back.pairs[1].1.place.z.to_bits(), 5f64.to_bits() ^ 1);
        assert_eq!(back.pairs[1].1.weight, -4.75);
    }

    /// Memories likewise, from ranks of which one sends none (its message
    /// is its empty store's count alone).
    #[test]
    fn memories_cross_ranks_to_the_bit() {
        let m = |k: u16| PairMemory::from_raw([5, k, 900]).unwrap();
        let all = vec![((0, 3), m(1)), ((2, 9), m(2)), ((7, 8), m(3))];
        let r0 = pack([all.iter().copied()], |i| i < 5);
        let r1 = pack([all.iter().copied()], |i| i >= 5);
        let r2 = pack([all.iter().copied()], |_| false);
        assert_eq!(r2.len(), 2);
        let [back] = unpack::<PairMemory, 1>(&[r1, r2, r0].concat());
        assert_eq!(back, all);
    }
}
