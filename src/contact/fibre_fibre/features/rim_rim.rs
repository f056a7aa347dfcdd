//! Rim–rim: a rim of each fibre (an L corner whose edges cross, two ends
//! meeting edge on edge). Circle against circle has no closed form (its
//! stationary points are the roots of a degree-8 polynomial), so this is
//! Newton's method on the two rim angles for a stationary point of the
//! squared distance `½|x(φ) − p(ψ)|²`, with the analytic Hessian, at most
//! [`RIM_RIM_STEPS`] steps, from the closest of: where the rims cross each
//! other's face planes (or, for near-parallel faces, on the line of the face
//! centres), where they cross in projection on one face plane (discs
//! overlapping sideways), and the rim–side points of the two rims (a rim point nearest
//! the other's axis that lies beyond the other's end plane is next to a
//! rim–rim minimum). When it does not converge, a descent from the same
//! start (Newton's step where the Hessian is positive definite, else along
//! its least curvature, halved until the distance decreases) looks for the
//! minimum, and failing that a branch and bound on the rims' distance
//! ([`rims_apart`]) may still show that no value of the pair matters.

use super::{cap_supports, face_centre, perp, rim_supports, Stationary};
use crate::contact::FibreGeom;
use glam::DVec3;
use std::cmp::Ordering;

/// Newton steps of the rim–rim distance (quadratic convergence from the
/// plane-crossing start: 3–5 steps on the poses of the tests).
const RIM_RIM_STEPS: usize = 20;
/// Most steps of the descent that follows a plain iteration that did not
/// converge (rims rolling along each other: 5–6 on `bed_10k`'s).
const RIM_RIM_DESCENT_STEPS: usize = 40;
/// Converged when the last step (sum of both angles) is below this (rad).
const RIM_RIM_TOL: f64 = 1e-10;
/// Largest angle step (rad): keeps a poor start from jumping across the rim.
const MAX_STEP: f64 = 0.5;
/// Below this |sin| between the axes the face planes are taken as parallel
/// for the start (their line of intersection is then far or ill defined).
const PARALLEL_PLANES_SIN: f64 = 0.1;

/// A rim circle `e + r (c w1 + s w2)` with `(c, s)` a unit pair.
#[derive(Clone, Copy)]
struct Rim {
    e: DVec3,
    r: f64,
    w1: DVec3,
    w2: DVec3,
}

impl Rim {
    fn new(f: &FibreGeom, sigma: f64, toward: DVec3) -> Self {
        let mut w1 = perp(toward, f.axis);
        let l = w1.length();
        w1 = if l > 1e-12 {
            w1 / l
        } else {
            f.axis.any_orthonormal_vector()
        };
        Rim {
            e: face_centre(f, sigma),
            r: f.radius,
            w1,
            w2: f.axis.cross(w1),
        }
    }

    #[inline]
    fn at(&self, (c, s): (f64, f64)) -> DVec3 {
        self.e + self.r * (c * self.w1 + s * self.w2)
    }

    #[inline]
    fn tangent(&self, (c, s): (f64, f64)) -> DVec3 {
        self.r * (c * self.w2 - s * self.w1)
    }

    /// The angle of the rim point nearest `x`.
    fn nearest(&self, x: DVec3) -> (f64, f64) {
        let d = x - self.e;
        let (c, s) = (d.dot(self.w1), d.dot(self.w2));
        let l = (c * c + s * s).sqrt();
        if l > 0.0 {
            (c / l, s / l)
        } else {
            (1.0, 0.0)
        }
    }

    /// The two angles where the circle crosses the plane through `q` with
    /// unit normal `m` (or comes nearest it), `w1` being along `m`'s
    /// in-plane part.
    fn plane_crossings(&self, q: DVec3, m: DVec3) -> [(f64, f64); 2] {
        let k = self.w1.dot(m) * self.r;
        let c = if k.abs() > 0.0 {
            (-(self.e - q).dot(m) / k).clamp(-1.0, 1.0)
        } else {
            1.0
        };
        let s = (1.0 - c * c).max(0.0).sqrt();
        [(c, s), (c, -s)]
    }

    /// The two angles where this rim crosses, in projection on its own
    /// plane, the circle of radius `r` about `q`'s projection; `None`
    /// when the circles do not cross.
    fn projected_crossings(&self, q: DVec3, r: f64) -> Option<[(f64, f64); 2]> {
        let (x, y) = ((q - self.e).dot(self.w1), (q - self.e).dot(self.w2));
        let d2 = x * x + y * y;
        let d = d2.sqrt();
        // Along the line of centres at `along` (radius units), off it `off`.
        let along = (d2 + self.r * self.r - r * r) / (2.0 * d * self.r);
        // (NaN, for concentric circles, is no crossing either.)
        if along.abs().partial_cmp(&1.0) != Some(Ordering::Less) {
            return None;
        }
        let off = (1.0 - along * along).sqrt();
        let (ux, uy) = (x / d, y / d);
        Some([
            (along * ux - off * uy, along * uy + off * ux),
            (along * ux + off * uy, along * uy - off * ux),
        ])
    }
}

