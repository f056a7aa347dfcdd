//! The parry check of the end-involved regime: parry3d-f64's GJK/EPA
//! cylinder–cylinder contact, used only as a seed normal and checked
//! against the exact support functions; its "no contact" verdict confirmed
//! by a separating axis ([`confirm_separated`]). What parry gets wrong, and
//! how often: docs/contacts.md, "The parry check".

use super::search::{circle_min, sphere_min};
use super::support::{projection_overlap, sig};
use super::Cand;
use crate::contact::{FibreGeom, KernelCounters};
use glam::{DQuat, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::Cylinder;

/// Relative tolerance on parry's depth against the projection overlap along
/// its own normal (diagnostic only: the depth used is always recomputed).
/// parry's EPA depth is off by up to ~5e-9 m (≈10 % of a 6e-8 m depth),
/// its known failures (exactly coaxial pairs) by O(1).
pub(super) const PARRY_REL_TOL: f64 = 1e-2;

/// Cylinder pose for parry: its cylinders are along local +Y.
#[inline]
fn parry_pose(f: &FibreGeom) -> Pose {
    Pose::from_parts(f.centre, DQuat::from_rotation_arc(DVec3::Y, f.axis))
}

/// parry's cylinder–cylinder contact, checked, for pairs closer than
/// `margin` (the domes' sags: a domed pair can touch while the exact
/// cylinders are up to `margin` apart). Checks: finite unit normal;
/// `depth ≤` capsule `bound`; `depth` within [`PARRY_REL_TOL`] of the exact
/// projection overlap along its own normal (an upper bound of the true
/// depth, equal to it for a correct MTD or closest-point direction).
/// `Err(normal)` = rejected (with parry's normal if finite, as one more
/// seed). `Ok(None)` = parry sees the exact cylinders more than `margin`
/// apart: see [`confirm_separated`].
pub(super) fn parry_contact(
    a: &FibreGeom,
    b: &FibreGeom,
    bound: f64,
    margin: f64,
    counters: &mut KernelCounters,
) -> Result<Option<Cand>, DVec3> {
    counters.parry_calls += 1;
    let ca = Cylinder::new(a.half_length, a.radius);
    let cb = Cylinder::new(b.half_length, b.radius);
    let Ok(res) = query::contact(&parry_pose(a), &ca, &parry_pose(b), &cb, margin) else {
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
    if !(depth_checks_out(a, b, bound, depth, n) && c.point1.is_finite() && c.point2.is_finite()) {
        return Err(n);
    }
    Ok(Some(Cand {
        depth,
        point: 0.5 * (c.point1 + c.point2),
        normal: n,
    }))
}

/// Whether a contact `(depth, n)` of A and B (`n` unit, the force on A)
/// can be right: `depth ≤` the capsule `bound`, and `depth` within
/// [`PARRY_REL_TOL`] of the exact projection overlap along `n` (an upper
/// bound of the true depth, equal to it for the minimum-translation
/// direction).
#[inline]
fn depth_checks_out(a: &FibreGeom, b: &FibreGeom, bound: f64, depth: f64, n: DVec3) -> bool {
    let tol = PARRY_REL_TOL * depth.abs() + 1e-8 * (a.radius + b.radius);
    let proj = projection_overlap(a, b, n);
    depth.is_finite() && depth <= bound + tol && (proj - depth).abs() <= tol
}

/// Whether one of the cheap axes (closest-point normal, centre line, the two
/// axes, their cross product) separates the two fibres by more than
/// `margin` (the domes' sags): an exact proof of no contact.
pub(super) fn cheap_axis_separates(
    a: &FibreGeom,
    b: &FibreGeom,
    margin: f64,
    cp_normal: DVec3,
) -> bool {
    let w = a.centre - b.centre;
    [cp_normal, w, a.axis, b.axis, a.axis.cross(b.axis)]
        .into_iter()
        .any(|d| {
            let l = d.length();
            l > 1e-300 && l.is_finite() && {
                let d = d / l;
                projection_overlap(a, b, d).min(projection_overlap(a, b, -d)) < -margin
            }
        })
}

/// Runtime guard on parry's "no contact" verdict: true if a direction is
/// found along which the exact projections are more than `margin` apart
/// (proof that even the domed cylinders are separated: they exceed the
/// exact ones by at most `margin` in every direction). Tries the cheap axes
/// first (closest-point normal, centre line, axes, common normal), then
/// local minimisations from each of them. A `false` is counted in
/// [`KernelCounters::parry_unconfirmed`]; parry's verdict is still
/// followed (GJK's separation answer is the reliable part of parry; the
/// local search is not a global proof of contact).
pub(super) fn confirm_separated(
    a: &FibreGeom,
    b: &FibreGeom,
    margin: f64,
    cp_normal: DVec3,
    counters: &mut KernelCounters,
) -> bool {
    let w = a.centre - b.centre;
    if cheap_axis_separates(a, b, margin, cp_normal) {
        return true;
    }
    // Local searches on both side circles and on the smooth branches, from
    // each cheap axis: a separating direction of two fibres is typically
    // on a side circle, far from all cheap axes.
    let apart = |m: DVec3| projection_overlap(a, b, m) < -margin;
    for d in [cp_normal, w, a.axis.cross(b.axis), a.axis, b.axis] {
        let l = d.length();
        if !(l > 1e-300 && l.is_finite()) {
            continue;
        }
        for st in [d / l, -d / l] {
            for u in [a.axis, b.axis] {
                if apart(circle_min(a, b, u, st)) {
                    return true;
                }
            }
            if apart(sphere_min(a, b, st, sig(-st, a.axis), sig(st, b.axis))) {
                return true;
            }
        }
    }
    counters.parry_unconfirmed += 1;
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::fibre_fibre::segment_closest_params;

    /// Test case 1's fibre (D = 0.01 m, L = 0.025 m).
    fn fib(centre: DVec3, axis: DVec3) -> FibreGeom {
        FibreGeom {
            centre,
            axis: axis.normalize(),
            radius: 0.005,
            half_length: 0.0125,
        }
    }

    /// Capsule bound `r_A + r_B − d_seg`, as the kernel passes it.
    fn bound(a: &FibreGeom, b: &FibreGeom) -> f64 {
        let (s, t) = segment_closest_params(a, b);
        a.radius + b.radius - (a.centre + s * a.axis - b.centre - t * b.axis).length()
    }

    const D0: f64 = 1e-6;

    /// Poses with a closed-form depth `D0` and force direction on A:
    /// exactly coaxial end to end (flat faces overlapping by `D0`; the
    /// x-axis pose is where parry 0.31 answers ≈ 2.7e-7 m along
    /// ≈ (−0.27, 0.68, 0.68)), and crossed at 90° and 60° (sides at
    /// distance D − `D0`).
    fn poses() -> Vec<(FibreGeom, FibreGeom, DVec3)> {
        let c = DVec3::new(0.1, 0.2, 0.3);
        let mut v = vec![];
        for axis in [DVec3::X, DVec3::Z, DVec3::new(1.0, 2.0, 3.0).normalize()] {
            let a = fib(c, axis);
            v.push((a, fib(c + (0.025 - D0) * axis, axis), -axis));
        }
        for t in [90f64, 60.0] {
            let t = t.to_radians();
            let a = fib(c, DVec3::X);
            let b = fib(
                c + DVec3::new(0.0, 0.01 - D0, 0.0),
                DVec3::new(t.cos(), 0.0, t.sin()),
            );
            v.push((a, b, -DVec3::Y));
        }
        v
    }

    /// Reference: the closed-form depths of [`poses`]. The checks accept
    /// the right answer, and reject the documented wrong one and any depth
    /// off by more than the tolerance.
    #[test]
    fn the_checks_accept_right_depths_and_reject_wrong_ones() {
        for (a, b, n) in poses() {
            let bound = bound(&a, &b);
            assert!(depth_checks_out(&a, &b, bound, D0, n), "{a:?} {b:?}");
            for wrong in [0.9 * D0, 1.1 * D0] {
                assert!(!depth_checks_out(&a, &b, bound, wrong, n), "{wrong} {a:?}");
            }
        }
        let (a, b, _) = poses()[0];
        let parry_031 = DVec3::new(-0.27, 0.68, 0.68).normalize();
        assert!(!depth_checks_out(&a, &b, bound(&a, &b), 2.7e-7, parry_031));
    }

    /// Reference: the closed-form depths again. Whatever parry answers,
    /// an answer the guard keeps has the right depth, and parry (reliable
    /// on crossings) is kept there; every query is counted.
    #[test]
    fn parry_answers_kept_have_the_right_depth() {
        let mut k = KernelCounters::default();
        let margin = 0.0;
        let poses = poses();
        for (i, (a, b, _)) in poses.iter().enumerate() {
            match parry_contact(a, b, bound(a, b), margin, &mut k) {
                Ok(Some(c)) => {
                    let tol = PARRY_REL_TOL * D0 + 1e-8 * (a.radius + b.radius);
                    assert!((c.depth - D0).abs() <= tol, "pose {i}: kept {}", c.depth);
                }
                Ok(None) => panic!("pose {i}: a touching pair called separated"),
                Err(_) => assert!(i < 3, "pose {i}: a crossing's answer rejected"),
            }
        }
        assert_eq!(k.parry_calls, poses.len() as u64);
    }
}
