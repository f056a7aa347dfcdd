//! Side–side fibre–fibre contact (closest points of the axis segments
//! interior, or near-parallel axes overlapping axially): the analytic
//! closest-point and end-disc-on-side depths, two points for a parallel
//! pair, and the axial escape of near-parallel pairs whose ends slide past
//! each other. Model and limits: docs/contacts.md, "Side–side".

use super::blend::{push_weighted, push_wrench, smooth_min, Blend, Wrench, TIE_BAND};
use super::end_involved::{axial_escape, penetration};
use super::features::rim_point_nearest_line;
use super::segment::axial_overlap;
use super::support::sig;
use super::{parallel_weight, Cand, PARALLEL_SIN};
use crate::contact::{ContactPoint, FibreGeom, KernelCounters};
use glam::DVec3;

/// Two candidate contacts whose normals are closer than this (cos 0.1 rad)
/// are one contact found twice.
const SAME_CONTACT_COS: f64 = 0.995;

/// End disc of one fibre (centre `e`, axis `ue`, radius `re`) against the
/// side of `other`: depth of the rim point deepest in `other`, i.e.
/// `max_φ (r_o − dist(rim(φ), axis_o))`, the rim point nearest `other`'s
/// axis line by the rim–side kernel's Newton iteration
/// ([`rim_point_nearest_line`]), so the result is the max over body-fixed
/// rim points and its gradient is the force at that point (envelope
/// theorem). Returns the normal pointing from `other` towards the end's
/// fibre.
#[inline]
fn end_vs_side(e: DVec3, ue: DVec3, re: f64, other: &FibreGeom) -> Cand {
    let (oc, ou, oh) = (other.centre, other.axis, other.half_length);
    let t = ou.dot(e - oc).clamp(-oh, oh);
    let v = e - (oc + t * ou);
    let dist = v.length();
    let n = if dist > 1e-300 {
        v / dist
    } else {
        ou.any_orthonormal_vector()
    };
    let capsule_depth = other.radius + re - dist;
    if capsule_depth <= 0.0 {
        // The rim lies within `re` of `e`: no rim point can touch.
        return Cand {
            depth: capsule_depth,
            point: e,
            normal: n,
        };
    }
    let p = rim_point_nearest_line(e, ue, re, oc, ou).map_or(e, |(p, _)| p);
    let tp = ou.dot(p - oc).clamp(-oh, oh);
    let qp = oc + tp * ou;
    let vp = p - qp;
    let dp = vp.length();
    let (depth, normal) = if dp > 1e-300 && vp.dot(n) > 0.0 {
        (other.radius - dp, vp / dp)
    } else {
        (other.radius + dp, n)
    };
    Cand {
        depth,
        point: 0.5 * (p + qp + other.radius * normal),
        normal,
    }
}

/// Contact of one of A's ends (`sign` = ±1) against B's side.
#[inline]
fn a_end(a: &FibreGeom, b: &FibreGeom, sign: f64) -> Cand {
    end_vs_side(
        a.centre + sign * a.half_length * a.axis,
        a.axis,
        a.radius,
        b,
    )
}

/// Contact of one of B's ends against A's side, normal flipped to act on A.
#[inline]
fn b_end(a: &FibreGeom, b: &FibreGeom, sign: f64) -> Cand {
    let mut c = end_vs_side(
        b.centre + sign * b.half_length * b.axis,
        b.axis,
        b.radius,
        a,
    );
    c.normal = -c.normal;
    c
}

/// The deeper of two candidates (`x` at a tie).
#[inline]
fn deeper(x: Cand, y: Cand) -> Cand {
    if y.depth > x.depth {
        y
    } else {
        x
    }
}

