//! Closed-form references a scene may declare (`[reference]`), and their check.

use super::check::Ctx;
use super::file::ReferenceSection;
use super::scene::Prescribed;
use crate::body::{Bodies, BodyState, Shape};
use crate::error::Result;
use crate::fmt::short3;
use crate::reference::{Manufactured, TorqueFree, Wave};
use crate::torque::PrescribedTorque;
use glam::{DQuat, DVec3};
use std::sync::Arc;

/// A closed-form orientation the scene declares (see `file::ReferenceSection`).
#[derive(Debug, Clone, PartialEq)]
pub enum ClosedForm {
    /// Sphere of inertia `i` at rest under `τ = A e^{Ct} â`.
    ExpTorqueSphere {
        /// The sphere's start orientation `q₀`.
        q0: DQuat,
        /// Unit direction `â` of the torque (world).
        axis: DVec3,
        /// `A`, N·m.
        a: f64,
        /// `C`, 1/s.
        c: f64,
        /// The sphere's moment of inertia, kg m².
        inertia: f64,
    },
    /// The exact torque-free motion of body 0 from its start.
    TorqueFree(Box<TorqueFree>),
    /// A manufactured solution; body 0 is driven by its torque.
    Manufactured(Arc<Manufactured>),
}

impl ClosedForm {
    /// Reference orientation of body 0 at time `t` (each form carries body
    /// 0's start: a run need not keep the scene's step-0 states).
    pub fn orientation(&self, t: f64) -> DQuat {
        match self {
            ClosedForm::ExpTorqueSphere {
                q0,
                axis,
                a,
                c,
                inertia,
            } => {
                let theta = a * ((c * t).exp() - 1.0 - c * t) / (inertia * c * c);
                DQuat::from_axis_angle(*axis, theta) * *q0
            }
            ClosedForm::TorqueFree(f) => f.orientation(t),
            ClosedForm::Manufactured(m) => m.orientation(t),
        }
    }
}

