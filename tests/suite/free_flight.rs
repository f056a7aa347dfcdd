//! Free flight: `split` against the exact torque-free motion over 10⁶
//! steps, and time reversibility of every rotator.
//!
//! The references are the closed forms of `fibresim::reference`, themselves
//! checked against tight rk4 runs to ≤ 1e-12 rad (`tests/suite/reference.rs`).

use crate::common;
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
    let mut worst = 0.0f64;
    let w = fibresim::run::integrate_observed(&s, |w| {
        if w.step % 10_000 == 0 {
            let e = geodesic_angle(w.states[0].rot.q, reference.orientation(w.time()));
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

/// The free-flight criterion: ≤ 1e-12 rad over 10⁶ free steps, for the
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
/// 1e-9 (a step coarse enough that rk4's own error shows) (`cargo test --release --test suite free_flight:: -- --nocapture` prints
/// every distance, quoted in docs/validation.md).
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

/// The long-run and reversibility table of every rotator:
/// 10⁶ steps on the asymmetric top (1e-4 s) and on the precessing fibre
/// (1e-5 s), energy and angular momentum against their start, orientation
/// against the closed form, and the round trip (forward 2 s at 5e-3 s on
/// the top, 0.2 s at 5e-4 s on the fibre, ω flipped, back). In the slow tier:
/// `cargo test --release --test suite free_flight::long_runs -- --ignored --nocapture`
/// prints the markdown docs/validation.md quotes and writes it to
/// `target/long_runs.md`.
#[test]
#[ignore = "slow tier: 10⁶ steps of every rotator on two scenes; prints the table the docs quote"]
fn long_runs_table() {
    use fibresim::study::long_run::{long_run, markdown, round_trip};
    let mut out = String::new();
    for (file, dt, rev_dt, rev_n) in [
        ("asymmetric_top.toml", 1e-4, 5e-3, 400),
        ("precessing_fibre.toml", 1e-5, 5e-4, 400),
    ] {
        let scene = scene_file(file);
        let runs: Vec<_> = RotatorKind::ALL
            .iter()
            .map(|&k| {
                let r = long_run(&scene, k, dt, 1_000_000, 10_000);
                let rev = round_trip(&scene, k, rev_dt, rev_n);
                eprintln!("{file} {k}: {:?} rev {rev:.2e}", r.trend);
                (r, rev)
            })
            .collect();
        let title = format!(
            "**`{file}`**, 10⁶ steps of {dt:e} s (samples every 10⁴ steps); reversibility: {rev_n} steps of {rev_dt:e} s forward and back"
        );
        out += &markdown(&title, &runs);
        out.push('\n');
    }
    println!("{out}");
    std::fs::write(
        concat!(env!("CARGO_MANIFEST_DIR"), "/target/long_runs.md"),
        &out,
    )
    .unwrap();
}