/// Closest-point contact of the axis segments (the deepest point of a
/// crossing), analytic; clamped parameters are handled by the end model.
#[inline]
pub(super) fn closest_point_contact(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64) -> Cand {
    let s_end = s.abs() >= a.half_length;
    let t_end = t.abs() >= b.half_length;
    match (s_end, t_end) {
        (false, false) => interior_contact(a, b, s, t),
        (true, false) => a_end(a, b, s.signum()),
        (false, true) => b_end(a, b, t.signum()),
        (true, true) => deeper(a_end(a, b, s.signum()), b_end(a, b, t.signum())),
    }
}

/// [`closest_point_contact`] of interior closest points `s`, `t`: the
/// contact of the two axis points. (Inlined into the crossing's path,
/// where a call passed its answer through memory.)
#[inline(always)]
fn interior_contact(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64) -> Cand {
    let pa = a.centre + s * a.axis;
    let pb = b.centre + t * b.axis;
    let v = pa - pb;
    let d = v.length();
    let n = if d > 1e-300 {
        v / d
    } else {
        let c = a.axis.cross(b.axis);
        if c.length_squared() > 1e-24 {
            c.normalize()
        } else {
            a.axis.any_orthonormal_vector()
        }
    };
    Cand {
        depth: a.radius + b.radius - d,
        point: 0.5 * (pa - a.radius * n + pb + b.radius * n),
        normal: n,
    }
}

/// What the side–side model gives.
// Returned by value once per call and never stored: boxing the rare
// escape's blends would allocate in the force loop.
#[allow(clippy::large_enum_variant)]
pub(super) enum SideSide {
    /// A crossing whose overlap ends do not touch: one point, weight 1.
    Crossing(Cand),
    /// The line model of the overlap's ends `lo`, `hi` (and the crossing
    /// `cp` when the closest points are interior), pushed with weights in
    /// closed form by [`SideSide::push`] (no [`Blend`] needed).
    Line {
        cp: Option<Crossing>,
        lo: Cand,
        hi: Cand,
    },
    /// `(main, second)` of the axial escape.
    Escape(Blend, Blend),
}

impl SideSide {
    /// Push the main contact with `main_weight` (and its couple
    /// `main_grad`) and the second with `second_weight` (`second_grad`).
    pub(super) fn push(
        self,
        out: &mut Vec<ContactPoint>,
        a: &FibreGeom,
        (main_weight, main_grad): (f64, DVec3),
        (second_weight, second_grad): (f64, DVec3),
    ) {
        let part =
            |out: &mut Vec<ContactPoint>, c: Cand, depth: f64, w: f64, (wt, g): (f64, DVec3)| {
                if w > 0.0 {
                    push_weighted(out, Cand { depth, ..c }, w * wt, w * g);
                }
            };
        match self {
            SideSide::Crossing(c) => push_weighted(out, c, main_weight, main_grad),
            SideSide::Line { cp, lo, hi } => {
                // δ_2 = smin(δ_lo, δ_hi); S = smax = −smin(−δ_lo, −δ_hi).
                let (m, wl, wh) = smooth_min(lo.depth, hi.depth, TIE_BAND);
                part(out, lo, m, wl, (second_weight, second_grad));
                part(out, hi, m, wh, (second_weight, second_grad));
                let (neg_s, sl, sh) = smooth_min(-lo.depth, -hi.depth, TIE_BAND);
                let (depth, wc, ws) = match cp {
                    Some(x) => {
                        let (neg, wc, ws) = smooth_min(-x.cand.depth, neg_s, x.band);
                        (-neg, wc, ws)
                    }
                    None => (-neg_s, 0.0, 1.0),
                };
                let main = (main_weight, main_grad);
                if let Some(x) = cp {
                    // The band's own gradient, ∂δ_main/∂ε = w_c w_S, on
                    // the crossing's part (weight w_c): see [`Crossing`].
                    if wc > 0.0 && ws > 0.0 && x.band_grad != DVec3::ZERO {
                        let c = Cand { depth, ..x.cand };
                        push_wrench(out, c, x.wrench(a, ws), a, wc * main_weight, wc * main_grad);
                    } else {
                        part(out, x.cand, depth, wc, main);
                    }
                }
                part(out, lo, depth, ws * sl, main);
                part(out, hi, depth, ws * sh, main);
            }
            SideSide::Escape(main, second) => {
                second.push(out, a, second_weight, second_grad);
                main.push(out, a, main_weight, main_grad);
            }
        }
    }
}

