//! Rim–face: a rim of one fibre on the domed face of the other (an L corner,
//! a tilted end landing on a face). Circle against sphere: the rim point
//! nearest the dome's centre, `p = e + r d⊥/|d⊥|`, closed form.

use super::{cap_supports, direction, face_centre, perp, rim_supports, Stationary};
use crate::contact::fibre_fibre::support::{dome_centre, dome_radius};
use crate::contact::FibreGeom;
use std::cmp::Ordering;

/// Rim of `f`'s end `sf` against the face (cap) of `o`'s end `so`: the
/// direction from `o`'s dome centre `s` to `f`'s rim point nearest `s`.
/// `None` when `s` lies over `f`'s face (`|d⊥| ≤ r`: the face, not the rim,
/// faces it) or on `f`'s axis. A local minimum when `o`'s support along
/// the direction is its cap and `f`'s the rim point.
// (Inlined into the scan: out of line its answer went through memory.)
#[inline(always)]
pub(in crate::contact::fibre_fibre) fn rim_face(
    f: &FibreGeom,
    sf: f64,
    o: &FibreGeom,
    so: f64,
) -> Option<Stationary> {
    let s = dome_centre(o, so);
    let e = face_centre(f, sf);
    let side = perp(s - e, f.axis);
    let sl = side.length();
    // (NaN included: not beyond the rim.)
    if sl.partial_cmp(&f.radius) != Some(Ordering::Greater) {
        return None;
    }
    let p = e + (f.radius / sl) * side;
    let d = p - s;
    let n = direction(d)?;
    let capped = cap_supports(o, n, so);
    // The rim point on `f`, `o`'s cap point `s + R_o n` when the cap
    // supports n: n·(x_o − x_f) = R_o − |d|.
    let lower = if capped {
        dome_radius(o.radius) - n.dot(d)
    } else {
        f64::NEG_INFINITY
    };
    Some(Stationary {
        n,
        point: p,
        lower,
        local_min: capped && rim_supports(f, -n, sf, p),
        converged: true,
        descended: false,
    })
}
