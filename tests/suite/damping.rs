//! Normal damping (`[contact] restitution`, src/contact/damping.rs): the
//! rebound against the stated e(v) of the model, and the energy budget with
//! the dissipated energy.
//!
//! References: `e` itself for one central contact (a fibre dropped end-on,
//! two fibres end to end); `exp(−α√2 π / √(5 − 2α²))` with `α = √5 (−ln e) /
//! √(ln² e + π²)` for a fibre landing flat on both ends (Antypov & Elliott
//! 2011; the module docs derive the √2).

use crate::common;
use common::scene_str;
use fibresim::run::integrate_observed;
use std::f64::consts::PI;

const MATERIAL: &str = "[material.pa]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n";

/// A box without gravity, floor at z = 0, fibre D = 0.01, L = 0.03.
fn scene(dt: f64, t_end: f64, e: f64, bodies: &str) -> String {
    format!(
        "[simulation]\ndt = {dt:e}\nt_end = {t_end:e}\n[box]\nmin = [-1.0, -1.0, 0.0]\nmax = [1.0, 1.0, 2.0]\nyoung = 5e7\npoisson = 0.35\n{MATERIAL}[contact]\nrestitution = {e}\n{bodies}"
    )
}

fn fibre(x: [f64; 3], axis: [f64; 3], v: [f64; 3]) -> String {
    format!(
        "[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.03\nmaterial = \"pa\"\nposition = {x:?}\naxis = {axis:?}\nvelocity = {v:?}\n"
    )
}

/// The Hertz time of a fibre–wall impact of mass m at speed v (closed form,
/// docs/guide.md, "Time-step advice": t = 2.868 (m²/(R* E*² v))^{1/5}).
fn hertz_time(m: f64, v: f64) -> f64 {
    let e_star = 5e7 / (2.0 * (1.0 - 0.35 * 0.35));
    2.868_265_699_195_331_5 * (m * m / (0.005 * e_star * e_star * v)).powf(0.2)
}

const MASS: f64 = 1100.0 * PI * 0.01 * 0.01 * 0.03 / 4.0;

/// Run until the body has left the contact: final velocity, and the
/// largest |E + E_dissipated − E₀| / E₀ over the run.
fn run(text: &str) -> (Vec<glam::DVec3>, f64, f64) {
    let s = scene_str(text);
    let mut budget: f64 = 0.0;
    let w = integrate_observed(&s, |w| {
        budget = budget.max(((w.ledger.total_full() - w.e0_full) / w.e0_full).abs());
    })
    .expect("stable");
    (
        w.states.iter().map(|s| s.v).collect(),
        budget,
        w.ledger.dissipated,
    )
}

/// End-on drop at speed v with `steps` steps per Hertz time: rebound
/// ratio, largest budget error, and the gap between the dissipated energy
/// and the kinetic energy lost, over the initial energy.
fn end_on(e: f64, v: f64, steps: f64) -> (f64, f64, f64) {
    let t_c = hertz_time(MASS, v);
    let dt = t_c / steps;
    let gap = 1e-4;
    let t_end = ((gap / v + 2.0 * t_c) / dt).ceil() * dt;
    let text = scene(
        dt,
        t_end,
        e,
        &fibre([0.0, 0.0, 0.015 + gap], [0.0, 0.0, 1.0], [0.0, 0.0, -v]),
    );
    let (vf, budget, diss) = run(&text);
    let e0 = 0.5 * MASS * v * v;
    let lost = e0 - 0.5 * MASS * vf[0].length_squared();
    (vf[0].z / v, budget, (diss - lost).abs() / e0)
}

