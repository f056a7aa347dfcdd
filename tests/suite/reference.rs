//! The exact references (`fibresim::reference`) against independent,
//! tightly converged numerical integrations: the torque-free asymmetric top
//! (both circulation regimes), the symmetric top, the Dzhanibekov flip
//! period, and the manufactured solution.
//!
//! The independent integration is `rk4` at a small step `δ`, whose own error
//! is bounded by Richardson's estimate `|q(δ) − q(2δ)|/15` (asserted below
//! 1e-13 rad, so a 1e-12 rad agreement is a test of the closed form).

use crate::common;
use common::*;
use fibresim::integrate::rotate::RotatorKind;
use fibresim::math::geodesic_angle;
use fibresim::scenario::{ClosedForm, Scene};
use glam::{DQuat, DVec3};

/// Orientation and body angular velocity of body 0 every `every` steps.
fn samples(scene: &Scene, kind: RotatorKind, dt: f64, every: u64) -> Vec<(f64, DQuat, DVec3)> {
    let mut s = scene.clone();
    let steps = (scene.sim.t_end() / dt).round() as u64;
    s.sim = fibresim::scenario::SimParams::with_steps(dt, steps, kind, None).unwrap();
    let mut out = vec![];
    fibresim::run::integrate_observed(&s, |w| {
        if w.step % every == 0 {
            out.push((w.time(), w.states[0].rot.q, w.states[0].rot.omega_b));
        }
    })
    .expect("the run completes");
    out
}

fn rigid(inertia: [f64; 3], omega: [f64; 3], t_end: f64) -> Scene {
    scene_str(&format!(
        r#"
[simulation]
dt = 1e-4
t_end = {t_end}
[[body]]
shape = "rigid"
mass = 1.0
inertia = {inertia:?}
position = [0.0, 0.0, 0.0]
quaternion = [0.9, 0.3, -0.2, 0.2449489742783178]
angular_velocity = {omega:?}
[reference]
closed_form = "torque-free"
"#
    ))
}

/// The closed form against rk4 at 2e-5 s (checked by Richardson from 4e-5 s)
/// at 20 times over the run: the largest orientation and angular-velocity
/// errors of the closed form.
fn closed_form_against_rk4(scene: &Scene, dt: f64) -> (f64, f64) {
    let reference = scene.reference.clone().expect("a closed form");
    let steps = (scene.sim.t_end() / dt).round() as u64;
    let every = steps / 20;
    let fine = samples(scene, RotatorKind::Rk4, dt, every);
    let coarse = samples(scene, RotatorKind::Rk4, 2.0 * dt, every / 2);
    let (mut worst_q, mut worst_w, mut rk4_err) = (0.0f64, 0.0f64, 0.0f64);
    let omega = |t: f64| match &reference {
        ClosedForm::TorqueFree(f) => f.omega_body(t),
        ClosedForm::Manufactured(m) => m.omega_body(t),
        _ => unreachable!(),
    };
    for ((t, q, w), (_, q2, _)) in fine.iter().zip(&coarse) {
        rk4_err = rk4_err.max(geodesic_angle(*q, *q2) / 15.0);
        worst_q = worst_q.max(geodesic_angle(reference.orientation(*t), *q));
        worst_w = worst_w.max((omega(*t) - *w).length() / w.length());
    }
    assert!(rk4_err < 1e-13, "the rk4 check is not tight: {rk4_err:e}");
    (worst_q, worst_w)
}

/// Jacobi's solution, `M² > 2E I₂` (circulation about the largest axis) and
/// `M² < 2E I₂` (about the smallest), from an oblique start: ≤ 1e-12 rad.
#[test]
fn asymmetric_top_matches_tight_rk4() {
    for (name, omega) in [
        ("about the largest axis", [5.0, 8.0, -6.0]),
        ("about the smallest axis", [14.0, 3.0, -2.0]),
    ] {
        let scene = rigid([2e-3, 3e-3, 4e-3], omega, 2.0);
        let (eq, ew) = closed_form_against_rk4(&scene, 2e-5);
        println!("asymmetric top, {name}: orientation {eq:.2e} rad, omega {ew:.2e} (relative)");
        assert!(eq < 1e-12 && ew < 1e-12, "{name}: {eq:e} rad, {ew:e}");
    }
}

