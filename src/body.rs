//! Shapes, their mass properties (docs/physics.md §2), and the per-body state.

use glam::{DQuat, DVec3};

/// A rigid body's shape. The fibre's symmetry axis is body x (the paper's `B`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// Solid flat-ended cylinder.
    Fibre {
        /// D, m.
        diameter: f64,
        /// L, m.
        length: f64,
    },
    /// Solid sphere.
    Sphere {
        /// m.
        diameter: f64,
    },
    /// A general rigid body given by its mass and principal inertia
    /// (`shape = "rigid"`, contact-free scenes only); its geometry is that of
    /// the uniform ellipsoid with the same mass properties, used only to
    /// bound the speed of its points.
    Rigid {
        /// Semi-axes of the equivalent ellipsoid along body x, y, z, m:
        /// `a² = 5 (I₂ + I₃ − I₁) / (2m)` and cyclically.
        semi_axes: DVec3,
    },
}

impl Shape {
    /// Volume, m³.
    pub fn volume(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Shape::Fibre { diameter, length } => PI * diameter * diameter * length / 4.0,
            Shape::Sphere { diameter } => PI * diameter.powi(3) / 6.0,
            Shape::Rigid { semi_axes: a } => 4.0 / 3.0 * PI * a.x * a.y * a.z,
        }
    }

    /// Principal moments of inertia per unit mass, body frame.
    fn inertia_per_mass(&self) -> DVec3 {
        match *self {
            Shape::Fibre { diameter, length } => {
                let r = 0.5 * diameter;
                let axial = r * r / 2.0;
                let transverse = (3.0 * r * r + length * length) / 12.0;
                DVec3::new(axial, transverse, transverse)
            }
            Shape::Sphere { diameter } => DVec3::splat(0.4 * (0.5 * diameter).powi(2)),
            Shape::Rigid { semi_axes: a } => {
                let a2 = a * a;
                0.2 * DVec3::new(a2.y + a2.z, a2.x + a2.z, a2.x + a2.y)
            }
        }
    }

    /// Diameter of the cylinder or the sphere (a rigid body's largest
    /// equivalent-ellipsoid diameter).
    pub fn diameter(&self) -> f64 {
        match *self {
            Shape::Fibre { diameter, .. } | Shape::Sphere { diameter } => diameter,
            Shape::Rigid { semi_axes } => 2.0 * semi_axes.max_element(),
        }
    }

    /// Radius of the smallest sphere about the centre of mass that holds the body.
    pub fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Fibre { diameter, length } => {
                0.5 * (diameter * diameter + length * length).sqrt()
            }
            Shape::Sphere { diameter } => 0.5 * diameter,
            Shape::Rigid { semi_axes } => semi_axes.max_element(),
        }
    }
}

/// Principal inertia (diagonal in the body frame) and its inverse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia {
    /// Principal moments `(I₁, I₂, I₃)`, kg m², body frame.
    pub principal: DVec3,
    /// Their reciprocals.
    pub inverse: DVec3,
}

impl Inertia {
    /// The inertia with these principal moments.
    pub fn new(principal: DVec3) -> Self {
        Inertia {
            principal,
            inverse: principal.recip(),
        }
    }

    /// Euler's equations in the body frame, paper Eq. 4:
    /// `dω_b/dt = I⁻¹ (τ_b − ω_b × I ω_b)`.
    #[inline]
    pub fn angular_acceleration(&self, omega_b: DVec3, torque_b: DVec3) -> DVec3 {
        self.inverse * (torque_b - omega_b.cross(self.principal * omega_b))
    }

    /// Eq. 4 with a world-frame torque `τ_w` at orientation `q`:
    /// `dω_b/dt = I⁻¹ (q* τ_w q − ω_b × I ω_b)` (a zero torque is not rotated,
    /// see [`crate::math::torque_to_body`]).
    #[inline]
    pub fn angular_acceleration_world(&self, q: DQuat, omega_b: DVec3, torque_w: DVec3) -> DVec3 {
        self.angular_acceleration(omega_b, crate::math::torque_to_body(q, torque_w))
    }

    /// Rotational kinetic energy `½ ω_b · I ω_b`.
    #[inline]
    pub fn kinetic_energy(&self, omega_b: DVec3) -> f64 {
        0.5 * omega_b.dot(self.principal * omega_b)
    }
}

/// Index of a [`Material`] in its scene's material table.
pub type MaterialId = u32;