/// Dropped end-on (one contact at the face centre): the rebound is e at
/// every speed, converging at first order in δt (the force sees the
/// half-step velocity; where in a step the contact starts adds a scatter
/// of the same size, so the test steps 8x finer: -1.07e-3 at 200 steps per
/// Hertz time, -1.26e-4 at 1600, for e = 0.3 at 0.2 m/s). The budget `E + E_dissipated` closes as well as
/// the elastic one does at the same δt (the same drop with e = 1): the
/// dissipated energy is the exact work of the damping forces.
#[test]
fn an_end_on_drop_rebounds_with_e_at_every_speed() {
    for v in [0.2, 2.0] {
        let (_, elastic, _) = end_on(1.0, v, 200.0);
        for e in [0.3, 0.7] {
            let (r1, b1, gap) = end_on(e, v, 200.0);
            let (r2, _, _) = end_on(e, v, 1600.0);
            let (err1, err2) = ((r1 - e).abs(), (r2 - e).abs());
            assert!(err1 < 5e-3 * e, "e = {e}, v = {v}: rebound {r1}");
            assert!(err2 < err1 / 3.0, "first order: {err1:e} then {err2:e}");
            assert!(
                b1 < 2.0 * elastic + 1e-12,
                "budget error {b1:e}, elastic {elastic:e}"
            );
            assert!(gap <= b1 + 1e-15, "dissipated vs lost {gap:e}");
        }
    }
}

/// Landing flat (one contact per end, both at once): e of two dampers on
/// half the mass each, the stated e_2 (0.158 for e = 0.3).
#[test]
fn a_flat_landing_rebounds_with_the_two_point_restitution() {
    let e: f64 = 0.3;
    let l = -e.ln();
    let alpha = 5f64.sqrt() * l / (l * l + PI * PI).sqrt();
    let a2 = alpha * 2f64.sqrt();
    let want = (-a2 * PI / (5.0 - a2 * a2).sqrt()).exp();
    assert!((want - 0.158).abs() < 1e-3, "{want}");
    let v = 1.0;
    // Two points of m/2 each: the Hertz time of mass m/2 per point.
    let t_c = hertz_time(0.5 * MASS, v);
    let dt = t_c / 400.0;
    let gap = 1e-4;
    let t_end = ((gap / v + 2.0 * t_c) / dt).ceil() * dt;
    let flat = |e: f64| {
        let body = fibre([0.0, 0.0, 0.005 + gap], [1.0, 0.0, 0.0], [0.0, 0.0, -v]);
        run(&scene(dt, t_end, e, &body))
    };
    let (vf, budget, _) = flat(e);
    let (_, elastic, _) = flat(1.0);
    let ratio = vf[0].z / v;
    assert!(
        (ratio - want).abs() < 5e-3 * want,
        "rebound {ratio}, stated {want}"
    );
    assert!(
        budget < 2.0 * elastic + 1e-12,
        "budget error {budget:e}, elastic {elastic:e}"
    );
}

