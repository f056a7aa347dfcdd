//! The bodies' stable global ids (the `body` column of the outputs,
//! diagnoses, checkpoints, body files), by storage index.

/// Global ids by storage index. A scene whose ids are its storage indices
/// (every `[[body]]` scene, every generated or replicated bed, every body
/// file numbered from 0 in order) keeps only their count: the list would
/// be 8 B per fibre of a bed's ~500 (docs/performance.md, "Memory").
/// Constructed only normalised ([`Ids::from`]), so two equal id lists are
/// equal values.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ids {
    /// Body `i` has id `i`, for `i < n`.
    Sequential(usize),
    /// Any other ids, by storage index (distinct: the loader checks it).
    Listed(Vec<u64>),
}

impl Default for Ids {
    fn default() -> Self {
        Ids::Sequential(0)
    }
}

impl From<Vec<u64>> for Ids {
    fn from(ids: Vec<u64>) -> Self {
        if ids.iter().enumerate().all(|(i, &id)| id == i as u64) {
            Ids::Sequential(ids.len())
        } else {
            Ids::Listed(ids)
        }
    }
}

impl Ids {
    /// The id of body `i` (panics past the end, as indexing does).
    #[inline]
    pub fn get(&self, i: usize) -> u64 {
        match self {
            Ids::Sequential(n) => {
                assert!(i < *n, "body {i} of {n}");
                i as u64
            }
            Ids::Listed(v) => v[i],
        }
    }

    /// How many bodies.
    pub fn len(&self) -> usize {
        match self {
            Ids::Sequential(n) => *n,
            Ids::Listed(v) => v.len(),
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The ids in storage order (per-row outputs walk it every step: no
    /// bounds check or match per id).
    pub fn iter(&self) -> IdsIter<'_> {
        match self {
            Ids::Sequential(n) => IdsIter::Sequential(0..*n as u64),
            Ids::Listed(v) => IdsIter::Listed(v.iter()),
        }
    }
}

/// [`Ids::iter`].
pub enum IdsIter<'a> {
    /// The storage indices.
    Sequential(std::ops::Range<u64>),
    /// A list.
    Listed(std::slice::Iter<'a, u64>),
}

impl Iterator for IdsIter<'_> {
    type Item = u64;

    #[inline]
    fn next(&mut self) -> Option<u64> {
        match self {
            IdsIter::Sequential(r) => r.next(),
            IdsIter::Listed(it) => it.next().copied(),
        }
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        match self {
            IdsIter::Sequential(r) => r.size_hint(),
            IdsIter::Listed(it) => it.size_hint(),
        }
    }
}

impl ExactSizeIterator for IdsIter<'_> {}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: the definition (ids equal to the storage index collapse
    /// to a count; any other list is kept as given).
    #[test]
    fn only_the_identity_collapses() {
        assert_eq!(Ids::from(vec![0, 1, 2]), Ids::Sequential(3));
        assert_eq!(Ids::from(vec![]), Ids::Sequential(0));
        assert_eq!(Ids::from(vec![1, 2, 3]), Ids::Listed(vec![1, 2, 3]));
        assert_eq!(Ids::from(vec![0, 2, 1]), Ids::Listed(vec![0, 2, 1]));
        let listed = Ids::from(vec![7, 3]);
        assert_eq!(listed.iter().collect::<Vec<_>>(), [7, 3]);
        assert_eq!((listed.get(1), listed.len()), (3, 2));
        let seq = Ids::from(vec![0, 1]);
        assert_eq!(seq.iter().collect::<Vec<_>>(), [0, 1]);
    }
}
