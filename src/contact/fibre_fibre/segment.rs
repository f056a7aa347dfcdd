//! Segment geometry of two fibre axes: the closest points of the axis
//! segments, and their axial overlap with its gradient.

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
