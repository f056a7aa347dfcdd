//! Temporal coherence of the end-involved depth: what a pair remembers of
//! its last scan, so that the next steps run one kernel instead of the
//! scan while the pair has provably not moved enough to change which local
//! minimum is the least, or to touch.
//!
//! Why it holds: the depth is the least local minimum of `pov(n)`
//! (end_involved.rs), and a rigid motion moving every point of a body by at
//! most `m` changes each of its support values, hence `pov(n)` for every
//! `n`, by at most `m`. The scan knows the least minimum `δ*` (its
//! winner's kernel) and a lower bound `δ* + g` of every other stationary
//! value it met, and of the features it did not run ([`Scan::room`]).
//! After motions whose bounds sum to `Δ`, the winner's minimum is at most
//! `δ* + Δ` and any other at least `δ* + g − Δ`: while `2Δ ≤ g − band` the
//! winner is still the least and no other minimum is within the tie band
//! (so the scan would not blend either). The winner's kernel then gives the
//! depth, its direction and its point, as the scan computes them. A kernel
//! that no longer certifies its minimum, or a value above `δ* + Δ` (the
//! kernel moved to another stationary point), hands back to the scan. A
//! pair apart along some direction by `s` stays apart while `Δ < s`.
//! (docs/contacts.md, "Temporal coherence".)
//!
//! [`Scan::room`]: super::end_involved

use super::features::{face_face, face_side, rim_face, rim_rim, rim_side, Stationary};
use crate::contact::FibreGeom;

/// A feature kernel of the scan and its ends: which one found the depth.
/// Bits 0–3 the kernel (1–8), bit 4 A's end (set: −1), bit 5 B's end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kernel(u8);

const FACE_SIDE_A: u8 = 1;
const RIM_SIDE_A: u8 = 2;
const FACE_SIDE_B: u8 = 3;
const RIM_SIDE_B: u8 = 4;
const FACE_FACE: u8 = 5;
const RIM_FACE_A: u8 = 6;
const RIM_FACE_B: u8 = 7;
const RIM_RIM: u8 = 8;
const KIND: u8 = 0x0f;
const END_A: u8 = 0x10;
const END_B: u8 = 0x20;

#[inline(always)]
fn end_bits(sa: f64, sb: f64) -> u8 {
    (if sa < 0.0 { END_A } else { 0 }) | (if sb < 0.0 { END_B } else { 0 })
}

impl Kernel {
    /// The kernel `on_a` of A's end `s` (`from_b`: `on_b` of B's end).
    #[inline(always)]
    fn of_end(from_b: bool, s: f64, on_a: u8, on_b: u8) -> Self {
        if from_b {
            Kernel(on_b | end_bits(1.0, s))
        } else {
            Kernel(on_a | end_bits(s, 1.0))
        }
    }

    /// Face–side of A's end `s` on B (`from_b`: of B's end on A).
    #[inline(always)]
    pub(super) fn face_side(from_b: bool, s: f64) -> Self {
        Self::of_end(from_b, s, FACE_SIDE_A, FACE_SIDE_B)
    }

    /// Rim–side of A's end `s` on B (`from_b`: of B's end on A).
    #[inline(always)]
    pub(super) fn rim_side(from_b: bool, s: f64) -> Self {
        Self::of_end(from_b, s, RIM_SIDE_A, RIM_SIDE_B)
    }

    /// Face–face of the ends `(sa, sb)`.
    #[inline(always)]
    pub(super) fn face_face(sa: f64, sb: f64) -> Self {
        Kernel(FACE_FACE | end_bits(sa, sb))
    }

    /// Rim–face of A's rim on B's face (`from_b`: B's rim on A's face).
    #[inline(always)]
    pub(super) fn rim_face(from_b: bool, sa: f64, sb: f64) -> Self {
        Kernel(if from_b { RIM_FACE_B } else { RIM_FACE_A } | end_bits(sa, sb))
    }

    /// Rim–rim of the ends `(sa, sb)`.
    #[inline(always)]
    pub(super) fn rim_rim(sa: f64, sb: f64) -> Self {
        Kernel(RIM_RIM | end_bits(sa, sb))
    }

