//! Support functions of a fibre, flat (exact) and with domed end faces,
//! and the projection overlaps built from them (separating-axis theorem:
//! the penetration depth of two convex bodies is the minimum over unit
//! directions of the overlap of their projections).
//!
//! Why the domes, and what they cost: docs/contacts.md, "End-face domes".

use crate::contact::FibreGeom;
use glam::DVec3;

/// End-face dome of the end-involved regimes: sine of the half-angle θc of
/// the spherical cap that replaces each flat end face for fibre–fibre
/// contact. The cap passes through the rim circle (rim and side exact) and
/// bulges out by the sag `σ = r (1 − cos θc)/sin θc ≈ r θc/2` at the face
/// centre (2.5 µm for r = 5 mm); its radius is `R = r/sin θc` (5 m). The
/// depth stays an exact penetration depth of convex bodies, C¹ across a
/// face; face contacts are deeper by at most `σ_A + σ_B`.
pub const END_FACE_DOME_SIN: f64 = 1e-3;

/// Exact support value of a cylinder in direction `n`:
/// `h(n) = n·c + h|n·a| + r|n⊥|` (closed form).
#[inline]
fn support_exact(f: &FibreGeom, n: DVec3) -> f64 {
    let na = n.dot(f.axis);
    n.dot(f.centre) + f.half_length * na.abs() + f.radius * (n - na * f.axis).length()
}

/// Dome geometry of [`END_FACE_DOME_SIN`] for radius `r`: `(R, σ, cos θc)`.
#[inline]
fn dome(r: f64) -> (f64, f64, f64) {
    let big_r = r / END_FACE_DOME_SIN;
    (big_r, big_r * (1.0 - DOME_COS), DOME_COS)
}

/// `cos θc = √(1 − sin² θc)` for [`END_FACE_DOME_SIN`] = 1e-3, to the bit
/// (a unit test recomputes it).
const DOME_COS: f64 = 0.999_999_499_999_875;

/// Cosine of the dome's half-angle θc: a direction `d` is supported by the
/// cap of end `σ` iff `σ d·a ≥ dome_cos()`.
#[inline]
pub(super) fn dome_cos() -> f64 {
    dome(1.0).2
}

/// Centre of the sphere whose cap is the dome of end `sigma` (radius
/// `r/`[`END_FACE_DOME_SIN`], on the axis, inside the fibre): the cap point in
/// the direction `n` is `dome_centre + R n` ([`support_branch`]).
#[inline]
pub(super) fn dome_centre(f: &FibreGeom, sigma: f64) -> DVec3 {
    let (big_r, sag, _) = dome(f.radius);
    f.centre + (sigma * (f.half_length + sag - big_r)) * f.axis
}

/// Radius of the end-face dome's sphere, `r/`[`END_FACE_DOME_SIN`].
#[inline]
pub(super) fn dome_radius(r: f64) -> f64 {
    dome(r).0
}

/// Sag of the end-face dome ([`END_FACE_DOME_SIN`]) of a fibre of radius
/// `r`: the largest amount by which the end-involved depth over-estimates
/// the flat cylinders' one, per face in contact.
#[inline]
pub fn dome_sag(r: f64) -> f64 {
    dome(r).1
}

/// Support of the domed cylinder (see [`END_FACE_DOME_SIN`]) of end
/// `sigma` = ±1, in the unit direction `n`: point `p` and value `n·p`.
/// Within θc of the face normal `sigma a` the point is on the cap
/// (`face centre + sigma (σ − R) a + R n`), elsewhere on the rim of that
/// end (`face centre + r n⊥/|n⊥|`). With `sigma = sign(n·a)` this is the
/// support of the domed body; with the other sign it is the smooth
/// continuation of the other end's branch (the support is the max of the
/// two, the kink being the side circle `n·a = 0`).
#[inline]
pub(super) fn support_branch(f: &FibreGeom, n: DVec3, sigma: f64) -> (DVec3, f64) {
    let na = n.dot(f.axis);
    let face = f.centre + sigma * f.half_length * f.axis;
    let (big_r, sag, cos_c) = dome(f.radius);
    let p = if sigma * na >= cos_c {
        face + (sigma * (sag - big_r)) * f.axis + big_r * n
    } else {
        let perp = n - na * f.axis;
        let pl = perp.length();
        if pl > 0.0 {
            face + (f.radius / pl) * perp
        } else {
            face
        }
    };
    (p, n.dot(p))
}

/// Support of the domed cylinder in the unit direction `n` (the end facing
/// `n`). Unique (the gradient of the support value) except on the side
/// circle `n·a = 0`, where it is a whole generator line.
#[inline]
pub(super) fn support(f: &FibreGeom, n: DVec3) -> (DVec3, f64) {
    support_branch(f, n, sig(n, f.axis))
}

/// Exact overlap of the projections of A and B on the unit direction `n`
/// (pointing from B towards A): `h_B(n) + h_A(−n)`. The penetration depth
/// is the minimum of this over all directions (separating-axis theorem), so
/// a correct MTD `(depth, n)` satisfies `depth = projection_overlap(n)` and
/// `depth ≤ projection_overlap(m)` for every other `m`; a direction with
/// `projection_overlap(n) ≤ 0` proves the pair separated.
#[inline]
pub fn projection_overlap(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> f64 {
    support_exact(b, n) + support_exact(a, -n)
}

/// Projection overlap of the domed cylinders ([`END_FACE_DOME_SIN`]),
/// `h̃_B(n) + h̃_A(−n)`: the function whose minimum over unit `n` is the
/// depth of regimes 1 and 3. Equal to [`projection_overlap`] unless `n` is
/// within θc of a face normal, and never more than `σ_A + σ_B` above it.
/// (Inlined: the scans call it ~5 times a pair.)
#[inline(always)]
pub fn domed_projection_overlap(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> f64 {
    domed_projection_supports(a, b, n).0
}

/// [`domed_projection_overlap`] with the two supports it is made of: A's
/// support point in `−n` and B's in `n` (the contact point is placed from
/// one of them: a remembered answer need not compute it again).
#[inline(always)]
pub(super) fn domed_projection_supports(
    a: &FibreGeom,
    b: &FibreGeom,
    n: DVec3,
) -> (f64, DVec3, DVec3) {
    let (on_b, h_b) = support(b, n);
    let (on_a, h_a) = support(a, -n);
    (h_b + h_a, on_a, on_b)
}

/// Sign of `d·u` (+1 for 0): the end of a fibre along `u` that faces `d`.
#[inline]
pub(super) fn sig(d: DVec3, u: DVec3) -> f64 {
    if d.dot(u) >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: the definition `cos θc = √(1 − sin² θc)`, evaluated.
    #[test]
    fn dome_cos_is_the_cosine_of_the_dome_angle() {
        let sin_c = END_FACE_DOME_SIN;
        assert_eq!(DOME_COS, (1.0 - sin_c * sin_c).sqrt());
    }
}
