//! A body's shape as the contact stage sees it: what varies per body, its
//! collider's pose ([`ColliderPose`]: centre and symmetry axis), and what
//! its constants fix, its collider's shape ([`ColliderShape`]: kind,
//! radius, half length), kept once per distinct body value as the
//! constants are (`Bodies`, [`Shapes`]). A kernel's input is assembled from
//! the two at the pair ([`Shapes::collider`]; a fibre's is a [`FibreGeom`]).
//!
//! One layout for every kind, so that the broad phase, the skin test, the
//! motion bound, the start-up overlap check and an MPI rank's ghost width
//! treat every body as the capsule of its axis segment: a fibre lies
//! inside its capsule; a sphere *is* a capsule of zero length (its pose's
//! axis is the fixed `x`: a sphere's contacts do not depend on its
//! orientation, so its pose does not turn and its motion bound is its
//! centre's shift). The kind tells the dispatch which kernel the pair's
//! colliders go to.

use super::fibre_fibre::dome_sag;
use super::{Collider, FibreGeom, SphereGeom};
use crate::body::{Bodies, Body, BodyState, Shape, ValueIndex};
use glam::DVec3;

/// The kind of a body's collider. A new shape is one variant here, its
/// [`ColliderShape::of`] and [`Shapes::collider`] arms and its kernels'
/// arms in [`super::dispatch`].
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

/// Where a body's collider is, the one record the contact stage keeps per
/// body: its centre and its unit symmetry axis (body x) in world
/// coordinates (a sphere's is the fixed `x`; by default, at the origin
/// along `x`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColliderPose {
    /// Centre of mass (world).
    pub centre: DVec3,
    /// Unit symmetry axis (world).
    pub axis: DVec3,
}

impl Default for ColliderPose {
    fn default() -> Self {
        ColliderPose {
            centre: DVec3::ZERO,
            axis: DVec3::X,
        }
    }
}

impl ColliderPose {
    /// The pose of a body of kind `kind` at state `s`.
    #[inline(always)]
    pub fn of(kind: ColliderKind, s: &BodyState) -> Self {
        ColliderPose {
            centre: s.x,
            axis: match kind {
                ColliderKind::Fibre => crate::math::body_x_axis(s.rot.q),
                ColliderKind::Sphere => DVec3::X,
            },
        }
    }
}

/// What a body's constants fix of its collider: its kind and its capsule
/// (radius, half length of the axis segment; a sphere's is 0), and the
/// reach of its motion bound ([`motion_bound`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColliderShape {
    /// The kernels' kind.
    pub kind: ColliderKind,
    /// D/2.
    pub radius: f64,
    /// L/2 (0 for a sphere).
    pub half_length: f64,
    /// The distance from the centre of the body's farthest point, domes
    /// included: `√((h + sag)² + r²)`.
    pub reach: f64,
}

impl ColliderShape {
    /// The collider shape of `body`.
    pub fn of(body: &Body) -> Self {
        let (kind, radius, half_length) = match body.shape {
            Shape::Fibre { diameter, length } => {
                (ColliderKind::Fibre, 0.5 * diameter, 0.5 * length)
            }
            Shape::Sphere { diameter } => (ColliderKind::Sphere, 0.5 * diameter, 0.0),
            Shape::Rigid { .. } => {
                unreachable!("scene validation admits no rigid body in contact scenes")
            }
        };
        ColliderShape {
            kind,
            radius,
            half_length,
            reach: Self::reach_of(radius, half_length),
        }
    }

    /// [`ColliderShape::reach`] of a capsule of radius `radius` and half
    /// length `half_length`.
    pub fn reach_of(radius: f64, half_length: f64) -> f64 {
        let along = half_length + dome_sag(radius);
        (along * along + radius * radius).sqrt()
    }

    /// The fibre of this shape at `pose` (the fibre kernels' input; a
    /// sphere's capsule of zero length).
    #[inline(always)]
    pub fn fibre(&self, pose: &ColliderPose) -> FibreGeom {
        FibreGeom {
            centre: pose.centre,
            axis: pose.axis,
            radius: self.radius,
            half_length: self.half_length,
        }
    }

    /// The collider of this shape at `pose`.
    #[inline(always)]
    pub fn collider(&self, pose: &ColliderPose) -> Collider<'static> {
        match self.kind {
            ColliderKind::Fibre => Collider::Fibre(self.fibre(pose)),
            ColliderKind::Sphere => Collider::Sphere(SphereGeom {
                centre: pose.centre,
                radius: self.radius,
            }),
        }
    }
}

/// The collider shape of each distinct body value of a contact scene, in
/// the order of [`Bodies::kinds`] (one for a bed of identical fibres).
pub fn shapes(bodies: &Bodies) -> Vec<ColliderShape> {
    bodies.kinds().iter().map(ColliderShape::of).collect()
}

/// Each body's collider shape by storage index: the table of [`shapes`]
/// read through the bodies' [`Bodies::index`] (nothing per body beyond
/// what the constants keep).
#[derive(Clone, Copy, Debug)]
pub struct Shapes<'a> {
    table: &'a [ColliderShape],
    index: ValueIndex<'a>,
    /// The one shape of every body, when the table has one (a bed of
    /// identical bodies): read without the index, at every pair.
    one: Option<&'a ColliderShape>,
}

impl<'a> Shapes<'a> {
    /// `table` (from [`shapes`]) for `bodies`.
    #[inline]
    pub fn new(table: &'a [ColliderShape], bodies: &'a Bodies) -> Self {
        Shapes {
            table,
            index: bodies.index(),
            one: table.first().filter(|_| table.len() == 1),
        }
    }

    /// Body `i`'s collider shape.
    #[inline(always)]
    pub fn get(self, i: usize) -> &'a ColliderShape {
        match self.one {
            Some(shape) => shape,
            None => &self.table[self.index.of(i)],
        }
    }

    /// Body `i`'s collider at `pose`.
    #[inline(always)]
    pub fn collider(self, i: usize, pose: &ColliderPose) -> Collider<'static> {
        self.get(i).collider(pose)
    }
}

/// The kernels' record of `body` at state `s`: its shape at its pose, as a
/// fibre (a sphere's with zero half length).
#[inline]
pub fn geom(body: &Body, s: &BodyState) -> FibreGeom {
    let shape = ColliderShape::of(body);
    shape.fibre(&ColliderPose::of(shape.kind, s))
}

/// A bound on how far any point of a body of reach `reach`
/// ([`ColliderShape::reach`]) moved from pose `old` to `new` (so how much
/// any of its support values changed): the centre's shift plus the
/// farthest point's `ρ |Δa|` (the least rotation taking one axis to the
/// other moves a point at distance ρ from the centre by ρ|Δa|). Rounded up
/// to f32 (4 bytes a body).
#[inline]
pub fn motion_bound(old: &ColliderPose, new: &ColliderPose, reach: f64) -> f32 {
    let m = old.centre.distance(new.centre) + reach * old.axis.distance(new.axis);
    let r = m as f32;
    if f64::from(r) < m {
        r.next_up()
    } else {
        r
    }
}
