//! Fibre–fibre contact.
//!
//! Regimes, tested in this order (the capsule bound `r_a + r_b − d_seg ≤ 0`
//! rejects first, since a cylinder lies inside the capsule of its axis):
//! 1. **Near-coaxial end to end** (`|a×b| <` [`COAXIAL_SIN`], axis offset `< r_b`,
//!    axes overlap axially by less than `min(r)`): A's facing end against B's
//!    end-face plane with the fibre–wall face model (parry is wrong here).
//! 2. **Side–side** (closest points of the axis segments interior to both, or
//!    `|a×b| <` [`PARALLEL_SIN`] with overlapping axial projections): analytic,
//!    see [`side_side`].
//! 3. **End involved** (T-junction, rim on rim): `parry3d_f64::query::contact`
//!    on two `Cylinder`s, checked (finite unit normal, `0 < depth ≤` capsule
//!    bound); a rejected answer falls back to the analytic end–segment
//!    contact and is counted in [`PARRY_REJECTS`].
//!
//! Limits: the potential is continuous within regimes 1 and 2 but only
//! approximately continuous across regime boundaries (parry's depth is not
//! an analytic function of the pose).

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
/// Below this |sin| an end-to-end pair counts as coaxial (≈ 1.1°).
pub const COAXIAL_SIN: f64 = 0.02;
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

const NONE: Cand = Cand {
    depth: f64::NEG_INFINITY,
    point: DVec3::ZERO,
    normal: DVec3::ZERO,
};

/// Any unit vector perpendicular to `u`.
#[inline]
fn any_perp(u: DVec3) -> DVec3 {
    u.any_orthonormal_vector()
}

/// End disc of one fibre (centre `e`, axis `ue`, radius `re`) against the
/// side of `other`. Takes the rim point facing `other`'s axis (exact for a
/// parallel pair, first-order otherwise) and measures its depth into the
/// other cylinder's lateral surface. Returns the normal pointing from
/// `other` towards the end's fibre.
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
    let m = n - n.dot(ue) * ue;
    let ml = m.length();
    let p = if ml > 1e-12 { e - (re / ml) * m } else { e };
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
    if c.depth > 0.0 {
        out.push(ContactPoint {
            point: c.point,
            normal: c.normal,
            overlap: c.depth,
            weight: 1.0,
        });
    }
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
fn side_side(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64, out: &mut Vec<ContactPoint>) {
    let cp = closest_point_contact(a, b, s, t);
    let sb = if a.axis.dot(b.axis) >= 0.0 { 1.0 } else { -1.0 };
    let lo = deeper(a_end(a, b, -1.0), b_end(a, b, -sb));
    let hi = deeper(a_end(a, b, 1.0), b_end(a, b, sb));
    let (big, small) = if hi.depth > lo.depth {
        (hi, lo)
    } else {
        (lo, hi)
    };
    let main = if big.depth >= cp.depth { big } else { cp };
    push(out, main);
    push(out, small);
}

/// Cylinder pose for parry: its cylinders are along local +Y.
#[inline]
fn parry_pose(f: &FibreGeom) -> Pose {
    Pose::from_parts(f.centre, DQuat::from_rotation_arc(DVec3::Y, f.axis))
}

/// parry's cylinder–cylinder contact, checked. `bound` = capsule depth.
fn parry_contact(a: &FibreGeom, b: &FibreGeom, bound: f64) -> Option<Option<Cand>> {
    PARRY_CALLS.fetch_add(1, Ordering::Relaxed);
    let ca = Cylinder::new(a.half_length, a.radius);
    let cb = Cylinder::new(b.half_length, b.radius);
    let res = query::contact(&parry_pose(a), &ca, &parry_pose(b), &cb, 0.0).ok()?;
    let Some(c) = res else {
        return Some(None);
    };
    let depth = -c.dist;
    let n = -c.normal1;
    let tol = 1e-9 * (a.radius + b.radius);
    let ok = depth.is_finite()
        && n.is_finite()
        && (n.length() - 1.0).abs() < 1e-6
        && depth <= bound + tol
        && c.point1.is_finite()
        && c.point2.is_finite();
    if !ok {
        return None;
    }
    if depth <= 0.0 {
        return Some(None);
    }
    Some(Some(Cand {
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
        let axial = w.dot(b.axis);
        let rho = (w - axial * b.axis).length();
        let axial_overlap = a.half_length + b.half_length - axial.abs();
        if rho < b.radius && axial_overlap < a.radius.min(b.radius) {
            let sgn_b = axial.signum();
            let n = sgn_b * b.axis;
            let offset = n.dot(b.centre) + b.half_length;
            let sgn_a = -a.axis.dot(w).signum();
            let c = a.centre + sgn_a * a.half_length * a.axis;
            let (depth, p) = end_face_vs_plane(c, a.axis, a.radius, n, offset);
            push(
                out,
                Cand {
                    depth,
                    point: p + 0.5 * depth * n,
                    normal: n,
                },
            );
            return;
        }
    }

    // 2. Side–side.
    let interior = s.abs() < a.half_length && t.abs() < b.half_length;
    let near_parallel = sin < PARALLEL_SIN && {
        let bb = a.axis.dot(b.axis).abs();
        let mid = -a.axis.dot(w);
        let lo = (mid - b.half_length * bb).max(-a.half_length);
        let hi = (mid + b.half_length * bb).min(a.half_length);
        hi > lo
    };
    if interior || near_parallel {
        side_side(a, b, s, t, out);
        return;
    }

    // 3. End involved: parry, checked.
    match parry_contact(a, b, bound) {
        Some(Some(c)) => push(out, c),
        Some(None) => {}
        None => {
            PARRY_REJECTS.fetch_add(1, Ordering::Relaxed);
            push(out, closest_point_contact(a, b, s, t));
        }
    }
}
