//! The end-involved depth of regimes 1 and 3 (and of the side–side axial
//! escape): `min_n h̃_B(n) + h̃_A(−n)` of the two domed cylinders, as the
//! least value over the stationary directions of every feature pair near
//! the contact (features/), each evaluated exactly. Why this finds the
//! minimum, and when it hands over to the iterative search: docs/contacts.md,
//! "End-involved kernels".
//!
//! The interface is [`penetration`] (the plain minimum), [`penetration_smoothed`]
//! (tied minima blended) and [`axial_escape`]; [`Scan`] is the one pass all
//! three share.

use super::blend::{push_weighted, smooth_min_c2, Blend, END_TIE_BAND};
use super::coherence::{memory_unit, Kernel, PairMemory, Recall};
use super::features::{face_centre, face_face, face_side, rim_face, rim_rim, rim_side, Stationary};
use super::parry_check::{confirm_separated, parry_contact};
use super::search::{self, SAME_MINIMUM_COS};
use super::segment::segment_closest_params;
use super::side_side::closest_point_contact;
use super::support::{
    dome_sag, domed_projection_overlap as pov, domed_projection_supports, sig, support,
};
use super::{room_beyond_parallel, room_in_regime, Cand};
use crate::contact::{ContactPoint, FibreGeom, KernelCounters};
use glam::DVec3;

/// A feature candidate this close to the best value (relative to the
/// radii) certifies it as a local minimum (the same direction reached by a
/// cheap axis first).
const CERTIFY_TOL: f64 = 1e-12;

/// Relative margin (of the radii) of a kernel's [`Stationary::lower`] for
/// the rounding of it and of `pov` (both a few ulps of the coordinates:
/// ~1e-15 m for a 10 m box, against 1e-11 m).
const LOWER_ROUNDING: f64 = 1e-9;

/// Room for the local minima of one scan that can tie with its best value
/// (within [`END_TIE_BAND`] of the best so far; the others cannot be the
/// runner-up of a blend). A scan has at most 24 (4 end-pair kernels for
/// each of the 4 end pairs, 2 end kernels for each of the 4 ends); when
/// more than this many are near, the highest gives way.
const MAX_MINIMA: usize = 8;

/// What a scan concluded.
enum Verdict {
    /// Apart (a direction with a non-positive overlap, or no end near
    /// enough to touch).
    Separated,
    /// The depth `best` > 0, a certified local minimum.
    Touching,
    /// No certified minimum, or an iteration that did not converge: the
    /// iterative search decides.
    Unsure,
}

/// One pass over the feature pairs of the ends near the contact.
struct Scan<'g> {
    a: &'g FibreGeom,
    b: &'g FibreGeom,
    /// Least value so far and its direction (force on A).
    best: f64,
    best_n: DVec3,
    /// `best` is a local minimum found by a feature kernel.
    certified: bool,
    minima: [(f64, DVec3); MAX_MINIMA],
    count: usize,
    /// A kernel did not converge.
    failed: bool,
    /// A kernel's answer came from rim–rim's descent
    /// ([`Stationary::descended`]): no memory.
    descended: bool,
    /// Some end is near enough to touch.
    any_near: bool,
    /// Upper bound of any value that matters (the capsule bound plus both
    /// sags plus the tie band).
    reach: f64,
    /// The kernel ([`Kernel`]) whose direction is `best_n`, if any.
    winner: Option<Kernel>,
    /// A lower bound of every stationary value of the features the scan
    /// did not run, or that gave no answer (ends and end pairs beyond
    /// `reach`, rim–rim pairs with no stationary point within it): what
    /// [`Scan::room`] counts for them.
    floor: f64,
    /// Every kernel answer: its value (a local minimum's, evaluated) or
    /// lower bound, direction (force on A), and whether a local minimum.
    answers: [(f64, DVec3, bool); MAX_ANSWERS],
    answered: usize,
}

/// Kernel answers of one scan, at most: 2 for each of the 4 ends, 4 for
/// each of the 4 end pairs.
const MAX_ANSWERS: usize = 24;

impl<'g> Scan<'g> {
    /// An empty scan of `a` and `b` (nothing found yet), for [`Scan::pass`].
    #[inline(always)]
    fn new(a: &'g FibreGeom, b: &'g FibreGeom) -> Self {
        Scan {
            a,
            b,
            best: f64::INFINITY,
            best_n: DVec3::ZERO,
            certified: false,
            minima: [(0.0, DVec3::ZERO); MAX_MINIMA],
            count: 0,
            failed: false,
            descended: false,
            any_near: false,
            reach: f64::INFINITY,
            winner: None,
            floor: f64::INFINITY,
            answers: [(0.0, DVec3::ZERO, false); MAX_ANSWERS],
            answered: 0,
        }
    }