/// Newton's step `−H⁻¹ g` for the gradient `g` and the Hessian
/// `(h11, h22, h12)` of determinant `det`.
#[inline(always)]
fn newton((g1, g2): (f64, f64), (h11, h22, h12): (f64, f64, f64), det: f64) -> (f64, f64) {
    (-(h22 * g1 - h12 * g2) / det, -(h11 * g2 - h12 * g1) / det)
}

/// Initial intervals of [`rims_apart`] (half-width π/16).
const APART_INTERVALS: usize = 16;
/// Most distance evaluations of [`rims_apart`] before it gives up.
const APART_EVALS: usize = 160;
/// `(cos, sin)` of π/16 · 2^−k, the half-widths of [`rims_apart`]'s
/// intervals at depth k.
const APART_HALF: [(f64, f64); 9] = {
    // (Evaluated: cos and sin are not const.)
    [
        (0.980_785_280_403_230_4, 0.195_090_322_016_128_28),
        (0.995_184_726_672_196_9, 0.098_017_140_329_560_6),
        (0.998_795_456_205_172_4, 0.049_067_674_327_418_015),
        (0.999_698_818_696_204_2, 0.024_541_228_522_912_288),
        (0.999_924_701_839_144_5, 0.012_271_538_285_719_925),
        (0.999_981_175_282_601_1, 0.006_135_884_649_154_475),
        (0.999_995_293_809_576_2, 0.003_067_956_762_965_976_4),
        (0.999_998_823_451_701_9, 0.001_533_980_186_284_766),
        (0.999_999_705_862_882_2, 0.000_766_990_318_742_704_5),
    ]
};

/// Whether every point of the rim `rf` is further than `reach` from the
/// rim `ro` (unit normal `uo`), proved by branch and bound on `rf`'s angle:
/// the distance from a point to a circle is 1-Lipschitz and the rim point
/// moves by at most `r_f |Δψ|`, so an interval of half-width `h` about an
/// angle at distance `d` from `ro` is cleared when `d − r_f h > reach`.
/// False when some point is within `reach`, or the bound needs more than
/// [`APART_EVALS`] evaluations or finer intervals than the table.
fn rims_apart(rf: &Rim, uo: DVec3, ro: &Rim, reach: f64) -> bool {
    let w0 = rf.e - ro.e;
    // Offsets from `ro`'s centre of the rim point (c, s): along uo,
    // z0 + c z1 + s z2; squared length q0 + c q1 + s q2.
    let (z0, z1, z2) = (w0.dot(uo), rf.r * rf.w1.dot(uo), rf.r * rf.w2.dot(uo));
    let (q0, q1, q2) = (
        w0.length_squared() + rf.r * rf.r,
        2.0 * rf.r * w0.dot(rf.w1),
        2.0 * rf.r * w0.dot(rf.w2),
    );
    let dist = |c: f64, s: f64| {
        let z = z0 + c * z1 + s * z2;
        let rho = (q0 + c * q1 + s * q2 - z * z).max(0.0).sqrt();
        (z * z + (rho - ro.r) * (rho - ro.r)).sqrt()
    };
    // Depth-first over (cos, sin, depth) of interval centres.
    let mut stack = [(0.0, 0.0, 0usize); APART_INTERVALS + APART_HALF.len()];
    let mut top = 0;
    let (mut c, mut s) = APART_HALF[0];
    let (c2, s2) = (2.0 * c * c - 1.0, 2.0 * s * c);
    for _ in 0..APART_INTERVALS {
        stack[top] = (c, s, 0);
        top += 1;
        (c, s) = (c * c2 - s * s2, s * c2 + c * s2);
    }
    let mut evals = 0;
    while top > 0 {
        top -= 1;
        let (c, s, k) = stack[top];
        evals += 1;
        let d = dist(c, s);
        // Half-width π/16 · 2^−k, a little widened for the rounding of the
        // rotated centres.
        let h = std::f64::consts::PI / 16.0 * 0.5f64.powi(k as i32) + 1e-12;
        if d - rf.r * h > reach {
            continue;
        }
        if d <= reach || evals >= APART_EVALS || k + 1 >= APART_HALF.len() {
            return false;
        }
        let (hc, hs) = APART_HALF[k + 1];
        stack[top] = (c * hc - s * hs, s * hc + c * hs, k + 1);
        stack[top + 1] = (c * hc + s * hs, s * hc - c * hs, k + 1);
        top += 2;
    }
    true
}

