//! The per-contact history store: what the law keeps of each touching
//! contact point between force computations ([`Record`]), by the
//! contact's identity ([`ContactKey`]: its pair and its slot).
//!
//! A store is a vector sorted by key, one per candidate list (walls,
//! body pairs). Each computation reads the last one ([`recall`]: mostly
//! the entry after the last one found, else a binary search) and writes a new one in list order, from the blocks in the
//! order they are added: a contact not touching this computation loses
//! its record, and the bits do not depend on the thread count. Only a
//! law that keeps something per contact (friction) has a store: a
//! frictionless scene keeps none (no bytes, no work).
//!
//! A point's slot (docs/contacts.md, "Friction"): a fibre's end (0 or 1)
//! against a wall; a sphere's 0 against a wall; the point's rank in the
//! kernel's output for a body pair (a single contact: 0; a parallel
//! pair's main point 0 and its second 1).

use super::law::Record;

/// A contact point's identity: body `a` and body `b` (`a < b`) or wall
/// `b` (in the walls' store), and the point's slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct ContactKey {
    pub a: u32,
    pub b: u32,
    pub slot: u8,
}

/// A contact's record with its identity.
pub(crate) type Entry = (ContactKey, Record);

/// The records of the touching contacts at the last computation.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct History {
    /// Body–wall contacts, sorted by key.
    pub walls: Vec<Entry>,
    /// Body–body contacts, sorted by key.
    pub pairs: Vec<Entry>,
}

/// The record of `key` in the sorted `store`; a fresh one (a contact that
/// starts touching) if it has none. `cursor` is where the last lookup
/// ended: the loop asks for the keys in the store's order, and most
/// contacts last, so the entry at the cursor is usually the one asked
/// for; otherwise a binary search places it.
#[inline]
pub(crate) fn recall(store: &[Entry], cursor: &mut usize, key: &ContactKey) -> Record {
    if let Some((k, r)) = store.get(*cursor) {
        if k == key {
            *cursor += 1;
            return *r;
        }
    }
    match store.binary_search_by(|(k, _)| k.cmp(key)) {
        Ok(i) => {
            *cursor = i + 1;
            store[i].1
        }
        Err(i) => {
            *cursor = i;
            Record::default()
        }
    }
}

/// `store` made sorted by key (a list's walls come body-major; a body's
/// walls and their slots are put in order here).
pub(crate) fn sorted(mut store: Vec<Entry>) -> Vec<Entry> {
    if !store.is_sorted_by_key(|e| e.0) {
        store.sort_unstable_by_key(|e| e.0);
    }
    store
}

/// Bytes of one entry in a checkpoint's states file: `u32` a, `u32` b,
/// `u8` slot, then the record's three `f64` (ξ), little-endian, exact bits.
pub(crate) const ENTRY_BYTES: usize = 33;

/// A record's numbers, in the order they are stored and sent.
#[inline]
pub(crate) fn record_to_raw(r: &Record) -> [f64; 3] {
    let Record { xi } = *r;
    xi.to_array()
}

/// The record of [`record_to_raw`]'s numbers.
#[inline]
pub(crate) fn record_from_raw(d: [f64; 3]) -> Record {
    Record {
        xi: glam::DVec3::from_array(d),
    }
}

impl History {
    /// Append the store to a checkpoint's states file: per list (walls,
    /// then pairs) a `u64` count and its entries ([`ENTRY_BYTES`] each).
    pub(crate) fn encode(&self, out: &mut Vec<u8>) {
        for store in [&self.walls, &self.pairs] {
            out.extend_from_slice(&(store.len() as u64).to_le_bytes());
            for (k, r) in store {
                out.extend_from_slice(&k.a.to_le_bytes());
                out.extend_from_slice(&k.b.to_le_bytes());
                out.push(k.slot);
                for x in record_to_raw(r) {
                    out.extend_from_slice(&x.to_bits().to_le_bytes());
                }
            }
        }
    }