    /// The scan of `a` and `b`; with `stop_at_separation` it returns as
    /// soon as a direction separates them (the contact kernel does not
    /// need the separation distance, the side–side escape does). `(s, t)`
    /// are the axis segments' closest-point parameters
    /// ([`segment_closest_params`]). (In place, not returning the scan: a
    /// returned scan was copied.)
    #[inline(always)]
    fn pass(&mut self, (s, t): (f64, f64), stop_at_separation: bool) {
        let (a, b) = (self.a, self.b);
        let cp = a.centre + s * a.axis - b.centre - t * b.axis;
        let bound = a.radius + b.radius - cp.length();
        let (sag_a, sag_b) = (dome_sag(a.radius), dome_sag(b.radius));
        // Upper bound of any value that matters.
        self.reach = bound + sag_a + sag_b + END_TIE_BAND;
        // Cheap axes first (the closest-point line, the centre line, the
        // common normal): most near misses of the capsules are separated
        // along one of them.
        for d in [cp, a.centre - b.centre, a.axis.cross(b.axis)] {
            self.axis(d);
            if stop_at_separation && self.best <= 0.0 {
                return;
            }
        }
        // The depth is at most the least of these values (each an upper
        // bound): no value above it plus the tie band matters.
        self.reach = self.reach.min(self.best.max(0.0) + END_TIE_BAND);
        // An end can hold a minimum only if its disc lies within `reach`
        // of the other body: a stationary value is ±|p_A − p_B| with both
        // supports on the surfaces (docs/contacts.md, "End-involved kernels").
        let lb = |f: &FibreGeom, sigma: f64, sag: f64, o: &FibreGeom| {
            let e = face_centre(f, sigma);
            let t = o
                .axis
                .dot(e - o.centre)
                .clamp(-o.half_length, o.half_length);
            (e - o.centre - t * o.axis).length() - f.radius - sag - o.radius
        };
        // Written out: `[1.0, -1.0].map(..)` was not inlined (it compiled
        // to an array drain).
        let lb_a = [lb(a, 1.0, sag_a, b), lb(a, -1.0, sag_a, b)];
        let lb_b = [lb(b, 1.0, sag_b, a), lb(b, -1.0, sag_b, a)];
        self.any_near = lb_a.iter().chain(&lb_b).any(|&x| x <= self.reach);
        // Ends first (their values tighten `reach`, their rim–side points
        // seed rim–rim), then the end pairs still within reach.
        // (Written out, in the order of the loop over (+, −) they replace:
        // the array iterators were not optimised away.)
        let rim_a0 = self.end(a, 1.0, b, lb_a[0], false);
        let rim_b0 = self.end(b, 1.0, a, lb_b[0], true);
        let rim_a1 = self.end(a, -1.0, b, lb_a[1], false);
        let rim_b1 = self.end(b, -1.0, a, lb_b[1], true);
        let (rim_a, rim_b) = ([rim_a0, rim_a1], [rim_b0, rim_b1]);
        if stop_at_separation && self.best <= 0.0 {
            return;
        }
        self.reach = self.reach.min(self.best.max(0.0) + END_TIE_BAND);
        // End pairs whose discs are further apart than `reach`
        // ([`end_pair_gap`]): each stationary value of their kernels is
        // ±|p_A − p_B| with both points on the two ends' caps or rims, so
        // none lies within ±reach. Above +reach none matters; below −reach
        // one would separate the pair, which an uncertified scan still
        // needs: those pairs are run after all when the scan would be
        // unsure (only in the contact kernel: the side–side escape wants
        // the separation's value).
        let near = |i: usize, j: usize| lb_a[i] <= self.reach && lb_b[j] <= self.reach;
        let (n00, n01, n10, n11) = (near(0, 0), near(0, 1), near(1, 0), near(1, 1));
        for (i, j, near) in [(0, 0, n00), (0, 1, n01), (1, 0, n10), (1, 1, n11)] {
            if !near {
                self.floor = self.floor.min(lb_a[i].max(lb_b[j]));
            }
        }
        let gap = (sag_a, sag_b, stop_at_separation);
        let d00 = n00 && self.near_pair((1.0, 1.0), [rim_a[0], rim_b[0]], gap);
        let d01 = n01 && self.near_pair((1.0, -1.0), [rim_a[0], rim_b[1]], gap);
        let d10 = n10 && self.near_pair((-1.0, 1.0), [rim_a[1], rim_b[0]], gap);
        let d11 = n11 && self.near_pair((-1.0, -1.0), [rim_a[1], rim_b[1]], gap);
        let deferred = [[d00, d01], [d10, d11]];
        if (d00 || d01 || d10 || d11) && matches!(self.verdict(), Verdict::Unsure) {
            for (i, sa) in [1.0, -1.0].into_iter().enumerate() {
                for (j, sb) in [1.0, -1.0].into_iter().enumerate() {
                    if deferred[i][j] {
                        self.end_pair((sa, sb), [rim_a[i], rim_b[j]]);
                    }
                }
            }
        }
    }