/// Elastic constants and density shared by the bodies made of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// The scenario's `[material.NAME]`, or `inline-K` for values given on
    /// a body (identical inline values share one entry).
    pub name: String,
    /// kg/m³.
    pub density: f64,
    /// Young's modulus, Pa, used only by contacts (NaN in contact-free
    /// scenes that do not give it).
    pub young: f64,
    /// Poisson ratio, likewise.
    pub poisson: f64,
    /// Its own Coulomb coefficient (`[material.NAME] friction`); `None`:
    /// the scene's `[contact]` default (`tangential::Friction`).
    pub friction: Option<f64>,
}

/// Constant mechanical properties of one body: what the step reads. Labels
/// (id, name) and materials live in their own tables of the scene, so the
/// hot loops stream only numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// The body's shape.
    pub shape: Shape,
    /// Its material in the scene's table.
    pub material: MaterialId,
    /// kg.
    pub mass: f64,
    /// `1/m`, kept so the step multiplies instead of dividing.
    pub inv_mass: f64,
    /// Principal inertia, body frame.
    pub inertia: Inertia,
}

impl Body {
    /// A body of `shape` and `density`, made of `material`.
    pub fn new(shape: Shape, material: MaterialId, density: f64) -> Self {
        let mass = density * shape.volume();
        Body {
            shape,
            material,
            mass,
            inv_mass: 1.0 / mass,
            inertia: Inertia::new(mass * shape.inertia_per_mass()),
        }
    }

    /// A rigid body of `mass` and principal moments `inertia` (body frame),
    /// which must satisfy the triangle inequalities `Iᵢ + Iⱼ ≥ I_k`
    /// (checked by the scenario), made of `material`.
    pub fn rigid(mass: f64, inertia: DVec3, material: MaterialId) -> Self {
        let semi2 = 2.5 / mass
            * DVec3::new(
                inertia.y + inertia.z - inertia.x,
                inertia.x + inertia.z - inertia.y,
                inertia.x + inertia.y - inertia.z,
            );
        Body {
            shape: Shape::Rigid {
                semi_axes: semi2.max(DVec3::ZERO).to_array().map(f64::sqrt).into(),
            },
            material,
            mass,
            inv_mass: 1.0 / mass,
            inertia: Inertia::new(inertia),
        }
    }
}

/// Rotational state advanced by a rotator: orientation (body → world) and the
/// body-frame angular velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotState {
    /// Orientation, body → world (unit).
    pub q: DQuat,
    /// Angular velocity in the body frame, rad/s.
    pub omega_b: DVec3,
}

/// Full kinematic state of one body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Centre of mass, m (world).
    pub x: DVec3,
    /// Its velocity, m/s (world).
    pub v: DVec3,
    /// Orientation and spin.
    pub rot: RotState,
}

/// The constants of a scene's bodies, by storage index, kept once per
/// distinct value: a table of the distinct [`Body`] values in order of
/// first appearance and each body's entry in it (one entry for all while
/// every body is the same, as in a bed of identical fibres). Two bodies
/// share an entry when every number of theirs has the same bits.
#[derive(Debug, Clone, Default)]
pub struct Bodies {
    /// The distinct values.
    kinds: Vec<Body>,
    /// Body `i`'s entry in `kinds` is `kind_of[i & mask]`: one entry (0)
    /// standing for every body while there is one value (`mask` 0), one
    /// per body once there are more (`mask` all ones); read without a
    /// branch.
    kind_of: Vec<u32>,
    mask: usize,
    /// Number of bodies.
    len: usize,
    /// The entry of each value, for [`Bodies::push`]; rebuilt on demand
    /// (empty after [`Bodies::shrink_to_fit`]).
    lookup: std::collections::HashMap<BodyBits, u32>,
}

/// Each body's entry in the distinct values of a [`Bodies`]
/// ([`Bodies::index`]), read as [`Bodies::kind`] reads it, without the
/// bodies: the row of body `i` in a table with one row per distinct value.
#[derive(Debug, Clone, Copy)]
pub struct ValueIndex<'a> {
    kind_of: &'a [u32],
    mask: usize,
}

impl ValueIndex<'_> {
    /// Body `i`'s entry (any `i` while every body is the same; the
    /// caller's own per-body arrays bound it).
    #[inline(always)]
    pub fn of(self, i: usize) -> usize {
        self.kind_of[i & self.mask] as usize
    }
}

/// Every number of a [`Body`], as bits (its identity in [`Bodies`]).
type BodyBits = [u64; 13];