    /// This kernel on `a` and `b`, as the scan calls it (rim–rim without
    /// its starting hints and reach), and whether its first body is B.
    #[inline(always)]
    pub(super) fn eval(self, a: &FibreGeom, b: &FibreGeom) -> (Option<Stationary>, bool) {
        let sa = if self.0 & END_A != 0 { -1.0 } else { 1.0 };
        let sb = if self.0 & END_B != 0 { -1.0 } else { 1.0 };
        match self.0 & KIND {
            FACE_SIDE_A => (face_side(a, sa, b), false),
            RIM_SIDE_A => (rim_side(a, sa, b), false),
            FACE_SIDE_B => (face_side(b, sb, a), true),
            RIM_SIDE_B => (rim_side(b, sb, a), true),
            FACE_FACE => (face_face(a, sa, b, sb), false),
            RIM_FACE_A => (rim_face(a, sa, b, sb), false),
            RIM_FACE_B => (rim_face(b, sb, a, sa), true),
            RIM_RIM => (rim_rim(a, sa, b, sb, [None, None], f64::INFINITY), false),
            _ => (None, false),
        }
    }
}

/// `code` of a pair apart (no kernel) in the end-involved regime: its
/// dispatch runs, and the regime's kernel answers nothing.
const APART: u8 = 0x40;
/// `code` of a pair apart whatever regime it falls in: passed over before
/// the dispatch (its capsules apart, which contain the domed cylinders; or
/// its cylinders apart with the axes kept out of the parallel band, where
/// the side–side regime claims only true overlaps: `fibre_fibre/mod.rs`).
const APART_ANY_REGIME: u8 = APART | 1;
/// `code` flag of a memory made at the last computation (by a scan at the
/// current pose): a checkpoint leaves it out, since the recomputation at
/// the checkpoint's states makes it again.
const FRESH: u8 = 0x80;
/// Added to a touching memory's kind 1–7 (kinds 9–15): the pair stays in
/// the end-involved regime at full weight for longer than the memory lasts
/// (`room_in_regime`, fibre_fibre/mod.rs), so its dispatch may go straight
/// to the kernel. Rim–rim (8) has no such twin (the four bits are full) and
/// always takes the whole dispatch. Only work changes, never an answer.
const IN_REGIME: u8 = 8;

/// Lengths in a pair's memory are counts of `(r_A + r_B)·2⁻²⁰` (9.5 nm for
/// two 5 mm radii; at most 65 535 of them, 6 % of the radii).
const UNIT_PER_RADII: f64 = 1.0 / (1u64 << 20) as f64;

/// The length unit of the pair `a`, `b`'s memory, m.
#[inline(always)]
pub fn memory_unit(a: &FibreGeom, b: &FibreGeom) -> f64 {
    (a.radius + b.radius) * UNIT_PER_RADII
}

/// What a fibre pair remembers between steps (5 bytes, packed: one per
/// candidate pair; all zero: nothing, the next step scans): the winner's
/// [`Kernel`] (its kinds 1–7 as 9–15 when kept in the regime,
/// [`IN_REGIME`]) or [`APART`] (and [`FRESH`]), the motion `left` (in
/// [`memory_unit`]s, rounded down) that the bodies may still make, and for
/// a touching pair `cap`, the largest depth its minimum may have by then
/// (rounded up): `δ* + Δ` is at most `cap − left`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C, packed)]
pub struct PairMemory {
    code: u8,
    left: u16,
    cap: u16,
}

/// What a memory says, for the kernel.
pub(super) enum Recall {
    /// Scan.
    Nothing,
    /// Apart: no contact.
    Apart,
    /// The depth is `kernel`'s minimum, at most `most` (m).
    Touching { kernel: Kernel, most: f64 },
}

impl PairMemory {
    /// Spend `motion` (m, the sum of both bodies' motion bounds since the
    /// last computation): forgotten when more than is left. No longer fresh.
    #[inline(always)]
    pub(super) fn spend(&mut self, motion: f64, unit: f64) {
        if self.code == 0 {
            return;
        }
        // Rounded up (by a whole unit on an exact multiple: `ceil` is a
        // library call on baseline x86-64); no motion spends nothing (a
        // resumed run's recomputation at the checkpoint's states). (NaN:
        // forgotten.)
        let spent = if motion == 0.0 {
            0.0
        } else {
            motion / unit + 1.0
        };
        let left = self.left;
        if spent <= f64::from(left) {
            self.left = left - spent as u16;
            self.code &= !FRESH;
        } else {
            *self = PairMemory::default();
        }
    }

    /// What it says (after [`PairMemory::spend`]).
    #[inline(always)]
    pub(super) fn recall(&self, unit: f64) -> Recall {
        match self.code {
            0 => Recall::Nothing,
            c if c & APART != 0 => Recall::Apart,
            c => {
                let kind = c & KIND;
                let kind = if self.in_regime() {
                    kind - IN_REGIME
                } else {
                    kind
                };
                Recall::Touching {
                    kernel: Kernel(kind | c & (END_A | END_B)),
                    most: f64::from(self.cap - self.left) * unit,
                }
            }
        }
    }

