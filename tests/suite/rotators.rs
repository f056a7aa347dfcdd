//! Rotator accuracy against closed forms and invariants.

use crate::common;
use common::*;
use fibresim::body::{Inertia, RotState};
use fibresim::integrate::rotate::{Direct, Rotator, RotatorFault, RotatorKind, Scalar};
use fibresim::math::{exp_map, geodesic_angle, rotate_tensor};
use glam::{DMat3, DQuat, DVec3};

/// Test case 3 (paper Table 2) at δt = 1e-4 against the closed form
/// θ(1) = A (e − 2)/I about y. Reference numbers: the closed form (exact) and
/// the paper's Table 2 (scalar 2.15 %, PCDM 0.63 % relative x-error).
#[test]
fn test_case_3_against_closed_form() {
    let scene = scene_file("torque_sphere.toml");
    let closed = scene
        .reference
        .clone()
        .expect("tc3 declares its closed form");
    let q_ref = closed.orientation(1.0);
    let x_ref = q_ref * DVec3::X;
    // Closed form, independently: I = 2/5 m r², m = ρ 4/3 π r³, r = 1.
    let inertia = 0.4 * 1100.0 * 4.0 / 3.0 * std::f64::consts::PI;
    let theta = 1e5 * (std::f64::consts::E - 2.0) / inertia;
    assert!((x_ref - DVec3::new(theta.cos(), 0.0, -theta.sin())).length() < 1e-12);
    // The paper's "theoretical result" is (2.934253e-1, 0, -9.55982e-1); the exact
    // closed form gives x = 2.934440e-1: the paper's value is off by 1.9e-5 in x
    // (an angle of 2e-5 rad), see docs/validation.md.
    assert!((x_ref.x - 0.2934440).abs() < 5e-8, "{x_ref}");
    assert!((x_ref.x - 0.2934253).abs() < 2.5e-5 && (x_ref.z + 0.955982).abs() < 1e-5);

    println!("rotator     angle err (rad)   x-error (%)   x");
    let mut errs = std::collections::BTreeMap::new();
    for kind in RotatorKind::ALL {
        let s = final_state(&scene, kind, 1e-4);
        let ang = geodesic_angle(s.rot.q, q_ref);
        let x = s.rot.q * DVec3::X;
        let xerr = ((x.x - x_ref.x) / x_ref.x).abs() * 100.0;
        println!("{:<11} {ang:<17.3e} {xerr:<13.4} {:.7}", kind.name(), x.x);
        errs.insert(kind, (ang, xerr));
    }
    // The target: pcdm (mid-step torque) within 1e-6 rad.
    assert!(errs[&RotatorKind::Pcdm].0 < 1e-6);
    // pcdm-start and scalar have the size of the paper's PCDM (0.63 %) and
    // scalar (2.15 %) errors, but they lag the closed form (x too large)
    // where the paper's results lead it: see the next test.
    assert!((errs[&RotatorKind::PcdmStart].1 - 0.63).abs() < 0.01);
    assert!((errs[&RotatorKind::Scalar].1 - 2.15).abs() < 0.01);
    for k in [RotatorKind::PcdmStart, RotatorKind::Scalar] {
        let x = final_state(&scene, k, 1e-4).rot.q * DVec3::X;
        assert!(x.x > x_ref.x, "{k} lags: x = {x}");
    }
    // Leap-frog is second order on a sphere (ω does not depend on q).
    assert!(errs[&RotatorKind::Leapfrog].0 < 1e-4);
    assert!(errs[&RotatorKind::Rk4].0 < 1e-9);
    // First-order schemes: error ≈ δt/2 (ω(1) + θ(1)) = 5e-5 (93.2 + 39.0) = 6.6e-3 rad.
    for k in [RotatorKind::Euler, RotatorKind::Scalar, RotatorKind::Direct] {
        assert!((errs[&k].0 - 6.6e-3).abs() < 0.3e-3, "{k}: {}", errs[&k].0);
    }
}