impl Body {
    fn bits(&self) -> BodyBits {
        let (tag, s) = match self.shape {
            Shape::Fibre { diameter, length } => (0, [diameter, length, 0.0]),
            Shape::Sphere { diameter } => (1, [diameter, 0.0, 0.0]),
            Shape::Rigid { semi_axes } => (2, semi_axes.to_array()),
        };
        let (p, i) = (self.inertia.principal, self.inertia.inverse);
        let f = [
            s[0],
            s[1],
            s[2],
            self.mass,
            self.inv_mass,
            p.x,
            p.y,
            p.z,
            i.x,
            i.y,
            i.z,
        ];
        let mut out = [0; 13];
        out[0] = tag;
        out[1] = u64::from(self.material);
        for (o, x) in out[2..].iter_mut().zip(f) {
            *o = x.to_bits();
        }
        out
    }
}

impl Bodies {
    /// No bodies.
    pub fn new() -> Self {
        Self::default()
    }

    /// `n` bodies all equal to `body`.
    pub fn uniform(body: Body, n: usize) -> Self {
        let mut b = Self::new();
        if n > 0 {
            b.push(body);
            b.len = n;
        }
        b
    }

    /// Number of bodies.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are none.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Body `i`'s constants (panics if `i >= len`).
    #[inline(always)]
    pub fn get(&self, i: usize) -> &Body {
        &self.kinds[self.kind(i)]
    }

    /// Body `i`'s entry in [`Bodies::kinds`] (panics if `i >= len`).
    #[inline(always)]
    pub fn kind(&self, i: usize) -> usize {
        assert!(i < self.len, "a body past the end");
        self.kind_of[i & self.mask] as usize
    }

    /// The distinct values, in order of first appearance.
    pub fn kinds(&self) -> &[Body] {
        &self.kinds
    }

    /// Each body's entry in [`Bodies::kinds`], for a table kept beside it
    /// with one row per distinct value (what a stage derives from the
    /// constants, kept once per value too).
    #[inline]
    pub fn index(&self) -> ValueIndex<'_> {
        ValueIndex {
            kind_of: &self.kind_of,
            mask: self.mask,
        }
    }

    /// Every body's constants, in storage order.
    pub fn iter(&self) -> Iter<'_> {
        Iter {
            kinds: &self.kinds,
            kind_of: &self.kind_of,
            mask: self.mask,
            next: 0..self.len,
        }
    }

    /// Every body's constants, in storage order, for the pool.
    pub fn par_iter(&self) -> impl rayon::iter::IndexedParallelIterator<Item = &Body> + '_ {
        use rayon::prelude::*;
        (0..self.len).into_par_iter().map(move |i| self.get(i))
    }

    /// Appends a body (sharing the entry of an equal one).
    pub fn push(&mut self, body: Body) {
        if self.lookup.len() != self.kinds.len() {
            self.lookup = (self.kinds.iter().enumerate())
                .map(|(k, b)| (b.bits(), k as u32))
                .collect();
        }
        let next = self.kinds.len() as u32;
        let k = *self.lookup.entry(body.bits()).or_insert(next);
        if k == next {
            self.kinds.push(body);
            match self.kinds.len() {
                1 => self.kind_of = vec![0],
                // The first other value: from here on each body has its entry.
                2 => {
                    self.kind_of = vec![0; self.len];
                    self.mask = usize::MAX;
                }
                _ => {}
            }
        }
        if self.mask != 0 {
            self.kind_of.push(k);
        }
        self.len += 1;
    }

    /// These bodies `copies` times over, one copy after the other.
    pub fn repeat(&self, copies: usize) -> Self {
        let mut out = self.clone();
        out.len = self.len * copies;
        if self.mask != 0 {
            out.kind_of = self.kind_of.repeat(copies);
        }
        out
    }

    /// Releases spare capacity and the lookup of [`Bodies::push`] (rebuilt
    /// if more are pushed).
    pub fn shrink_to_fit(&mut self) {
        self.kinds.shrink_to_fit();
        self.kind_of.shrink_to_fit();
        self.lookup = Default::default();
    }
}

impl PartialEq for Bodies {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl std::ops::Index<usize> for Bodies {
    type Output = Body;
    #[inline(always)]
    fn index(&self, i: usize) -> &Body {
        self.get(i)
    }
}

impl FromIterator<Body> for Bodies {
    fn from_iter<I: IntoIterator<Item = Body>>(iter: I) -> Self {
        let mut b = Self::new();
        b.extend(iter);
        b.shrink_to_fit();
        b
    }
}

impl Extend<Body> for Bodies {
    fn extend<I: IntoIterator<Item = Body>>(&mut self, iter: I) {
        for body in iter {
            self.push(body);
        }
    }
}

impl<'a> IntoIterator for &'a Bodies {
    type Item = &'a Body;
    type IntoIter = Iter<'a>;
    fn into_iter(self) -> Iter<'a> {
        self.iter()
    }
}