    /// Touching at depth `depth` by `kernel`'s minimum, for a motion of
    /// `room` (m), or less where the cap would not fit its 16 bits;
    /// nothing when that leaves under one unit. Kept in its regime (see
    /// [`IN_REGIME`]) when `in_regime`, how far the pair may move while its
    /// dispatch sends it to the kernel at full weight, covers what is left.
    #[inline]
    pub(super) fn touching(
        kernel: Kernel,
        depth: f64,
        room: f64,
        unit: f64,
        in_regime: f64,
    ) -> Self {
        let depth = (depth / unit).ceil();
        let left = (room / unit).min(f64::from(u16::MAX) - depth).floor();
        let cap = depth + left;
        if left >= 1.0 && cap <= f64::from(u16::MAX) {
            let kept = kernel.0 & KIND < RIM_RIM && in_regime >= left * unit;
            let code = if kept { kernel.0 + IN_REGIME } else { kernel.0 };
            PairMemory {
                code: code | FRESH,
                left: left as u16,
                cap: cap as u16,
            }
        } else {
            PairMemory::default()
        }
    }

    /// Whether it is a touching memory that the dispatch may hand straight
    /// to its kernel (after [`PairMemory::spend`]; see [`IN_REGIME`]).
    #[inline(always)]
    pub(crate) fn in_regime(&self) -> bool {
        self.code & KIND > RIM_RIM
    }

    /// Apart by more than `gap` (m) in the end-involved regime.
    #[inline]
    pub(super) fn apart(gap: f64, unit: f64) -> Self {
        Self::apart_coded(APART, gap, unit)
    }

    /// Apart by more than `gap` (m) in every regime.
    #[inline]
    pub(super) fn apart_any_regime(gap: f64, unit: f64) -> Self {
        Self::apart_coded(APART_ANY_REGIME, gap, unit)
    }

    #[inline(always)]
    fn apart_coded(code: u8, gap: f64, unit: f64) -> Self {
        // (`as` truncates: the floor, without its library call.)
        let left = (gap / unit).min(f64::from(u16::MAX));
        if left >= 1.0 {
            PairMemory {
                code: code | FRESH,
                left: left as u16,
                cap: 0,
            }
        } else {
            PairMemory::default()
        }
    }

    /// Capsules apart by more than `gap` (m): apart in every regime. A
    /// touching memory is kept as it is instead: a remembered answer equals
    /// the scan's to rounding, not bits, so dropping one would change
    /// results, not only work.
    #[inline(always)]
    pub(super) fn note_capsules_apart(&mut self, gap: f64, unit: f64) {
        if !self.is_touching() {
            *self = Self::apart_any_regime(gap, unit);
        }
    }

    /// Whether the pair is still apart in every regime (after
    /// [`PairMemory::spend`]): nothing to compute.
    #[inline(always)]
    pub(super) fn passed_over(&self) -> bool {
        self.code & !FRESH == APART_ANY_REGIME
    }

    /// Whether it changes what the kernel answers (a touching memory) and
    /// was not made at the last computation: what a checkpoint keeps (a
    /// pair apart only saves work; a fresh memory the resumed run's
    /// recomputation makes again).
    #[inline]
    pub fn kept_by_checkpoints(&self) -> bool {
        self.code != 0 && self.code & (APART | FRESH) == 0
    }

    /// Whether it is a touching one (made or kept at any time).
    #[inline]
    pub fn is_touching(&self) -> bool {
        self.code != 0 && self.code & APART == 0
    }

    /// The raw fields `[code, left, cap]`, for checkpoints and MPI.
    #[inline]
    pub fn to_raw(self) -> [u16; 3] {
        [u16::from(self.code), self.left, self.cap]
    }

    /// [`PairMemory::to_raw`] back, whatever the code (`contact/replay.rs`
    /// restores every memory a recorded call left).
    #[cfg(feature = "replay")]
    pub fn from_raw_any([code, left, cap]: [u16; 3]) -> Self {
        PairMemory {
            code: code as u8,
            left,
            cap,
        }
    }