    /// The store at the start of `b` (as [`History::encode`] wrote it) for
    /// `n` bodies and `walls` walls, and the bytes it took; or what is
    /// wrong: a truncated section, a key no run writes, keys out of order.
    pub(crate) fn decode(b: &[u8], n: usize, walls: usize) -> Result<(Self, usize), String> {
        let mut at = 0;
        let mut h = History::default();
        for (name, pairs) in [("wall", false), ("pair", true)] {
            let count = b
                .get(at..at + 8)
                .map(|w| u64::from_le_bytes(w.try_into().expect("8 bytes")))
                .ok_or("the contacts' records are truncated")? as usize;
            at += 8;
            let len = count
                .checked_mul(ENTRY_BYTES)
                .filter(|&l| at + l <= b.len())
                .ok_or("the contacts' records are truncated")?;
            let store = if pairs { &mut h.pairs } else { &mut h.walls };
            store.reserve(count);
            for e in b[at..at + len].chunks_exact(ENTRY_BYTES) {
                let word = |i: usize| u32::from_le_bytes(e[i..i + 4].try_into().expect("4 bytes"));
                let f = |i: usize| {
                    f64::from_bits(u64::from_le_bytes(e[i..i + 8].try_into().expect("8 bytes")))
                };
                let key = ContactKey {
                    a: word(0),
                    b: word(4),
                    slot: e[8],
                };
                let valid = (key.a as usize) < n
                    && if pairs {
                        key.a < key.b && (key.b as usize) < n
                    } else {
                        (key.b as usize) < walls
                    };
                if !valid {
                    return Err(format!(
                        "{name} contact ({}, {}, slot {}) is not one a run writes",
                        key.a, key.b, key.slot
                    ));
                }
                if store.last().is_some_and(|(k, _)| *k >= key) {
                    return Err(format!(
                        "{name} contacts out of order at ({}, {}, slot {})",
                        key.a, key.b, key.slot
                    ));
                }
                store.push((key, record_from_raw([f(9), f(17), f(25)])));
            }
            at += len;
        }
        Ok((h, at))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A key present gives its record; a key absent, a fresh record.
    #[test]
    fn a_contact_finds_its_record_and_a_new_one_starts_at_rest() {
        let key = |a, b, slot| ContactKey { a, b, slot };
        let rec = |x| Record {
            xi: DVec3::new(x, 0.0, 0.0),
        };
        let store = sorted(vec![
            (key(3, 1, 0), rec(3.0)),
            (key(0, 4, 1), rec(2.0)),
            (key(0, 4, 0), rec(1.0)),
        ]);
        // In order (the cursor hits), out of order and absent (searched).
        let c = &mut 0;
        assert_eq!(recall(&store, c, &key(0, 4, 0)), rec(1.0));
        assert_eq!(recall(&store, c, &key(0, 4, 1)), rec(2.0));
        assert_eq!(recall(&store, c, &key(3, 1, 0)), rec(3.0));
        assert_eq!(recall(&store, c, &key(3, 1, 1)), Record::default());
        assert_eq!(recall(&store, c, &key(0, 4, 1)), rec(2.0));
        assert_eq!(*c, 2);
        assert_eq!(recall(&store, c, &key(0, 5, 0)), Record::default());
        assert_eq!(recall(&store, c, &key(3, 1, 0)), rec(3.0));
    }

    /// A store written into a states file reads back to the bit, and a
    /// damaged one is refused.
    #[test]
    fn a_store_round_trips_through_its_bytes() {
        let key = |a, b, slot| ContactKey { a, b, slot };
        let rec = |x: f64| Record {
            xi: DVec3::new(x, -x * 1e-3, f64::from_bits(x.to_bits() ^ 1)),
        };
        let h = History {
            walls: vec![(key(0, 5, 1), rec(1e-7)), (key(2, 0, 0), rec(-3e-9))],
            pairs: vec![(key(0, 4, 0), rec(2e-8)), (key(0, 4, 1), rec(-0.0))],
        };
        let mut b = vec![];
        h.encode(&mut b);
        assert_eq!(b.len(), 16 + 4 * ENTRY_BYTES);
        let (back, used) = History::decode(&b, 5, 6).unwrap();
        assert_eq!(used, b.len());
        let bits = |h: &History| {
            h.walls
                .iter()
                .chain(&h.pairs)
                .map(|(k, r)| (*k, record_to_raw(r).map(f64::to_bits)))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&back), bits(&h));
        assert!(History::decode(&b[..b.len() - 1], 5, 6).is_err());
        assert!(History::decode(&b, 4, 6).is_err(), "body 4 of 4");
        assert!(History::decode(&b, 5, 5).is_err(), "wall 5 of 5");
    }
}