/// Width of the smooth maximum of the crossing and the line contact's
/// ends (m) for a parallel pair (`|a×b| ≤` [`super::PARALLEL_BLEND_SIN`]):
/// below the ε/4 by which the ends' smooth maximum exceeds their plain
/// maximum at a tie, so an exactly parallel pair (crossing depth = end
/// depth up to rounding) gives the crossing no weight. It fades with the
/// parallel blend weight to 0 at [`PARALLEL_SIN`], see [`Crossing`].
const CROSSING_BAND: f64 = TIE_BAND / 8.0;

/// The crossing (closest points interior) of the line model with the band
/// `ε_c = CROSSING_BAND · w(|a×b|)` of its smooth maximum with the ends
/// (`w` the parallel blend weight, gradient `band_grad = CROSSING_BAND ·
/// ∂w/∂φ_A`).
///
/// Why the band fades: where the crossing point slides off an end, the
/// crossing depth equals that end's depth (they tie exactly), and beyond
/// it the model is `S` or regime 3's exact depth; a fixed band put the
/// main depth ε_c/4 (31 nm) above both there, a jump in the potential at
/// the switch (`spinning_fibres`: a 5e-4 % energy step at every δt).
/// With `ε_c = 0` for crossed pairs the main depth is the plain
/// `max(δ_cp, S) = δ_cp` up to the switch, continuous; the tie the band
/// is for (an exactly parallel pair) keeps it. Between, `∂δ_main/∂ε_c =
/// w_c w_S` (the C¹ formula) times `band_grad` is a pure couple of the
/// potential, pushed with the crossing's part as a [`Wrench`].
#[derive(Clone, Copy)]
pub(super) struct Crossing {
    cand: Cand,
    band: f64,
    band_grad: DVec3,
}

impl Crossing {
    fn new(cand: Cand, a: &FibreGeom, b: &FibreGeom) -> Self {
        let sin = a.axis.cross(b.axis).length();
        let (w, grad) = parallel_weight(a, b, sin);
        Self {
            cand,
            band: CROSSING_BAND * w,
            band_grad: CROSSING_BAND * grad,
        }
    }

    /// `−∇_A δ_main / w_c` of the crossing's part when the ends' weight is
    /// `ws`: the force along its normal, and the torque of that force plus
    /// `−w_S ∂ε_c/∂φ_A` (the band's couple, `∂δ_main/∂ε_c = w_c w_S`).
    fn wrench(&self, a: &FibreGeom, ws: f64) -> Wrench {
        let c = self.cand;
        Wrench {
            force: c.normal,
            torque: (c.point - a.centre).cross(c.normal) - ws * self.band_grad,
        }
    }

    /// `smax(δ_cp, ends)` over the band as a [`Blend`], the crossing's part
    /// carrying the band's couple.
    fn smax(&self, ends: Blend, a: &FibreGeom) -> Blend {
        let (_, _, ws) = smooth_min(-self.cand.depth, -ends.depth, self.band);
        let cp = if ws > 0.0 && ws < 1.0 && self.band_grad != DVec3::ZERO {
            Blend::with_wrench(self.cand, self.wrench(a, ws))
        } else {
            Blend::single(self.cand)
        };
        cp.smax(ends, self.band)
    }
}

/// Margin of [`ends_clear_of_lines`] over the rounding of its bound, in
/// units of `(reach + along)²`: the rounding of `s`, `t` (hence of `v ⊥
/// a, b`) is ~1e-16 of the lengths, and enters squared, so the margin
/// scales with the lengths too (a fixed share of the reach² failed from
/// `h/reach ≈ 2000` on).
const CLEAR_MARGIN: f64 = 1e-9;

