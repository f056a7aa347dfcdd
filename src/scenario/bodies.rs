//! One `[[body]]` table into a body, its initial state and its prescribed
//! torque; the scene's material table.

use super::check::{self, Ctx};
use super::file::{BodySection, ScenarioFile, ShapeName};
use crate::body::{Body, BodyState, Material, MaterialId, RotState, Shape};
use crate::error::Result;
use crate::fmt::short;
use crate::torque::PrescribedTorque;
use glam::{DQuat, DVec3};

/// Bodies (any point of them) must move slower than this, m/s.
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;

/// Euclidean norm without overflow for huge components (1e300).
fn norm(v: DVec3) -> f64 {
    let s = v.abs().max_element();
    if s > 0.0 && s.is_finite() {
        s * (v / s).length()
    } else {
        s
    }
}

/// Exact axis-aligned bounds of a body ([`crate::contact::aabb`]).
pub fn aabb(shape: &Shape, st: &BodyState) -> (DVec3, DVec3) {
    crate::contact::aabb(shape, st.x, st.rot.q * DVec3::X)
}

pub(super) fn build_body(
    cx: &Ctx,
    raw: &ScenarioFile,
    i: usize,
    b: &BodySection,
    needs_contacts: bool,
    materials: &mut Materials,
) -> Result<(Body, BodyState, Option<PrescribedTorque>)> {
    let key = |k: &str| format!("body[{i}].{k}");
    if b.shape == ShapeName::Rigid {
        return build_rigid(cx, i, b, needs_contacts, materials);
    }
    for (k, given) in [("mass", b.mass.is_some()), ("inertia", b.inertia.is_some())] {
        if given {
            return Err(cx.err(&key(k), check::rigid_only(k)));
        }
    }
    let diameter = match b.diameter {
        Some(d) => cx.positive(&key("diameter"), d)?,
        None => return Err(cx.err(&key("diameter"), "give the `diameter` (m)")),
    };
    let shape = match (b.shape, b.length) {
        (ShapeName::Fibre, Some(l)) => Shape::Fibre {
            diameter,
            length: cx.positive(&key("length"), l)?,
        },
        (ShapeName::Fibre, None) => {
            return Err(cx.err(&key("length"), "a fibre needs `length` (m)"))
        }
        (ShapeName::Sphere, None) => Shape::Sphere { diameter },
        (ShapeName::Sphere, Some(_)) => return Err(cx.err(&key("length"), check::SPHERE_LENGTH)),
        (ShapeName::Rigid, _) => unreachable!("built above"),
    };

    // Material: a named table or inline values, not both. Messages name
    // where the value was given.
    let mkey = |k: &str| match &b.material {
        Some(m) => format!("material.{m}.{k}"),
        None => key(k),
    };
    let (density, young, poisson, friction) = match &b.material {
        Some(m) => {
            if b.density.is_some() || b.young.is_some() || b.poisson.is_some() {
                return Err(cx.err(&key("material"), check::MATERIAL_AND_INLINE));
            }
            let mat = raw.material.get(m).ok_or_else(|| {
                let known: Vec<&str> = raw.material.keys().map(String::as_str).collect();
                cx.err(&key("material"), check::unknown_material(m, &known))
            })?;
            // (`friction` is checked with the `[material]` tables.)
            (mat.density, mat.young, mat.poisson, mat.friction)
        }
        None => (
            b.density
                .ok_or_else(|| cx.err(&key("density"), "give `density` (kg/m^3) or `material`"))?,
            b.young,
            b.poisson,
            None,
        ),
    };
    let density = cx.positive(&mkey("density"), density)?;
    let (young, poisson) = if needs_contacts {
        let e = young.ok_or_else(|| {
            cx.err(
                &mkey("young"),
                "bodies that can touch need Young's modulus `young` (Pa)",
            )
        })?;
        let nu = poisson.ok_or_else(|| {
            cx.err(
                &mkey("poisson"),
                "bodies that can touch need Poisson's ratio `poisson`",
            )
        })?;
        (
            cx.positive(&mkey("young"), e)?,
            cx.poisson(&mkey("poisson"), nu)?,
        )
    } else {
        (young.unwrap_or(f64::NAN), poisson.unwrap_or(f64::NAN))
    };

    let (q, x, v, omega_w) = kinematics(cx, i, b, &shape)?;
    let torque = prescribed(cx, i, b)?;
    let material = materials.intern(b.material.as_deref(), density, young, poisson, friction);
    let body = Body::new(shape, material, density);
    let state = BodyState {
        x,
        v,
        rot: RotState {
            q,
            omega_b: q.conjugate() * omega_w,
        },
    };
    Ok((body, state, torque))
}

