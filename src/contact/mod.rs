//! Contacts of rigid flat-ended cylindrical fibres and spheres (with each
//! other and with the walls of a box) and the Hertz force law they feed
//! (docs/physics.md §3).
//!
//! Every kernel appends [`ContactPoint`]s; the force on body A is
//! `weight * F_hertz(overlap) * normal` acting at `point` (on B the opposite),
//! and the stored energy is `weight * U_hertz(overlap)`. Every model is a
//! potential whose exact gradient is the returned force and torque (checked
//! by finite differences in the tests), except on documented measure-zero
//! switching sets.
//!
//! The pieces: [`shape`] gives each body its collider: a pose per body
//! and a shape (kind, radius, half length) per distinct body value; [`dispatch`] maps a kind pair to its kernel ([`fibre_fibre`],
//! [`fibre_wall`], [`sphere_sphere`], [`sphere_wall`], [`sphere_fibre`]); `law/` turns a contact point into
//! its loads (the Hertz law [`hertz`], the restitution [`damping`]), its
//! constants tabled once per pair of contact kinds; [`broad`] keeps the
//! candidate pairs; `blocks.rs` is the one loop over them; `ledger.rs`
//! accounts the work of the non-conservative loads; [`stage`] runs a
//! computation. [`tangential`] is the friction law (a spring per contact
//! and the Coulomb cap) that the law's tangential part calls in frictional
//! scenes; `history.rs` keeps each touching contact's spring by its pair
//! and slot. Models, limits and their history: docs/contacts.md; the
//! pipeline: docs/architecture.md.

pub(crate) mod blocks;
pub mod broad;
pub(crate) mod carry;
pub mod damping;
pub mod dispatch;
pub mod fibre_fibre;
pub mod fibre_wall;
pub mod hertz;
mod hertz_spheres;
pub(crate) mod history;
pub(crate) mod law;
pub(crate) mod ledger;
pub(crate) mod memory;
pub(crate) mod overlap_check;
#[cfg(feature = "replay")]
pub mod replay;
pub mod shape;
pub mod sphere;
pub mod sphere_fibre;
pub mod sphere_sphere;
pub mod sphere_wall;
pub mod stage;
pub mod tangential;
pub mod walls;

pub use broad::{aabb, candidate_pairs};
pub use dispatch::{contacts, contacts_remembering, Collider};
pub use fibre_fibre::{contact_fibre_fibre, contact_fibre_fibre_remembering, PairMemory};
pub use fibre_wall::contact_fibre_wall;
pub use hertz::HertzLaw;
pub use shape::{ColliderKind, ColliderPose, ColliderShape};
pub use sphere::SphereGeom;
pub use sphere_fibre::{
    contact_fibre_sphere, contact_sphere_fibre, sphere_fibre_depth, SphereFibreDepth,
    SphereFibreFeature,
};
pub use sphere_sphere::{contact_sphere_sphere, sphere_sphere_point};
pub use sphere_wall::contact_sphere_wall;
pub use walls::{box_walls, Wall, Walls};

use glam::DVec3;

/// A fibre as the kernels see it: solid flat-ended cylinder. Assembled at
/// a pair from the body's pose and its shape (`shape.rs`); the broad phase
/// and the overlap check see a sphere as one of zero half length.
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

/// Diagnostic counts of the kernels, added to by every call they are passed
/// to. Each caller owns its counters (the stage keeps one set for its whole
/// life), so concurrent callers never see each other's counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KernelCounters {
    /// parry contact queries (end-involved fibre–fibre pairs whose feature
    /// scan handed over to the iterative search, see `fallbacks`).
    pub parry_calls: u64,
    /// parry answers rejected by the sanity checks (the depth is recomputed
    /// either way; parry's normal, if finite, still seeds the search).
    pub parry_rejects: u64,
    /// parry "no contact" verdicts that no separating axis confirmed (parry
    /// is still followed; zero in the tests and in test case 2).
    pub parry_unconfirmed: u64,
    /// End-involved fibre–fibre depths computed by the feature-pair
    /// kernels (each a scan of the feature pairs near the contact).
    pub end_scans: u64,
    /// Of those, the scans that could not certify their answer and handed
    /// over to the iterative search (seeded by parry: each is also one
    /// `parry_calls`, except in the side–side escape, which seeds it with
    /// its own normals).
    pub fallbacks: u64,
    /// End-involved depths answered from the pair's memory of its last
    /// scan (one kernel, or nothing for a pair still apart) instead of a
    /// scan (`fibre_fibre/coherence.rs`).
    pub remembered: u64,
    /// Fibre pairs passed over before the regime dispatch: apart in every
    /// regime by more than they moved since (their memory: capsules apart,
    /// or cylinders apart away from the parallel band).
    pub passed_over: u64,
}

impl std::ops::Add for KernelCounters {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        KernelCounters {
            parry_calls: self.parry_calls + o.parry_calls,
            parry_rejects: self.parry_rejects + o.parry_rejects,
            parry_unconfirmed: self.parry_unconfirmed + o.parry_unconfirmed,
            end_scans: self.end_scans + o.end_scans,
            fallbacks: self.fallbacks + o.fallbacks,
            remembered: self.remembered + o.remembered,
            passed_over: self.passed_over + o.passed_over,
        }
    }
}
