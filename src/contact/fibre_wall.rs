//! Fibre–wall contact: exact, analytic, one contact per end face.
//!
//! # Model (why it conserves energy)
//! For end `i` (`c_i = centre ± half_length·axis`) the exact depth of its
//! deepest rim point is `δ_i = offset − n·c_i + r s`, `s = |n⊥|`,
//! `n⊥ = n − (n·a)a` (a convex cylinder always touches a plane first at a
//! rim). `s` has a cone-shaped kink at `s = 0` (axis normal to the wall): the
//! deepest rim point jumps around the rim and the tilt torque would be
//! bang-bang. We therefore use, per end, the smooth effective depth
//!
//! `δ_i = offset − n·c_i + r g(s)`, `g(s) = s` for `s ≥ s0`,
//! `g(s) = 2s²/s0 − s³/s0²` for `s < s0` (`s0` = [`FACE_BLEND_SIN`]),
//!
//! `g` is C¹ with `g(0) = g'(0) = 0`, so the potential `Σ_i U(δ_i)` is C¹ in
//! the pose. Its exact gradient is a single force `F(δ_i) n` applied at
//! `p_i = c_i + r g'(s) u`, `u = −n⊥/s` (the rim direction facing the wall):
//! a rotation ω changes `r g(s)` by exactly `−r g'(s) n·(ω×u)` (envelope
//! argument, see the unit test), so returned forces/torques are the gradient.
//!
//! # Load sharing
//! Each end carries its own contact with weight 1.
//! * **Standing on an end face** (`s = 0`): one Hertz point at the face
//!   centre, with the depth of the face. This is the resultant of a
//!   face load (no torque), not a flat-punch law: the force is still
//!   Hertz's `F(δ)` with `R* = D/2` (SPEC §3), i.e. the face is as stiff as
//!   a sphere of the fibre's radius.
//! * **Tilted by at least asin s0** (0.14°): the exact single Hertz point at
//!   the deepest rim point (a corner impact).
//! * In between, the lever arm moves continuously from the face centre to
//!   the rim.
//! * **Lying flat**: two weight-1 points, one per end (a line contact as two
//!   Hertz points, no chatter since each end owns its point).
//!
//! # Limits
//! * For tilt below asin s0 the depth is under-estimated relative to the
//!   rim by `r (s − g(s)) = r s (1 − s/s0)²`, at most `(4/27) r s0` at
//!   `s = s0/3` (1.85 µm for r = 5 mm; the resting overlap of a test-case
//!   fibre standing under gravity is 4.1 µm). The lever arm `r g'(s)`
//!   reaches `4/3 r` at `s = 2s0/3`, outside the body (the cubic must
//!   overshoot to satisfy `g(s0) = s0`, `g'(s0) = 1`; any C¹ blend that is
//!   exact at both ends does).
//! * Tilt stiffness inside the band: `F (4r/s0 − h)` (8.0 m × F): the rocking
//!   period of a test-case fibre at the largest wall force of the test cases
//!   (41 N, end-on drop from 0.5 m) is 123 µs, ≥ 1200 steps at δt = 1e-7.
//!   The dt guard of `run` checks the Hertz collision time only (≈ 600 µs
//!   there); at its 5-steps limit this mode is unresolved.
//! * Hertz with R* = D/2 is used for every regime (face, rim, line), as the
//!   SPEC prescribes; a flat-punch or line-contact law is not modelled.
//! * The second derivative of the potential jumps at `s = s0` (C¹, not C²).

use super::{ContactPoint, FibreGeom, Wall};
use glam::DVec3;

/// sin of the tilt below which an end face is treated as a face, not a rim
/// (≈ 0.14°). Trade-off: the depth error inside the band is ≤ (4/27) r s0
/// (1.85 µm for r = 5 mm), the tilt stiffness near upright is ~4 F r / s0.
///
/// Why 0.0025 (was 0.01, error 7.4 µm, larger than the 4.1 µm resting
/// overlap of a standing test-case fibre): the error is now below half of
/// that overlap, and the tilt mode it creates, 2× faster than at 0.01, is
/// still resolved by ≥ 1200 steps per period at δt = 1e-7 and ≥ 120 at
/// 1e-6 at the largest wall force of the test cases (see the module docs).
/// Smaller widths cost resolution as `s0^{-1/2}` for a linear gain.
pub const FACE_BLEND_SIN: f64 = 0.0025;

/// Smoothed rim extent `g(s)` and its derivative `g'(s)` for blend width `s0`.
#[inline]
pub fn face_blend(s: f64, s0: f64) -> (f64, f64) {
    if s >= s0 {
        (s, 1.0)
    } else {
        let x = s / s0;
        (s0 * x * x * (2.0 - x), x * (4.0 - 3.0 * x))
    }
}

/// Contact of one end face (centre `c`, unit axis `a`, radius `r`) with the
/// half-space `n·x <= offset`, face blend width `s0`. Returns (depth,
/// application point on the body).
#[inline]
pub(crate) fn end_face_vs_plane(
    c: DVec3,
    a: DVec3,
    r: f64,
    n: DVec3,
    offset: f64,
    s0: f64,
) -> (f64, DVec3) {
    let n_perp = n - n.dot(a) * a;
    let s = n_perp.length();
    let (g, dg) = face_blend(s, s0);
    let depth = offset - n.dot(c) + r * g;
    let p = if s > 0.0 && dg != 0.0 {
        c - (r * dg / s) * n_perp
    } else {
        c
    };
    (depth, p)
}

/// Fibre–wall contacts: up to two (one per end face), weight 1 each.
pub fn contact_fibre_wall(f: &FibreGeom, w: &Wall, out: &mut Vec<ContactPoint>) {
    let n = w.normal;
    // Cheap reject: the whole cylinder is above the plane.
    let reach = f.half_length * n.dot(f.axis).abs() + f.radius;
    if n.dot(f.centre) - reach >= w.offset {
        return;
    }
    for sign in [-1.0, 1.0] {
        let c = f.centre + sign * f.half_length * f.axis;
        let (depth, p) = end_face_vs_plane(c, f.axis, f.radius, n, w.offset, FACE_BLEND_SIN);
        if depth > 0.0 {
            out.push(ContactPoint {
                point: p + 0.5 * depth * n,
                normal: n,
                overlap: depth,
                weight: 1.0,
                weight_grad: DVec3::ZERO,
            });
        }
    }
}
