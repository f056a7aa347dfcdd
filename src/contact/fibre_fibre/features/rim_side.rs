//! Rim–side: a rim of one fibre on the side of the other (a tilted end on a
//! side, the commonest end-involved contact of a bed). Circle against the
//! axis line: the rim point nearest the line, by Newton's method on the
//! rim angle (closed-form derivatives of a degree-2 trigonometric
//! polynomial) from the best of 12 sampled angles, at most
//! [`RIM_NEWTON_STEPS`] steps.

use super::{between_end_planes, direction, face_centre, perp, rim_supports, Stationary};
use crate::contact::FibreGeom;
use glam::DVec3;
use std::cmp::Ordering;

/// Most Newton steps of the rim–line distance after the sampled start
/// (quadratic convergence from within the basin: 2–4 steps on the poses of
/// the tests, one for a parallel pair; a start near a maximum takes clamped
/// descent steps first: at 8, 3 pairs of `bed_10k` failed every step and
/// fell back); a step below [`RIM_STEP_TOL`] ends it.
const RIM_NEWTON_STEPS: usize = 16;
/// Converged when the last angle step is below this (rad): the depth is
/// then exact to ~r·1e-20 and the force direction to 1e-10.
const RIM_STEP_TOL: f64 = 1e-10;
/// Largest angle step (tangent form, rad).
const MAX_STEP: f64 = 0.5;
/// Cosine of the largest angle between the face normal and the rim–side
/// direction at which [`rim_side`] tries the distance's other minimum
/// (≈ 2.6°; bed_10k's certified ones are within 0.93°).
const FLAT_FACE_COS: f64 = 0.999;
/// `(cos, sin)` of the start angles sampled around the rim, 30° apart (the
/// squared distance is a trigonometric polynomial of degree 2: at most two
/// minima, whose basins the samples resolve).
const SAMPLES: [(f64, f64); 12] = {
    const C: f64 = 0.866_025_403_784_438_6; // cos 30° = √3/2
    [
        (1.0, 0.0),
        (C, 0.5),
        (0.5, C),
        (0.0, 1.0),
        (-0.5, C),
        (-C, 0.5),
        (-1.0, 0.0),
        (-C, -0.5),
        (-0.5, -C),
        (0.0, -1.0),
        (0.5, -C),
        (C, -0.5),
    ]
};

/// The point of the rim circle (centre `e`, unit normal `u`, radius `r`)
/// nearest the line `oc + t ou`, and whether Newton's method converged.
/// `None` when the line's offset from `e` has no component in the rim
/// plane (the line pierces the face along its axis: every rim point is as
/// near). The squared distance is `f(φ) = |P(e − oc) + r P(cos φ e1 +
/// sin φ e2)|²` (`P` the projection ⊥ `ou`, `e1` facing the line), a
/// trigonometric polynomial `k0 + k1 c + k2 s + k3 c² + k4 s² + k5 c s` of
/// degree 2 whose up to two local minima can be far apart (a rim seen
/// almost edge-on): Newton's method with the closed-form derivatives
/// starts at the least of the 12 [`SAMPLES`], or, where the first harmonic
/// dominates (one minimum; checked numerically: two minima need a
/// first-to-second amplitude ratio below 3.74), at its minimum. The angle is updated by
/// rotating `(cos φ, sin φ)` and renormalising (`tan` of the step instead
/// of the step: the error stays cubic).
#[inline]
pub(in crate::contact::fibre_fibre) fn rim_point_nearest_line(
    e: DVec3,
    u: DVec3,
    r: f64,
    oc: DVec3,
    ou: DVec3,
) -> Option<(DVec3, bool)> {
    rim_point_stationary(e, u, r, oc, ou, None)
}

