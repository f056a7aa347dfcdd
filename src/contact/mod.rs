//! Contact geometry for rigid flat-ended cylindrical fibres (fibre–wall,
//! fibre–fibre) and the Hertz force law they feed.
//!
//! Every kernel appends [`ContactPoint`]s; the force on body A is
//! `weight * F_hertz(overlap) * normal` acting at `point` (on B the opposite),
//! and the stored energy is `weight * U_hertz(overlap)`.
//!
//! Load sharing (each contact is its own Hertz point, R* of SPEC §3 for all):
//! * fibre–wall: one contact per end face, depth of its deepest rim point
//!   with the rim term smoothed within 0.14° of upright, see [`fibre_wall`].
//!   Standing on an end: one Hertz point at the face centre, the resultant
//!   of a uniform face load (not a flat-punch law); tilted: the exact corner
//!   point; lying flat: two points, one per end.
//! * fibre–fibre side–side: potential `U(δ_main) + U(min(δ_lo, δ_hi))`,
//!   one point at a crossing, two points at the ends of the overlap for a
//!   parallel pair, see [`fibre_fibre`]. The second point fades out (and
//!   the end-involved model fades in when the closest points are not
//!   interior) over |sin| ∈ [0.02, 0.035] with an orientation-dependent
//!   weight; its gradient is the couple carried in
//!   [`ContactPoint::weight_grad`].
//! * fibre–fibre with an end: one point, the penetration depth of the two
//!   fibres with domed end faces (sag 2.5 µm), so a face on a side, rim or
//!   face has a smooth lever arm; where two local minima of that depth tie
//!   (two escape directions, within 10 µm), two points whose weights are the
//!   derivatives of a C² smooth minimum (they sum to 1).
//!
//! Every model is a potential whose exact gradient is the returned
//! force/torque (checked by finite differences in the tests), except on
//! documented measure-zero switching sets.

pub mod broad;
pub mod fibre_fibre;
pub mod fibre_wall;
pub mod hertz;
pub mod stage;

pub use broad::{candidate_pairs, candidate_pairs_with, fibre_aabb};
pub use fibre_fibre::contact_fibre_fibre;
pub use fibre_wall::contact_fibre_wall;
pub use hertz::HertzLaw;

use glam::DVec3;

/// A fibre as the kernels see it: solid flat-ended cylinder.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FibreGeom {
    /// Centre of mass (world).
    pub centre: DVec3,
    /// Unit symmetry axis (body x) in world coordinates.
    pub axis: DVec3,
    /// D/2.
    pub radius: f64,
    /// L/2.
    pub half_length: f64,
}

/// Half-space wall of an axis-aligned box: plane `normal·x = offset`, the
/// box interior is `normal·x >= offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    /// Unit normal pointing into the box.
    pub normal: DVec3,
    /// Plane offset.
    pub offset: f64,
}

/// One Hertz contact: force on A is `weight * F(overlap) * normal` at `point`,
/// energy `weight * U(overlap)`.
///
/// `normal` is `−∂overlap/∂x_A`, the gradient of the depth with respect to
/// a translation of A: a unit vector for every geometric contact. The one
/// exception is a depth whose gradient is not a force along a single line
/// (the capped second contact of the fibre–fibre axial escape): it is
/// emitted as two points of half the weight with non-unit `normal`s whose
/// forces and torques sum to its exact gradient.
///
/// A weight that depends on the relative orientation of the two bodies (the
/// fibre–fibre parallel blend, see [`fibre_fibre::PARALLEL_BLEND_SIN`])
/// carries its gradient: the potential `weight·U(overlap)` then also exerts
/// the pure couple `−U(overlap) * weight_grad` on A and `+U(overlap) *
/// weight_grad` on B (no net force). Zero for constant weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// Application point (world), midway between the two surfaces.
    pub point: DVec3,
    /// Direction of the force on body A, `−∂overlap/∂x_A` (unit except for
    /// the split contact described above).
    pub normal: DVec3,
    /// Overlap δ > 0 (m).
    pub overlap: f64,
    /// Share of the Hertz force/energy, in (0, 1].
    pub weight: f64,
    /// Gradient of `weight` with respect to a rotation of A (rotation
    /// vector, 1/rad); with respect to a rotation of B it is the negative.
    pub weight_grad: DVec3,
}
