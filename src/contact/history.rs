//! The per-contact history store: what the law keeps of each touching
//! contact point between force computations ([`Record`]), by the
//! contact's identity ([`ContactKey`]: its pair and its slot). The record
//! is a client of the carrying (`carry.rs`: 9 bytes of key, 56 of
//! record), which writes it into checkpoints and sends it between MPI
//! ranks as it does the pairs' memories.
//!
//! A store is a vector sorted by key, one per candidate list (walls,
//! body pairs). Each computation reads the last one (mostly the entries
//! after the last ones found, else a binary search) and writes a new one
//! in list order, from the blocks in the order they are added: a contact
//! not touching this computation loses its record, and the bits do not
//! depend on the thread count. Only a law that keeps something per
//! contact (friction) has a store: a frictionless scene keeps none (no
//! bytes, no work).
//!
//! How a point finds its record (docs/contacts.md, "Friction"): against a
//! wall by its slot, a fibre's end (0 or 1), a sphere's 0 ([`recall`]); a
//! body pair's points by place ([`recall_by_place`]): they take the old
//! records of the same pair one to one, nearest first, within a reach, as
//! Bullet's persistent manifold matches a new point to its cached ones
//! (`btPersistentManifold::getCacheEntry`, its contact breaking
//! threshold); a point left over copies the nearest record within reach. The kernels' output changes shape (parts appear
//! and vanish as their weights reach 0), so a point's rank in it is no
//! identity; its place is. A pair's slot is then only the point's rank,
//! which keeps the store sorted and its keys unique.

use super::carry::{decode_as, encode, Carried, Key};
use super::law::Record;
use glam::DVec3;

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

/// The records one candidate's points start from, in their order (a
/// candidate has a handful of points: no allocation).
pub(crate) type Recalled = smallvec::SmallVec<[Record; 8]>;

/// The old records of body pair `(a, b)` in the sorted `store` (empty if
/// it had none); `cursor` as for [`recall`], left after them.
#[inline]
pub(crate) fn pair_records<'s>(
    store: &'s [Entry],
    cursor: &mut usize,
    (a, b): (u32, u32),
) -> &'s [Entry] {
    let of_pair = |e: &Entry| (e.0.a, e.0.b) == (a, b);
    let start = match store.get(*cursor) {
        Some(e) if of_pair(e) => *cursor,
        _ => store.partition_point(|(k, _)| (k.a, k.b) < (a, b)),
    };
    let len = store[start..].iter().take_while(|e| of_pair(e)).count();
    *cursor = start + len;
    &store[start..start + len]
}

/// The records a body pair's new points start from, in their order, into
/// `out`: `old` are the pair's records of the last computation, `points`
/// the new points' places (relative to body A's centre, as
/// [`Record::place`]) and weights.
///
/// A point's distance to a record is taken in place and weight, the
/// weight scaled by `reach`: `√(|Δp|² + (reach Δw)²)`. A kernel can give
/// two parts at one place (a line contact's end as the main contact's
/// part and as the second's; a side–side part and the end-involved part
/// it blends into): their weights tell them apart, where their places
/// differ by rounding only. One to one, nearest first: of all old–new
/// distances, the smallest is taken first (ties to the lower old index,
/// then the lower new one), and so on while both sides have one left and
/// the distance is at most `reach`; a point left over then takes a copy of
/// the nearest record within reach (taken or not), and one with none
/// within reach starts from rest. A record without a place (read from a checkpoint that had none)
/// is at distance 0 from the new point of its own rank, and out of reach
/// of the others. One record and one point (a single contact) take one
/// distance ([`recall_one_by_place`]).
#[inline]
pub(crate) fn recall_by_place(
    old: &[Entry],
    points: impl ExactSizeIterator<Item = (DVec3, f64)> + Clone,
    reach: f64,
    out: &mut Recalled,
) {
    let n = points.len();
    let start = out.len();
    out.extend(std::iter::repeat_n(Record::default(), n));
    let reach2 = reach * reach;
    // Greedy by distance over the pair's few points (a kernel gives a
    // handful): `MASK` bits of each side; points beyond start from rest.
    const MASK: usize = 64;
    let (mut old_left, mut new_left) = (mask(old.len().min(MASK)), mask(n.min(MASK)));
    while old_left != 0 && new_left != 0 {
        let mut best: Option<(f64, usize, usize)> = None;
        for (i, e) in old.iter().enumerate().take(MASK) {
            if old_left & (1 << i) == 0 {
                continue;
            }
            for (j, p) in points.clone().enumerate().take(MASK) {
                if new_left & (1 << j) == 0 {
                    continue;
                }
                let d = distance2(e, j, p, reach);
                if d <= reach2 && best.is_none_or(|(b, _, _)| d < b) {
                    best = Some((d, i, j));
                }
            }
        }
        let Some((_, i, j)) = best else { break };
        out[start + j] = old[i].1;
        old_left &= !(1 << i);
        new_left &= !(1 << j);
    }
    // A point left over takes a copy of the nearest record within reach,
    // taken or not: it is more of a contact patch already touching (a part
    // come in beside another, a split's second half).
    if new_left != 0 && !old.is_empty() {
        for (j, p) in points.enumerate().take(MASK) {
            if new_left & (1 << j) == 0 {
                continue;
            }
            let mut best: Option<(f64, usize)> = None;
            for (i, e) in old.iter().enumerate() {
                let d = distance2(e, j, p, reach);
                if d <= reach2 && best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, i));
                }
            }
            if let Some((_, i)) = best {
                out[start + j] = old[i].1;
            }
        }
    }
}

