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