    /// The face–side and rim–side kernels of `f`'s end `sg` against `o`
    /// when its lower bound `lb` is within reach; the rim–side point.
    #[inline(always)]
    fn end(
        &mut self,
        f: &FibreGeom,
        sg: f64,
        o: &FibreGeom,
        lb: f64,
        from_b: bool,
    ) -> Option<DVec3> {
        if lb <= self.reach {
            self.feature(face_side(f, sg, o), from_b, Kernel::face_side(from_b, sg));
            self.feature(rim_side(f, sg, o), from_b, Kernel::rim_side(from_b, sg))
        } else {
            // Every stationary value of this end's features is at least lb.
            self.floor = self.floor.min(lb);
            None
        }
    }

    /// The end pair `(sa, sb)` of two ends within reach: deferred (true)
    /// when, with `stop_at_separation`, its discs are further apart than
    /// `reach` plus the sags ([`end_pair_gap`]), else run.
    #[inline(always)]
    fn near_pair(
        &mut self,
        (sa, sb): (f64, f64),
        hints: [Option<DVec3>; 2],
        (sag_a, sag_b, stop_at_separation): (f64, f64, bool),
    ) -> bool {
        if stop_at_separation {
            let reach = self.reach.min(self.best.max(0.0) + END_TIE_BAND);
            let gap = end_pair_gap(self.a, sa, self.b, sb) - sag_a - sag_b;
            if gap > reach {
                self.floor = self.floor.min(gap);
                return true;
            }
        }
        self.end_pair((sa, sb), hints);
        false
    }

    /// The four kernels of the end pair `(sa, sb)` (A's end, B's end);
    /// `hints` are the ends' rim–side points, seeds of rim–rim.
    #[inline(always)]
    fn end_pair(&mut self, (sa, sb): (f64, f64), hints: [Option<DVec3>; 2]) {
        let (a, b) = (self.a, self.b);
        self.feature(face_face(a, sa, b, sb), false, Kernel::face_face(sa, sb));
        self.feature(
            rim_face(a, sa, b, sb),
            false,
            Kernel::rim_face(false, sa, sb),
        );
        self.feature(rim_face(b, sb, a, sa), true, Kernel::rim_face(true, sa, sb));
        // (The best value may have dropped in this loop.)
        let reach = self.reach.min(self.best.max(0.0) + END_TIE_BAND);
        let rims = rim_rim(a, sa, b, sb, hints, reach);
        if rims.is_none() {
            // (The rims further apart than `reach`, or no stationary point.)
            self.floor = self.floor.min(reach);
        }
        self.feature(rims, false, Kernel::rim_rim(sa, sb));
    }

    /// A cheap axis `±d`: an upper bound, no minimum. Of the two signs only
    /// the one pointing from B's centre towards A's is evaluated: for
    /// centrally symmetric bodies `h(n) − h(−n) = 2 n·c`, so
    /// `pov(n) − pov(−n) = 2 n·(c_B − c_A)`, and that sign is the lower.
    fn axis(&mut self, d: DVec3) {
        let l = d.length();
        if !(l > 1e-300 && l.is_finite()) {
            return;
        }
        let n = if d.dot(self.a.centre - self.b.centre) >= 0.0 {
            d / l
        } else {
            -d / l
        };
        let v = pov(self.a, self.b, n);
        if v < self.best {
            (self.best, self.best_n, self.certified) = (v, n, false);
            self.winner = None;
        }
    }