/// [`rim_point_nearest_line`]'s iteration, from the sampled start or, with
/// `away`, from the rim point opposite `away` (the other minimum's basin).
/// (Inlined: out of line its arguments and answer went through memory,
/// and inlined `away = None` is folded.)
#[inline(always)]
fn rim_point_stationary(
    e: DVec3,
    u: DVec3,
    r: f64,
    oc: DVec3,
    ou: DVec3,
    away: Option<DVec3>,
) -> Option<(DVec3, bool)> {
    let a0 = perp(e - oc, ou);
    let m = perp(a0, u);
    let ml = m.length();
    if ml.partial_cmp(&(1e-12 * a0.length().max(r))) != Some(Ordering::Greater) {
        return None;
    }
    let e1 = -m / ml;
    let e2 = u.cross(e1);
    let (b1, b2) = (perp(e1, ou), perp(e2, ou));
    let k1 = 2.0 * r * a0.dot(b1);
    let k2 = 2.0 * r * a0.dot(b2);
    let k3 = r * r * b1.dot(b1);
    let k4 = r * r * b2.dot(b2);
    let k5 = 2.0 * r * r * b1.dot(b2);
    // f − k0 (the constant |a0|² plays no part).
    let f = |c: f64, s: f64| c * (k1 + k3 * c + k5 * s) + s * (k2 + k4 * s);
    // With the first harmonic (amplitude |(k1, k2)|) more than 4 times the
    // second (½|(k3 − k4, k5)|), f has one minimum, next to the first
    // harmonic's (a rim seen face-on, as an end disc of a near-parallel
    // pair): start there; else at the least sample.
    let a1 = (k1 * k1 + k2 * k2).sqrt();
    let a2 = 0.5 * ((k3 - k4) * (k3 - k4) + k5 * k5).sqrt();
    let (mut c, mut s) = if let Some(p) = away {
        let d = p - e;
        let (c, s) = (-d.dot(e1), -d.dot(e2));
        let l = (c * c + s * s).sqrt();
        (c / l, s / l)
    } else if a1 > 4.0 * a2 {
        (-k1 / a1, -k2 / a1)
    } else {
        let (mut c, mut s, mut best) = (1.0f64, 0.0f64, f(1.0, 0.0));
        for &(ck, sk) in &SAMPLES[1..] {
            let v = f(ck, sk);
            if v < best {
                (c, s, best) = (ck, sk, v);
            }
        }
        (c, s)
    };
    let mut converged = false;
    for _ in 0..RIM_NEWTON_STEPS {
        let (c2, s2, cs) = (c * c - s * s, 2.0 * s * c, s * c);
        let d1 = -k1 * s + k2 * c + 2.0 * (k4 - k3) * cs + k5 * c2;
        let d2 = -k1 * c - k2 * s + (k4 - k3) * 2.0 * c2 - 2.0 * k5 * s2;
        // Where f is concave, a fixed descent step.
        let step = if d2 > 0.0 {
            (-d1 / d2).clamp(-MAX_STEP, MAX_STEP)
        } else {
            -MAX_STEP * d1.signum()
        };
        let (c1, s1) = (c - s * step, s + c * step);
        let l = (c1 * c1 + s1 * s1).sqrt();
        (c, s) = (c1 / l, s1 / l);
        if step.abs() < RIM_STEP_TOL {
            converged = d2 > 0.0;
            break;
        }
    }
    Some((e + r * (c * e1 + s * e2), converged))
}

/// Rim of `f`'s end `sf` against `o`'s side: the direction ⊥ `o`'s axis
/// from the axis to the rim point nearest it (or, when `f` is not
/// supported there, to the distance's other local minimum if it is). A
/// local minimum when `f`'s support towards `o` along it is that rim point
/// (the line is outside the rim circle's projection) and the point lies
/// between `o`'s end planes. (Inlined into the scan: out of line its
/// answer went through memory.)
#[inline(always)]
pub(in crate::contact::fibre_fibre) fn rim_side(
    f: &FibreGeom,
    sf: f64,
    o: &FibreGeom,
) -> Option<Stationary> {
    let e = face_centre(f, sf);
    let (p, converged) = rim_point_nearest_line(e, f.axis, f.radius, o.centre, o.axis)?;
    let d = perp(p - o.centre, o.axis);
    let n = direction(d)?;
    // A face nearly flat on the side (tilted just past the dome, o's axis
    // under the face): the nearest point's direction can be supported by
    // another rim point while the distance's other local minimum, in the
    // basin opposite, passes the same tests (most of the scans of
    // `bed_10k` that could not be certified). Tried only within [`FLAT_FACE_COS`]
    // of the face normal; elsewhere an unsupported point stays
    // uncertified (the scan then falls back: a cost, not an error).
    if converged && sf * f.axis.dot(-n) > FLAT_FACE_COS && !rim_supports(f, -n, sf, p) {
        let other = rim_point_stationary(e, f.axis, f.radius, o.centre, o.axis, Some(p));
        if let Some((q, true)) = other {
            if let Some(m) = direction(perp(q - o.centre, o.axis)) {
                if rim_supports(f, -m, sf, q) && between_end_planes(o, q) {
                    return Some(Stationary {
                        n: m,
                        point: q,
                        lower: o.radius - m.dot(q - o.centre),
                        local_min: true,
                        converged: true,
                        descended: false,
                    });
                }
            }
        }
    }
    // The rim point on `f`, `o`'s side point `c + t a + r_o n` (n ⊥ a, any
    // t): n·(x_o − x_f) = r_o − n·(p − o.centre).
    Some(Stationary {
        n,
        point: p,
        lower: o.radius - n.dot(p - o.centre),
        local_min: converged && rim_supports(f, -n, sf, p) && between_end_planes(o, p),
        converged,
        descended: false,
    })
}
