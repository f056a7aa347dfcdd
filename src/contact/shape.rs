//! A body's shape as the contact stage sees it: its collider kind (what the
//! dispatch matches on, [`super::dispatch`]) and its geometry record.
//!
//! The record is one layout for every kind ([`FibreGeom`]: centre, axis,
//! radius, half length), so that the broad phase, the skin test, the motion
//! bound, the start-up overlap check and an MPI rank's ghost width treat
//! every body as the capsule of its axis segment: a fibre lies inside its
//! capsule; a sphere *is* a capsule of zero length (its record's axis is
//! the fixed `x`: a sphere's contacts do not depend on its orientation, so
//! its record does not turn and its motion bound is its centre's shift).
//! The kind, one byte per body kept apart from the records, tells the
//! dispatch which kernel reads the record.

use super::{Collider, FibreGeom, SphereGeom};
use crate::body::{Bodies, Body, BodyState, Shape};

/// The kind of a body's collider. A new shape is one variant here, its
/// record in [`geom`], its [`collider`] arm and its kernels' arms in
/// [`super::dispatch`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum ColliderKind {
    /// A solid flat-ended cylinder.
    Fibre = 0,
    /// A solid sphere.
    Sphere = 1,
}

impl ColliderKind {
    /// The collider kind of `shape`; `None` for a shape that has no contact
    /// kernels (a general rigid body: contact-free scenes only).
    pub fn of(shape: &Shape) -> Option<Self> {
        match shape {
            Shape::Fibre { .. } => Some(ColliderKind::Fibre),
            Shape::Sphere { .. } => Some(ColliderKind::Sphere),
            Shape::Rigid { .. } => None,
        }
    }

    /// The kind's name, as scenario files spell its shape.
    pub fn name(self) -> &'static str {
        match self {
            ColliderKind::Fibre => "fibre",
            ColliderKind::Sphere => "sphere",
        }
    }
}

/// The kernels' record of `body` at state `s` (see the module
/// documentation).
#[inline]
pub fn geom(body: &Body, s: &BodyState) -> FibreGeom {
    match body.shape {
        Shape::Fibre { diameter, length } => FibreGeom {
            centre: s.x,
            axis: crate::math::body_x_axis(s.rot.q),
            radius: 0.5 * diameter,
            half_length: 0.5 * length,
        },
        Shape::Sphere { diameter } => FibreGeom {
            centre: s.x,
            axis: glam::DVec3::X,
            radius: 0.5 * diameter,
            half_length: 0.0,
        },
        Shape::Rigid { .. } => {
            unreachable!("scene validation admits no rigid body in contact scenes")
        }
    }
}

/// The collider of a body of kind `kind` whose record is `g`.
#[inline(always)]
pub fn collider(kind: ColliderKind, g: &FibreGeom) -> Collider<'_> {
    match kind {
        ColliderKind::Fibre => Collider::Fibre(g),
        ColliderKind::Sphere => Collider::Sphere(SphereGeom {
            centre: g.centre,
            radius: g.radius,
        }),
    }
}

/// The collider kind of every body of a contact scene, by storage index.
pub fn kinds(bodies: &Bodies) -> Vec<ColliderKind> {
    bodies
        .iter()
        .map(|b| {
            ColliderKind::of(&b.shape)
                .expect("scene validation admits no rigid body in contact scenes")
        })
        .collect()
}
