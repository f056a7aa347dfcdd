//! Free flight: `split` against the exact torque-free motion over 10⁶
//! steps, and time reversibility of every rotator.
//!
//! The references are the closed forms of `fibresim::reference`, themselves
//! checked against tight rk4 runs to ≤ 1e-12 rad (`tests/reference.rs`).

mod common;
use common::*;
use fibresim::integrate::rotate::RotatorKind;
use fibresim::math::geodesic_angle;
use fibresim::scenario::{Scene, SimParams};

/// `split` over `steps` steps of `dt`: the largest orientation error against
/// the scene's closed form, sampled every 10⁴ steps, and the final relative
/// errors of the energy and of |L|.
fn split_free_flight(scene: &Scene, dt: f64, steps: u64) -> (f64, f64, f64) {
    let mut s = scene.clone();
    s.sim = SimParams::with_steps(dt, steps, RotatorKind::Split, None).unwrap();
    let reference = scene.reference.clone().expect("a closed form");
    let q0 = scene.initial[0].rot.q;
    let mut worst = 0.0f64;
    let w = fibresim::run::integrate_observed(&s, |w| {
        if w.step % 10_000 == 0 {
            let e = geodesic_angle(w.states[0].rot.q, reference.orientation(w.time(), q0));
            worst = worst.max(e);
        }
    })
    .expect("the run completes");
    let i = scene.bodies[0].inertia.principal;
    let (w0, w1) = (scene.initial[0].rot.omega_b, w.states[0].rot.omega_b);
    let energy = |w: glam::DVec3| (i * w).dot(w);
    let momentum = |w: glam::DVec3| (i * w).length();
    (
        worst,
        (energy(w1) / energy(w0) - 1.0).abs(),
        (momentum(w1) / momentum(w0) - 1.0).abs(),
    )
}

/// The criterion: ≤ 1e-12 rad over 10⁶ free steps, for the
/// asymmetric top (elliptic-function flow, 100 s at 1e-4 s) and for the
/// precessing fibre (closed-form flow, 10 s at 1e-5 s).
#[test]
fn split_is_exact_over_a_million_free_steps() {
    for (file, dt) in [
        ("asymmetric_top.toml", 1e-4),
        ("precessing_fibre.toml", 1e-5),
    ] {
        let scene = scene_file(file);
        let (worst, de, dl) = split_free_flight(&scene, dt, 1_000_000);
        println!("split, {file}, 1e6 steps of {dt:e} s: largest error {worst:.2e} rad, energy {de:.1e}, |L| {dl:.1e} (relative)");
        assert!(worst <= 1e-12, "{file}: {worst:e} rad");
        // ω is derived from q each step, so energy and |L| carry q's rounding.
        assert!(
            de < 1e-11 && dl < 1e-11,
            "{file}: energy {de:e}, |L| {dl:e}"
        );
    }
}

/// Run forward `n` steps, flip ω, run `n` steps back: the distance from the
/// start (geodesic angle plus the relative ω difference). Torque-free
/// asymmetric top, so every scheme's free-flight map is what is tested.
fn round_trip(kind: RotatorKind, dt: f64, n: u64) -> f64 {
    let mut scene = scene_file("asymmetric_top.toml");
    scene.reference = None;
    scene.sim = SimParams::with_steps(dt, n, kind, None).unwrap();
    // The first-order schemes gain > 10 % energy at this step: measure
    // their distance rather than stop them.
    scene.guards.energy_error_pct = f64::INFINITY;
    let start = scene.initial[0].rot;
    let there = fibresim::run::integrate_observed(&scene, |_| {})
        .unwrap()
        .states[0]
        .rot;
    scene.initial[0].rot.q = there.q;
    scene.initial[0].rot.omega_b = -there.omega_b;
    let back = fibresim::run::integrate_observed(&scene, |_| {})
        .unwrap()
        .states[0]
        .rot;
    geodesic_angle(back.q, start.q)
        + (back.omega_b + start.omega_b).length() / start.omega_b.length()
}

/// `RotatorInfo::reversible` holds: a reversible scheme returns to rounding
/// (< 1e-11 after 2 × 400 steps of 5e-3 s), the others miss by more than
/// 1e-9 (a step coarse enough that rk4's own error shows) (`cargo test --release --test free_flight -- --nocapture` prints
/// every distance, quoted in the README).
#[test]
fn reversibility_is_as_listed() {
    for kind in RotatorKind::ALL {
        let d = round_trip(kind, 5e-3, 400);
        let listed = kind.info().reversible;
        println!("{:<12} forward 2 s, ω flipped, back 2 s: distance {d:.2e} (listed reversible: {listed})", kind.name());
        if listed {
            assert!(d < 1e-11, "{kind}: listed reversible, distance {d:e}");
        } else {
            assert!(d > 1e-9, "{kind}: listed not reversible, distance {d:e}");
        }
    }
}
