//! Face–side: the domed face of one fibre on the side of the other (a
//! T-junction, the face lying flat on a side). Sphere against the axis
//! line: the perpendicular from the line to the dome centre, closed form.

use super::{between_end_planes, cap_supports, direction, perp, Stationary};
use crate::contact::fibre_fibre::support::{dome_centre, dome_radius};
use crate::contact::FibreGeom;

/// Face (cap) of `f`'s end `sf` against `o`'s side: the direction ⊥ `o`'s
/// axis from it to `f`'s dome centre. `None` unless the face can be
/// supported along a direction ⊥ `o`'s axis (`|a_f·a_o| ≤ sin θc`) or when
/// the dome centre is on `o`'s axis. A local minimum when `f`'s support
/// along it is the cap and that cap point lies between `o`'s end planes.
// (Inlined into the scan: most calls end at the first test, and out of
// line every answer went through memory.)
#[inline(always)]
pub(in crate::contact::fibre_fibre) fn face_side(
    f: &FibreGeom,
    sf: f64,
    o: &FibreGeom,
) -> Option<Stationary> {
    use crate::contact::fibre_fibre::END_FACE_DOME_SIN;
    if f.axis.dot(o.axis).abs() > END_FACE_DOME_SIN {
        return None;
    }
    let s = dome_centre(f, sf);
    let d = perp(s - o.centre, o.axis);
    let n = direction(d)?;
    let point = s - dome_radius(f.radius) * n;
    let capped = cap_supports(f, -n, sf);
    // The cap point on `f`, and `o`'s side point `c + t a + r_o n` (n ⊥ a,
    // any t): n·(x_o − x_f) = r_o − n·(point − o.centre).
    let lower = if capped {
        o.radius - n.dot(point - o.centre)
    } else {
        f64::NEG_INFINITY
    };
    Some(Stationary {
        n,
        point,
        lower,
        local_min: capped && between_end_planes(o, point),
        converged: true,
        descended: false,
    })
}
