//! Fibre–wall contact: exact, analytic, one contact per end face.
//!
//! For end `i` (`c_i = centre ± half_length·axis`) the depth of its deepest
//! rim point is `offset − n·c_i + r s`, `s = |n⊥|`, `n⊥ = n − (n·a)a` (a
//! convex cylinder touches a plane first at a rim). `s` has a cone point at
//! `s = 0` (axis normal to the wall), so each end uses the smooth effective
//! depth
//!
//! `δ_i = offset − n·c_i + r g(s)`, `g(s) = s` for `s ≥ s0`,
//! `g(s) = 2s²/s0 − s³/s0²` for `s < s0` (`s0` = [`FACE_BLEND_SIN`]),
//!
//! C¹ with `g(0) = g'(0) = 0`. Its exact gradient is the single force
//! `F(δ_i) n` at `p_i = c_i + r g'(s) u`, `u = −n⊥/s` (envelope argument).
//! Standing on a face: one Hertz point at the face centre (the resultant of
//! the face load, Hertz with `R* = D/2`, not a flat-punch law); tilted by
//! at least asin s0 (0.14°): the exact corner point; lying flat: one point
//! per end.
//!
//! Limits: inside the band the depth is under-estimated by at most
//! `(4/27) r s0` (1.85 µm for r = 5 mm) and the lever arm reaches `4/3 r`;
//! the potential is C¹, not C², at `s = s0`. Derivations, the tilt mode
//! the band creates, and the choice of `s0`: docs/contacts.md,
//! "Fibre–wall".

use super::{ContactPoint, FibreGeom, Wall};
use glam::DVec3;

/// sin of the tilt below which an end face is treated as a face, not a rim
/// (≈ 0.14°). Trade-off: the depth error inside the band is ≤ (4/27) r s0
/// (1.85 µm for r = 5 mm), the tilt stiffness near upright is ~4 F r / s0
/// (why 0.0025: docs/contacts.md, "Fibre–wall").
pub const FACE_BLEND_SIN: f64 = 0.0025;

/// Smoothed rim extent `g(s)` and its derivative `g'(s)` for blend width `s0`.
#[inline]
fn face_blend(s: f64, s0: f64) -> (f64, f64) {
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
fn end_face_vs_plane(c: DVec3, a: DVec3, r: f64, n: DVec3, offset: f64, s0: f64) -> (f64, DVec3) {
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

/// Fibre–wall contacts of `f` with `w`, appended to `out`: up to two (one
/// per end face), weight 1 each; normal = the wall's (force on the fibre).
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