/// The keys of `[reference]` each closed form takes.
fn keys_given(r: &ReferenceSection) -> [(&'static str, bool); 7] {
    [
        ("axis", r.axis.is_some()),
        ("a", r.a.is_some()),
        ("c", r.c.is_some()),
        ("precession_axis", r.precession_axis.is_some()),
        ("spin_axis", r.spin_axis.is_some()),
        ("precession", r.precession.is_some()),
        ("spin", r.spin.is_some()),
    ]
}

/// Check `[reference]` against the scene and build it. The manufactured
/// form also sets body 0's start angular velocity and adds its torque.
pub(super) fn build_reference(
    cx: &Ctx,
    r: &ReferenceSection,
    bodies: &Bodies,
    initial: &mut [BodyState],
    torques: &mut Vec<Prescribed>,
    needs_contacts: bool,
) -> Result<ClosedForm> {
    let kind = r.closed_form.as_str();
    let wanted: &[&str] = match kind {
        "exp-torque-sphere" => &["axis", "a", "c"],
        "torque-free" => &[],
        "manufactured" => &["precession_axis", "spin_axis", "precession", "spin"],
        _ => {
            return Err(cx.err(
                "reference.closed_form",
                super::check::unknown_name(super::keys::Kind::ClosedForm, kind),
            ))
        }
    };
    for (key, given) in keys_given(r) {
        let want = wanted.contains(&key);
        if given && !want {
            return Err(cx.err(
                &format!("reference.{key}"),
                format!("not used by closed_form = \"{kind}\"; remove it"),
            ));
        }
        if want && !given {
            return Err(cx.err(
                &format!("reference.{key}"),
                format!("closed_form = \"{kind}\" needs `{key}`"),
            ));
        }
    }
    match kind {
        "exp-torque-sphere" => exp_torque_sphere(cx, r, bodies, initial, torques),
        "torque-free" => torque_free(cx, bodies, initial, torques, needs_contacts),
        _ => manufactured(cx, r, bodies, initial, torques, needs_contacts),
    }
}

/// One body, nothing to touch: the closed forms for a single free body.
fn single_free_body(cx: &Ctx, kind: &str, bodies: &Bodies, needs_contacts: bool) -> Result<()> {
    if bodies.len() != 1 || needs_contacts {
        return Err(cx.err(
            "reference",
            format!("closed_form = \"{kind}\" describes one body that touches nothing: give exactly one [[body]] and no [box]"),
        ));
    }
    Ok(())
}

fn torque_free(
    cx: &Ctx,
    bodies: &Bodies,
    initial: &[BodyState],
    torques: &[Prescribed],
    needs_contacts: bool,
) -> Result<ClosedForm> {
    single_free_body(cx, "torque-free", bodies, needs_contacts)?;
    if !torques.is_empty() {
        return Err(cx.err(
            "body[0].torque",
            "closed_form = \"torque-free\" assumes no torque; remove the body's `torque`",
        ));
    }
    let rot = initial[0].rot;
    TorqueFree::new(bodies[0].inertia.principal, rot.q, rot.omega_b)
        .map(|f| ClosedForm::TorqueFree(Box::new(f)))
        .map_err(|_| {
            cx.err(
                "body[0].angular_velocity",
                "the start lies exactly on the separatrix M^2 = 2 E I2 (the motion only approaches the intermediate axis, forever); perturb the angular velocity",
            )
        })
}

fn unit_axis(cx: &Ctx, key: &str, v: [f64; 3]) -> Result<DVec3> {
    let v = cx.finite3(key, v)?;
    if v.length() < 1e-12 {
        return Err(cx.err(key, "the axis direction must be non-zero"));
    }
    Ok(v.normalize())
}

fn wave(cx: &Ctx, key: &str, w: [f64; 3]) -> Result<Wave> {
    let [a, b, c] = cx.finite3(key, w)?.to_array();
    Ok(Wave { a, b, c })
}

fn manufactured(
    cx: &Ctx,
    r: &ReferenceSection,
    bodies: &Bodies,
    initial: &mut [BodyState],
    torques: &mut Vec<Prescribed>,
    needs_contacts: bool,
) -> Result<ClosedForm> {
    single_free_body(cx, "manufactured", bodies, needs_contacts)?;
    let (Some(u), Some(v), Some(p), Some(s)) =
        (r.precession_axis, r.spin_axis, r.precession, r.spin)
    else {
        unreachable!("the keys were checked")
    };
    let m = Manufactured {
        inertia: bodies[0].inertia.principal,
        q0: initial[0].rot.q,
        u: unit_axis(cx, "reference.precession_axis", u)?,
        v: unit_axis(cx, "reference.spin_axis", v)?,
        phi: wave(cx, "reference.precession", p)?,
        psi: wave(cx, "reference.spin", s)?,
    };
    if !torques.is_empty() {
        return Err(cx.err(
            "body[0].torque",
            "closed_form = \"manufactured\" supplies the torque of its solution; remove the body's `torque`",
        ));
    }
    let omega0 = m.omega_body(0.0);
    if initial[0].rot.omega_b != DVec3::ZERO {
        return Err(cx.err(
            "body[0].angular_velocity",
            format!(
                "closed_form = \"manufactured\" sets the start angular velocity ({} rad/s, world); remove `angular_velocity`",
                short3(m.q0 * omega0)
            ),
        ));
    }
    initial[0].rot.omega_b = omega0;
    let m = Arc::new(m);
    torques.push(Prescribed {
        body: 0,
        torque: PrescribedTorque::manufactured(m.clone()),
    });
    Ok(ClosedForm::Manufactured(m))
}

fn exp_torque_sphere(
    cx: &Ctx,
    r: &ReferenceSection,
    bodies: &Bodies,
    initial: &[BodyState],
    torques: &[Prescribed],
) -> Result<ClosedForm> {
    let (Some(axis), Some(a), Some(c)) = (r.axis, r.a, r.c) else {
        unreachable!("the keys were checked")
    };
    let axis = cx.finite3("reference.axis", axis)?;
    if axis.length() < 1e-12 || !a.is_finite() || !c.is_finite() || c == 0.0 {
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
        let want = a * (c * t).exp() * axis;
        let got = torque.at(t);
        if (got - want).length() > 1e-9 * want.length().max(1e-300) {
            return Err(cx.err(
                "reference",
                format!(
                    "the body's torque at t = {t} is {}, but the closed form assumes {}",
                    short3(got),
                    short3(want)
                ),
            ));
        }
    }
    Ok(ClosedForm::ExpTorqueSphere {
        q0: initial[0].rot.q,
        axis,
        a,
        c,
        inertia: bodies[0].inertia.principal.x,
    })
}
