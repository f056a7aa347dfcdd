//! Feature-pair kernels of the end-involved depth: one closed-form or
//! fixed-iteration kernel per pair of surface features of two domed
//! cylinders (after Kodam et al., Chem. Eng. Sci. 65 (2010), parts I–II,
//! whose case split by features we follow; the domes are ours).
//!
//! The depth `min_n h̃_B(n) + h̃_A(−n)` (support.rs) is the maximum of four
//! smooth branches (one per pair of ends), kinked only on each body's side
//! circle `n ⊥ axis`, where that body's support is a whole generator. Every
//! local minimum therefore is a stationary point of one of these feature
//! pairs, each a two-body distance problem with a closed form or a 1- or
//! 2-D Newton iteration:
//!
//! | feature pair | supports | file |
//! |---|---|---|
//! | face–face | cap, cap (two spheres of radius `r/sin θc`) | `face_face.rs` |
//! | rim–face | rim point, cap (circle vs sphere) | `rim_face.rs` |
//! | face–side | cap, generator (sphere vs axis line) | `face_side.rs` |
//! | rim–side | rim point, generator (circle vs line, 1-D Newton) | `rim_side.rs` |
//! | rim–rim | rim point, rim point (circle vs circle, 2-D Newton) | `rim_rim.rs` |
//!
//! (Side–side, both supports generators, is the closest-point contact of
//! the axis segments: `side_side.rs`.) Each kernel takes the two bodies in
//! the roles of its features: `f` owns the first feature (end `sf`), `o`
//! the second. It returns the stationary direction `n` from `o` towards
//! `f` (the force on `f`), and whether it is a local minimum of the depth
//! on the sphere: in the feature pair's own region (each body's support
//! there is the feature assumed) and, for the iterations, converged and of
//! positive curvature. The value is never taken from the kernel: the
//! caller evaluates the exact domed projection overlap along `n`, an upper
//! bound of the depth whatever the kernel returned.

mod face_face;
mod face_side;
mod rim_face;
mod rim_rim;
mod rim_side;

pub(super) use face_face::face_face;
pub(super) use face_side::face_side;
pub(super) use rim_face::rim_face;
pub(super) use rim_rim::rim_rim;
pub(super) use rim_side::{rim_point_nearest_line, rim_side};

use super::support::{dome_cos, sig};
use crate::contact::FibreGeom;
use glam::DVec3;

/// A stationary direction of a feature pair: `n` points from the second
/// feature's body towards the first's (the force on the first body).
#[derive(Clone, Copy, Debug)]
pub(super) struct Stationary {
    pub(super) n: DVec3,
    /// The first feature's support point (on `f`) at `n`.
    pub(super) point: DVec3,
    /// A lower bound of the domed projection overlap along `n`,
    /// `n·(x_o − x_f)` for two points `x_o` of `o` and `x_f` of `f` the
    /// kernel already has (`h_o(n) ≥ n·x_o`, `h_f(−n) ≥ −n·x_f`), or −∞:
    /// the scan need not evaluate a direction this far above its best.
    pub(super) lower: f64,
    /// A local minimum of the depth on the sphere (see the module doc).
    pub(super) local_min: bool,
    /// The iteration converged (always true for closed forms). A kernel
    /// that did not is the one reason the end-involved scan falls back.
    pub(super) converged: bool,
    /// Found by rim–rim's descent after its Newton iteration failed: the
    /// stationary point Newton was heading for (a saddle, which may become
    /// a minimum) is not among the scan's answers, so the scan's room
    /// would not count it and its pair remembers nothing.
    pub(super) descended: bool,
}

/// Centre of end `sigma`'s face (the rim circle's centre).
#[inline]
pub(super) fn face_centre(f: &FibreGeom, sigma: f64) -> DVec3 {
    f.centre + (sigma * f.half_length) * f.axis
}

/// Whether `f`'s support in the unit direction `d` is on the cap of end
/// `sigma`.
#[inline]
fn cap_supports(f: &FibreGeom, d: DVec3, sigma: f64) -> bool {
    sigma * d.dot(f.axis) >= dome_cos()
}

/// Whether `f`'s support in the unit direction `d` is the rim point `p` of
/// end `sigma`: that end faces `d`, `d` is off the cap, and `d`'s component
/// in the rim plane points from the face centre towards `p`. (Inlined: it
/// runs about twice a fibre-step in a bed, and the call showed in the
/// step's cost: `cargo bench --bench bed`.)
#[inline(always)]
fn rim_supports(f: &FibreGeom, d: DVec3, sigma: f64, p: DVec3) -> bool {
    let da = d.dot(f.axis);
    sig(d, f.axis) == sigma
        && sigma * da < dome_cos()
        && (d - da * f.axis).dot(p - face_centre(f, sigma)) > 0.0
}

/// Whether the point `p` lies between `f`'s end planes (where a support on
/// `f`'s side circle is a local minimum, not a kink).
#[inline]
fn between_end_planes(f: &FibreGeom, p: DVec3) -> bool {
    f.axis.dot(p - f.centre).abs() <= f.half_length
}

/// The unit vector along `d`, or `None` when `d` is zero (or not finite):
/// the kernels' stationary direction.
#[inline]
fn direction(d: DVec3) -> Option<DVec3> {
    let l = d.length();
    (l > 0.0).then(|| d / l)
}

/// Component of `x` perpendicular to the unit `u`.
#[inline]
fn perp(x: DVec3, u: DVec3) -> DVec3 {
    x - x.dot(u) * u
}
