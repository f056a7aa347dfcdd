//! `split4`: Yoshida's fourth-order symmetric composition of [`super::Split`]
//! (H. Yoshida, Phys. Lett. A 150 (1990) 262, Eq. 5.19 with `k = 1`):
//! `Φ_{w₁h} ∘ Φ_{w₀h} ∘ Φ_{w₁h}`, `w₁ = 1/(2 − 2^{1/3})`, `w₀ = 1 − 2w₁`.
//!
//! Each sub-step is a whole `split` step: its own half-kicks, exact free
//! flow and force evaluation (the step's stage sequence has three
//! open/forces/close sub-steps, a prescribed torque taken at each sub-step's
//! own time). **Contact-free scenes only**: the contact stage's damping
//! ledger and per-step impact bounds are written for one force evaluation per
//! step of `δt`, so a scene that computes contacts refuses `split4` (exit 2,
//! [`super::RotatorKind::contact_refusal`]); the studies leave it out there.
//! Symmetric and a composition of symplectic maps: symplectic,
//! time-reversible, exact in free flight, fourth order for smooth torques.
//! Three torque (and, with contacts, force) evaluations per step; the middle
//! sub-step goes backwards in time (`w₀ < 0`).
//!
//! Suzuki's five-stage composition (`w = 1/(4 − 4^{1/3})`, Phys. Lett. A 146
//! (1990) 319) has a 1/40 smaller error constant here but five evaluations;
//! on test case 4 Yoshida's three reach a given error in less time
//! (docs/validation.md, "At equal run time").

use super::split::SplitAux;
use super::Split;
use super::{Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::integrate::scheme::Stage;
use glam::DVec3;

/// `1/(2 − 2^{1/3})`.
const W1: f64 = 1.351_207_191_959_657_8;
/// `1 − 2 w₁ = −2^{1/3}/(2 − 2^{1/3})`.
const W0: f64 = -1.702_414_383_919_315_3;
/// Where the second sub-step ends, `w₁ + w₀`.
const MID: f64 = W1 + W0;

/// The three sub-steps of Yoshida's composition.
const YOSHIDA: &[Stage] = &[
    Stage::Open { start: 0.0, h: W1 },
    Stage::Forces,
    Stage::Close { end: W1, h: W1 },
    Stage::Open { start: W1, h: W0 },
    Stage::Forces,
    Stage::Close { end: MID, h: W0 },
    Stage::Open { start: MID, h: W1 },
    Stage::Forces,
    Stage::Close { end: 1.0, h: W1 },
];

/// Yoshida's fourth-order composition of `split`.
pub struct Split4;

impl Rotator for Split4 {
    type Aux = SplitAux;

    const INFO: RotatorInfo = RotatorInfo {
        name: "split4",
        title: "Yoshida's 4th-order symmetric composition of split: three split sub-steps, forces at each",
        equations: "Yoshida 1990 on split",
        order: 4,
        order_free: 0,
        symplectic: true,
        reversible: true,
        torque_evals: 3,
        torque_contract: "split's half-kicks at each sub-step's own time t_n + c dt, c = 0, w1, 1 - w1, 1 (w1 = 1.35)",
        contact_contract: "refused: contact-free scenes only (exit 2; the contact stage is written for one force evaluation per step)",
        closing_kick: true,
        diagnostic: false,
    };

    const STAGES: &'static [Stage] = YOSHIDA;

    fn start(rot: &RotState, inertia: &Inertia) -> SplitAux {
        <Split as Rotator>::start(rot, inertia)
    }

    /// A whole `split` step over the sub-step.
    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut SplitAux,
        inertia: &Inertia,
        torque: T,
        t: f64,
        h: f64,
    ) -> Result<(), RotatorFault> {
        <Split as Rotator>::advance(rot, aux, inertia, torque, t, h)
    }

    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut SplitAux,
        inertia: &Inertia,
        torque: T,
        t_end: f64,
        h: f64,
    ) {
        <Split as Rotator>::finish(rot, aux, inertia, torque, t_end, h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients() {
        let cbrt2 = 2f64.cbrt();
        assert!((W1 - 1.0 / (2.0 - cbrt2)).abs() < 1e-15);
        assert!((W0 + cbrt2 / (2.0 - cbrt2)).abs() < 1e-15);
        assert!((2.0 * W1 + W0 - 1.0).abs() < 1e-15);
        assert!(crate::integrate::scheme::is_valid(YOSHIDA));
    }
}

/// The order harness of `tests/suite/rotator_order.rs` on `split4` (listed only in
/// unit tests): fourth order on every torque case, exact on the torque-free
/// top. Before `split` renormalised after its free flow, the manufactured
/// case stopped at a ~1e-10 rad floor (fitted 0.90).
#[cfg(test)]
mod order {
    use crate::integrate::rotate::RotatorKind;
    use crate::study::order::{cases, measure, reference};

    #[test]
    fn fourth_order_on_every_case() {
        for case in cases() {
            let m = measure(&case, RotatorKind::Split4, reference(&case));
            println!("{:<14} {m}", case.name);
            if case.expected_order(RotatorKind::Split4) == 0 {
                let worst = m.errors.iter().cloned().fold(0.0, f64::max);
                assert!(worst < 1e-12, "{}: {worst:e} rad", case.name);
            } else {
                assert_eq!(m.window.len(), 4, "{}: {m}", case.name);
                assert!((m.order - 4.0).abs() < 0.2, "{}: {m}", case.name);
            }
        }
    }
}

/// In a scene that computes contacts `split4` is refused, bad input naming
/// `simulation.rotator` (exit 2), before any step.
#[cfg(test)]
mod contacts {
    use crate::integrate::rotate::RotatorKind;

    #[test]
    fn refused_in_contact_scenes() {
        let text = "[simulation]\ndt = 1e-6\nt_end = 1e-5\nrotator = \"split4\"\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [0.1, 0.1, 0.1]\nyoung = 5e7\npoisson = 0.23\n[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.025\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [0.05, 0.05, 0.05]\n";
        let scene = crate::scenario::parse_str(text, "<box>").expect("a valid scene");
        assert!(scene.needs_contacts());
        let dir = tempfile::tempdir().unwrap();
        let opts = crate::run::RunOptions {
            out_dir: dir.path().to_path_buf(),
            ..Default::default()
        };
        let err = crate::run::run(&scene, &opts).expect_err("refused");
        assert_eq!(err.exit_code(), 2, "{err}");
        assert!(err.to_string().contains("simulation.rotator"), "{err}");
        assert!(RotatorKind::Split.contact_refusal().is_none());
        assert_eq!(RotatorKind::Split4.force_evaluations(), 3);
    }
}
