//! Fibre–fibre contact.
//!
//! Regimes, tested in this order (the capsule bound `r_a + r_b − d_seg ≤ 0`
//! rejects first, since a cylinder lies inside the capsule of its axis):
//! 1. **Near-coaxial end to end** (`|a×b| <` [`COAXIAL_SIN`], axes overlap
//!    axially by less than `min(r)`, A's application point over B's face):
//!    A's facing end against B's end-face plane with the fibre–wall face
//!    model (smooth tilt torque; parry is wrong for exactly coaxial pairs).
//! 2. **Side–side** (closest points of the axis segments interior to both, or
//!    `|a×b| <` [`PARALLEL_SIN`] with overlapping axial projections): analytic,
//!    see [`side_side`]. Its second contact, and (closest points not
//!    interior) its main contact, are blended with regime 3 over
//!    `|a×b| ∈ [`[`PARALLEL_BLEND_SIN`]`, `[`PARALLEL_SIN`]`]` by an
//!    orientation-dependent weight whose gradient is a pure couple
//!    ([`ContactPoint::weight_grad`]), so the potential is continuous at
//!    `PARALLEL_SIN`.
//! 3. **End involved** (T-junction, rim on rim): `parry3d_f64::query::contact`
//!    on two `Cylinder`s gives the contact normal (its "no contact" verdict
//!    is trusted); the depth is then recomputed exactly as
//!    `min_n h_B(n) + h_A(−n)` (closed-form support functions) by a local
//!    search seeded with parry's normal, see [`penetration`]. parry's own
//!    depth is only checked ([`PARRY_REJECTS`] counts disagreements above
//!    [`PARRY_REL_TOL`]): it is off by up to ~1e-8 m (EPA tolerance) and is
//!    wrong for exactly coaxial pairs.
//!
//! Limits: the potential is continuous within each regime; across regime
//! boundaries it is continuous only approximately (the models agree to
//! first order there, e.g. crossing point sliding off an end). A face lying
//! exactly flat on a side (T-junction) is a cone point of the depth in the
//! tilt angle (as an unsmoothed end face on a wall would be): the tilt
//! torque is bang-bang there; no face blend is applied in regime 3 (a
//! blended support is not convex and loses shallow end contacts). This
//! needs the face normal exactly ⊥ the other axis, so it is non-generic.