/// Whether every end centre of a crossing pair is beyond the capsule reach
/// `r_A + r_B` of the other's axis *line*, hence of its segment (what
/// `side_side`'s per-end test asks, in a dozen operations). For closest
/// points `s`, `t` interior and `depth` the crossing's: there `v = p_A −
/// p_B` is ⊥ both axes, so A's end `h_A ∓ s` along A from `p_A` is at
/// `√(|v|² + (h_A ∓ s)² |a×b|²)` from B's line; the nearer end (`h_A −
/// |s|`) decides (and likewise B's). Only where `segment_closest_params`
/// solved for the lines' closest points ([`SOLVED_SIN2`]): its parallel
/// branch takes the middle of the overlap, where `v` need not be ⊥ A.
#[inline(always)]
fn ends_clear_of_lines(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64, depth: f64) -> bool {
    let reach = a.radius + b.radius;
    let d = reach - depth;
    let along = (a.half_length - s.abs()).min(b.half_length - t.abs());
    let sin2 = a.axis.cross(b.axis).length_squared();
    let margin = CLEAR_MARGIN * (reach + along) * (reach + along);
    sin2 > SOLVED_SIN2 && d * d + along * along * sin2 >= reach * reach + margin
}

/// `|a×b|²` above which [`ends_clear_of_lines`] trusts `s`, `t` to be the
/// lines' closest points (100× `segment_closest_params`'s parallel
/// threshold on `1 − (a·b)²`, beyond their rounding difference).
const SOLVED_SIN2: f64 = 1e-12;

