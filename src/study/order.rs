//! The measured order of a rotator, the check behind every `RotatorInfo::order`
//! (`tests/suite/rotator_order.rs` runs it for each rotator of the list).
//!
//! A case is a contact-free scene with a general load (asymmetric inertia or
//! a time-dependent torque in full 3-D). The rotator runs on a ladder of
//! halving steps; the error is the geodesic angle of the final orientation
//! to the scene's exact reference (`[reference]`: the manufactured solution,
//! the torque-free top), or else to an `rk4` reference at a step well below
//! the ladder, whose own error is estimated by Richardson
//! (`|q(δ) − q(2δ)| / 15`). The order is the least-squares slope over the
//! finest four rungs whose errors stand clear of the reference error and of
//! rounding: the asymptotic range, whatever the scheme's error constant.
//! On a torque-free case the expected order is `RotatorInfo::order_free`,
//! and a scheme exact there (`order_free = 0`) must stay at rounding on
//! every rung.

use super::fit::fit_order;
use crate::error::Diagnosis;
use crate::integrate::rotate::RotatorKind;
use crate::math::geodesic_angle;
use crate::scenario::Scene;

/// Errors below this (rad) are rounding, whatever the reference.
pub const ROUNDING_FLOOR: f64 = 1e-11;

/// A scene and its step ladder.
#[derive(Debug, Clone)]
pub struct OrderCase {
    /// The case's name, for messages.
    pub name: &'static str,
    /// The scene, contact-free.
    pub scene: Scene,
    /// Steps, coarsest first, each a fixed fraction of the previous.
    pub dts: Vec<f64>,
    /// The reference's step (when the scene has no exact reference).
    pub dt_ref: f64,
    /// No torque acts: the expected order is `order_free`.
    pub torque_free: bool,
}

impl OrderCase {
    /// The order `kind` should show on this case (0: exact to rounding).
    pub fn expected_order(&self, kind: RotatorKind) -> u32 {
        let i = kind.info();
        if self.torque_free {
            i.order_free
        } else {
            i.order
        }
    }
}

/// What [`measure`] found.
#[derive(Debug, Clone)]
pub struct OrderMeasurement {
    /// The rotator measured.
    pub kind: RotatorKind,
    /// The fitted slope over [`OrderMeasurement::window`].
    pub order: f64,
    /// The ladder's steps.
    pub dts: Vec<f64>,
    /// The error at each rung, rad (infinite where a guard stopped it).
    pub errors: Vec<f64>,
    /// Indices of the rungs fitted.
    pub window: std::ops::Range<usize>,
    /// Richardson estimate of the reference's own error, rad.
    pub reference_error: f64,
}

impl std::fmt::Display for OrderMeasurement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // With no asymptotic range, show every rung.
        let w = if self.window.is_empty() {
            0..self.errors.len()
        } else {
            self.window.clone()
        };
        let errs: Vec<String> = self.errors[w.clone()]
            .iter()
            .map(|e| format!("{e:.3e}"))
            .collect();
        write!(
            f,
            "{:<12} order {:.3} on dt {:?}: errors [{}]; reference error ~{:.1e}",
            self.kind.name(),
            self.order,
            &self.dts[w],
            errs.join(", "),
            self.reference_error
        )
    }
}

/// A case whose ladder divides the step by `ratio` per rung.
fn case(
    name: &'static str,
    text: &str,
    (dt0, ratio, rungs): (f64, f64, usize),
    dt_ref: f64,
) -> OrderCase {
    let scene = crate::scenario::parse_str(text, name).expect("the order cases are valid");
    // Each step divides the end time exactly, so every run ends at T.
    let t_end = scene.sim.t_end();
    let dts = (0..rungs)
        .map(|k| t_end / (t_end * ratio.powi(k as i32) / dt0).round())
        .collect();
    OrderCase {
        name,
        torque_free: !scene.has_prescribed_torque(),
        scene,
        dts,
        dt_ref,
    }
}

/// Test case 4 (docs/physics.md §6): the paper's fibre under its growing
/// time-dependent torque, ω up to ~4e3 rad/s at T = 0.1 s. The ladder steps
/// by √2: a fourth-order scheme as accurate as `split4` falls from its
/// asymptotic range's top (~5e-8 rad) to the reference's floor in fewer
/// than four halvings.
pub fn test_case_4() -> OrderCase {
    case(
        "test case 4",
        include_str!("../../scenarios/torque_fibre.toml"),
        (4.5e-5, std::f64::consts::SQRT_2, 18),
        2.5e-8,
    )
}