    /// A feature kernel's answer; `from_b` when the kernel's first body is
    /// B (its direction then points from A to B: the force on A is −n).
    /// Returns the kernel's support point on its first body, if any.
    /// (Inlined: called out of line, each answer went through memory.)
    #[inline(always)]
    fn feature(&mut self, st: Option<Stationary>, from_b: bool, kernel: Kernel) -> Option<DVec3> {
        let st = st?;
        self.failed |= !st.converged;
        self.descended |= st.descended;
        // A value at least `best + END_TIE_BAND` changes nothing below
        // (no new best, no certification, no tied minimum): the kernel's
        // lower bound, less its rounding, proves it without `pov`.
        let rounding = LOWER_ROUNDING * (self.a.radius + self.b.radius);
        let n = if from_b { -st.n } else { st.n };
        if st.lower - rounding >= self.best + END_TIE_BAND {
            self.answer(st.lower - rounding, n, st.local_min);
            return Some(st.point);
        }
        let v = pov(self.a, self.b, n);
        self.answer(
            if st.local_min { v } else { st.lower - rounding },
            n,
            st.local_min,
        );
        let tol = CERTIFY_TOL * (self.a.radius + self.b.radius);
        if v < self.best - tol {
            (self.best, self.best_n, self.certified) = (v, n, st.local_min);
            self.winner = Some(kernel);
        } else if st.local_min && !self.certified && v <= self.best + tol {
            // The same minimum a cheap axis (or an uncertified kernel)
            // reached first: the kernel's direction is the minimiser.
            (self.best, self.best_n, self.certified) = (v.min(self.best), n, true);
            self.winner = Some(kernel);
        }
        if st.local_min && v < self.best + END_TIE_BAND {
            if self.count < MAX_MINIMA {
                self.minima[self.count] = (v, n);
                self.count += 1;
            } else if let Some(m) = self.minima.iter_mut().max_by(|x, y| x.0.total_cmp(&y.0)) {
                if v < m.0 {
                    *m = (v, n);
                }
            }
        }
        Some(st.point)
    }

    /// Note a kernel answer for [`Scan::room`].
    #[inline(always)]
    fn answer(&mut self, value: f64, n: DVec3, local_min: bool) {
        if self.answered < MAX_ANSWERS {
            self.answers[self.answered] = (value, n, local_min);
            self.answered += 1;
        }
    }

    /// How far the bodies may move (the sum of both motion bounds) before
    /// another stationary point could become a minimum within the tie
    /// band of `best`, or the least (coherence.rs): for each answer in
    /// another direction than `best_n` with a finite value or lower bound
    /// `ℓ` (which moves by at most the motion, as the points it is made of
    /// do), `Δ` must stay below `(ℓ − best − band)/2` when `ℓ ≥ best`; an
    /// answer below `best` is not where the features support (no value is
    /// below the depth), and gets there only once `ℓ` has risen to the
    /// depth: `Δ < (best − ℓ)/2`. The ends and pairs not run count with
    /// their lower bounds (`floor`).
    fn room(&self) -> f64 {
        let tol = CERTIFY_TOL * (self.a.radius + self.b.radius);
        let mut room = 0.5 * (self.floor - self.best - END_TIE_BAND);
        for &(l, n, local_min) in &self.answers[..self.answered] {
            if !l.is_finite() || n.dot(self.best_n) >= SAME_MINIMUM_COS {
                continue;
            }
            let r = if local_min || l >= self.best - tol {
                0.5 * (l - self.best - END_TIE_BAND)
            } else {
                0.5 * (self.best - l)
            };
            room = room.min(r);
        }
        room
    }

    fn verdict(&self) -> Verdict {
        if self.best <= 0.0 || !self.any_near {
            Verdict::Separated
        } else if self.best > self.reach {
            if self.failed {
                Verdict::Unsure
            } else {
                Verdict::Separated
            }
        } else if self.certified && !self.failed {
            Verdict::Touching
        } else {
            Verdict::Unsure
        }
    }

    /// The least local minimum in another direction than the best.
    fn runner_up(&self) -> Option<(f64, DVec3)> {
        let mut runner: Option<(f64, DVec3)> = None;
        for &(v, n) in &self.minima[..self.count] {
            if n.dot(self.best_n) < SAME_MINIMUM_COS && runner.is_none_or(|r| v < r.0) {
                runner = Some((v, n));
            }
        }
        runner
    }
}

/// Relative margin of [`end_pair_gap`] for its own rounding (lengths of
/// the order of the fibres, computed to a few ulps).
const GAP_ROUNDING: f64 = 1e-12;