/// Two fibres end to end (one contact between the face centres, pure
/// translation, m* = m/2): the relative speed comes back times e.
#[test]
fn a_coaxial_head_on_pair_separates_with_e() {
    let e = 0.5;
    let v: f64 = 0.5;
    let dt: f64 = 2e-7;
    let gap = 1e-4;
    let t_end = ((gap / (2.0 * v) + 2e-3) / dt).ceil() * dt;
    let bodies = fibre(
        [-0.015 - gap / 2.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
        [v, 0.0, 0.0],
    ) + &fibre(
        [0.015 + gap / 2.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
        [-v, 0.0, 0.0],
    );
    let (vf, budget, _) = run(&scene(dt, t_end, e, &bodies));
    let (_, elastic, _) = run(&scene(dt, t_end, 1.0, &bodies));
    let ratio = (vf[1].x - vf[0].x) / (2.0 * v);
    assert!((ratio - e).abs() < 5e-3 * e, "relative rebound {ratio}");
    assert!(vf[0].x < 0.0 && vf[1].x > 0.0);
    assert!(
        budget < 2.0 * elastic + 1e-12,
        "budget error {budget:e}, elastic {elastic:e}"
    );
}

/// `restitution = 1` is the elastic scene: the same bytes as without the
/// table (no damping is built), and no `e_dissipated` column.
#[test]
fn restitution_one_runs_exactly_as_an_elastic_scene() {
    let dir = tempfile::tempdir().unwrap();
    let body = fibre([0.0, 0.0, 0.0175], [0.0, 0.3, 1.0], [0.0, 0.0, -1.0]);
    let elastic = scene(1e-6, 2e-3, 1.0, &body).replace("[contact]\nrestitution = 1\n", "");
    let one = scene(1e-6, 2e-3, 1.0, &body);
    assert!(one.contains("restitution = 1\n") && !elastic.contains("restitution"));
    let mut out = vec![];
    for (name, text) in [("a", elastic), ("b", one)] {
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        let o = common::fibresim(&[
            "run",
            path.to_str().unwrap(),
            "-q",
            "--out",
            dir.path().join(name).to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out.push(std::fs::read(dir.path().join(name).join("energy.csv")).unwrap());
    }
    assert_eq!(out[0], out[1]);
    assert!(!String::from_utf8_lossy(&out[0]).contains("e_dissipated"));
}

/// A fibre tilted 30° from the vertical dropped onto the floor lands on
/// one rim point, off its axis: the damping force there has a lever arm
/// and brakes the spin the landing gives the fibre. The ledger takes that
/// torque's work at the angular velocity at the middle of the interval
/// the torque drives (src/contact/ledger.rs), whichever one the rotator
/// hands the forces: the half-step one (`omelyan`, the default), the
/// start-of-step one (`pcdm`) or the predicted middle itself
/// (`pcdm-staggered`). Reference: the same landing elastic (e = 1), whose
/// budget error is the integrator's alone, second order. At 100 and 200
/// steps per Hertz time the damped budget error must fall at least 3-fold
/// (second order: 4; at the angular velocity the forces see it falls
/// 2-fold, a first-order bias of `(δt/2) T·Δω` a step) and stay within
/// 1.2 times the elastic one, for each kick–drift–kick and staggered
/// rotator; `pcdm`, first order with contacts, must not exceed 1.2 times
/// its elastic error either.
#[test]
fn a_tilted_landing_closes_the_damped_budget_at_second_order() {
    let v = 1.0;
    let t_c = hertz_time(MASS, v);
    let axis = [0.0, 0.5, 3f64.sqrt() / 2.0];
    // The rim's lowest point: the end face's centre less the radius along
    // the face's steepest descent.
    let low = 0.015 * axis[2] + 0.005 * axis[1];
    let gap = 1e-4;
    let budget = |rotator: &str, steps: f64| {
        let dt = t_c / steps;
        let t_end = ((gap / v + 3.0 * t_c) / dt).ceil() * dt;
        let body = fibre([0.0, 0.0, low + gap], axis, [0.0, 0.0, -v]);
        let named = |e: f64| {
            scene(dt, t_end, e, &body).replace("[box]", &format!("rotator = \"{rotator}\"\n[box]"))
        };
        let (vf, damped, _) = run(&named(0.3));
        let (_, elastic, _) = run(&named(1.0));
        assert!(vf[0].z > 0.0, "the fibre has not left the floor: {vf:?}");
        eprintln!(
            "{rotator}, {steps} steps per Hertz time: budget error {damped:e}, elastic {elastic:e}"
        );
        assert!(
            damped < 1.2 * elastic,
            "{rotator}: budget error {damped:e}, elastic {elastic:e}"
        );
        damped
    };
    for rotator in ["omelyan", "pcdm-staggered", "pcdm"] {
        let (coarse, fine) = (budget(rotator, 100.0), budget(rotator, 200.0));
        if rotator != "pcdm" {
            assert!(
                fine < coarse / 3.0,
                "{rotator}: budget error {coarse:e} then {fine:e}: not second order"
            );
        }
    }
}