/// A smooth general load of our choosing: the same fibre spinning and
/// tumbling (ω_0 = (40, 25, −10) rad/s, world) under a bounded,
/// time-dependent torque in full 3-D.
pub fn smooth_torque() -> OrderCase {
    case(
        "smooth torque",
        r#"
[simulation]
dt = 1e-4
t_end = 0.2
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
position = [0.0, 0.0, 0.0]
axis = [0.6, 0.8, 0.0]
angular_velocity = [40.0, 25.0, -10.0]
torque = ["2e-6*sin(30*t)", "1e-6*cos(20*t)", "5e-7"]
"#,
        (4e-3, 2.0, 10),
        1e-6,
    )
}

/// The manufactured solution (`scenarios/manufactured.toml`): an asymmetric
/// rigid body driven along a known `q(t)` by the time-dependent torque it
/// implies, in full 3-D with gyroscopic coupling; exact reference.
pub fn manufactured() -> OrderCase {
    case(
        "manufactured",
        include_str!("../../scenarios/manufactured.toml"),
        (1.6e-2, 2.0, 10),
        f64::NAN,
    )
}

/// The torque-free asymmetric top (`scenarios/asymmetric_top.toml`):
/// Jacobi's elliptic-function solution as the reference.
pub fn asymmetric_top() -> OrderCase {
    case(
        "asymmetric top",
        include_str!("../../scenarios/asymmetric_top.toml"),
        (4e-2, 2.0, 10),
        f64::NAN,
    )
}

/// The cases every rotator's listed order is checked on.
pub fn cases() -> Vec<OrderCase> {
    vec![
        test_case_4(),
        smooth_torque(),
        manufactured(),
        asymmetric_top(),
    ]
}

fn final_orientation(scene: &Scene, kind: RotatorKind, dt: f64) -> Result<glam::DQuat, Diagnosis> {
    Ok(crate::run::integrate(scene, kind, dt)?[0].rot.q)
}

/// The reference orientation at the case's end, and its estimated error
/// (0 for an exact reference: it is accurate to ~1e-13 rad,
/// `tests/suite/reference.rs`).
pub fn reference(case: &OrderCase) -> (glam::DQuat, f64) {
    if let Some(exact) = &case.scene.reference {
        return (exact.orientation(case.scene.sim.t_end()), 0.0);
    }
    let fine = final_orientation(&case.scene, RotatorKind::Rk4, case.dt_ref)
        .expect("the rk4 reference runs");
    let coarse = final_orientation(&case.scene, RotatorKind::Rk4, 2.0 * case.dt_ref)
        .expect("the rk4 reference runs");
    (fine, geodesic_angle(fine, coarse) / 15.0)
}

/// Measure `kind`'s order on `case` against `reference` (from [`reference()`]).
/// A rung that stops (a guard) has an infinite error and is never fitted.
pub fn measure(
    case: &OrderCase,
    kind: RotatorKind,
    reference: (glam::DQuat, f64),
) -> OrderMeasurement {
    let (q_ref, ref_err) = reference;
    let errors: Vec<f64> = case
        .dts
        .iter()
        .map(|&dt| {
            final_orientation(&case.scene, kind, dt)
                .map_or(f64::INFINITY, |q| geodesic_angle(q, q_ref))
        })
        .collect();
    let floor = ROUNDING_FLOOR.max(100.0 * ref_err);
    let clear = |e: f64| e.is_finite() && e > floor;
    // The finest four consecutive rungs clear of the floor (or fewer, if
    // the ladder has no four: then the fit says so by its window).
    let n = errors.len();
    let mut window = 0..0;
    for end in (4..=n).rev() {
        if errors[end - 4..end].iter().all(|&e| clear(e)) {
            window = end - 4..end;
            break;
        }
    }
    let order =
        fit_order(&case.dts[window.clone()], &errors[window.clone()]).map_or(f64::NAN, |f| f.order);
    OrderMeasurement {
        kind,
        order,
        dts: case.dts.clone(),
        errors,
        window,
        reference_error: ref_err,
    }
}
