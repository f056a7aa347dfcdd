//! What contacts keep between force computations, and the one mechanism
//! that carries it (in the spirit of LAMMPS's `fix neigh/history`: per
//! pair, records of a size each kind declares).
//!
//! Each kind of record is a client ([`Carried`]): it names its key (a
//! [`Key`]: a body pair `i < j`, or a contact point, its pair or wall and
//! its slot) and how one record is written to and read from bytes, of a
//! fixed size. What moves records is written here once, generic over the
//! client, as sorted runs of entries (key, record):
//! - across a neighbour-list rebuild, [`entries`] lists the old records by
//!   key and [`place`] gives each new candidate its own, or a fresh one;
//! - into a checkpoint's states file and back, [`encode`] and
//!   [`decode`]: a `u64` count, then per entry its key's bytes and its
//!   record's, little-endian, floats as their exact bits, keys strictly
//!   ascending;
//! - across MPI ranks (`ranks/carry.rs`), those same bytes, each rank
//!   sending the entries whose key's [`Key::first`] body it owns.
//!
//! The clients (docs/contacts.md, "Pair memories" and "Identity and
//! history"): the fibre pairs' memories of their end-involved scans
//! (`memory.rs`: 6 bytes per body pair, in an array aligned with the
//! candidate list), and the touching contacts' records (`history.rs`:
//! friction's springs, 56 bytes per contact point, in sorted stores).
//! The hot loop reads and writes each in its own layout; only the
//! carrying is shared.

/// A record's identity, as the carrying sees it.
pub(crate) trait Key: Copy + Ord {
    /// Bytes of a key in a states file.
    const BYTES: usize;
    /// Append the key's bytes.
    fn put(&self, out: &mut Vec<u8>);
    /// The key of [`Key::BYTES`] bytes.
    fn get(b: &[u8]) -> Self;
    /// The body whose owner sends the record to the other MPI ranks (each
    /// record once): the pair's first body.
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    fn first(&self) -> u32;
    /// The key as messages name it.
    fn describe(&self) -> String;
    /// The candidate it belongs to: a body pair, or a body and a wall.
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    fn candidate(&self) -> (u32, u32);
}

/// A kind of record the carrying moves: fixed size, exact bytes.
pub(crate) trait Carried: Copy {
    /// What identifies it.
    type Key: Key;
    /// Bytes of a record in a states file.
    const BYTES: usize;
    /// Append the record's bytes.
    fn put(&self, out: &mut Vec<u8>);
    /// The record of [`Carried::BYTES`] bytes; `None` if no run writes it.
    fn get(b: &[u8]) -> Option<Self>;
}

/// A record with its key.
pub(crate) type Entry<R> = (<R as Carried>::Key, R);

/// The records of `keys` (sorted) taken from `entries` (sorted by key):
/// the keys found keep theirs, the others start with `R::default()`.
pub(crate) fn place<R: Carried + Default>(
    keys: &[R::Key],
    entries: impl IntoIterator<Item = Entry<R>>,
) -> Vec<R> {
    let mut entries = entries.into_iter().peekable();
    keys.iter()
        .map(|p| {
            while entries.next_if(|(q, _)| q < p).is_some() {}
            entries
                .next_if(|(q, _)| q == p)
                .map_or_else(R::default, |(_, m)| m)
        })
        .collect()
}

/// The entries of `entries` (sorted by key) whose candidate is one of
/// `candidates` (sorted): what a sorted store keeps of a new list.
#[cfg_attr(not(feature = "mpi"), allow(dead_code))]
pub(crate) fn listed<R: Carried>(
    candidates: &[(u32, u32)],
    mut entries: Vec<Entry<R>>,
) -> Vec<Entry<R>> {
    let mut at = 0;
    entries.retain(|(k, _)| {
        let c = k.candidate();
        at += candidates[at..].partition_point(|&p| p < c);
        candidates.get(at) == Some(&c)
    });
    entries
}

/// The records of `keys` (aligned with them) with their keys, those that
/// `keep` accepts.
pub(crate) fn entries<'a, R: Carried>(
    keys: &'a [R::Key],
    records: &'a [R],
    keep: impl Fn(&R) -> bool + 'a,
) -> impl Iterator<Item = Entry<R>> + 'a {
    keys.iter()
        .copied()
        .zip(records.iter().copied())
        .filter(move |(_, r)| keep(r))
}

/// Append `entries` (sorted by key): a `u64` count, then each key's and
/// record's bytes.
pub(crate) fn encode<R: Carried>(entries: impl IntoIterator<Item = Entry<R>>, out: &mut Vec<u8>) {
    let at = out.len();
    out.extend_from_slice(&0u64.to_le_bytes());
    let mut count = 0u64;
    for (k, r) in entries {
        k.put(out);
        r.put(out);
        count += 1;
    }
    out[at..at + 8].copy_from_slice(&count.to_le_bytes());
}

/// The entries at the start of `b` (as [`encode`] wrote them) and the
/// bytes they took, or what is wrong: a truncated section, a key `valid`
/// refuses or a record no run writes, keys out of order. `what` names
/// one entry in the message.
pub(crate) fn decode<R: Carried>(
    b: &[u8],
    what: &str,
    valid: impl Fn(&R::Key) -> bool,
) -> Result<(Vec<Entry<R>>, usize), String> {
    decode_as(b, R::BYTES, R::get, what, valid)
}