/// A lower bound of the distance between the flat end discs of `f`'s end
/// `sf` and `o`'s end `so` (centres `e_f`, `e_o`, unit normals the axes,
/// radii `r_f`, `r_o`; `w = e_o − e_f`, `sin θ = |a_f × a_o|`). Proof: with
/// `x = e_f + u` (`u ⊥ a_f`, `|u| ≤ r_f`) and `p = e_o + v` (`v ⊥ a_o`,
/// `|v| ≤ r_o`), `p − x = w + v − u`. Along `a_f`, `u` has no part and
/// `|v·a_f| ≤ |v| |a_f − (a_f·a_o) a_o| ≤ r_o sin θ`, so that component is
/// at least `z = |w·a_f| − r_o sin θ`; across `a_f` the component is at
/// least `ρ = |w⊥| − r_o − r_f` (triangle inequality); the two are
/// orthogonal, so `|p − x| ≥ √(z₊² + ρ₊²)`, and the same with the roles
/// swapped. Each end's cap and rim lie within its sag of its disc (the cap
/// is a graph of height in `[0, σ]` over the disc), so the distance between
/// any points of the two ends' caps and rims is at least this minus both
/// sags (docs/contacts.md, "End-involved kernels").
fn end_pair_gap(f: &FibreGeom, sf: f64, o: &FibreGeom, so: f64) -> f64 {
    let w = face_centre(o, so) - face_centre(f, sf);
    let sin = f.axis.cross(o.axis).length();
    let one = |u: DVec3, r_own: f64, r_other: f64| {
        let z = w.dot(u);
        let axial = (z.abs() - r_other * sin).max(0.0);
        let across = ((w - z * u).length() - r_own - r_other).max(0.0);
        (axial * axial + across * across).sqrt()
    };
    let gap = one(f.axis, f.radius, o.radius).max(one(o.axis, o.radius, f.radius));
    gap - GAP_ROUNDING * (w.length() + f.radius + o.radius)
}

/// The end-involved depth (plain minimum) of `a` and `b` with its contact,
/// for the side–side escape: exact while the depth is above `−reach`, and
/// `−reach` (a separation beyond every value that matters there) when the
/// scan proves the pair further apart. Falls back to the iterative search
/// from `seeds` when the scan is unsure (counted in `counters`).
pub(super) fn penetration(
    a: &FibreGeom,
    b: &FibreGeom,
    seeds: [DVec3; 2],
    counters: &mut KernelCounters,
) -> Cand {
    counters.end_scans += 1;
    let mut scan = Scan::new(a, b);
    scan.pass(segment_closest_params(a, b), false);
    match scan.verdict() {
        Verdict::Touching => contact_along(a, b, scan.best_n, scan.best),
        Verdict::Separated => {
            let depth = if scan.best <= 0.0 {
                scan.best.max(-scan.reach)
            } else {
                -scan.reach
            };
            contact_along(a, b, scan.best_n, depth)
        }
        Verdict::Unsure => {
            counters.fallbacks += 1;
            search::penetration(a, b, seeds)
        }
    }
}

