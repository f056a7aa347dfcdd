//! No rotation at all: `q` and `ω_b` stay as they start, torques are ignored.
//!
//! A diagnostic, not a scheme: with rotation frozen, the energy error of a
//! contact scene is that of velocity Verlet and the contact model alone, which
//! separates their share from the rotators' (docs/validation.md, test cases 1–2).

use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use glam::DVec3;

/// The no-rotation diagnostic.
pub struct Frozen;

impl Rotator for Frozen {
    type Aux = ();

    const INFO: RotatorInfo = RotatorInfo {
        name: "frozen",
        title: "Diagnostic: no rotation at all, to separate the contact model's and Verlet's energy error from the rotators'",
        equations: "none",
        order: 0,
        order_free: 0,
        symplectic: false,
        reversible: false,
        torque_evals: 0,
        torque_contract: "never asks for torque",
        contact_contract: "ignored",
        closing_kick: false,
        diagnostic: true,
    };

    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        _rot: &mut RotState,
        _aux: &mut (),
        _inertia: &Inertia,
        _torque: T,
        _t_n: f64,
        _dt: f64,
    ) -> Result<(), RotatorFault> {
        Ok(())
    }
}