/// The symmetric top (test case 1's fibre, ω_b = (60, 25, −15) rad/s).
#[test]
fn precessing_fibre_matches_tight_rk4() {
    let mut scene = scene_file("precessing_fibre.toml");
    scene.sim = fibresim::scenario::SimParams::new(1e-5, 0.5, RotatorKind::Rk4, None, "<test>", "")
        .unwrap();
    let (eq, ew) = closed_form_against_rk4(&scene, 2e-6);
    println!("precessing fibre: orientation {eq:.2e} rad, omega {ew:.2e} (relative)");
    assert!(eq < 1e-12 && ew < 1e-12, "{eq:e} rad, {ew:e}");
}

/// The manufactured solution: its torque drives rk4 onto its orientation.
#[test]
fn manufactured_solution_is_the_motion_its_torque_drives() {
    let scene = scene_file("manufactured.toml");
    let (eq, ew) = closed_form_against_rk4(&scene, 1e-5);
    println!("manufactured: orientation {eq:.2e} rad, omega {ew:.2e} (relative)");
    assert!(eq < 1e-12 && ew < 1e-12, "{eq:e} rad, {ew:e}");
    // ω = 2 q* q̇ by a central difference of the closed-form orientation.
    let Some(ClosedForm::Manufactured(m)) = &scene.reference else {
        unreachable!()
    };
    for t in [0.0, 0.31, 0.77] {
        let h = 1e-5;
        let dq = (m.orientation(t + h) - m.orientation(t - h)) * (1.0 / (2.0 * h));
        let w = m.orientation(t).conjugate() * dq * 2.0;
        let fd = DVec3::new(w.x, w.y, w.z);
        assert!(
            (fd - m.omega_body(t)).length() < 1e-6 * fd.length(),
            "{fd} vs {}",
            m.omega_body(t)
        );
    }
}

/// The Dzhanibekov flip: after one flip period `2K/λ` Jacobi's solution has
/// `(ω₁, ω₂, ω₃) → (−ω₁, −ω₂, ω₃)` in the working frame (`cn` and `sn` change
/// sign over `2K`, `dn` does not): checked on a tight rk4 run of exactly that
/// length. Then the flips of a 20 s `split` run come every `2K/λ`.
#[test]
fn dzhanibekov_flip_period() {
    let scene = scene_file("dzhanibekov.toml");
    let Some(ClosedForm::TorqueFree(f)) = &scene.reference else {
        panic!("the scene declares the torque-free form")
    };
    let period = f.flip_period().expect("three distinct moments");
    println!("flip period 2K/lambda = {period:.12} s");
    // rk4 over one period, 2^15 steps (the step error is ~1e-14 rad).
    let mut s = scene.clone();
    s.sim =
        fibresim::scenario::SimParams::with_steps(period / 32768.0, 32768, RotatorKind::Rk4, None)
            .unwrap();
    let end = fibresim::run::integrate_observed(&s, |_| {})
        .unwrap()
        .states[0]
        .rot
        .omega_b;
    let w0 = scene.initial[0].rot.omega_b;
    // Here the working frame is (x, y, z) with y intermediate: x and y flip.
    let want = DVec3::new(-w0.x, -w0.y, w0.z);
    println!("omega after one period {end}, expected {want}");
    assert!(
        (end - want).length() < 1e-9 * w0.length(),
        "{end} vs {want}"
    );

    // The flips of body y in a split run (zero crossings of ω_y, linearly
    // interpolated) are one period apart.
    let runs = samples(&scene, RotatorKind::Split, 1e-3, 1);
    let crossings: Vec<f64> = runs
        .windows(2)
        .filter(|p| p[0].2.y.signum() != p[1].2.y.signum())
        .map(|p| p[0].0 - p[0].2.y * (p[1].0 - p[0].0) / (p[1].2.y - p[0].2.y))
        .collect();
    assert!(crossings.len() >= 6, "{crossings:?}");
    for pair in crossings.windows(2) {
        let gap = pair[1] - pair[0];
        assert!(
            (gap - period).abs() < 1e-6 * period,
            "flips {pair:?}: {gap} s vs {period} s"
        );
    }
    println!(
        "{} flips, every {:.9} s",
        crossings.len(),
        (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
    );
}