/// The end-involved contacts of `a` and `b` with their ties smoothed,
/// pushed to `out` with the overall `weight` (none when apart): [`penetration`]'s minimum `δ1` and, when the lowest *other*
/// local minimum `δ2` (a different escape direction) is within
/// [`END_TIE_BAND`] of it, their C² smooth minimum `m(δ1, δ2)`
/// ([`smooth_min_c2`]), pushed as two contacts (one per minimum, its own
/// normal and point) at depth `m` with weights `∂m/∂δ_i` (summing to 1):
/// energy `U(m)`, forces its exact gradient (each minimum's by the envelope
/// theorem). The weights depend on the pose only through `δ1, δ2` and sum to
/// 1, so they carry no `ContactPoint::weight_grad` of their own (the
/// caller's `weight` and `weight_grad` multiply them). C², not C¹: leap-frog's
/// energy error follows the curvature of the potential (docs/contacts.md,
/// "Ties"). `st` are the segments' closest-point parameters. When the scan
/// is unsure, parry (checked) seeds the iterative search instead (seeded
/// also by the closest-point normal), counted in `counters.fallbacks`.
#[allow(clippy::too_many_arguments)]
pub(super) fn penetration_smoothed(
    a: &FibreGeom,
    b: &FibreGeom,
    st: (f64, f64),
    out: &mut Vec<ContactPoint>,
    weight: f64,
    weight_grad: DVec3,
    counters: &mut KernelCounters,
    memory: Option<&mut PairMemory>,
) {
    let mut memory = memory;
    let unit = memory_unit(a, b);
    if let Some(m) = memory.as_deref_mut() {
        match m.recall(unit) {
            Recall::Apart => {
                counters.remembered += 1;
                return;
            }
            Recall::Touching { kernel, most } => {
                if let Some(c) = remembered(a, b, kernel, most) {
                    counters.remembered += 1;
                    push_weighted(out, c, weight, weight_grad);
                    return;
                }
            }
            Recall::Nothing => {}
        }
        *m = PairMemory::default();
    }
    counters.end_scans += 1;
    let mut scan = Scan::new(a, b);
    scan.pass(st, true);
    match scan.verdict() {
        Verdict::Separated => {
            if let Some(m) = memory {
                // Apart along best_n by −best: no direction's overlap can
                // turn positive before the bodies move that much. Passed
                // over before the dispatch while no other regime can claim
                // the pair (`room_beyond_parallel`), if that lasts half as
                // long; else asked again each step, here.
                let (gap, room) = (-scan.best, room_beyond_parallel(a, b));
                *m = if room >= 0.5 * gap {
                    PairMemory::apart_any_regime(gap.min(room), unit)
                } else {
                    PairMemory::apart(gap, unit)
                };
            }
        }
        Verdict::Touching => {
            let first = contact_along(a, b, scan.best_n, scan.best);
            let runner = scan.runner_up();
            match runner {
                Some((v, n)) if v - scan.best < END_TIE_BAND => {
                    let other = Blend::single(contact_along(a, b, n, v));
                    Blend::single(first)
                        .smin_by(other, |x, y| smooth_min_c2(x, y, END_TIE_BAND))
                        .push(out, a, weight, weight_grad);
                }
                _ => push_weighted(out, first, weight, weight_grad),
            }
            if let (Some(m), Some(kernel), true, false) =
                (memory, scan.winner, scan.certified, scan.descended)
            {
                let margin = LOWER_ROUNDING * (a.radius + b.radius);
                let room = scan.room() - margin;
                *m = PairMemory::touching(kernel, scan.best, room, unit, room_in_regime(a, b));
            }
        }
        Verdict::Unsure => {
            counters.fallbacks += 1;
            if let Some(blend) = fallback_smoothed(a, b, counters) {
                blend.push(out, a, weight, weight_grad);
            }
        }
    }
}

/// The answer of a memory kept in its regime ([`PairMemory::in_regime`]),
/// before the dispatch: the dispatch would reach [`penetration_smoothed`]
/// at full weight and answer the same from the memory, once its first test
/// finds the capsules overlapping, which a true overlap deeper than that
/// test's rounding ensures. `false` (nothing done: the dispatch runs)
/// otherwise. (Out of line: inlined into the dispatch, it made every
/// dispatch dearer; `cargo bench --bench bed` measures the step.)
#[inline(never)]
pub(super) fn remembered_in_regime(
    a: &FibreGeom,
    b: &FibreGeom,
    memory: &PairMemory,
    out: &mut Vec<ContactPoint>,
    counters: &mut KernelCounters,
) -> bool {
    let Recall::Touching { kernel, most } = memory.recall(memory_unit(a, b)) else {
        return false;
    };
    match remembered(a, b, kernel, most) {
        Some(c) if c.depth > LOWER_ROUNDING * (a.radius + b.radius) => {
            counters.remembered += 1;
            push_weighted(out, c, 1.0, DVec3::ZERO);
            true
        }
        _ => false,
    }
}

/// The depth of a remembered pair by its winner's kernel alone: `None`
/// (the scan runs) unless the kernel still certifies a local minimum whose
/// value is positive and at most `most` (`δ* + Δ`, see coherence.rs).
#[inline(always)]
fn remembered(a: &FibreGeom, b: &FibreGeom, kernel: Kernel, most: f64) -> Option<Cand> {
    let (st, from_b) = kernel.eval(a, b);
    let st = st?;
    if !(st.local_min && st.converged) {
        return None;
    }
    let n = if from_b { -st.n } else { st.n };
    let (v, on_a, on_b) = domed_projection_supports(a, b, n);
    (v > 0.0 && v <= most).then(|| contact_at(a, b, n, v, || on_a, || on_b))
}

/// The iterative search of the previous kernel (search.rs), seeded by
/// parry's checked normal; parry's "no contact" is confirmed by a
/// separating axis.
fn fallback_smoothed(a: &FibreGeom, b: &FibreGeom, counters: &mut KernelCounters) -> Option<Blend> {
    let (s, t) = segment_closest_params(a, b);
    let cp_normal = closest_point_contact(a, b, s, t).normal;
    let bound = a.radius + b.radius - (a.centre + s * a.axis - b.centre - t * b.axis).length();
    let margin = dome_sag(a.radius) + dome_sag(b.radius);
    let parry_n = match parry_contact(a, b, bound, margin, counters) {
        Ok(None) => {
            confirm_separated(a, b, margin, cp_normal, counters);
            return None;
        }
        Ok(Some(c)) => c.normal,
        Err(n) => {
            counters.parry_rejects += 1;
            n
        }
    };
    let blend = search::penetration_smoothed(a, b, [cp_normal, parry_n]);
    (blend.depth > 0.0).then_some(blend)
}

