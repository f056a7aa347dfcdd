//! The fibre pairs' memories of their end-involved scans across ranks
//! (`contact/memory.rs`). A touching memory changes what the kernel answers
//! (at the scan's rounding), so a pair must carry the one-process memory
//! whichever rank computes it: at every rebuild each rank sends the
//! touching memories of the pairs whose first body it owns (each pair's
//! once), and every rank gives its new candidates theirs; at a checkpoint
//! rank 0 gathers those a checkpoint keeps. (A pair apart only saves work:
//! it starts again from a scan.)

use crate::contact::fibre_fibre::PairMemory;
use crate::contact::memory::Entry;

/// Doubles of one memory on the wire: the pair and the raw fields, each
/// packed in the bits of one `f64` (copied, never computed with).
pub(super) const WIRE: usize = 2;

/// `entries` as wire doubles.
pub(super) fn encode(entries: impl Iterator<Item = Entry>) -> Vec<f64> {
    entries
        .flat_map(|((i, j), m)| {
            let [code, left, cap] = m.to_raw().map(u64::from);
            [
                f64::from_bits(u64::from(i) << 32 | u64::from(j)),
                f64::from_bits(code << 32 | left << 16 | cap),
            ]
        })
        .collect()
}

/// The memories of wire doubles from every rank, sorted by pair (each
/// rank's are sorted; their union is not).
pub(super) fn decode(wire: &[f64]) -> Vec<Entry> {
    let mut out: Vec<Entry> = wire
        .chunks_exact(WIRE)
        .map(|d| {
            let (p, m) = (d[0].to_bits(), d[1].to_bits());
            let raw = [(m >> 32) as u16, (m >> 16) as u16, m as u16];
            let memory = PairMemory::from_raw(raw).expect("a rank sends touching memories");
            (((p >> 32) as u32, p as u32), memory)
        })
        .collect();
    out.sort_unstable_by_key(|e| e.0);
    out
}