/// The bodies' constants in storage order ([`Bodies::iter`]).
#[derive(Clone)]
pub struct Iter<'a> {
    kinds: &'a [Body],
    kind_of: &'a [u32],
    mask: usize,
    next: std::ops::Range<usize>,
}

impl<'a> Iter<'a> {
    #[inline(always)]
    fn at(&self, i: usize) -> &'a Body {
        &self.kinds[self.kind_of[i & self.mask] as usize]
    }
}

impl<'a> Iterator for Iter<'a> {
    type Item = &'a Body;
    #[inline(always)]
    fn next(&mut self) -> Option<&'a Body> {
        self.next.next().map(|i| self.at(i))
    }
    #[inline]
    fn size_hint(&self) -> (usize, Option<usize>) {
        self.next.size_hint()
    }
}

impl ExactSizeIterator for Iter<'_> {}

impl<'a> DoubleEndedIterator for Iter<'a> {
    fn next_back(&mut self) -> Option<&'a Body> {
        self.next.next_back().map(|i| self.at(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fibre(length: f64, material: MaterialId) -> Body {
        let shape = Shape::Fibre {
            diameter: 0.01,
            length,
        };
        Body::new(shape, material, 1100.0)
    }

    /// Reference: the same bodies in a plain `Vec`, read back one by one.
    #[test]
    fn equal_bodies_share_an_entry_and_each_reads_back_its_own() {
        let sphere = Body::new(Shape::Sphere { diameter: 0.01 }, 0, 1100.0);
        let rigid = Body::rigid(2.0, DVec3::new(1.0, 1.5, 2.0), 1);
        let list = [
            fibre(0.03, 0),
            fibre(0.03, 0),
            fibre(0.03, 1),
            sphere,
            fibre(0.03, 0),
            fibre(0.030000000000000002, 0),
            rigid,
            sphere,
        ];
        let b: Bodies = list.iter().copied().collect();
        assert_eq!((b.len(), b.kinds().len()), (list.len(), 5));
        for (i, want) in list.iter().enumerate() {
            assert_eq!(b.get(i), want);
            assert_eq!(&b[i], want);
        }
        assert!(b.iter().eq(list.iter()));
        assert!(b.iter().rev().eq(list.iter().rev()));
        assert_eq!(b.iter().len(), list.len());
        assert_eq!(b.kind(4), b.kind(0));
        assert_ne!(b.kind(5), b.kind(0));
        // Pushing after the lookup was dropped finds the old entries.
        let mut more = b.clone();
        more.push(sphere);
        more.push(fibre(0.04, 0));
        assert_eq!(more.kinds().len(), 6);
        assert_eq!(more.kind(8), b.kind(3));
        assert_eq!(more[9], fibre(0.04, 0));
    }

    #[test]
    fn bodies_all_alike_keep_one_value_and_nothing_per_body() {
        let b: Bodies = std::iter::repeat_n(fibre(0.03, 0), 1000).collect();
        assert_eq!((b.len(), b.kinds().len(), b.kind_of.len()), (1000, 1, 1));
        assert_eq!(b, Bodies::uniform(fibre(0.03, 0), 1000));
        assert_ne!(b, Bodies::uniform(fibre(0.03, 0), 999));
        assert_ne!(b, Bodies::uniform(fibre(0.03, 1), 1000));
        // A second value gives every body its entry.
        let mut two = b.clone();
        two.push(fibre(0.05, 0));
        assert_eq!(
            (two.kind_of.len(), two.kind(999), two.kind(1000)),
            (1001, 0, 1)
        );
        assert_eq!(two[1000], fibre(0.05, 0));
    }

    #[test]
    #[should_panic(expected = "a body past the end")]
    fn a_body_past_the_end_is_refused() {
        let _ = Bodies::uniform(fibre(0.03, 0), 3)[3];
    }

    #[test]
    fn repeat_is_the_copies_one_after_the_other() {
        let list = [fibre(0.03, 0), fibre(0.02, 0), fibre(0.03, 0)];
        let b: Bodies = list.iter().copied().collect();
        let want: Vec<Body> = (0..4).flat_map(|_| list).collect();
        assert!(b.repeat(4).iter().eq(want.iter()));
        assert_eq!(b.repeat(4), want.into_iter().collect());
        let one = Bodies::uniform(list[0], 5).repeat(3);
        assert_eq!((one.len(), one.kind_of.len()), (15, 1));
    }
}
