//! Observed order of convergence of every rotator of the list, against the
//! order its `RotatorInfo` states.
//!
//! The harness is `fibresim::study::order`: an `rk4` reference at a step far
//! below the ladder, its own error estimated by Richardson
//! (`|q(δ) − q(2δ)| / (2⁴ − 1)`); only rungs whose errors exceed 100 times
//! that estimate (and rounding) are fitted. Run with `-- --nocapture` for
//! the table docs/validation.md quotes.

use crate::common;
use common::*;
use fibresim::integrate::rotate::RotatorKind;

use fibresim::study::order::{cases, measure, reference};

/// Every scheme of the rotator list, on every order case, shows the order
/// its `RotatorInfo` states (`order` under a torque, `order_free` on the
/// torque-free top; a scheme exact in free flight stays below 1e-12 rad on
/// every rung there): a scheme added to the list is checked here without a
/// line of this file changing.
#[test]
#[ignore = "slow tier: every listed rotator's order fit on every case"]
fn every_listed_rotator_has_its_stated_order() {
    for case in cases() {
        let r = reference(&case);
        for kind in RotatorKind::ALL {
            let m = measure(&case, kind, r);
            let expected = case.expected_order(kind);
            if expected == 0 {
                let worst = m.errors.iter().cloned().fold(0.0, f64::max);
                println!(
                    "{:<14} {:<12} exact: largest error {worst:.2e} rad over dt {:?}",
                    case.name,
                    kind.name(),
                    case.dts
                );
                assert!(worst < 1e-12, "{kind} on {}: {worst:e} rad", case.name);
                continue;
            }
            println!("{:<14} {m} (listed {expected})", case.name);
            assert_eq!(
                m.window.len(),
                4,
                "{}: no asymptotic range on {}: {m}",
                kind,
                case.name
            );
            let want = f64::from(expected);
            assert!(
                (m.order - want).abs() < 0.2,
                "{kind} on {}: observed order {:.3}, listed {want}",
                case.name,
                m.order
            );
        }
    }
}

/// Leap-frog is second order on a sphere, where ω does not depend on q (the
/// `q_n` conversion of its half-step velocity is exact): test case 3 against
/// its closed form (docs/physics.md §6), the reference that needs no estimate.
#[test]
fn leapfrog_is_second_order_on_a_sphere() {
    let scene = scene_file("torque_sphere.toml");
    let closed = scene
        .reference
        .clone()
        .expect("tc3 declares its closed form");
    let q_ref = closed.orientation(scene.sim.t_end());
    let dts = [1e-3, 5e-4, 2.5e-4, 1.25e-4];
    let errs: Vec<f64> = dts
        .iter()
        .map(|&dt| {
            let q = final_state(&scene, RotatorKind::Leapfrog, dt).rot.q;
            fibresim::math::geodesic_angle(q, q_ref)
        })
        .collect();
    let order = fitted_order(&dts, &errs);
    println!("test case 3    leapfrog    dt={dts:?} err={errs:?} order={order:.3} (expected 2)");
    assert!((order - 2.0).abs() < 0.1, "observed order {order:.3}");
}