use super::fibre_wall::end_face_vs_plane;
use super::{ContactPoint, FibreGeom};
use glam::{DQuat, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::Cylinder;
use std::sync::atomic::{AtomicU64, Ordering};

/// Below this |sin| of the inter-axis angle a pair counts as parallel for the
/// line-contact treatment (≈ 2°).
pub const PARALLEL_SIN: f64 = 0.035;
/// Lower edge of the parallel blend band: the side–side-only terms (the
/// second contact, and the side–side main contact where regime 3 takes over)
/// have weight `w(|a×b|)`, 1 up to this |sin|, 0 from [`PARALLEL_SIN`] on,
/// C¹ (smoothstep) in between; the exact-depth contact of regime 3 gets
/// `1 − w` there. The weight's gradient is a pure couple
/// ([`ContactPoint::weight_grad`]), so forces stay the exact gradient and
/// the potential is continuous across `PARALLEL_SIN` (≈ 1.15°–2°).
pub const PARALLEL_BLEND_SIN: f64 = 0.02;
/// Below this |sin| an end-to-end pair counts as coaxial (≈ 1.1°).
pub const COAXIAL_SIN: f64 = 0.02;
/// Face blend width of the coaxial face model (half of [`COAXIAL_SIN`], so
/// at the regime boundary the model is the exact rim-on-face-plane depth).
pub const COAXIAL_BLEND_SIN: f64 = 0.01;
/// Relative tolerance on parry's depth against the projection overlap along
/// its own normal (diagnostic only: the depth used is always recomputed).
/// parry's EPA depth is off by up to ~5e-9 m (≈10 % of a 6e-8 m depth),
/// its known failures (exactly coaxial pairs) by O(1).
pub const PARRY_REL_TOL: f64 = 1e-2;
/// Number of parry answers rejected by the sanity checks (diagnostics).
pub static PARRY_REJECTS: AtomicU64 = AtomicU64::new(0);
/// Number of parry calls (diagnostics).
pub static PARRY_CALLS: AtomicU64 = AtomicU64::new(0);

/// Closest-point parameters `(s, t)` of segments `ca + s ua` (|s| ≤ ha) and
/// `cb + t ub` (|t| ≤ hb) (Ericson, RTCD §5.1.9, centred form). For parallel
/// segments `s` is the middle of the overlap of the projections, so the
/// answer is stable instead of jumping between ends.
#[inline]
pub fn segment_closest_params(a: &FibreGeom, b: &FibreGeom) -> (f64, f64) {
    let (ha, hb) = (a.half_length, b.half_length);
    let w = a.centre - b.centre;
    let bb = a.axis.dot(b.axis);
    let d = a.axis.dot(w);
    let e = b.axis.dot(w);
    let denom = 1.0 - bb * bb;
    let mut s = if denom > 1e-14 {
        ((bb * e - d) / denom).clamp(-ha, ha)
    } else {
        let lo = (-d - hb * bb.abs()).max(-ha);
        let hi = (-d + hb * bb.abs()).min(ha);
        (0.5 * (lo + hi)).clamp(-ha, ha)
    };
    let mut t = bb * s + e;
    if t < -hb || t > hb {
        t = t.clamp(-hb, hb);
        s = (bb * t - d).clamp(-ha, ha);
    }
    (s, t)
}

/// A candidate contact with A's force normal.
#[derive(Clone, Copy)]
struct Cand {
    depth: f64,
    point: DVec3,
    normal: DVec3,
}

/// Any unit vector perpendicular to `u`.
#[inline]
fn any_perp(u: DVec3) -> DVec3 {
    u.any_orthonormal_vector()
}

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
        any_perp(ou)
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

#[inline]
fn deeper(x: Cand, y: Cand) -> Cand {
    if y.depth > x.depth {
        y
    } else {
        x
    }
}

#[inline]
fn push(out: &mut Vec<ContactPoint>, c: Cand) {
    push_weighted(out, c, 1.0, DVec3::ZERO);
}

#[inline]
fn push_weighted(out: &mut Vec<ContactPoint>, c: Cand, weight: f64, weight_grad: DVec3) {
    if c.depth > 0.0 && weight > 0.0 {
        out.push(ContactPoint {
            point: c.point,
            normal: c.normal,
            overlap: c.depth,
            weight,
            weight_grad,
        });
    }
}

/// Parallel blend weight `w(sin)` (see [`PARALLEL_BLEND_SIN`]) and its
/// gradient with respect to a rotation of A: `dw/dsin · ∂sin/∂φ_A` with
/// `∂|a×b|/∂φ_A = −(a·b) (a×b)/|a×b|`.
#[inline]
fn parallel_weight(a: &FibreGeom, b: &FibreGeom, sin: f64) -> (f64, DVec3) {
    if sin <= PARALLEL_BLEND_SIN {
        return (1.0, DVec3::ZERO);
    }
    if sin >= PARALLEL_SIN {
        return (0.0, DVec3::ZERO);
    }
    let width = PARALLEL_SIN - PARALLEL_BLEND_SIN;
    let x = (sin - PARALLEL_BLEND_SIN) / width;
    let w = 1.0 - x * x * (3.0 - 2.0 * x);
    let dw = -6.0 * x * (1.0 - x) / width;
    let grad = (-dw * a.axis.dot(b.axis) / sin) * a.axis.cross(b.axis);
    (w, grad)
}

/// Closest-point contact of the axis segments (the deepest point of a
/// crossing), analytic; clamped parameters are handled by the end model.
#[inline]
fn closest_point_contact(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64) -> Cand {
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
                    any_perp(a.axis)
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
/// exact penetration depth `δ_pd` ([`penetration`], min over directions) is
/// computed; the main contact becomes it if shallower, and the second one
/// is capped at `ℓ − δ_pd`, so the pair fades continuously to zero at
/// `ℓ = δ_pd` instead of dropping two full contacts. Limit: inside that
/// window (`ℓ < 2δ`, a few µm of sliding) the capped second contact's force
/// is not the exact gradient of its cap.
///
/// Returns `(main, second)`; the caller weights the second contact (and,
/// outside the interior case, the main one) by the parallel blend weight.
fn side_side(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64, axial_len: f64) -> (Cand, Cand) {
    let cp = closest_point_contact(a, b, s, t);
    let sb = if a.axis.dot(b.axis) >= 0.0 { 1.0 } else { -1.0 };
    let lo = deeper(a_end(a, b, -1.0), b_end(a, b, -sb));
    let hi = deeper(a_end(a, b, 1.0), b_end(a, b, sb));
    let (big, mut small) = if hi.depth > lo.depth {
        (hi, lo)
    } else {
        (lo, hi)
    };
    let mut main = if big.depth >= cp.depth { big } else { cp };
    let sin = a.axis.cross(b.axis).length();
    if sin < PARALLEL_SIN
        && main.depth > 0.0
        && axial_len < 2.0 * main.depth + (a.radius + b.radius) * sin
    {
        let pd = penetration(a, b, [main.normal, cp.normal]);
        if pd.depth < main.depth - 1e-12 * (a.radius + b.radius) {
            main = pd;
        }
        // At the switch ℓ = 2δ_main this cap is inactive (ℓ − δ_pd ≥ δ_small).
        small.depth = small.depth.min(axial_len - pd.depth);
    }
    (main, small)
}

/// Near-coaxial end-to-end contact: A's facing end face (with the
/// fibre–wall face blend, width [`COAXIAL_BLEND_SIN`]) against the plane of
/// B's facing end face; `None` when the pair is not end to end (axial
/// overlap ≥ min radius) or A's application point is not over B's face
/// (then the contact is rim on rim and goes to parry).
fn coaxial(a: &FibreGeom, b: &FibreGeom) -> Option<Cand> {
    let w = a.centre - b.centre;
    let axial = w.dot(b.axis);
    let axial_overlap = a.half_length + b.half_length - axial.abs();
    if axial_overlap >= a.radius.min(b.radius) {
        return None;
    }
    let n = axial.signum() * b.axis;
    let offset = n.dot(b.centre) + b.half_length;
    let c = a.centre - a.axis.dot(w).signum() * a.half_length * a.axis;
    let (depth, p) = end_face_vs_plane(c, a.axis, a.radius, n, offset, COAXIAL_BLEND_SIN);
    let lateral = p - b.centre;
    if (lateral - lateral.dot(b.axis) * b.axis).length() > b.radius {
        return None;
    }
    Some(Cand {
        depth,
        point: p + 0.5 * depth * n,
        normal: n,
    })
}

/// Support point of a cylinder in direction `n` and its support value
/// `h(n) = n·c + h|n·a| + r|n⊥|` (exact; the point is its gradient, the
/// end-face centre when `n` is along the axis).
///
/// The face cone point is deliberately *not* blended here: a blended
/// support (`g(s) < s`) is not a convex body's, and min over `n` then
/// misses shallow end-to-end contacts with a lateral offset.
#[inline]
fn support(f: &FibreGeom, n: DVec3) -> (DVec3, f64) {
    let na = n.dot(f.axis);
    let perp = n - na * f.axis;
    let pl = perp.length();
    let mut p = f.centre + na.signum() * f.half_length * f.axis;
    if pl > 1e-12 {
        p += (f.radius / pl) * perp;
    }
    (
        p,
        n.dot(f.centre) + f.half_length * na.abs() + f.radius * pl,
    )
}

/// Overlap of the projections of A and B on the unit direction `n`
/// (pointing from B towards A): `h_B(n) + h_A(−n)`. The penetration depth
/// is the minimum of this over all directions (separating-axis theorem), so
/// a correct MTD `(depth, n)` satisfies `depth = projection_overlap(n)` and
/// `depth ≤ projection_overlap(m)` for every other `m`.
#[inline]
pub fn projection_overlap(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> f64 {
    support(b, n).1 + support(a, -n).1
}

/// Cylinder pose for parry: its cylinders are along local +Y.
#[inline]
fn parry_pose(f: &FibreGeom) -> Pose {
    Pose::from_parts(f.centre, DQuat::from_rotation_arc(DVec3::Y, f.axis))
}

/// parry's cylinder–cylinder contact, checked:
/// finite unit normal; `depth ≤` capsule `bound`; `depth` within
/// [`PARRY_REL_TOL`] of the projection overlap along its own normal (an
/// exact upper bound of the true depth); not deeper than the
/// separating-axis estimate. `Err(normal)` = rejected (with parry's normal
/// if finite, as one more axis for the fallback). parry's "no contact" is
/// trusted (its known failures are wrong contacts, not missed ones).
fn parry_contact(a: &FibreGeom, b: &FibreGeom, bound: f64) -> Result<Option<Cand>, DVec3> {
    PARRY_CALLS.fetch_add(1, Ordering::Relaxed);
    let ca = Cylinder::new(a.half_length, a.radius);
    let cb = Cylinder::new(b.half_length, b.radius);
    let Ok(res) = query::contact(&parry_pose(a), &ca, &parry_pose(b), &cb, 0.0) else {
        return Err(DVec3::ZERO);
    };
    let Some(c) = res else {
        return Ok(None);
    };
    let depth = -c.dist;
    let n = -c.normal1;
    if !(n.is_finite() && (n.length() - 1.0).abs() < 1e-9) {
        return Err(DVec3::ZERO);
    }
    let tol = PARRY_REL_TOL * depth.abs() + 1e-8 * (a.radius + b.radius);
    let proj = projection_overlap(a, b, n);
    let ok = depth.is_finite()
        && depth <= bound + tol
        && (proj - depth).abs() <= tol
        && c.point1.is_finite()
        && c.point2.is_finite();
    if !ok {
        return Err(n);
    }
    if depth <= 0.0 {
        return Ok(None);
    }
    Ok(Some(Cand {
        depth,
        point: 0.5 * (c.point1 + c.point2),
        normal: n,
    }))
}

/// Fibre–fibre contacts (0–2 points); normal = direction of the force on A.
pub fn contact_fibre_fibre(a: &FibreGeom, b: &FibreGeom, out: &mut Vec<ContactPoint>) {
    let (s, t) = segment_closest_params(a, b);
    let d_seg = (a.centre + s * a.axis - b.centre - t * b.axis).length();
    let bound = a.radius + b.radius - d_seg;
    if bound <= 0.0 {
        return;
    }
    let sin = a.axis.cross(b.axis).length();
    let w = a.centre - b.centre;

    // 1. Near-coaxial end to end.
    if sin < COAXIAL_SIN {
        if let Some(c) = coaxial(a, b) {
            push(out, c);
            return;
        }
    }

    // 2. Side–side.
    let interior = s.abs() < a.half_length && t.abs() < b.half_length;
    // Axial overlap of the segments, measured along A.
    let axial_len = {
        let bb = a.axis.dot(b.axis).abs();
        let mid = -a.axis.dot(w);
        let lo = (mid - b.half_length * bb).max(-a.half_length);
        let hi = (mid + b.half_length * bb).min(a.half_length);
        hi - lo
    };
    // Parallel blend: potential U(δ_main) + w·U(δ_2) when interior, else
    // w·(U(δ_main) + U(δ_2)) + (1 − w)·U(δ_pd) (regime 3's exact depth), so
    // the second contact and the model switch fade in/out continuously.
    let (w_par, w_grad) = parallel_weight(a, b, sin);
    let mut w_side = 0.0;
    if interior || (sin < PARALLEL_SIN && axial_len > 0.0) {
        let (main, second) = side_side(a, b, s, t, axial_len);
        push_weighted(out, second, w_par, w_grad);
        if interior {
            push(out, main);
            return;
        }
        push_weighted(out, main, w_par, w_grad);
        if w_par >= 1.0 {
            return;
        }
        w_side = w_par;
    }

    // 3. End involved: parry's normal (checked) seeds an exact minimisation
    //    of the projection overlap over the cylinders' feature manifolds.
    let cp = closest_point_contact(a, b, s, t);
    let (parry_n, parry_ok) = match parry_contact(a, b, bound) {
        Ok(None) => return,
        Ok(Some(c)) => (c.normal, true),
        Err(n) => (n, false),
    };
    if !parry_ok {
        PARRY_REJECTS.fetch_add(1, Ordering::Relaxed);
    }
    let (w_pd, g_pd) = if w_side > 0.0 {
        (1.0 - w_side, -w_grad)
    } else {
        (1.0, DVec3::ZERO)
    };
    push_weighted(out, penetration(a, b, [cp.normal, parry_n]), w_pd, g_pd);
}

/// Projection overlap along `n` (see [`projection_overlap`]).
#[inline]
fn pov(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> f64 {
    projection_overlap(a, b, n)
}

/// Penetration depth of two cylinders = `min_n projection_overlap(n)`
/// (convexity). The overlap function is smooth except on each cylinder's
/// "side" great circle (`n ⊥ axis`, support jumps between end rims) and at
/// its face normals (cone points). The minimum is therefore searched on each
/// feature manifold: the face normals and common normal (points), the two
/// side circles (1-D Newton), and the generic sphere (2-D Newton, rim on
/// rim), all seeded by parry's normal / the closest-point normal. Every
/// value is an exact upper bound of the depth, the least one is returned.
/// At a smooth or circle minimum the force at the support point of the
/// body whose support is unique is the exact gradient of the depth
/// (envelope theorem).
fn penetration(a: &FibreGeom, b: &FibreGeom, seeds: [DVec3; 2]) -> Cand {
    let w = a.centre - b.centre;
    let mut best_n = DVec3::ZERO;
    let mut best = f64::INFINITY;
    let consider = |n: DVec3, best_n: &mut DVec3, best: &mut f64| {
        let l = n.length();
        if !(l > 1e-12 && l.is_finite()) {
            return;
        }
        for m in [n / l, -n / l] {
            let v = pov(a, b, m);
            if v < *best {
                *best = v;
                *best_n = m;
            }
        }
    };
    for d in [a.axis, b.axis, a.axis.cross(b.axis), w, seeds[0], seeds[1]] {
        consider(d, &mut best_n, &mut best);
    }
    let start = if pov(a, b, seeds[1]) <= best + 1e-9 * (a.radius + b.radius) {
        seeds[1]
    } else {
        best_n
    };
    // Side circles of B and of A (only when the seed is near one: parry's
    // normal is accurate to far better than this), then the generic sphere.
    for u in [b.axis, a.axis] {
        if start.dot(u).abs() < 0.1 {
            let m = circle_min(a, b, u, start);
            consider(m, &mut best_n, &mut best);
        }
    }
    // Generic (rim on rim).
    let m = sphere_min(a, b, start);
    consider(m, &mut best_n, &mut best);
    let n = best_n;
    let (sb, _) = support(b, n);
    let (sa, _) = support(a, -n);
    // Use the support point of the body whose support is the more clearly
    // unique. A support is degenerate at a face normal (|n⊥axis| = 0: the
    // whole face) and on a side circle (n·axis = 0: a generator line). The
    // Newton searches land *near* such points, not on them, so a fixed
    // tolerance is not enough: a minimiser 4e-12 off a face normal made the
    // face's "unique" rim point arbitrary and the torque wrong (seen in test
    // case 2, end on end at 16°; `tests/contact_geometry.rs` keeps that pose).
    // Both distances are measured as sines of angles: `1 − |n·axis|` (the
    // old face measure) is quadratic in the angle, so a rim point 3.5e-5 rad
    // off the face normal looked as degenerate (6e-10) as a minimiser
    // exactly on the other body's side circle, and the midpoint of A's rim
    // and B's far end was used (test case 2, t = 0.354567 s).
    let clarity = |f: &FibreGeom, d: DVec3| {
        let na = d.dot(f.axis);
        na.abs().min((d - na * f.axis).length())
    };
    let (ca, cb) = (clarity(a, -n), clarity(b, n));
    let point = if ca.max(cb) < 1e-9 {
        0.5 * (sa + sb)
    } else if ca >= cb {
        sa + 0.5 * best * n
    } else {
        sb - 0.5 * best * n
    };
    Cand {
        depth: best,
        point,
        normal: n,
    }
}

/// 1-D Newton (numerical derivatives, backtracking) on the great circle
/// `n ⊥ u`, starting from the projection of `seed`.
fn circle_min(a: &FibreGeom, b: &FibreGeom, u: DVec3, seed: DVec3) -> DVec3 {
    let mut e1 = seed - seed.dot(u) * u;
    if e1.length_squared() < 1e-24 {
        e1 = u.any_orthonormal_vector();
    }
    let e1 = e1.normalize();
    let e2 = u.cross(e1);
    let at = |th: f64| {
        let (sn, cs) = th.sin_cos();
        cs * e1 + sn * e2
    };
    let f = |th: f64| pov(a, b, at(th));
    let mut th = 0.0;
    let mut v = f(th);
    let eps = 1e-5;
    for _ in 0..30 {
        let (fp, fm) = (f(th + eps), f(th - eps));
        let d1 = (fp - fm) / (2.0 * eps);
        let d2 = (fp - 2.0 * v + fm) / (eps * eps);
        let mut step = if d2 > 0.0 {
            -d1 / d2
        } else {
            -0.05 * d1.signum()
        };
        step = step.clamp(-0.5, 0.5);
        if step.abs() < 1e-11 {
            break;
        }
        let mut moved = false;
        for _ in 0..12 {
            let nv = f(th + step);
            if nv < v {
                th += step;
                v = nv;
                moved = true;
                break;
            }
            step *= 0.5;
        }
        if !moved || step.abs() < 1e-13 {
            break;
        }
    }
    at(th)
}

/// 2-D damped Newton on the sphere (analytic gradient `s_B(n) − s_A(−n)`,
/// Hessian by central differences of it), accepting only decreases.
fn sphere_min(a: &FibreGeom, b: &FibreGeom, seed: DVec3) -> DVec3 {
    let mut n = seed;
    let mut best = pov(a, b, n);
    for _ in 0..30 {
        let e1 = n.any_orthonormal_vector();
        let e2 = n.cross(e1);
        let grad = |m: DVec3| {
            let g = support(b, m).0 - support(a, -m).0;
            (g.dot(e1), g.dot(e2))
        };
        let (g1, g2) = grad(n);
        let eps = 1e-6;
        let (p1, q1) = grad((n + eps * e1).normalize());
        let (m1, r1) = grad((n - eps * e1).normalize());
        let (p2, q2) = grad((n + eps * e2).normalize());
        let (m2, r2) = grad((n - eps * e2).normalize());
        let h11 = (p1 - m1) / (2.0 * eps);
        let h22 = (q2 - r2) / (2.0 * eps);
        let h12 = 0.25 * ((q1 - r1) + (p2 - m2)) / eps;
        let det = h11 * h22 - h12 * h12;
        let (mut d1, mut d2) = if h11 > 0.0 && det > 0.0 {
            (-(h22 * g1 - h12 * g2) / det, -(h11 * g2 - h12 * g1) / det)
        } else {
            let gl = (g1 * g1 + g2 * g2).sqrt().max(1e-300);
            (-0.05 * g1 / gl, -0.05 * g2 / gl)
        };
        if d1.abs() + d2.abs() < 1e-11 {
            break;
        }
        let mut moved = false;
        for _ in 0..12 {
            let m = (n + d1 * e1 + d2 * e2).normalize();
            let v = pov(a, b, m);
            if v < best {
                best = v;
                n = m;
                moved = true;
                break;
            }
            d1 *= 0.5;
            d2 *= 0.5;
        }
        if !moved || d1.abs() + d2.abs() < 1e-13 {
            break;
        }
    }
    n
}
