//! Face–face: the caps of one end of each fibre (end to end, near-coaxial).
//! Two spheres of radius `R = r/sin θc`: the depth is `R_f + R_o − |s_f − s_o|`
//! along the line of their centres (closed form).

use super::{cap_supports, direction, Stationary};
use crate::contact::fibre_fibre::support::{dome_centre, dome_radius};
use crate::contact::FibreGeom;

/// Face of `f`'s end `sf` against the face of `o`'s end `so`: the line of
/// the dome centres, from `o`'s towards `f`'s. A local minimum when both
/// supports along it are those caps (the faces within 2θc of antiparallel).
// (Inlined into the scan: out of line its answer went through memory.)
#[inline(always)]
pub(in crate::contact::fibre_fibre) fn face_face(
    f: &FibreGeom,
    sf: f64,
    o: &FibreGeom,
    so: f64,
) -> Option<Stationary> {
    let sc = dome_centre(f, sf);
    let d = sc - dome_centre(o, so);
    let n = direction(d)?;
    let local_min = cap_supports(o, n, so) && cap_supports(f, -n, sf);
    // Both cap points on the bodies: n·(x_o − x_f) = R_o + R_f − |d|.
    let lower = if local_min {
        dome_radius(o.radius) + dome_radius(f.radius) - n.dot(d)
    } else {
        f64::NEG_INFINITY
    };
    Some(Stationary {
        n,
        point: sc - dome_radius(f.radius) * n,
        lower,
        local_min,
        converged: true,
        descended: false,
    })
}
