//! What contacts keep (`contact/carry.rs`: the fibre pairs' memories,
//! the contacts' records) across ranks, for every client alike. A record
//! changes what its contact computes, so it must be the one-process
//! record whichever rank computes that contact. Between rebuilds each
//! rank keeps those of its own candidates (a contact computed on two
//! ranks, its bodies having two owners, makes the same record on both
//! from the same inputs). At a rebuild every rank sends the entries whose
//! key's first body it owns (each record once) and every rank takes those
//! of its new candidates; at a checkpoint rank 0 gathers them. One
//! message carries every client's entries, a section per store as the
//! states file writes it (`carry::encode`), eight bytes to a word, copied
//! and never computed with.

use crate::contact::carry::{decode, encode, Carried, Entry, Key};

/// One rank's message: sections of entries, one per store, each a
/// states file's section (`carry::encode`).
#[derive(Debug, Default)]
pub(super) struct Message(Vec<u8>);

impl Message {
    /// Add `store`'s section (sorted by key): the entries whose key's
    /// first body `mine` accepts.
    pub(super) fn add<R: Carried>(
        &mut self,
        store: impl IntoIterator<Item = Entry<R>>,
        mine: impl Fn(u32) -> bool,
    ) {
        encode(
            store.into_iter().filter(|(k, _)| mine(k.first())),
            &mut self.0,
        );
    }

    /// The words sent: the byte count, then the bytes, eight to a word.
    pub(super) fn words(&self) -> Vec<f64> {
        let mut words = vec![f64::from_bits(self.0.len() as u64)];
        words.extend(self.0.chunks(8).map(|c| {
            let mut w = [0u8; 8];
            w[..c.len()].copy_from_slice(c);
            f64::from_bits(u64::from_le_bytes(w))
        }));
        words
    }
}

/// Every rank's [`Message`] (their words one after the other), read
/// section by section in the order they were added.
#[derive(Debug)]
pub(super) struct Received {
    /// Each rank's bytes and where its next section starts.
    parts: Vec<(Vec<u8>, usize)>,
}

impl Received {
    /// The messages of `words`.
    pub(super) fn new(words: &[f64]) -> Self {
        let mut parts = vec![];
        let mut rest = words;
        while let Some((len, tail)) = rest.split_first() {
            let len = len.to_bits() as usize;
            let (part, after) = tail.split_at(len.div_ceil(8));
            rest = after;
            let bytes = part
                .iter()
                .flat_map(|w| w.to_bits().to_le_bytes())
                .take(len)
                .collect();
            parts.push((bytes, 0));
        }
        Received { parts }
    }

    /// The next section of every rank's message, merged and sorted by
    /// key (each rank's entries are sorted; their union is not).
    pub(super) fn take<R: Carried>(&mut self) -> Vec<Entry<R>> {
        let mut store = vec![];
        for (bytes, at) in &mut self.parts {
            let (entries, used) =
                decode::<R>(&bytes[*at..], "sent", |_| true).expect("a rank sends what it keeps");
            store.extend(entries);
            *at += used;
        }
        store.sort_unstable_by_key(|e| e.0);
        store
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::fibre_fibre::PairMemory;
    use crate::contact::history::{ContactKey, History};
    use crate::contact::law::Record;
    use glam::DVec3;

    /// Two ranks' memories and records, each sending its own, give every
    /// one back to the bit, sorted, whatever the ranks' order; a rank that
    /// sends none sends its sections' counts.
    #[test]
    fn what_contacts_keep_crosses_ranks_to_the_bit() {
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
        let m = |k: u16| PairMemory::from_raw([5, k, 900]).unwrap();
        let memories = vec![((0, 3), m(1)), ((2, 9), m(2)), ((7, 8), m(3))];
        // Rank 0 owns bodies below 3, rank 1 the others up to 5, rank 2 none.
        let message = |mine: &dyn Fn(u32) -> bool| {
            let mut msg = Message::default();
            msg.add(memories.iter().copied(), mine);
            msg.add(h.walls.iter().copied(), mine);
            msg.add(h.pairs.iter().copied(), mine);
            msg.words()
        };
        let r0 = message(&|a| a < 3);
        let r1 = message(&|a| a >= 3);
        let r2 = message(&|_| false);
        assert_eq!(r2.len(), 1 + 3);
        let mut got = Received::new(&[r1, r2, r0].concat());
        assert_eq!(got.take::<PairMemory>(), memories);
        let (walls, pairs) = (got.take::<Record>(), got.take::<Record>());
        let back = History { walls, pairs };
        assert_eq!(back, h);
        assert_eq!(back.walls[0].1.xi.y.to_bits(), (-0.0f64).to_bits());
        assert_eq!(back.pairs[1].1.place.z.to_bits(), 5f64.to_bits() ^ 1);
        assert_eq!(back.pairs[1].1.weight, -4.75);
    }
}