/// [`recall_by_place`] for a pair with one new point at `point` (place,
/// weight): the common case, without gathering.
#[inline(always)]
pub(crate) fn recall_one_by_place(old: &[Entry], point: (DVec3, f64), reach: f64) -> Record {
    match old {
        [] => Record::default(),
        [e] => {
            if distance2(e, 0, point, reach) <= reach * reach {
                e.1
            } else {
                Record::default()
            }
        }
        _ => {
            let mut out = Recalled::new();
            recall_by_place(old, std::iter::once(point), reach, &mut out);
            out[0]
        }
    }
}

/// The squared distance of record `e` to the new point of rank `j` at
/// `(p, w)` (place, weight) for [`recall_by_place`] and its reach `reach`.
#[inline(always)]
fn distance2((k, r): &Entry, j: usize, (p, w): (DVec3, f64), reach: f64) -> f64 {
    let d = r.place.distance_squared(p) + (reach * (r.weight - w)).powi(2);
    // A record without a place (NaN) reads as at its own rank.
    if !d.is_nan() {
        d
    } else if usize::from(k.slot) == j {
        0.0
    } else {
        f64::INFINITY
    }
}

/// The lowest `k` bits set.
#[inline]
fn mask(k: usize) -> u64 {
    if k >= 64 {
        u64::MAX
    } else {
        (1 << k) - 1
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

/// Bytes of one record in a states file of the format before places
/// (`fibresim-checkpoint-6`): ξ alone.
const XI_BYTES: usize = 8 * 3;

/// Numbers in a record ([`record_to_raw`]).
pub(crate) const RAW: usize = 7;

/// A record's numbers, in the order they are stored and sent: ξ, the
/// place, the weight.
#[inline]
pub(crate) fn record_to_raw(r: &Record) -> [f64; RAW] {
    let Record { xi, place, weight } = *r;
    [xi.x, xi.y, xi.z, place.x, place.y, place.z, weight]
}

/// The record of [`record_to_raw`]'s numbers.
#[inline]
pub(crate) fn record_from_raw(d: [f64; RAW]) -> Record {
    Record {
        xi: DVec3::new(d[0], d[1], d[2]),
        place: DVec3::new(d[3], d[4], d[5]),
        weight: d[6],
    }
}

/// The `k`-th little-endian `f64` of `b`, exact bits.
fn f64_at(b: &[u8], k: usize) -> f64 {
    f64::from_bits(u64::from_le_bytes(
        b[8 * k..8 * k + 8].try_into().expect("8 bytes"),
    ))
}

impl Key for ContactKey {
    const BYTES: usize = 9;

    fn put(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.a.to_le_bytes());
        out.extend_from_slice(&self.b.to_le_bytes());
        out.push(self.slot);
    }

    fn get(b: &[u8]) -> Self {
        let word = |i: usize| u32::from_le_bytes(b[i..i + 4].try_into().expect("4 bytes"));
        ContactKey {
            a: word(0),
            b: word(4),
            slot: b[8],
        }
    }

    fn first(&self) -> u32 {
        self.a
    }

    fn describe(&self) -> String {
        format!("({}, {}, slot {})", self.a, self.b, self.slot)
    }

    fn candidate(&self) -> (u32, u32) {
        (self.a, self.b)
    }
}

/// The record as a client of the carrying (`carry.rs`): its seven
/// numbers ([`record_to_raw`]), exact bits.
impl Carried for Record {
    type Key = ContactKey;
    const BYTES: usize = 8 * RAW;

    fn put(&self, out: &mut Vec<u8>) {
        for x in record_to_raw(self) {
            out.extend_from_slice(&x.to_bits().to_le_bytes());
        }
    }

    fn get(b: &[u8]) -> Option<Self> {
        Some(record_from_raw(std::array::from_fn(|k| f64_at(b, k))))
    }
}

/// A record of the format before places: ξ only, the place and weight
/// NaN (a body pair's record then goes to the new point of its own rank,
/// [`recall_by_place`]).
fn record_without_place(b: &[u8]) -> Option<Record> {
    let mut raw = [f64::NAN; RAW];
    for (k, x) in raw.iter_mut().take(3).enumerate() {
        *x = f64_at(b, k);
    }
    Some(record_from_raw(raw))
}

impl History {
    /// Append the store to a checkpoint's states file (`carry.rs`): the
    /// walls' entries, then the pairs' (a key of `u32` a, `u32` b, `u8`
    /// slot, and the record's seven `f64`: ξ, the place, the weight).
    pub(crate) fn encode(&self, out: &mut Vec<u8>) {
        encode(self.walls.iter().copied(), out);
        encode(self.pairs.iter().copied(), out);
    }

    /// The store at the start of `b` (as [`History::encode`] wrote it) for
    /// `n` bodies and `walls` walls, and the bytes it took; or what is
    /// wrong: a truncated section, a key no run writes, keys out of order.
    /// Without `places` (the format before them) the entries hold ξ only,
    /// and each record's place is NaN: a pair's record then goes to the
    /// new point of its own rank ([`recall_by_place`]), the old rule.
    pub(crate) fn decode(
        b: &[u8],
        n: usize,
        walls: usize,
        places: bool,
    ) -> Result<(Self, usize), String> {
        type Read = fn(&[u8]) -> Option<Record>;
        let (bytes, read): (usize, Read) = if places {
            (Record::BYTES, Record::get)
        } else {
            (XI_BYTES, record_without_place)
        };
        let (wall_entries, at) = decode_as(b, bytes, read, "wall contact", |k: &ContactKey| {
            (k.a as usize) < n && (k.b as usize) < walls
        })?;
        let (pair_entries, used) =
            decode_as(&b[at..], bytes, read, "pair contact", |k: &ContactKey| {
                k.a < k.b && (k.b as usize) < n
            })?;
        let h = History {
            walls: wall_entries,
            pairs: pair_entries,
        };
        Ok((h, at + used))
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
            ..Record::default()
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
            place: DVec3::new(-x, 1e-300, x * 7.0),
            weight: 0.5 - x,
        };
        let h = History {
            walls: vec![(key(0, 5, 1), rec(1e-7)), (key(2, 0, 0), rec(-3e-9))],
            pairs: vec![(key(0, 4, 0), rec(2e-8)), (key(0, 4, 1), rec(-0.0))],
        };
        let mut b = vec![];
        h.encode(&mut b);
        assert_eq!(b.len(), 16 + 4 * (9 + 8 * 7));
        let (back, used) = History::decode(&b, 5, 6, true).unwrap();
        assert_eq!(used, b.len());
        let bits = |h: &History| {
            h.walls
                .iter()
                .chain(&h.pairs)
                .map(|(k, r)| (*k, record_to_raw(r).map(f64::to_bits)))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&back), bits(&h));
        assert!(History::decode(&b[..b.len() - 1], 5, 6, true).is_err());
        assert!(History::decode(&b, 4, 6, true).is_err(), "body 4 of 4");
        assert!(History::decode(&b, 5, 5, true).is_err(), "wall 5 of 5");

        // The format before places: key and ξ only (33 bytes an entry),
        // read with NaN places and weights.
        let mut old = vec![];
        for store in [&h.walls, &h.pairs] {
            old.extend_from_slice(&(store.len() as u64).to_le_bytes());
            for (k, r) in store {
                old.extend_from_slice(&k.a.to_le_bytes());
                old.extend_from_slice(&k.b.to_le_bytes());
                old.push(k.slot);
                for x in r.xi.to_array() {
                    old.extend_from_slice(&x.to_bits().to_le_bytes());
                }
            }
        }
        assert_eq!(old.len(), 16 + 4 * (9 + 8 * 3));
        let (back, used) = History::decode(&old, 5, 6, false).unwrap();
        assert_eq!(used, old.len());
        for ((k, r), (k0, r0)) in back
            .walls
            .iter()
            .chain(&back.pairs)
            .zip(h.walls.iter().chain(&h.pairs))
        {
            assert_eq!(k, k0);
            assert_eq!(
                r.xi.to_array().map(f64::to_bits),
                r0.xi.to_array().map(f64::to_bits)
            );
            assert!(r.place.is_nan() && r.weight.is_nan());
        }
    }

    fn entry(slot: u8, place: [f64; 3], weight: f64, xi: f64) -> Entry {
        let key = ContactKey { a: 1, b: 2, slot };
        let record = Record {
            xi: DVec3::new(xi, 0.0, 0.0),
            place: DVec3::from_array(place),
            weight,
        };
        (key, record)
    }

    /// The springs a pair's new points `points` (place, weight) take of
    /// `old`, within `reach` (0: started from rest).
    fn taken(old: &[Entry], points: &[([f64; 3], f64)], reach: f64) -> Vec<f64> {
        let mut out = Recalled::new();
        let places = points.iter().map(|&(p, w)| (DVec3::from_array(p), w));
        recall_by_place(old, places, reach, &mut out);
        out.iter().map(|r| r.xi.x).collect()
    }

    /// Reference: the rule's statement (docs/contacts.md, "Identity and
    /// history"), case by case: nearest first, one to one, within the
    /// reach; weights tell apart parts at one place; a record without a
    /// place goes to its own rank.
    #[test]
    fn a_pair_s_points_take_the_nearest_records_one_to_one() {
        let r = 1e-3;
        // One record, one point: within the reach or not.
        let one = [entry(0, [0.0, 0.0, 0.0], 1.0, 7.0)];
        assert_eq!(taken(&one, &[([0.9e-3, 0.0, 0.0], 1.0)], r), [7.0]);
        assert_eq!(taken(&one, &[([1.1e-3, 0.0, 0.0], 1.0)], r), [0.0]);
        // A part appears before the others (ranks shift): each keeps its own.
        let old = [
            entry(0, [0.0, 0.0, 0.0], 1.0, 1.0),
            entry(1, [5e-3, 0.0, 0.0], 1.0, 2.0),
        ];
        let new = [
            ([2e-3, 0.0, 0.0], 0.01),
            ([1e-6, 0.0, 0.0], 1.0),
            ([5e-3, 1e-6, 0.0], 1.0),
        ];
        assert_eq!(taken(&old, &new, r), [0.0, 1.0, 2.0]);
        // Two records nearest one point: the nearer takes it, the other
        // goes to the next nearest within reach.
        let old = [
            entry(0, [0.0, 0.0, 0.0], 1.0, 1.0),
            entry(1, [0.4e-3, 0.0, 0.0], 1.0, 2.0),
        ];
        let new = [([0.1e-3, 0.0, 0.0], 1.0), ([0.5e-3, 0.0, 0.0], 1.0)];
        assert_eq!(taken(&old, &new, r), [1.0, 2.0]);
        let new = [([0.9e-3, 0.0, 0.0], 1.0), ([0.3e-3, 0.0, 0.0], 1.0)];
        assert_eq!(
            taken(&old, &new, r),
            [1.0, 2.0],
            "1 is nearer, 0 within reach"
        );
        // Two parts at one place (rounding apart): the weights decide.
        let old = [
            entry(0, [0.0, 0.0, 0.0], 0.999, 1.0),
            entry(1, [1e-18, 0.0, 0.0], 0.001, 2.0),
        ];
        let new = [([0.0, 0.0, 0.0], 0.002), ([1e-18, 0.0, 0.0], 0.998)];
        assert_eq!(taken(&old, &new, r), [2.0, 1.0]);
        // A tie goes to the lower old index, then the lower new one.
        let old = [
            entry(0, [0.0, 0.0, 0.0], 1.0, 1.0),
            entry(1, [0.0, 0.0, 0.0], 1.0, 2.0),
        ];
        assert_eq!(taken(&old, &[([0.0, 0.0, 0.0], 1.0)], r), [1.0]);
        // A point left over copies the nearest record within reach.
        let new = [
            ([0.0, 0.0, 0.0], 1.0),
            ([0.5e-3, 0.0, 0.0], 1.0),
            ([2e-3, 0.0, 0.0], 1.0),
        ];
        assert_eq!(taken(&old[..1], &new, r), [1.0, 1.0, 0.0]);
        // Records without a place: each to the point of its own rank.
        let nan = [f64::NAN; 3];
        let old = [entry(0, nan, f64::NAN, 1.0), entry(2, nan, f64::NAN, 3.0)];
        let new = [([9.0, 0.0, 0.0], 1.0); 2];
        assert_eq!(taken(&old, &new, r), [1.0, 0.0]);
        assert_eq!(taken(&old[..1], &new[..1], r), [1.0]);
    }
}
