//! Segment geometry of two fibre axes: the closest points of the axis
//! segments, and their axial overlap with its gradient.

use super::PARALLEL_SIN;
use crate::contact::FibreGeom;
use glam::DVec3;

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

/// How far `a` and `b` may move (the sum of their motion bounds, which
/// bound every segment point's displacement and each axis's turn, `|Δa| ≤
/// m/h`) with their segments' closest points off the interior (`|s| = h_A`
/// or `|t| = h_B` in [`segment_closest_params`]); 0 when they are interior
/// or within the parallel band (`|a×b| <` [`PARALLEL_SIN`], where
/// `segment_closest_params` may take its parallel branch). A's line meets
/// the plane through B's line that holds `m = a×b/σ`, `σ = |a×b|`, at the
/// lines' closest point `s*`, so `|s*| > h_A`
/// exactly when A's ends `e` lie on one side of that plane, at signed
/// distances `ν·(e − q)`, `ν = b×m`, `q` any point of B's segment (the one
/// nearest `e`). A motion `Δ` moves `e` and `q` by at most `Δ` together and
/// turns `ν` by `|Δb| + |Δm| ≤ (1 + 2/σ)Δ/h` (`|Δ(u/|u|)| ≤ 2|Δu|/|u|`,
/// `|Δ(a×b)| ≤ |Δa| + |Δb|`; `h` the shorter half-length), so each
/// distance changes by at most `Δ(1 + |e − q|(1 + 2/σ)/h)`. The same with A
/// and B swapped; the larger room holds. (The margin covers the rounding
/// of the distances and of `s*`.)
pub(super) fn room_off_interior(a: &FibreGeom, b: &FibreGeom) -> f64 {
    let u = a.axis.cross(b.axis);
    let sin = u.length();
    if sin < PARALLEL_SIN {
        return 0.0;
    }
    let m = u / sin;
    let turn = (1.0 + 2.0 / sin) / a.half_length.min(b.half_length);
    // `f`'s ends against the plane through `o`'s line.
    let room = |f: &FibreGeom, o: &FibreGeom| {
        let nu = o.axis.cross(m);
        let end = |sign: f64| {
            let e = f.centre + sign * f.half_length * f.axis;
            let along = o
                .axis
                .dot(e - o.centre)
                .clamp(-o.half_length, o.half_length);
            let lever = e.distance(o.centre + along * o.axis);
            (nu.dot(e - o.centre), lever)
        };
        let ((d0, l0), (d1, l1)) = (end(-1.0), end(1.0));
        if d0 * d1 <= 0.0 {
            return 0.0;
        }
        let margin = 1e-12 * (f.half_length + o.half_length + l0.max(l1));
        let room0 = (d0.abs() - margin) / (1.0 + l0 * turn);
        let room1 = (d1.abs() - margin) / (1.0 + l1 * turn);
        room0.min(room1).max(0.0)
    };
    room(a, b).max(room(b, a))
}

/// Axial overlap `ℓ` of the segments (measured along A) and its gradient
/// with respect to A's translation and rotation (rotation vector, about
/// A's centre): `ℓ = min(m + h_B|a·b|, h_A) − max(m − h_B|a·b|, −h_A)`,
/// `m = −a·(c_A − c_B)`.
pub(super) struct AxialOverlap {
    /// `ℓ` (m); negative when the projections are apart.
    pub(super) len: f64,
    /// `∂ℓ/∂x_A`.
    pub(super) grad_x: DVec3,
    /// `∂ℓ/∂φ_A`.
    pub(super) grad_rot: DVec3,
}