/// Axial escape of a near-parallel pair: the least of the end-pair
/// stationary directions (face–face, rim–face both ways, rim–rim) of the
/// ends facing each other along the most competitive face normal (over the
/// ends, as opposed to sideways), or that face normal itself. A smooth
/// function of the pose where the least is unique.
pub(super) fn axial_escape(a: &FibreGeom, b: &FibreGeom) -> Cand {
    let mut face = a.axis;
    let mut face_v = f64::INFINITY;
    for u in [a.axis, -a.axis, b.axis, -b.axis] {
        let v = pov(a, b, u);
        if v < face_v {
            face_v = v;
            face = u;
        }
    }
    let (fa, fb) = (sig(-face, a.axis), sig(face, b.axis));
    let (mut best, mut best_n) = (face_v, face);
    for (st, from_b) in [
        (face_face(a, fa, b, fb), false),
        (rim_face(a, fa, b, fb), false),
        (rim_face(b, fb, a, fa), true),
        (rim_rim(a, fa, b, fb, [None, None], f64::INFINITY), false),
    ] {
        if let Some(st) = st {
            let n = if from_b { -st.n } else { st.n };
            let v = pov(a, b, n);
            if v < best {
                (best, best_n) = (v, n);
            }
        }
    }
    contact_along(a, b, best_n, best)
}

/// Below this |n·axis| for both bodies, the depth minimiser is taken to be
/// on both side circles (generators crossing, see [`generator_crossing`]).
const SIDE_CIRCLE_TOL: f64 = 1e-7;

/// The contact of a depth minimum `depth` at the unit direction `n` (force
/// on A): its application point, on the body whose support is the more
/// clearly unique. With domed faces the only degenerate supports are on the
/// side circles (n·axis = 0: a generator line), so the clarity is
/// |n·axis| (a sine, like the distance of the minimiser from that circle):
/// a minimiser 1e-12 off B's side circle makes B's "unique" support an
/// arbitrary end of its generator (history: docs/contacts.md, "Penetration
/// search").
pub(super) fn contact_along(a: &FibreGeom, b: &FibreGeom, n: DVec3, depth: f64) -> Cand {
    contact_at(a, b, n, depth, || support(a, -n).0, || support(b, n).0)
}

/// [`contact_along`] with A's support in `−n` and B's in `n` given (made
/// only if needed).
#[inline(always)]
fn contact_at(
    a: &FibreGeom,
    b: &FibreGeom,
    n: DVec3,
    depth: f64,
    on_a: impl FnOnce() -> DVec3,
    on_b: impl FnOnce() -> DVec3,
) -> Cand {
    let (ca, cb) = (n.dot(a.axis).abs(), n.dot(b.axis).abs());
    let point = if ca.max(cb) < SIDE_CIRCLE_TOL {
        generator_crossing(a, b, n)
    } else if ca >= cb {
        on_a() + 0.5 * depth * n
    } else {
        on_b() - 0.5 * depth * n
    };
    Cand {
        depth,
        point,
        normal: n,
    }
}