    /// [`PairMemory::to_raw`] back: `None` unless it is a valid touching
    /// memory (a kernel 1–8, or 1–7 kept in its regime, with its ends, no
    /// other bit, `left ≤ cap`).
    pub fn from_raw([code, left, cap]: [u16; 3]) -> Option<Self> {
        let code = u8::try_from(code).ok()?;
        let kind = code & KIND;
        let known = KIND | END_A | END_B | FRESH;
        (kind != 0 && code & !known == 0 && left <= cap).then_some(PairMemory { code, left, cap })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: the definition of the fixed-point fields. Spending rounds
    /// the motion up and the room down, so the memory never outlasts the
    /// motion it was given; `most` is at least the depth plus what was spent.
    #[test]
    fn a_memory_spends_no_more_than_its_room() {
        let unit = 1e-8;
        let k = Kernel::rim_side(false, 1.0);
        let mut m = PairMemory::touching(k, 1.5e-5, 2.05e-7, unit, 0.0);
        assert_eq!({ m.left }, 20);
        let mut spent = 0.0;
        for step in 0.. {
            m.spend(2.1e-8, unit);
            spent += 2.1e-8;
            match m.recall(unit) {
                Recall::Touching { most, .. } => {
                    assert!(spent <= 2.05e-7, "step {step}: {spent} spent");
                    assert!(most >= 1.5e-5 + spent, "step {step}: {most}");
                }
                Recall::Nothing => {
                    // Three units a step: 20 last 6 steps, the 7th is refused.
                    assert_eq!(step, 6);
                    break;
                }
                Recall::Apart => unreachable!(),
            }
        }
        assert_eq!(
            PairMemory::touching(k, 1e-5, 0.5 * unit, unit, 0.0),
            PairMemory::default()
        );
        assert_eq!(
            PairMemory::touching(k, 1.0, 1e-6, unit, 0.0),
            PairMemory::default()
        );
        // A room without bound takes what the cap leaves.
        let wide = PairMemory::touching(k, 1e-4, f64::INFINITY, unit, 0.0);
        assert_eq!((wide.left, wide.cap), (u16::MAX - 10_000, u16::MAX));
        assert_eq!(std::mem::size_of::<PairMemory>(), 5);
        let mut still = PairMemory::apart(1e-6, unit);
        still.spend(0.0, unit);
        assert_eq!({ still.left }, 100, "no motion, nothing spent");
        let mut nan = PairMemory::apart(1e-6, unit);
        nan.spend(f64::NAN, unit);
        assert_eq!(nan, PairMemory::default());
    }

    /// The raw round trip keeps touching memories and refuses the rest.
    #[test]
    fn raw_fields_round_trip() {
        let m = PairMemory::touching(Kernel::rim_rim(-1.0, 1.0), 1e-5, 1e-6, 1e-8, 0.0);
        assert_eq!(PairMemory::from_raw(m.to_raw()), Some(m));
        let kept = PairMemory::touching(Kernel::rim_side(true, -1.0), 1e-5, 1e-6, 1e-8, 1e-6);
        assert!(kept.in_regime());
        assert_eq!(PairMemory::from_raw(kept.to_raw()), Some(kept));
        assert_eq!(
            PairMemory::from_raw(PairMemory::apart(1e-6, 1e-8).to_raw()),
            None
        );
        assert_eq!(PairMemory::from_raw([0, 0, 0]), None);
        assert_eq!(PairMemory::from_raw([0x100 | 2, 0, 0]), None);
        assert_eq!(PairMemory::from_raw([2, 5, 4]), None);
    }

    /// Reference: the definition of [`IN_REGIME`]. A memory is kept in its
    /// regime exactly when that room covers its own, never for rim–rim, and
    /// recalls the same kernel, depth cap and room either way.
    #[test]
    fn a_memory_in_its_regime_recalls_the_same() {
        let unit = 1e-8;
        let kernels = [
            Kernel::face_side(false, 1.0),
            Kernel::rim_side(false, -1.0),
            Kernel::face_side(true, 1.0),
            Kernel::rim_side(true, -1.0),
            Kernel::face_face(-1.0, 1.0),
            Kernel::rim_face(false, 1.0, -1.0),
            Kernel::rim_face(true, -1.0, -1.0),
            Kernel::rim_rim(-1.0, -1.0),
        ];
        for k in kernels {
            let plain = PairMemory::touching(k, 1e-5, 2e-7, unit, 1.9e-7);
            let kept = PairMemory::touching(k, 1e-5, 2e-7, unit, 2e-7);
            assert!(!plain.in_regime());
            assert_eq!(kept.in_regime(), k != Kernel::rim_rim(-1.0, -1.0), "{k:?}");
            assert_eq!((plain.left, plain.cap), (kept.left, kept.cap));
            // The memory's own room is what the cap leaves (55 535 units
            // here), not the scan's (unbounded).
            let capped = PairMemory::touching(k, 1e-4, f64::INFINITY, unit, 5.6e-4);
            assert_eq!(capped.in_regime(), kept.in_regime(), "{k:?}");
            for mut m in [plain, kept, capped] {
                m.spend(1e-8, unit);
                let Recall::Touching { kernel, most } = m.recall(unit) else {
                    panic!("{k:?}: no longer touching")
                };
                assert_eq!(kernel, k);
                assert_eq!(most, f64::from(m.cap - m.left) * unit);
            }
        }
    }
}