#[inline]
pub(super) fn axial_overlap(a: &FibreGeom, b: &FibreGeom) -> AxialOverlap {
    let w = a.centre - b.centre;
    let ab = a.axis.dot(b.axis);
    let bb = ab.abs();
    let mid = -a.axis.dot(w);
    let (mid_x, mid_rot) = (-a.axis, -a.axis.cross(w));
    let bb_rot = ab.signum() * a.axis.cross(b.axis);
    let (mut len, mut grad_x, mut grad_rot) = (0.0, DVec3::ZERO, DVec3::ZERO);
    let hi = mid + b.half_length * bb;
    if hi < a.half_length {
        len += hi;
        grad_x += mid_x;
        grad_rot += mid_rot + b.half_length * bb_rot;
    } else {
        len += a.half_length;
    }
    let lo = mid - b.half_length * bb;
    if lo > -a.half_length {
        len -= lo;
        grad_x -= mid_x;
        grad_rot -= mid_rot - b.half_length * bb_rot;
    } else {
        len += a.half_length;
    }
    AxialOverlap {
        len,
        grad_x,
        grad_rot,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::fibre_fibre::uniform::Uniform;
    use crate::contact::stage::motion_bound;
    use glam::DQuat;

    fn interior(a: &FibreGeom, b: &FibreGeom) -> bool {
        let (s, t) = segment_closest_params(a, b);
        s.abs() < a.half_length && t.abs() < b.half_length
    }

    /// `f` moved by `shift` and turned by `turn` (rotation vector) about
    /// its centre.
    fn moved(f: &FibreGeom, shift: DVec3, turn: DVec3) -> FibreGeom {
        FibreGeom {
            centre: f.centre + shift,
            axis: DQuat::from_scaled_axis(turn) * f.axis,
            ..*f
        }
    }

    /// Reference: the dispatch's own `interior` test on moved poses. Random
    /// pairs off the interior, each body moved and turned at random, then
    /// the motion scaled so that the two motion bounds sum to the room:
    /// never interior. Five motions in six are aimed: an axis turned either
    /// way in the plane of both axes or out of it, or both bodies pushed and
    /// turned towards each other's nearest point.
    #[test]
    fn the_room_keeps_the_closest_points_off_the_interior() {
        let mut u = Uniform(0x5eed_0f1e_7e71_0400);
        let mut pairs = 0;
        while pairs < 3000 {
            let a = u.fibre(0.05);
            // Half the pairs from the parallel band's edge (2°) to 6°,
            // where a turn slides the lines' closest point fastest.
            let sin = if pairs % 2 == 0 {
                0.036 + 0.064 * u.next()
            } else {
                u.next()
            };
            let normal = a.axis.cross(u.vec(1.0)).normalize();
            let b = FibreGeom {
                half_length: 0.005 + 0.03 * u.next(),
                radius: 0.002 + 0.004 * u.next(),
                axis: DQuat::from_axis_angle(normal, sin.asin()) * a.axis,
                ..u.fibre(0.05)
            };
            if interior(&a, &b) {
                continue;
            }
            let room = room_off_interior(&a, &b);
            if room <= 0.0 {
                continue;
            }
            pairs += 1;
            for k in 0..40 {
                let (mut sa, mut ta, mut sb, mut tb) =
                    (u.vec(1.0), u.vec(1.0), u.vec(1.0), u.vec(1.0));
                let (s, t) = segment_closest_params(&a, &b);
                let (pa, pb) = (a.centre + s * a.axis, b.centre + t * b.axis);
                let m = a.axis.cross(b.axis).normalize();
                let sign = if k % 12 < 6 { 1.0 } else { -1.0 };
                // Turns nearly pure (a turn of 1 rad moves the ends ~0.015
                // m, a shift of 1 m by 1 m): the room's `2/σ` term is the
                // common normal's turn, which only a tilt out of the plane
                // of both axes makes.
                let (small_a, small_b) = (0.001 * sa, 0.001 * sb);
                match k % 6 {
                    // An axis swung in the plane of both, either way.
                    0 => (sa, ta, sb, tb) = (small_a, sign * m, small_b, 0.01 * tb),
                    1 => (sa, ta, sb, tb) = (small_a, 0.01 * ta, small_b, sign * m),
                    // An axis tilted out of that plane, either way.
                    2 => (sa, ta, sb, tb) = (small_a, sign * a.axis.cross(m), small_b, 0.01 * tb),
                    3 => (sa, ta, sb, tb) = (small_a, 0.01 * ta, small_b, sign * b.axis.cross(m)),
                    // Both pushed and turned towards each other's nearest point.
                    4 => {
                        sa = pb - pa + 0.2 * (pb - pa).length() * sa;
                        sb = pa - pb;
                        ta = a.axis.cross(pb - a.centre) + 0.2 * ta;
                        tb = b.axis.cross(pa - b.centre) + 0.2 * tb;
                    }
                    _ => {}
                }
                // Scale to the room (bisection on the scale factor).
                let total = |x: f64| {
                    f64::from(motion_bound(&a, &moved(&a, x * sa, x * ta)))
                        + f64::from(motion_bound(&b, &moved(&b, x * sb, x * tb)))
                };
                let (mut lo, mut hi) = (0.0, 1.0);
                while total(hi) <= room {
                    hi *= 2.0;
                }
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if total(mid) <= room {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let (a2, b2) = (moved(&a, lo * sa, lo * ta), moved(&b, lo * sb, lo * tb));
                assert!(
                    !interior(&a2, &b2),
                    "interior after a motion of {} within the room {room}: {a:?} {b:?}",
                    total(lo)
                );
            }
        }
    }

    /// Reference: a T-junction whose end overlaps the other's side by 1 mm
    /// (the commonest end-involved contact of a bed). Moved straight
    /// along its own axis past the other's line by the room's worth, it
    /// stays off the interior; the room is not vanishingly small against
    /// the motion that does make it interior (the end's distance past the
    /// line, 4 mm).
    #[test]
    fn a_t_junction_keeps_a_room_of_its_order() {
        let a = FibreGeom {
            centre: DVec3::new(0.0, 0.0, 0.015 + 0.004),
            axis: DVec3::Z,
            radius: 0.005,
            half_length: 0.015,
        };
        let b = FibreGeom {
            centre: DVec3::ZERO,
            axis: DVec3::X,
            radius: 0.005,
            half_length: 0.015,
        };
        assert!(!interior(&a, &b));
        let room = room_off_interior(&a, &b);
        let pushed = moved(&a, -room * DVec3::Z, DVec3::ZERO);
        assert!(!interior(&pushed, &b));
        let through = moved(&a, -0.0041 * DVec3::Z, DVec3::ZERO);
        assert!(interior(&through, &b));
        assert!(room > 0.004 / 20.0, "room {room}");
    }
}