/// The paper's Table 2 vectors, signs included, come out of our schemes when
/// the torque is taken at the *end* of each step, `t_{n+1}` (a clock advanced
/// before the torque is evaluated), and the scalar method advances ω before q.
/// Reference numbers: the paper's Table 2, scalar (0.2871152, 0, −0.9578961),
/// PCDM (0.2915775, 0, −0.9565472). Both are reproduced to 3e-6 (they print
/// 7 digits); with the torque at `t_n` the same schemes miss by 1e-2 on the
/// other side of the closed form (previous test).
#[test]
fn paper_table_2_is_reproduced_with_the_torque_at_the_step_end() {
    let text = include_str!("../../scenarios/torque_sphere.toml");
    let text = &text[..text.find("[reference]").expect("tc3 has a reference")];
    let dt = 1e-4;
    let shifted = |shift: f64, omega_y: f64| {
        let t = text
            .replace("\"1e5*exp(t)\"", &format!("\"1e5*exp(t+{shift:e})\""))
            .replace(
                "quaternion = [1.0, 0.0, 0.0, 0.0]",
                &format!(
                    "quaternion = [1.0, 0.0, 0.0, 0.0]\nangular_velocity = [0.0, {omega_y:e}, 0.0]"
                ),
            );
        scene_str(&t)
    };
    // PCDM with both torques at t_{n+1}: pcdm-start (both at t_n) under τ(t + δt).
    let x = final_state(&shifted(dt, 0.0), RotatorKind::PcdmStart, dt)
        .rot
        .q
        * DVec3::X;
    println!("PCDM, torque at t_n+1:   {x}  (paper 0.2915775, 0, -0.9565472)");
    assert!(
        (x - DVec3::new(0.2915775, 0.0, -0.9565472)).length() < 5e-6,
        "{x}"
    );
    // Scalar with ω first, `ω_{n+1} = ω_n + δt τ(t_{n+1})/I`, then q with
    // ω_{n+1}: our scalar (q with ω_n, then ω with τ(t_n)) run one step ahead in
    // ω, i.e. from ω_1 = δt τ(δt)/I under τ(t + 2δt).
    let inertia = 0.4 * 1100.0 * 4.0 / 3.0 * std::f64::consts::PI;
    let omega_1 = dt * 1e5 * dt.exp() / inertia;
    let x = final_state(&shifted(2.0 * dt, omega_1), RotatorKind::Scalar, dt)
        .rot
        .q
        * DVec3::X;
    println!("scalar, ω first at t_n+1: {x}  (paper 0.2871152, 0, -0.9578961)");
    assert!(
        (x - DVec3::new(0.2871152, 0.0, -0.9578961)).length() < 5e-6,
        "{x}"
    );
}

fn inertia() -> Inertia {
    Inertia::new(DVec3::new(2.7e-8, 1.26e-7, 1.26e-7))
}

/// A deterministic pseudo-random stream (no dependency needed for a test).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64) / ((1u64 << 53) as f64)
}

fn random_unit(seed: &mut u64) -> DVec3 {
    loop {
        let v = DVec3::new(lcg(seed), lcg(seed), lcg(seed)) * 2.0 - 1.0;
        let n = v.length();
        if n > 0.1 && n < 1.0 {
            return v / n;
        }
    }
}

/// Scalar (Eq. 45) equals direct multiplication (Eq. 49–50) while ‖ω‖δt < π.
#[test]
fn scalar_equals_direct_below_pi() {
    let mut seed = 7;
    let mut worst: f64 = 0.0;
    for i in 0..2000 {
        let q = exp_map(random_unit(&mut seed) * 3.0 * lcg(&mut seed));
        let dt = 1e-3;
        let w_norm_dt = std::f64::consts::PI * 0.99 * (i as f64 / 2000.0);
        let omega_b = random_unit(&mut seed) * (w_norm_dt / dt);
        let torque = |_t: f64| DVec3::new(1e-7, -2e-7, 3e-8);
        let mut a = RotState { q, omega_b };
        let mut b = a;
        Scalar::advance(&mut a, &mut (), &inertia(), torque, 0.0, dt).unwrap();
        Direct::advance(&mut b, &mut (), &inertia(), torque, 0.0, dt).unwrap();
        worst = worst.max(geodesic_angle(a.q, b.q));
        assert_eq!(a.omega_b, b.omega_b);
    }
    println!(
        "largest scalar-vs-direct angle over 2000 steps up to ||w||dt = 0.99 pi: {worst:.2e} rad"
    );
    assert!(worst < 1e-13);
}

/// At the pole of tan the scalar method refuses the step instead of returning a number.
#[test]
fn scalar_singularity_is_an_error() {
    let dt = 1e-3;
    for w_dt in [std::f64::consts::PI, std::f64::consts::PI * 1.0000001, 5.0] {
        let mut s = RotState {
            q: DQuat::IDENTITY,
            omega_b: DVec3::new(0.0, w_dt / dt, 0.0),
        };
        let before = s;
        let r = Scalar::advance(&mut s, &mut (), &inertia(), |_| DVec3::ZERO, 0.0, dt);
        assert!(
            matches!(r, Err(RotatorFault::ScalarSingularity { half_angle }) if half_angle >= std::f64::consts::FRAC_PI_2)
        );
        assert_eq!(s, before, "a refused step leaves the state untouched");
    }
    // Through a whole run: a named diagnosis, not garbage.
    let scene = scene_str(
        r#"
[simulation]
dt = 1e-3
t_end = 1.0
rotator = "scalar"
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
position = [0.0, 0.0, 0.0]
angular_velocity = [0.0, 4000.0, 0.0]
"#,
    );
    let d = fibresim::run::integrate_observed(&scene, |_| {}).expect_err("stops");
    assert_eq!(d.kind, fibresim::stop::StopKind::ScalarSingularity);
    assert_eq!(d.step, 0);
    assert!((d.value - 2.0).abs() < 1e-12 && d.limit == std::f64::consts::FRAC_PI_2);
}