/// [`decode`] with records of `bytes` bytes each, read by `read` (an
/// older format's records).
pub(crate) fn decode_as<R: Carried>(
    b: &[u8],
    bytes: usize,
    read: impl Fn(&[u8]) -> Option<R>,
    what: &str,
    valid: impl Fn(&R::Key) -> bool,
) -> Result<(Vec<Entry<R>>, usize), String> {
    let truncated = || format!("the {what} entries are truncated");
    let count = b
        .get(..8)
        .map(|w| u64::from_le_bytes(w.try_into().expect("8 bytes")))
        .ok_or_else(truncated)?;
    let per = <R::Key as Key>::BYTES + bytes;
    let len = usize::try_from(count)
        .ok()
        .and_then(|c| c.checked_mul(per))
        .filter(|&l| 8 + l <= b.len())
        .ok_or_else(truncated)?;
    let mut out: Vec<Entry<R>> = Vec::with_capacity(len / per.max(1));
    for (k, e) in b[8..8 + len].chunks_exact(per).enumerate() {
        let (key, rest) = e.split_at(<R::Key as Key>::BYTES);
        let key = <R::Key as Key>::get(key);
        let record = read(rest)
            .filter(|_| valid(&key))
            .ok_or_else(|| format!("{what} {k} {} is not one a run writes", key.describe()))?;
        if out.last().is_some_and(|(p, _)| *p >= key) {
            return Err(format!("{what} {k} {} is out of order", key.describe()));
        }
        out.push((key, record));
    }
    Ok((out, 8 + len))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A test client: a byte keyed by a `u16`, with `0xff` no run writes.
    #[derive(Debug, Clone, Copy, Default, PartialEq)]
    struct Tag(u8);

    impl Key for u16 {
        const BYTES: usize = 2;
        fn put(&self, out: &mut Vec<u8>) {
            out.extend_from_slice(&self.to_le_bytes());
        }
        fn get(b: &[u8]) -> Self {
            u16::from_le_bytes([b[0], b[1]])
        }
        fn first(&self) -> u32 {
            u32::from(*self)
        }
        fn describe(&self) -> String {
            format!("({self})")
        }
        fn candidate(&self) -> (u32, u32) {
            (u32::from(*self / 10), u32::from(*self % 10))
        }
    }

    impl Carried for Tag {
        type Key = u16;
        const BYTES: usize = 1;
        fn put(&self, out: &mut Vec<u8>) {
            out.push(self.0);
        }
        fn get(b: &[u8]) -> Option<Self> {
            (b[0] != 0xff).then_some(Tag(b[0]))
        }
    }

    /// Reference: a lookup by key in a map (an independent code path).
    #[test]
    fn records_follow_their_keys_across_lists() {
        let old = [1u16, 5, 23, 49, 78];
        let records = [Tag(1), Tag(2), Tag(3), Tag(0), Tag(5)];
        let new = [2u16, 5, 23, 49, 67, 78, 89];
        let carried = place(&new, entries(&old, &records, |t| *t != Tag(0)));
        let map: std::collections::HashMap<_, _> = old.iter().zip(&records).collect();
        for (k, c) in new.iter().zip(&carried) {
            assert_eq!(*c, map.get(k).map_or(Tag(0), |t| **t), "{k}");
        }
        assert_eq!(carried.iter().filter(|c| **c != Tag(0)).count(), 3);
    }

    /// Reference: membership by a linear search (an independent code path).
    #[test]
    fn a_sorted_store_keeps_the_entries_of_its_candidates() {
        let e: Vec<(u16, Tag)> = [3u16, 4, 15, 17, 40, 41, 99]
            .iter()
            .map(|&k| (k, Tag(k as u8)))
            .collect();
        let candidates = [(0, 4), (1, 5), (1, 6), (4, 1), (8, 8)];
        let kept = listed(&candidates, e.clone());
        let want: Vec<_> = e
            .into_iter()
            .filter(|(k, _)| candidates.contains(&k.candidate()))
            .collect();
        assert_eq!(kept, want);
        assert_eq!(kept.len(), 3);
        assert_eq!(listed::<Tag>(&[], vec![(1, Tag(1))]), vec![]);
    }

    /// Entries written read back with the bytes they took, after what came
    /// before; a damaged section is refused, naming the entry.
    #[test]
    fn entries_round_trip_through_their_bytes() {
        let e = vec![(3u16, Tag(7)), (9, Tag(0)), (700, Tag(254))];
        let mut b = vec![];
        encode(e.iter().copied(), &mut b);
        assert_eq!(b.len(), 8 + 3 * 3);
        b.push(42);
        let (back, used) = decode::<Tag>(&b, "tag", |_| true).unwrap();
        assert_eq!((back, used), (e.clone(), 17));
        let err = |b: &[u8], valid: fn(&u16) -> bool| decode::<Tag>(b, "tag", valid).unwrap_err();
        assert!(err(&b[..16], |_| true).contains("truncated"));
        assert_eq!(err(&b, |k| *k < 700), "tag 2 (700) is not one a run writes");
        let mut bad = b.clone();
        bad[8 + 3 + 2] = 0xff;
        assert_eq!(err(&bad, |_| true), "tag 1 (9) is not one a run writes");
        let mut swapped = b.clone();
        swapped[8 + 3..8 + 5].copy_from_slice(&2u16.to_le_bytes());
        assert_eq!(err(&swapped, |_| true), "tag 1 (2) is out of order");
        let mut none = vec![];
        encode::<Tag>([], &mut none);
        assert_eq!(decode::<Tag>(&none, "tag", |_| true), Ok((vec![], 8)));
    }
}