/// A `shape = "rigid"` body: `mass` and principal `inertia` instead of a
/// size and a material; contact-free scenes only.
fn build_rigid(
    cx: &Ctx,
    i: usize,
    b: &BodySection,
    needs_contacts: bool,
    materials: &mut Materials,
) -> Result<(Body, BodyState, Option<PrescribedTorque>)> {
    let key = |k: &str| format!("body[{i}].{k}");
    if needs_contacts {
        return Err(cx.err(&key("shape"), check::RIGID_CONTACTS));
    }
    let given = [
        b.diameter.is_some(),
        b.length.is_some(),
        b.material.is_some(),
        b.density.is_some(),
        b.young.is_some(),
        b.poisson.is_some(),
    ];
    if let Some((k, _)) = check::NOT_FOR_RIGID.iter().zip(given).find(|(_, g)| *g) {
        return Err(cx.err(&key(k), check::not_for_rigid(k)));
    }
    let mass = match b.mass {
        Some(m) => cx.positive(&key("mass"), m)?,
        None => return Err(cx.err(&key("mass"), "a rigid body needs its `mass` (kg)")),
    };
    let Some(moments) = b.inertia else {
        return Err(cx.err(
            &key("inertia"),
            "a rigid body needs its principal moments `inertia = [I1, I2, I3]` about body x, y, z (kg m^2)",
        ));
    };
    for (k, &m) in moments.iter().enumerate() {
        cx.positive(&key(&format!("inertia[{k}]")), m)?;
    }
    if let Some(m) = check::not_inertia(moments) {
        return Err(cx.err(&key("inertia"), m));
    }
    let shape_probe = Body::rigid(mass, DVec3::from_array(moments), 0).shape;
    let (q, x, v, omega_w) = kinematics(cx, i, b, &shape_probe)?;
    let torque = prescribed(cx, i, b)?;
    let material = materials.intern(None, f64::NAN, f64::NAN, f64::NAN, None);
    let body = Body::rigid(mass, DVec3::from_array(moments), material);
    let state = BodyState {
        x,
        v,
        rot: RotState {
            q,
            omega_b: q.conjugate() * omega_w,
        },
    };
    Ok((body, state, torque))
}

/// Orientation, position, velocity and world angular velocity of a body,
/// checked.
fn kinematics(
    cx: &Ctx,
    i: usize,
    b: &BodySection,
    shape: &Shape,
) -> Result<(DQuat, DVec3, DVec3, DVec3)> {
    let key = |k: &str| format!("body[{i}].{k}");
    let q = match (b.axis, b.quaternion) {
        (Some(_), Some(_)) => return Err(cx.err(&key("axis"), check::AXIS_AND_QUATERNION)),
        (Some(a), None) => {
            let a = cx.finite3(&key("axis"), a)?;
            if a.length() < 1e-12 {
                return Err(cx.err(&key("axis"), check::ZERO_AXIS));
            }
            super::axis::rotation_from_x(a.normalize())
        }
        (None, Some(c)) => {
            let q = crate::math::quat_wxyz(c);
            if let Some(m) = check::not_unit_quaternion(q.length()) {
                return Err(cx.err(&key("quaternion"), m));
            }
            // Only input rounding (< 1e-6) is removed here.
            q.normalize()
        }
        (None, None) => DQuat::IDENTITY,
    };
    let x = cx.finite3(&key("position"), b.position)?;
    let v = cx.finite3(&key("velocity"), b.velocity)?;
    let omega_w = cx.finite3(&key("angular_velocity"), b.angular_velocity)?;
    // Newtonian mechanics: a point of the body at or above the speed of light
    // is not physical (and its energy may overflow, defeating the dt advice).
    let rim = norm(omega_w) * shape.bounding_radius();
    for (k, speed, what) in [
        ("velocity", norm(v), "speed"),
        (
            "angular_velocity",
            rim,
            "rim speed |omega| x bounding radius",
        ),
    ] {
        if speed >= SPEED_OF_LIGHT {
            return Err(cx.err(
                &key(k),
                format!("{what} {} m/s is not physical (at or above the speed of light, 3e8 m/s; fibresim is Newtonian); give a speed far below it", short(speed)),
            ));
        }
    }
    Ok((q, x, v, omega_w))
}

/// The body's prescribed torque, compiled.
fn prescribed(cx: &Ctx, i: usize, b: &BodySection) -> Result<Option<PrescribedTorque>> {
    let key = |k: &str| format!("body[{i}].{k}");
    Ok(match &b.torque {
        Some(t) => {
            let texts = [t[0].text(), t[1].text(), t[2].text()];
            Some(
                PrescribedTorque::parse(&texts)
                    .map_err(|(c, msg)| cx.err(&key(&format!("torque[{c}]")), msg))?,
            )
        }
        None => None,
    })
}

/// The scene's material table: named `[material.NAME]` tables in the order
/// bodies first use them, and inline values, one entry per distinct set.
#[derive(Default)]
pub(super) struct Materials {
    pub(super) table: Vec<Material>,
}

impl Materials {
    pub(super) fn intern(
        &mut self,
        name: Option<&str>,
        density: f64,
        young: f64,
        poisson: f64,
        friction: Option<f64>,
    ) -> MaterialId {
        let same = |m: &Material| match name {
            Some(n) => m.name == n,
            None => {
                m.name.starts_with("inline-")
                    && [m.density, m.young, m.poisson].map(f64::to_bits)
                        == [density, young, poisson].map(f64::to_bits)
            }
        };
        if let Some(k) = self.table.iter().position(same) {
            return k as MaterialId;
        }
        let inline = self
            .table
            .iter()
            .filter(|m| m.name.starts_with("inline-"))
            .count();
        self.table.push(Material {
            name: name.map_or_else(|| format!("inline-{inline}"), str::to_string),
            density,
            young,
            poisson,
            friction,
        });
        (self.table.len() - 1) as MaterialId
    }
}