/// Unit-norm drift of each rotator over 1e6 steps of a tumbling, torqued fibre.
#[test]
fn unit_norm_drift_over_a_million_steps() {
    let scene = scene_str(
        r#"
[simulation]
dt = 1e-6
t_end = 1.0
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
position = [0.0, 0.0, 0.0]
axis = [0.6, 0.8, 0.0]
angular_velocity = [300.0, 120.0, -50.0]
torque = ["2e-6*sin(30*t)", "1e-6*cos(20*t)", "5e-7"]
"#,
    );
    for kind in RotatorKind::ALL {
        let mut s = scene.clone();
        s.sim = s.sim.with_rotator(kind);
        let mut worst: f64 = 0.0;
        fibresim::run::integrate_observed(&s, |w| {
            worst = worst.max((w.states[0].rot.q.length() - 1.0).abs())
        })
        .expect("completes");
        println!(
            "{:<11} max | ||q|| - 1 | over 1e6 steps: {worst:.2e}",
            kind.name()
        );
        assert!(worst < 1e-12, "{kind}: {worst:e}");
    }
}

/// Eq. 29 equals R T Rᵀ (Eq. 7) for random rotations and general (non-symmetric) tensors.
#[test]
fn tensor_transform_eq29_equals_r_t_rt() {
    let mut seed = 11;
    for _ in 0..1000 {
        let q = exp_map(random_unit(&mut seed) * 6.0 * lcg(&mut seed));
        let t = DMat3::from_cols_array(&std::array::from_fn(|_| lcg(&mut seed) * 2.0 - 1.0));
        let r = DMat3::from_quat(q);
        let want = r * t * r.transpose();
        let got = rotate_tensor(q, t);
        assert!(
            (got - want)
                .abs()
                .to_cols_array()
                .iter()
                .all(|d| *d < 1e-14),
            "{got} vs {want}"
        );
    }
    // Inertia of a fibre with axis rotated onto y: the axial moment moves to yy.
    let i_b = DMat3::from_diagonal(DVec3::new(1.0, 5.0, 5.0));
    let q = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    let i_w = rotate_tensor(q, i_b);
    assert!((i_w.y_axis.y - 1.0).abs() < 1e-15 && (i_w.x_axis.x - 5.0).abs() < 1e-15);
}

/// Torque-free axisymmetric fibre: regular precession, closed form
/// `q(t) = exp(ω_p t L̂) q0 exp(λ t e_x)` with `ω_p = |L|/I_t`,
/// `λ = ω_1 (I_t − I_1)/I_t` (Landau & Lifshitz, Mechanics §33).
#[test]
fn torque_free_precession_closed_form() {
    let scene = scene_str(
        r#"
[simulation]
dt = 1e-5
t_end = 0.1
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
position = [0.0, 0.0, 0.0]
quaternion = [1.0, 0.0, 0.0, 0.0]
angular_velocity = [80.0, 30.0, 0.0]
"#,
    );
    let i = scene.bodies[0].inertia.principal;
    let w0 = DVec3::new(80.0, 30.0, 0.0);
    let l = i * w0; // q0 = identity: body = world at t = 0
    let t = 0.1;
    let (i1, it) = (i.x, i.y);
    let q_exact = exp_map(l.normalize() * (l.length() / it * t))
        * exp_map(DVec3::X * (w0.x * (it - i1) / it * t));
    // Sanity of the closed form itself against a fine rk4 run.
    let fine = final_state(&scene, RotatorKind::Rk4, 1e-6);
    assert!(geodesic_angle(fine.rot.q, q_exact) < 1e-11);
    for kind in RotatorKind::ALL {
        let s = final_state(&scene, kind, 1e-5);
        let err = geodesic_angle(s.rot.q, q_exact);
        println!(
            "{:<11} precession angle error at t = 0.1 s, dt = 1e-5: {err:.3e} rad",
            kind.name()
        );
        let bound = match kind.info().order {
            1 => 1e-2,
            2 => 1e-5,
            _ => 1e-9,
        };
        assert!(err < bound, "{kind}: {err:e}");
    }
}