/// Side–side model, potential `U(δ_main) + U(δ_2)` with
/// `δ_2 = smin(δ_lo, δ_hi)`, `S = smax(δ_lo, δ_hi) = δ_lo + δ_hi − δ_2` (C¹,
/// band [`TIE_BAND`]) and `δ_main = S`, or `smax(δ_cp, S)` (band
/// [`CROSSING_BAND`]) when the closest points are interior.
///
/// `δ_lo`/`δ_hi` are the depths at the two ends of the axial overlap (the
/// deeper of "A's end vs B's side" and "B's end vs A's side" on that side);
/// `δ_cp` is the closest-point depth, never below them.
/// * Crossed pair: the ends are far apart, `δ_lo, δ_hi < 0`: one Hertz point
///   at the crossing, weight 1.
/// * Parallel pair: two points at the ends of the overlap, potential
///   `U(S) + U(δ_2)`, smooth under rocking (at a tie both ends carry half
///   of each, the depths `δ ± ε/4`), no chatter.
/// * Scissored and rocked at once (the crossing inside the overlap, the
///   ends tied): `U(δ_cp) + U(δ_2)`, still C¹: the second contact moves
///   smoothly from one end to the other instead of switching (the plain
///   `min` made the torque jump by 2 (ℓ/2) F there, and for an exactly
///   parallel pair rounding picked the crossing or an end: a torque pulse of
///   ~F ℓ/2 in one step).
///
/// The potential is C¹ in the pose except where the end defining an
/// overlap end switches from A to B, and where a crossing point slides off
/// an end (the crossing depth then meets the end model only to first
/// order).
///
/// Axial escape (near-parallel pairs only): when the axial overlap `ℓ` of
/// the segments is below `2δ_main` (ends sliding past each other), the
/// main depth becomes the smooth minimum ([`TIE_BAND`]) of the sideways
/// depth and the over-the-end escape ([`axial_escape`]), and the second is
/// capped at `smin(δ_2, ℓ − δ_pd)` and at `δ_pd + ε/4` (`δ_pd` =
/// [`penetration`], min over directions): the pair fades continuously to
/// zero at `ℓ = δ_pd`, and nothing is left when it is separated
/// (`δ_pd ≤ 0`). `ℓ − δ_pd` carries its exact gradient (`∇ℓ` in closed
/// form) as a [`Wrench`]. Limit: for exactly parallel axes `ℓ − δ_pd` has a
/// rocking kink (measure zero). Why each piece: docs/contacts.md,
/// "Side–side".
///
/// Returns the crossing alone (one point, weight 1) when the overlap's
/// ends do not touch, else `(main, second)`: the caller weights the second
/// contact (and, outside the interior case, the main one) by the parallel
/// blend weight. `counters` counts the end-involved scans of the escape.
/// (Inlined: out of line its answer went through memory, a cost on every
/// crossing: `cargo bench --bench kernels`, `side_side`.)
#[inline(always)]
pub(super) fn side_side(
    a: &FibreGeom,
    b: &FibreGeom,
    s: f64,
    t: f64,
    counters: &mut KernelCounters,
) -> SideSide {
    let interior = s.abs() < a.half_length && t.abs() < b.half_length;
    let cp = if interior {
        interior_contact(a, b, s, t)
    } else {
        closest_point_contact(a, b, s, t)
    };
    // The common crossing, decided before any end model: no end disc
    // within the capsule reach of the other axis (so δ_lo, δ_hi ≤ 0, see
    // below) and the crossing deep enough to beat their smooth maximum.
    if interior && cp.depth >= 0.25 * TIE_BAND + CROSSING_BAND {
        if ends_clear_of_lines(a, b, s, t, cp.depth) {
            return SideSide::Crossing(cp);
        }
        let clear = |f: &FibreGeom, o: &FibreGeom, sign: f64| {
            let e = f.centre + sign * f.half_length * f.axis;
            let t = o
                .axis
                .dot(e - o.centre)
                .clamp(-o.half_length, o.half_length);
            let reach = f.radius + o.radius;
            (e - o.centre - t * o.axis).length_squared() >= reach * reach
        };
        if clear(a, b, 1.0) && clear(a, b, -1.0) && clear(b, a, 1.0) && clear(b, a, -1.0) {
            return SideSide::Crossing(cp);
        }
    }
    let sb = sig(a.axis, b.axis);
    let lo = deeper(a_end(a, b, -1.0), b_end(a, b, -sb));
    let hi = deeper(a_end(a, b, 1.0), b_end(a, b, sb));
    // A crossing whose overlap ends do not touch: the smooth min of the
    // ends is then ≤ 0 and the crossing beats their smooth max (≤ max +
    // ε/4) by more than its band, so the model is exactly one point.
    if interior
        && lo.depth <= 0.0
        && hi.depth <= 0.0
        && cp.depth >= lo.depth.max(hi.depth) + 0.25 * TIE_BAND + CROSSING_BAND
    {
        return SideSide::Crossing(cp);
    }
    let crossing = Crossing::new(cp, a, b);
    let line = SideSide::Line {
        cp: interior.then_some(crossing),
        lo,
        hi,
    };
    let (lo_b, hi_b) = (Blend::single(lo), Blend::single(hi));
    let first_depth = {
        let ends = -smooth_min(-lo.depth, -hi.depth, TIE_BAND).0;
        if interior {
            -smooth_min(-cp.depth, -ends, crossing.band).0
        } else {
            ends
        }
    };
    let sin = a.axis.cross(b.axis).length();
    let ell = axial_overlap(a, b);
    // The switch lies TIE_BAND beyond ℓ = 2δ_main so that no smooth
    // minimum below is active there (ℓ − δ_pd ≥ δ_main + ε ≥ δ_2 + ε,
    // and the axial escape is ~ℓ).
    if !(sin < PARALLEL_SIN
        && first_depth > 0.0
        && ell.len < 2.0 * first_depth + TIE_BAND + (a.radius + b.radius) * sin)
    {
        return line;
    }
    // The escape (rare: ends sliding past each other) composes Blends.
    let second = lo_b.smin(hi_b);
    let ends = lo_b.smax(hi_b, TIE_BAND);
    let first = if interior {
        crossing.smax(ends, a)
    } else {
        ends
    };
    // The sideways contact's direction (its deepest candidate) seeds the
    // fallback and tells whether the axial escape found the same contact.
    let big = if hi.depth > lo.depth { hi } else { lo };
    let main = if big.depth >= cp.depth { big } else { cp };
    let pd = penetration(a, b, [main.normal, cp.normal], counters);
    // Main depth: smin(δ_side, δ_axial), the sideways and the over-the-end
    // escapes (a plain min switches the force direction in one step). When
    // the axial escape is the sideways minimum itself, the two are one
    // contact: a plain min has no kink.
    let ax = axial_escape(a, b);
    let main = if ax.normal.dot(main.normal) > SAME_CONTACT_COS {
        if ax.depth < first.depth {
            Blend::single(ax)
        } else {
            first
        }
    } else {
        first.smin(Blend::single(ax))
    };
    // Second depth: min(smin(δ_2, ℓ − δ_pd), δ_pd + ε/4). The cap
    // ℓ − δ_pd fades the pair out as the ends slide past each other, with
    // its exact gradient: ∇ℓ in closed form, −∇_A δ_pd = the force F n at
    // pd's point. The cap by δ_pd removes the second contact with the first
    // when the pair separates; a plain min, offset by ε/4, since a true
    // local depth never exceeds the penetration depth (δ_2 ≤ δ_pd), so
    // it only bites on the end model's capsule-like depths near the other
    // fibre's end.
    let arm = pd.point - a.centre;
    let capped = Blend::with_wrench(
        Cand {
            depth: ell.len - pd.depth,
            ..pd
        },
        Wrench {
            force: -ell.grad_x - pd.normal,
            torque: -ell.grad_rot - arm.cross(pd.normal),
        },
    );
    let second = second.smin(capped);
    let pd_cap = pd.depth + 0.25 * TIE_BAND;
    let second = if pd_cap < second.depth {
        Blend::single(Cand {
            depth: pd_cap,
            ..pd
        })
    } else {
        second
    };
    SideSide::Escape(main, second)
}

