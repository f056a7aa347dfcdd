//! Side–side fibre–fibre contact (closest points of the axis segments
//! interior, or near-parallel axes overlapping axially): the analytic
//! closest-point and end-disc-on-side depths, two points for a parallel
//! pair, and the axial escape of near-parallel pairs whose ends slide past
//! each other. Model and limits: docs/contacts.md, "Side–side".

use super::blend::{Blend, Wrench, TIE_BAND};
use super::penetration::{axial_escape, penetration};
use super::segment::axial_overlap;
use super::support::sig;
use super::{Cand, PARALLEL_SIN};
use crate::contact::FibreGeom;
use glam::DVec3;

/// Two candidate contacts whose normals are closer than this (cos 0.1 rad)
/// are one contact found twice.
const SAME_CONTACT_COS: f64 = 0.995;

/// End disc of one fibre (centre `e`, axis `ue`, radius `re`) against the
/// side of `other`: depth of the rim point deepest in `other`, i.e.
/// `max_φ (r_o − dist(rim(φ), axis_o))`. Start from the rim point facing
/// `other`'s axis (exact for a parallel pair) and polish φ with Newton steps
/// on `dist²`, so the result is the max over body-fixed rim points and its
/// gradient is the force at that point (envelope theorem). Returns the
/// normal pointing from `other` towards the end's fibre.
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
    let m = n - n.dot(ue) * ue;
    let ml = m.length();
    let p = if ml > 1e-12 {
        // Rim frame: e1 faces `other`, e2 = ue × e1; minimise
        // f(φ) = |A + re (cos φ B1 + sin φ B2)|², B = component ⊥ ou.
        let e1 = -m / ml;
        let e2 = ue.cross(e1);
        let perp = |x: DVec3| x - ou.dot(x) * ou;
        let (a0, b1, b2) = (perp(e - oc), perp(e1), perp(e2));
        let mut phi = 0.0f64;
        for _ in 0..3 {
            let (sn, cs) = phi.sin_cos();
            let r = a0 + re * (cs * b1 + sn * b2);
            let dr = re * (cs * b2 - sn * b1);
            let d2r = -re * (cs * b1 + sn * b2);
            let g = r.dot(dr);
            let h = dr.dot(dr) + r.dot(d2r);
            if h <= 0.0 {
                break;
            }
            let step = g / h;
            phi -= step;
            if step.abs() < 1e-14 {
                break;
            }
        }
        let (sn, cs) = phi.sin_cos();
        e + re * (cs * e1 + sn * e2)
    } else {
        e
    };
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
        (false, false) => {
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
        (true, false) => a_end(a, b, s.signum()),
        (false, true) => b_end(a, b, t.signum()),
        (true, true) => deeper(a_end(a, b, s.signum()), b_end(a, b, t.signum())),
    }
}

/// Side–side model, potential `U(δ_main) + U(min(δ_lo, δ_hi))`.
///
/// `δ_lo`/`δ_hi` are the depths at the two ends of the axial overlap (the
/// deeper of "A's end vs B's side" and "B's end vs A's side" on that side);
/// `δ_main = max(δ_cp, δ_lo, δ_hi)` with `δ_cp` the closest-point depth.
/// * Crossed pair: the ends are far apart, `δ_lo, δ_hi < 0`: one Hertz point
///   at the crossing, weight 1.
/// * Parallel pair: the segment minimum sits at an end of the overlap, so
///   `δ_main = max(δ_lo, δ_hi)` and the potential is `U(δ_lo) + U(δ_hi)`:
///   two weight-1 points at the ends of the overlap, smooth under rocking
///   (the kinks of max and min cancel), no chatter.
///
/// The potential is continuous everywhere (max/min of continuous depths);
/// forces jump only on the measure-zero set where, with an interior closest
/// point, `δ_lo = δ_hi` (scissored and rocked at once) or where the
/// end defining an overlap end switches from A to B.
///
/// Axial escape (near-parallel pairs only): when the axial overlap `ℓ` of
/// the segments is below `2δ_main` (ends sliding past each other), the
/// main depth becomes the smooth minimum ([`TIE_BAND`]) of the sideways
/// depth and the over-the-end escape ([`axial_escape`]), and the second is
/// capped at `smin(δ_small, ℓ − δ_pd)` and at `δ_pd + ε/4` (`δ_pd` =
/// [`penetration`], min over directions): the pair fades continuously to
/// zero at `ℓ = δ_pd`, and nothing is left when it is separated
/// (`δ_pd ≤ 0`). `ℓ − δ_pd` carries its exact gradient (`∇ℓ` in closed
/// form) as a [`Wrench`]. Limit: for exactly parallel axes `ℓ − δ_pd` has a
/// rocking kink (measure zero). Why each piece: docs/contacts.md,
/// "Side–side".
///
/// Returns `(main, second)`; the caller weights the second contact (and,
/// outside the interior case, the main one) by the parallel blend weight.
pub(super) fn side_side(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64) -> (Blend, Blend) {
    let cp = closest_point_contact(a, b, s, t);
    let sb = sig(a.axis, b.axis);
    let lo = deeper(a_end(a, b, -1.0), b_end(a, b, -sb));
    let hi = deeper(a_end(a, b, 1.0), b_end(a, b, sb));
    let (big, small) = if hi.depth > lo.depth {
        (hi, lo)
    } else {
        (lo, hi)
    };
    let main = if big.depth >= cp.depth { big } else { cp };
    let sin = a.axis.cross(b.axis).length();
    let ell = axial_overlap(a, b);
    // The switch lies TIE_BAND beyond ℓ = 2δ_main so that no smooth
    // minimum below is active there (ℓ − δ_pd ≥ δ_main + ε ≥ δ_small + ε,
    // and the axial escape is ~ℓ).
    if !(sin < PARALLEL_SIN
        && main.depth > 0.0
        && ell.len < 2.0 * main.depth + TIE_BAND + (a.radius + b.radius) * sin)
    {
        return (Blend::single(main), Blend::single(small));
    }
    let pd = penetration(a, b, [main.normal, cp.normal]);
    // Main depth: smin(δ_side, δ_axial), the sideways and the over-the-end
    // escapes (a plain min switches the force direction in one step). When
    // the search from the face normal slid down to the sideways minimum
    // itself, the two are one contact: a plain min has no kink.
    let ax = axial_escape(a, b);
    let main = if ax.normal.dot(main.normal) > SAME_CONTACT_COS {
        Blend::single(if ax.depth < main.depth { ax } else { main })
    } else {
        Blend::single(main).smin(Blend::single(ax))
    };
    // Second depth: min(smin(δ_small, ℓ − δ_pd), δ_pd + ε/4). The cap
    // ℓ − δ_pd fades the pair out as the ends slide past each other, with
    // its exact gradient: ∇ℓ in closed form, −∇_A δ_pd = the force F n at
    // pd's point. The cap by δ_pd removes the second contact with the first
    // when the pair separates; a plain min, offset by ε/4, since a true
    // local depth never exceeds the penetration depth (δ_small ≤ δ_pd), so
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
    let second = Blend::single(small).smin(capped);
    let pd_cap = pd.depth + 0.25 * TIE_BAND;
    let second = if pd_cap < second.depth {
        Blend::single(Cand {
            depth: pd_cap,
            ..pd
        })
    } else {
        second
    };
    (main, second)
}
