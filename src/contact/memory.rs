//! The pairs' memories ([`PairMemory`], `fibre_fibre/coherence.rs`) along
//! a candidate list: one per pair candidate, in the list's order, carried
//! across rebuilds by pair, and listed by pair for checkpoints and MPI.
//! A touching memory changes what the kernel answers (at the rounding of
//! the scan), so every run that must give the same bits (any thread
//! count, any rank count, resumed) carries the same ones; a pair apart
//! only saves work.

use super::fibre_fibre::PairMemory;

/// A memory with its pair `(i, j)`, `i < j`.
pub type Entry = ((u32, u32), PairMemory);

/// The memories of `pairs` (sorted) taken from `entries` (sorted by pair):
/// the pairs found keep theirs, the others start with none.
pub(crate) fn place(
    pairs: &[(u32, u32)],
    entries: impl IntoIterator<Item = Entry>,
) -> Vec<PairMemory> {
    let mut entries = entries.into_iter().peekable();
    pairs
        .iter()
        .map(|p| {
            while entries.next_if(|(q, _)| q < p).is_some() {}
            entries
                .next_if(|(q, _)| q == p)
                .map_or_else(PairMemory::default, |(_, m)| m)
        })
        .collect()
}

/// The memories of `pairs` and their pairs, those that `keep` accepts.
pub(crate) fn entries<'a>(
    pairs: &'a [(u32, u32)],
    memory: &'a [PairMemory],
    keep: impl Fn(&PairMemory) -> bool + 'a,
) -> impl Iterator<Item = Entry> + 'a {
    pairs
        .iter()
        .copied()
        .zip(memory.iter().copied())
        .filter(move |(_, m)| keep(m))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: a lookup by pair in a map (an independent code path).
    #[test]
    fn memories_follow_their_pairs_across_lists() {
        let unit = 1e-8;
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
        let _ = unit;
    }
}