#[cfg(test)]
mod tests {
    use super::super::uniform::Uniform;
    use super::*;
    use crate::contact::fibre_fibre::segment_closest_params;

    /// A fibre of random size (D 4–12 mm, L 10–70 mm) within `spread` of
    /// the origin.
    fn fibre(u: &mut Uniform, spread: f64) -> FibreGeom {
        let mut f = u.fibre(spread);
        f.radius = 0.002 + 0.004 * u.next();
        f.half_length = 0.005 + 0.03 * u.next();
        f
    }

    /// Reference: the distance from `p` to the segment of `f`'s axis,
    /// by the point's projection on the line clamped to the segment (the
    /// squared distance along the segment is a convex parabola).
    fn to_segment(p: DVec3, f: &FibreGeom) -> f64 {
        let along = (p - f.centre)
            .dot(f.axis)
            .clamp(-f.half_length, f.half_length);
        (p - f.centre - along * f.axis).length()
    }

    /// The exact per-end test of `side_side`, by the reference distance.
    fn every_end_clear(a: &FibreGeom, b: &FibreGeom) -> bool {
        let reach = a.radius + b.radius;
        [(a, b), (b, a)].iter().all(|(f, o)| {
            [1.0, -1.0]
                .iter()
                .all(|&sign| to_segment(f.centre + sign * f.half_length * f.axis, o) >= reach)
        })
    }

    /// `ends_clear_of_lines` where `side_side` asks it (closest points
    /// interior, the crossing at least its band deep).
    fn said_clear(a: &FibreGeom, b: &FibreGeom) -> Option<bool> {
        let (s, t) = segment_closest_params(a, b);
        if s.abs() >= a.half_length || t.abs() >= b.half_length {
            return None;
        }
        let cp = interior_contact(a, b, s, t);
        (cp.depth >= 0.25 * TIE_BAND + CROSSING_BAND)
            .then(|| ends_clear_of_lines(a, b, s, t, cp.depth))
    }

