//! The pairs' memories ([`PairMemory`], `fibre_fibre/coherence.rs`) as a
//! client of the carrying (`carry.rs`): one per pair candidate, in an
//! array aligned with the candidate list, keyed by the pair `(i, j)`,
//! `i < j`, 6 bytes (the three `u16` of [`PairMemory::to_raw`]). A
//! touching memory changes what the kernel answers (at the rounding of
//! the scan), so every run that must give the same bits (any thread
//! count, any rank count, resumed) carries the same ones; a pair apart
//! only saves work.

use super::carry::{Carried, Key};
use super::fibre_fibre::PairMemory;

pub(crate) use super::carry::{entries, place};

/// A memory with its pair `(i, j)`, `i < j`.
pub type Entry = ((u32, u32), PairMemory);

/// What an entry is called in messages.
pub(crate) const WHAT: &str = "pair memory";

impl Key for (u32, u32) {
    const BYTES: usize = 8;

    fn put(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.0.to_le_bytes());
        out.extend_from_slice(&self.1.to_le_bytes());
    }

    fn get(b: &[u8]) -> Self {
        let word = |i: usize| u32::from_le_bytes(b[i..i + 4].try_into().expect("4 bytes"));
        (word(0), word(4))
    }

    fn first(&self) -> u32 {
        self.0
    }

    fn describe(&self) -> String {
        format!("({}, {})", self.0, self.1)
    }

    fn candidate(&self) -> (u32, u32) {
        *self
    }
}

impl Carried for PairMemory {
    type Key = (u32, u32);
    const BYTES: usize = 6;

    fn put(&self, out: &mut Vec<u8>) {
        for x in self.to_raw() {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }

    /// Only a touching memory is carried ([`PairMemory::from_raw`]).
    fn get(b: &[u8]) -> Option<Self> {
        let half = |i: usize| u16::from_le_bytes([b[i], b[i + 1]]);
        PairMemory::from_raw([half(0), half(2), half(4)])
    }
}

/// Whether `(i, j)` is a pair a run of `n` bodies lists.
pub(crate) fn valid_pair(n: usize) -> impl Fn(&(u32, u32)) -> bool {
    move |&(i, j)| i < j && (j as usize) < n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::carry::{decode, encode};

    /// Reference: a lookup by pair in a map (an independent code path).
    #[test]
    fn memories_follow_their_pairs_across_lists() {
        let m = |k: u16| PairMemory::from_raw([2, k, 1000]).unwrap();
        let old = [(0, 1), (0, 5), (2, 3), (4, 9), (7, 8)];
        let memory: Vec<PairMemory> = (0..5)
            .map(|k| {
                if k == 3 {
                    PairMemory::default()
                } else {
                    m(k + 1)
                }
            })
            .collect();
        let new = [(0, 2), (0, 5), (2, 3), (4, 9), (6, 7), (7, 8), (8, 9)];
        let carried = place(
            &new,
            entries(&old, &memory, |m| *m != PairMemory::default()),
        );
        let map: std::collections::HashMap<_, _> = old.iter().zip(&memory).collect();
        for (p, c) in new.iter().zip(&carried) {
            assert_eq!(
                *c,
                map.get(p).map_or(PairMemory::default(), |m| **m),
                "{p:?}"
            );
        }
        assert_eq!(
            carried
                .iter()
                .filter(|c| **c != PairMemory::default())
                .count(),
            3
        );
    }

    /// Reference: the states file's layout of a memory (docs/outputs-and-resume.md):
    /// `u32` i, `u32` j, the three `u16` of the raw fields, little-endian.
    #[test]
    fn a_memory_s_bytes_are_its_pair_and_raw_fields() {
        let m = PairMemory::from_raw([3, 7, 500]).unwrap();
        let mut b = vec![];
        encode([((2, 70000), m)], &mut b);
        let mut want = 1u64.to_le_bytes().to_vec();
        for w in [2u32, 70000] {
            want.extend_from_slice(&w.to_le_bytes());
        }
        for h in [3u16, 7, 500] {
            want.extend_from_slice(&h.to_le_bytes());
        }
        assert_eq!(b, want);
        assert_eq!(
            decode::<PairMemory>(&b, WHAT, valid_pair(70001)),
            Ok((vec![((2, 70000), m)], 22))
        );
        assert!(decode::<PairMemory>(&b, WHAT, valid_pair(70000)).is_err());
        // A memory apart (no kernel) is not carried.
        let mut apart = b.clone();
        apart[16..18].copy_from_slice(&0u16.to_le_bytes());
        assert!(decode::<PairMemory>(&apart, WHAT, valid_pair(70001)).is_err());
    }
}
