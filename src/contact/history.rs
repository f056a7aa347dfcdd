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
}