    /// `ends_clear_of_lines` is sufficient: wherever it says clear, every
    /// end centre of both fibres is at least the capsule reach from the
    /// other's axis segment (the per-end test it stands in for). Random
    /// crossings of random sizes, placed so that ends often come near the
    /// other fibre; it must also say clear for most of the clear ones (not
    /// vacuous).
    #[test]
    fn ends_clear_of_lines_implies_every_end_clear() {
        let mut u = Uniform(0x9e37_79b9_7f4a_7c15);
        let (mut crossings, mut said, mut clear) = (0, 0, 0);
        for _ in 0..200_000 {
            let (a, b) = (fibre(&mut u, 0.02), fibre(&mut u, 0.02));
            let Some(says) = said_clear(&a, &b) else {
                continue;
            };
            crossings += 1;
            let truly = every_end_clear(&a, &b);
            clear += usize::from(truly);
            if says {
                said += 1;
                assert!(truly, "{a:?} {b:?}: said clear, an end is within the reach");
            }
        }
        assert!(crossings > 20_000, "{crossings} crossings");
        assert!(
            clear < crossings * 9 / 10,
            "{clear} of {crossings}: few ends near"
        );
        assert!(said > clear * 9 / 10, "said clear {said} of {clear} clear");
    }

    /// At the threshold: A's nearer end placed at `reach·(1 + k·1e-12)`
    /// from B's line (its projection inside B, B's ends far), k = −50…50,
    /// for `h/reach` 1.5, 50 and 2500 (the tilt making that end's distance
    /// half from the tilt, half from the offset `d`): never said clear,
    /// since within the margin. And the parallel branch (|a×b| = 9e-8,
    /// 20 m fibres of 1 µm radius, a crossing 1 µm deep, an end 1.4 nm
    /// within the reach): not said clear.
    #[test]
    fn ends_clear_of_lines_holds_at_the_threshold_and_when_parallel() {
        let mut tried = 0;
        let cases: [(f64, f64); 3] = [(0.005, 1.5), (0.002, 50.0), (1e-4, 2500.0)];
        for (r, ratio) in cases {
            let reach = 2.0 * r;
            let h = ratio * reach;
            let s = 0.1 * h;
            let sin = 0.5 * reach / (h - s);
            let a_axis = DVec3::new((1.0 - sin * sin).sqrt(), sin, 0.0);
            let b = FibreGeom {
                centre: DVec3::new(0.3, -0.2, 0.1),
                axis: DVec3::X,
                radius: r,
                half_length: 4.0 * h,
            };
            for k in -50..=50 {
                let target = reach * (1.0 + f64::from(k) * 1e-12);
                let d = (target * target - 0.25 * reach * reach).sqrt();
                let a = FibreGeom {
                    centre: b.centre + DVec3::new(0.0, 0.0, d) - s * a_axis,
                    axis: a_axis,
                    radius: r,
                    half_length: h,
                };
                let says = said_clear(&a, &b).expect("a crossing");
                tried += 1;
                assert!(
                    !says,
                    "k = {k}, h/reach = {ratio}: said clear within the margin"
                );
                if k < 0 {
                    assert!(
                        !every_end_clear(&a, &b),
                        "k = {k}: the pose is not at the threshold"
                    );
                }
            }
        }
        assert_eq!(tried, 303);
        let parallel = |y: f64, tilt: f64| FibreGeom {
            centre: DVec3::new(0.0, y, 0.0),
            axis: DVec3::new(tilt.cos(), tilt.sin(), 0.0),
            radius: 1e-6,
            half_length: 20.0,
        };
        let (a, b) = (parallel(1e-6, 9e-8), parallel(0.0, 0.0));
        assert_eq!(said_clear(&a, &b), Some(false));
        assert!(!every_end_clear(&a, &b));
    }
}
