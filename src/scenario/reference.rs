//! Closed-form references a scene may declare (`[reference]`), and their check.

use super::check::Ctx;
use super::file::ReferenceSection;
use super::scene::Prescribed;
use crate::body::{Body, BodyState, Shape};
use crate::error::Result;
use glam::{DQuat, DVec3};

/// A closed-form orientation the scene declares (see `file::ReferenceSection`).
#[derive(Debug, Clone, PartialEq)]
pub enum ClosedForm {
    /// Sphere of inertia `i` at rest under `τ = A e^{Ct} â`.
    ExpTorqueSphere {
        /// Unit direction `â` of the torque (world).
        axis: DVec3,
        /// `A`, N·m.
        a: f64,
        /// `C`, 1/s.
        c: f64,
        /// The sphere's moment of inertia, kg m².
        inertia: f64,
    },
}

impl ClosedForm {
    /// Reference orientation at time `t` (body 0).
    pub fn orientation(&self, t: f64, q0: DQuat) -> DQuat {
        match *self {
            ClosedForm::ExpTorqueSphere {
                axis,
                a,
                c,
                inertia,
            } => {
                let theta = a * ((c * t).exp() - 1.0 - c * t) / (inertia * c * c);
                DQuat::from_axis_angle(axis, theta) * q0
            }
        }
    }
}

pub(super) fn build_reference(
    cx: &Ctx,
    r: &ReferenceSection,
    bodies: &[Body],
    initial: &[BodyState],
    torques: &[Prescribed],
) -> Result<ClosedForm> {
    if r.closed_form != "exp-torque-sphere" {
        return Err(cx.err(
            "reference.closed_form",
            format!(
                "unknown closed form `{}`; known: exp-torque-sphere",
                r.closed_form
            ),
        ));
    }
    let axis = cx.finite3("reference.axis", r.axis)?;
    if axis.length() < 1e-12 || !r.a.is_finite() || !r.c.is_finite() || r.c == 0.0 {
        return Err(cx.err(
            "reference",
            "needs a non-zero axis, finite a and a non-zero finite c",
        ));
    }
    let axis = axis.normalize();
    let ok_body = bodies.len() == 1
        && matches!(bodies[0].shape, Shape::Sphere { .. })
        && initial[0].rot.omega_b == DVec3::ZERO;
    if !ok_body {
        return Err(cx.err(
            "reference",
            "exp-torque-sphere needs exactly one sphere, initially at rest",
        ));
    }
    // The declared closed form must describe the declared torque: check it.
    let torque = torques.first().map(|p| &p.torque).ok_or_else(|| {
        cx.err(
            "reference",
            "exp-torque-sphere needs a prescribed torque on the sphere",
        )
    })?;
    for t in [0.0, 0.37, 1.0] {
        let want = r.a * (r.c * t).exp() * axis;
        let got = torque.at(t);
        if (got - want).length() > 1e-9 * want.length().max(1e-300) {
            return Err(cx.err(
                "reference",
                format!(
                    "the body's torque at t = {t} is {got}, but the closed form assumes {want}"
                ),
            ));
        }
    }
    Ok(ClosedForm::ExpTorqueSphere {
        axis,
        a: r.a,
        c: r.c,
        inertia: bodies[0].inertia.principal.x,
    })
}