/// Rotate the unit pair `(c, s)` by the angle `t` (tangent form, then
/// renormalised).
#[inline]
fn turn((c, s): (f64, f64), t: f64) -> (f64, f64) {
    let (c1, s1) = (c - s * t, s + c * t);
    let l = (c1 * c1 + s1 * s1).sqrt();
    (c1 / l, s1 / l)
}

/// Rim of `f`'s end `sf` against the rim of `o`'s end `so`: the direction
/// from `o` towards `f` at a stationary point of the rims' distance (along
/// `x − p` when they interpenetrate, the other way when apart; whichever
/// the supports confirm). A local minimum when converged, the squared
/// distance has a positive definite Hessian there (for depths small
/// against the radii this is the depth's own minimum), and both supports
/// along the direction are those rim points. `None` when the rims meet
/// exactly (no direction), the iteration left the rims' neighbourhood, or
/// the rims are further apart than `reach` (no value that matters).
pub(in crate::contact::fibre_fibre) fn rim_rim(
    f: &FibreGeom,
    sf: f64,
    o: &FibreGeom,
    so: f64,
    hints: [Option<DVec3>; 2],
    reach: f64,
) -> Option<Stationary> {
    let (ef, eo) = (face_centre(f, sf), face_centre(o, so));
    // A stationary value is ±|x − p|, at least the rims' distance: skip
    // rims further apart than `reach` (bounding spheres; each rim's
    // distance from the other's face plane).
    let sin = f.axis.cross(o.axis).length();
    let w = eo - ef;
    if w.length() - f.radius - o.radius > reach
        || w.dot(f.axis).abs() - o.radius * sin > reach
        || w.dot(o.axis).abs() - f.radius * sin > reach
    {
        return None;
    }
    let planes_cross = sin >= PARALLEL_PLANES_SIN;
    let (rf, ro) = if planes_cross {
        // w1 of each rim along the other's face normal: the crossings of
        // the other's face plane are then symmetric about w1.
        (Rim::new(f, sf, o.axis), Rim::new(o, so, f.axis))
    } else {
        // Near-parallel faces: w1 facing the other face's centre.
        (Rim::new(f, sf, eo - ef), Rim::new(o, so, ef - eo))
    };
    // Starts: the rims' crossings of each other's face planes (or, for
    // near-parallel faces, the rim points facing each other), and each
    // hint (a rim point of `f`, then of `o`, near the other body: the
    // rim–side points) with the other rim's point nearest it; the closest
    // pair wins.
    let mut starts = [((1.0, 0.0), (1.0, 0.0)); 8];
    let mut k = 1;
    if planes_cross {
        let cf = rf.plane_crossings(eo, o.axis);
        let co = ro.plane_crossings(ef, f.axis);
        k = 0;
        for &x in &cf {
            for &y in &co {
                starts[k] = (x, y);
                k += 1;
            }
        }
    }
    // Where the rims cross in projection on `f`'s face plane (discs
    // overlapping sideways, faces nearly parallel: the facing points are
    // then inside the other disc, far from the minimum).
    if let Some(crossings) = rf.projected_crossings(eo, o.radius) {
        for x in crossings {
            starts[k] = (x, ro.nearest(rf.at(x)));
            k += 1;
        }
    }
    if let Some(h) = hints[0] {
        let pf0 = rf.nearest(h);
        starts[k] = (pf0, ro.nearest(rf.at(pf0)));
        k += 1;
    }
    if let Some(h) = hints[1] {
        let po0 = ro.nearest(h);
        starts[k] = (rf.nearest(ro.at(po0)), po0);
        k += 1;
    }
    let (mut pf, mut po) = starts[0];
    let mut nearest = f64::INFINITY;
    for &(x, y) in &starts[..k] {
        let d = (ro.at(y) - rf.at(x)).length_squared();
        if d < nearest {
            (nearest, pf, po) = (d, x, y);
        }
    }
    // F = ½|x − p|²: ∂F/∂φ = d·x', ∂F/∂ψ = −d·p'; x'' = −(x − e_o). The
    // gradient and the Hessian `(h11, h22, h12)`.
    let derivatives = |po: (f64, f64), pf: (f64, f64)| {
        let (x, p) = (ro.at(po), rf.at(pf));
        let (tx, tp) = (ro.tangent(po), rf.tangent(pf));
        let d = x - p;
        let g = (d.dot(tx), -d.dot(tp));
        let h = (
            tx.dot(tx) - d.dot(x - ro.e),
            tp.dot(tp) + d.dot(p - rf.e),
            -tx.dot(tp),
        );
        (g, h)
    };
    let start = (pf, po);
    let mut converged = false;
    let (mut h11, mut h22, mut h12) = (0.0, 0.0, 0.0);
    for _ in 0..RIM_RIM_STEPS {
        let ((g1, g2), h) = derivatives(po, pf);
        (h11, h22, h12) = h;
        let det = h11 * h22 - h12 * h12;
        if det.abs().partial_cmp(&(1e-30 * (ro.r * rf.r).powi(2))) != Some(Ordering::Greater) {
            break;
        }
        let (dphi, dpsi) = newton((g1, g2), h, det);
        let (dphi, dpsi) = (
            dphi.clamp(-MAX_STEP, MAX_STEP),
            dpsi.clamp(-MAX_STEP, MAX_STEP),
        );
        po = turn(po, dphi);
        pf = turn(pf, dpsi);
        if dphi.abs() + dpsi.abs() < RIM_RIM_TOL {
            converged = true;
            break;
        }
    }
    let descended = !converged;
    if descended {
        // Rims that roll along each other (an L corner near 90°): the
        // Hessian is nearly singular along the roll and changes sign close
        // by, and the plain iteration cycles. Again from the start, as a
        // descent: Newton's step where the Hessian is positive definite,
        // else a full step along its least curvature's eigenvector,
        // downhill; each halved until the distance decreases.
        (pf, po) = start;
        let dist2 = |po: (f64, f64), pf: (f64, f64)| (ro.at(po) - rf.at(pf)).length_squared();
        let mut now = dist2(po, pf);
        for _ in 0..RIM_RIM_DESCENT_STEPS {
            let ((g1, g2), h) = derivatives(po, pf);
            (h11, h22, h12) = h;
            let det = h11 * h22 - h12 * h12;
            let (dphi, dpsi) = if h11 > 0.0 && det > 0.0 {
                newton((g1, g2), h, det)
            } else {
                // Along the eigenvector of the least curvature, downhill.
                let least = 0.5 * (h11 + h22 - ((h11 - h22).powi(2) + 4.0 * h12 * h12).sqrt());
                let (v1, v2) = if (h11 - least).abs() > (h22 - least).abs() {
                    (h12, least - h11)
                } else {
                    (least - h22, h12)
                };
                let l = (v1 * v1 + v2 * v2).sqrt();
                let down = if g1 * v1 + g2 * v2 > 0.0 {
                    -MAX_STEP
                } else {
                    MAX_STEP
                } / l;
                (down * v1, down * v2)
            };
            let (dphi, dpsi) = (
                dphi.clamp(-MAX_STEP, MAX_STEP),
                dpsi.clamp(-MAX_STEP, MAX_STEP),
            );
            let mut t = 1.0;
            let (qo, qf, v) = loop {
                let (qo, qf) = (turn(po, t * dphi), turn(pf, t * dpsi));
                let v = dist2(qo, qf);
                if v <= now || t < 1e-6 {
                    break (qo, qf, v);
                }
                t *= 0.5;
            };
            (po, pf, now) = (qo, qf, v);
            if t * (dphi.abs() + dpsi.abs()) < RIM_RIM_TOL {
                converged = h11 > 0.0 && det > 0.0;
                break;
            }
        }
    }
    // Not converged (a start in a saddle's basin): no stationary value
    // matters if the rims are provably further apart than `reach`.
    if !converged && rims_apart(&rf, o.axis, &ro, reach) {
        return None;
    }
    let (x, p) = (ro.at(po), rf.at(pf));
    let d = x - p;
    let l = d.length();
    if !(l > 0.0 && l < ro.r + rf.r) {
        return None;
    }
    // A degenerate Hessian (rims coaxial: a whole circle of stationary
    // points) along a direction a cap supports is no rim–rim minimum: the
    // faces hold it (face_face, rim_face).
    let capped = |n: DVec3| cap_supports(o, n, so) || cap_supports(f, -n, sf);
    if !converged && capped(d / l) && capped(-d / l) {
        converged = true;
    }
    let positive_curvature = h11 > 0.0 && h11 * h22 - h12 * h12 > 0.0;
    // Interpenetrating: x is beyond p along n (n = d/|d|); apart: −d/|d|.
    let pick = [d / l, -d / l]
        .into_iter()
        .find(|&n| rim_supports(o, n, so, x) && rim_supports(f, -n, sf, p));
    let n = pick.unwrap_or(d / l);
    Some(Stationary {
        n,
        point: p,
        // Both rim points on the bodies.
        lower: n.dot(d),
        local_min: converged && positive_curvature && pick.is_some(),
        converged,
        descended,
    })
}