/// Both supports are generator lines (`n ⊥` both axes): the contact point
/// is midway between the closest points of the two generator segments.
fn generator_crossing(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> DVec3 {
    let gen = |f: &FibreGeom, d: DVec3| {
        let perp = d - d.dot(f.axis) * f.axis;
        let l = perp.length();
        let u = if l > 1e-300 {
            perp / l
        } else {
            f.axis.any_orthonormal_vector()
        };
        FibreGeom {
            centre: f.centre + f.radius * u,
            radius: 0.0,
            ..*f
        }
    };
    let (ga, gb) = (gen(a, -n), gen(b, n));
    let (s, t) = segment_closest_params(&ga, &gb);
    0.5 * (ga.centre + s * ga.axis + gb.centre + t * gb.axis)
}

#[cfg(test)]
mod tests {
    use super::super::uniform::Uniform;
    use super::*;

    /// Distance from `q` to the disc (centre `e`, unit normal `u`, radius
    /// `r`), closed form.
    fn point_disc(q: DVec3, e: DVec3, u: DVec3, r: f64) -> f64 {
        let w = q - e;
        let z = w.dot(u);
        let rho = (w - z * u).length();
        if rho <= r {
            z.abs()
        } else {
            (z * z + (rho - r) * (rho - r)).sqrt()
        }
    }

    /// Reference: brute force. Two discs' distance is reached with a point
    /// on a rim (intersecting discs: an end of their common chord; apart:
    /// a closest pair, interior only for parallel planes, slides to a rim),
    /// so it is the least rim-sample-to-disc distance, within `r π/N` above
    /// the true one. The bound must stay below it on random poses, tight
    /// (within 0.5 mm) on some.
    #[test]
    fn end_pair_gap_is_below_the_discs_distance() {
        const N: usize = 2000;
        let mut u = Uniform(0x9e37_79b9_7f4a_7c15);
        let rim_to_disc = |f: &FibreGeom, sf: f64, o: &FibreGeom, so: f64| {
            let e = face_centre(f, sf);
            let w1 = f.axis.any_orthonormal_vector();
            let w2 = f.axis.cross(w1);
            (0..N)
                .map(|k| {
                    let t = k as f64 * std::f64::consts::TAU / N as f64;
                    let p = e + f.radius * (t.cos() * w1 + t.sin() * w2);
                    point_disc(p, face_centre(o, so), o.axis, o.radius)
                })
                .fold(f64::INFINITY, f64::min)
        };
        let mut tight = 0;
        for _ in 0..400 {
            let (a, b) = (u.fibre(0.06), u.fibre(0.06));
            for (sa, sb) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                let brute = rim_to_disc(&a, sa, &b, sb).min(rim_to_disc(&b, sb, &a, sa));
                let gap = end_pair_gap(&a, sa, &b, sb);
                assert!(gap <= brute, "gap {gap} > distance {brute}: {a:?} {b:?}");
                tight += usize::from(gap > 0.0 && brute - gap < 5e-4);
            }
        }
        assert!(tight > 20, "{tight} tight poses");
    }

    /// Reference: the definition `pov(n) = h_o(n) + h_f(−n)`, evaluated by
    /// `domed_projection_overlap`. Every kernel's `lower` must stay below
    /// it, and equal it (to rounding) where the kernel's supports are the
    /// features assumed (to the rounding of the domes' 10 m radii, 1e-13 m;
    /// the scan allows [`LOWER_ROUNDING`]), on random poses and on near-coaxial end-to-end
    /// ones (where the caps support) and T-junctions (face on side).
    #[test]
    fn kernel_lower_bounds_are_below_the_overlap() {
        let mut u = Uniform(0x2545_f491_4f6c_dd1d);
        let mut exact = [0usize; 5];
        for k in 0..3000 {
            let a = u.fibre(0.04);
            let b = if k % 3 == 0 {
                u.fibre(0.04)
            } else if k % 3 == 1 {
                // A T-junction: an end face on A's side, the axes within
                // ~0.1 mrad of perpendicular (where face–side exists).
                let axis = (a.axis.any_orthonormal_vector() + u.vec(2e-4)).normalize();
                FibreGeom {
                    centre: a.centre + 0.02 * (u.next() - 0.5) * a.axis + 0.0175 * axis,
                    axis,
                    ..a
                }
            } else {
                // End to end, the faces within ~1 mrad of antiparallel.
                let axis = (a.axis + u.vec(2e-3)).normalize();
                FibreGeom {
                    centre: a.centre + (0.025 + 2.0 * (u.next() - 0.5) * 1e-5) * axis + u.vec(4e-3),
                    axis,
                    ..a
                }
            };
            for (f, o) in [(&a, &b), (&b, &a)] {
                for (sf, so) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                    let kernels = [
                        face_face(f, sf, o, so),
                        rim_face(f, sf, o, so),
                        face_side(f, sf, o),
                        rim_side(f, sf, o),
                        rim_rim(f, sf, o, so, [None, None], f64::INFINITY),
                    ];
                    for (i, st) in kernels.into_iter().enumerate() {
                        let Some(st) = st else { continue };
                        let v = pov(f, o, st.n);
                        // (Rounding: face–face's is of its 10 m dome radii.)
                        assert!(st.lower <= v + 1e-13, "kernel {i}: {} > {v}", st.lower);
                        exact[i] += usize::from(st.local_min && (st.lower - v).abs() < 1e-13);
                    }
                }
            }
        }
        assert!(
            exact.iter().all(|&n| n > 0),
            "exact lower bounds per kernel: {exact:?}"
        );
    }
}
