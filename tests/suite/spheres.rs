//! Spheres in contact scenes, through the command line: a sphere hitting a
//! wall and two spheres colliding head-on against Hertz's closed forms,
//! with and without restitution; a sphere dropped on a fibre's side and on
//! its end face.
//!
//! References (computed here from the scene's inputs, never from the
//! program): for `F = (4/3) E* √R* δ^{3/2}` and an impact at relative speed
//! `v`, the peak overlap `δ_max = (15 m* v²/(16 E* √R*))^{2/5}` and the
//! contact time `t_c = 2 I δ_max / v`, `I = ∫₀¹ (1 − x^{5/2})^{−1/2} dx =
//! (2/5) B(2/5, 1/2)` (Johnson, Contact Mechanics (1985) §11.4; the Γ
//! values from Abramowitz & Stegun, Table 6.1), i.e. `t_c = 2.868
//! (m*²/(R* E*² v))^{1/5}`; an elastic collision gives the speeds of the
//! one-dimensional elastic impact back.

use crate::common::{fibresim, ok, read_bytes};
use std::f64::consts::PI;
use std::path::Path;

/// `I = (2/5) Γ(2/5) Γ(1/2) / Γ(9/10)`.
fn hertz_integral() -> f64 {
    0.4 * 2.218_159_543_757_688 * PI.sqrt() / 1.068_628_702_119_319_4
}

/// `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂`.
fn e_star(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// Hertz's peak overlap and contact time of an impact of reduced mass
/// `m`, effective radius `r`, effective modulus `e` at speed `v`.
fn hertz(m: f64, r: f64, e: f64, v: f64) -> (f64, f64) {
    let d_max = (15.0 * m * v * v / (16.0 * e * r.sqrt())).powf(0.4);
    (d_max, 2.0 * hertz_integral() * d_max / v)
}

const DENSITY: f64 = 1100.0;
const YOUNG: f64 = 5e7;
const POISSON: f64 = 0.35;
const WALL_YOUNG: f64 = 5e7;
const WALL_POISSON: f64 = 0.23;

fn mass(d: f64) -> f64 {
    DENSITY * PI * d * d * d / 6.0
}

fn sphere(d: f64, x: [f64; 3], v: [f64; 3]) -> String {
    format!("[[body]]\nshape = \"sphere\"\nmaterial = \"m\"\ndiameter = {d}\nposition = {x:?}\nvelocity = {v:?}\n")
}

fn fibre(x: [f64; 3], axis: [f64; 3], v: [f64; 3]) -> String {
    format!("[[body]]\nshape = \"fibre\"\nmaterial = \"m\"\ndiameter = 0.01\nlength = 0.025\nposition = {x:?}\naxis = {axis:?}\nvelocity = {v:?}\n")
}

/// A scene in the box [−0.2, 0.2]² × [0, 0.4] (floor at z = 0).
fn scene(sim: &str, extra: &str, bodies: &[String]) -> String {
    format!(
        "[simulation]\n{sim}\n{extra}\n[box]\nmin = [-0.2, -0.2, 0.0]\nmax = [0.2, 0.2, 0.4]\nyoung = {WALL_YOUNG}\npoisson = {WALL_POISSON}\n[material.m]\ndensity = {DENSITY}\nyoung = {YOUNG}\npoisson = {POISSON}\n{}",
        bodies.concat()
    )
}

/// What a run wrote: per row of energy.csv `(contacts, max_overlap_ratio,
/// energy_error_full_pct)`, and the summary.
struct Run {
    rows: Vec<(u64, f64, f64)>,
    summary: serde_json::Value,
}

impl Run {
    fn final_v(&self, body: usize) -> [f64; 3] {
        let v = &self.summary["final"][body]["v"];
        [0, 1, 2].map(|k| v[k].as_f64().expect("a velocity"))
    }

    /// Rows with a live contact, and the largest overlap ratio seen.
    fn contact(&self) -> (usize, f64) {
        let n = self.rows.iter().filter(|r| r.0 > 0).count();
        let peak = self.rows.iter().map(|r| r.1).fold(0.0, f64::max);
        (n, peak)
    }
}

/// `fibresim run` of `text` with one row per step.
fn run(dir: &Path, name: &str, text: &str) -> Run {
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(&file, text).unwrap();
    let out = dir.join(name);
    ok(fibresim(&[
        "run",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--every",
        "1",
        "-q",
    ]));
    let csv = String::from_utf8(read_bytes(&out.join("energy.csv"))).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let (c, o, e) = (
        col("contacts"),
        col("max_overlap_ratio"),
        col("energy_error_full_pct"),
    );
    let rows = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[c].parse().unwrap(),
                f[o].parse().unwrap(),
                f[e].parse().unwrap(),
            )
        })
        .collect();
    let summary = serde_json::from_slice(&read_bytes(&out.join("summary.json"))).unwrap();
    Run { rows, summary }
}

/// `n` rows of a live contact, at `dt`, against the contact time `t_c`:
/// the first and the last touching step may each start or end up to one
/// step from the true contact, so `|n δt − t_c| ≤ 2 δt`.
fn assert_duration(n: usize, dt: f64, t_c: f64) {
    let t = n as f64 * dt;
    assert!(
        (t - t_c).abs() <= 2.0 * dt,
        "contact lasted {t:e} s ({n} steps), Hertz {t_c:e} s"
    );
}

/// The sampled peak overlap against `d_max`: at `S = t_c/δt` steps per
/// contact the sampled maximum is below the true one by at most
/// `F_max δt²/(8 m*) = (5/8) δ_max (v δt / δ_max)²/2 ≤ 5 δ_max/S²`
/// (`F_max/m* = (5/4) v²/δ_max` and `t_c < 3 δ_max/v`), and the
/// integrator's error is of the same order `(δt/t_c)²`; `10/S²` holds both.
fn assert_peak(peak: f64, d_max: f64, steps: f64) {
    let tol = 10.0 / (steps * steps);
    assert!(
        (peak - d_max).abs() <= tol * d_max,
        "peak overlap {peak:e} m, Hertz {d_max:e} m (tolerance {tol:e} relative)"
    );
}

/// Steps per Hertz contact time in the closed-form tests.
const STEPS: f64 = 1000.0;

/// A sphere (D = 0.01 m) hits the floor at 1 m/s, no gravity: the contact
/// lasts the Hertz time of `m* = m`, `R* = D/2`, the peak overlap is
/// Hertz's, and it leaves at 1 m/s (elastic) or at `e` m/s with
/// `wall_restitution = e` (to 5e-3 e at 200 steps per contact time, the
/// damping's first-order error: tests/suite/damping.rs).
#[test]
fn a_sphere_hits_a_wall_for_the_hertz_time_and_depth() {
    let dir = tempfile::tempdir().unwrap();
    let (d, v) = (0.01, 1.0);
    let e = e_star(YOUNG, POISSON, WALL_YOUNG, WALL_POISSON);
    let (d_max, t_c) = hertz(mass(d), 0.5 * d, e, v);
    let dt = t_c / STEPS;
    let gap = 5.0 * dt * v;
    let t_end = ((gap / v + 1.2 * t_c) / dt).ceil() * dt;
    let body = sphere(d, [0.0, 0.0, 0.5 * d + gap], [0.0, 0.0, -v]);
    let elastic = run(
        dir.path(),
        "wall",
        &scene(&format!("dt = {dt:e}\nt_end = {t_end:e}"), "", &[body]),
    );
    let (n, peak) = elastic.contact();
    eprintln!(
        "wall: {n} steps of {dt:e} s, Hertz {t_c:e} s; peak {:e} m, Hertz {d_max:e} m",
        peak * d
    );
    assert_duration(n, dt, t_c);
    assert_peak(peak * d, d_max, STEPS);
    let out = elastic.final_v(0);
    assert!(
        (out[2] - v).abs() <= 1e-6 * v && out[0] == 0.0 && out[1] == 0.0,
        "rebound {out:?}"
    );

    let e_wall = 0.5;
    let dt = t_c / 200.0;
    let t_end = ((gap / v + 1.5 * t_c) / dt).ceil() * dt;
    let body = sphere(d, [0.0, 0.0, 0.5 * d + gap], [0.0, 0.0, -v]);
    let damped = run(
        dir.path(),
        "wall_damped",
        &scene(
            &format!("dt = {dt:e}\nt_end = {t_end:e}"),
            &format!("[contact]\nrestitution = 1.0\nwall_restitution = {e_wall}"),
            &[body],
        ),
    );
    let out = damped.final_v(0)[2];
    assert!(
        (out / v - e_wall).abs() <= 5e-3 * e_wall,
        "rebound {out} m/s from {v} m/s, e = {e_wall}"
    );
}

/// Two spheres of different diameters (0.01 and 0.006 m) head-on at 1 m/s
/// each, no gravity, no wall in reach: the contact lasts the Hertz time of
/// `m* = m₁m₂/(m₁ + m₂)`, `R* = R₁R₂/(R₁ + R₂)`, `E* = E/(2(1 − ν²))` at
/// the relative speed 2 m/s, its peak overlap over the smaller diameter is
/// Hertz's, and they leave with the speeds of the elastic impact; with
/// `restitution = e`, the relative speed comes back times e.
#[test]
fn two_spheres_collide_head_on_for_the_hertz_time_and_depth() {
    let dir = tempfile::tempdir().unwrap();
    let (d1, d2, v) = (0.01, 0.006, 1.0);
    let (m1, m2) = (mass(d1), mass(d2));
    let m_star = m1 * m2 / (m1 + m2);
    let r_star = 0.5 * d1 * 0.5 * d2 / (0.5 * d1 + 0.5 * d2);
    let e = e_star(YOUNG, POISSON, YOUNG, POISSON);
    let (d_max, t_c) = hertz(m_star, r_star, e, 2.0 * v);
    let gap = 1e-5;
    let bodies = || {
        let x = 0.5 * (d1 + d2 + gap);
        [
            sphere(d1, [-0.5 * x, 0.0, 0.2], [v, 0.0, 0.0]),
            sphere(d2, [0.5 * x, 0.0, 0.2], [-v, 0.0, 0.0]),
        ]
    };
    let dt = t_c / STEPS;
    let t_end = ((gap / (2.0 * v) + 1.2 * t_c) / dt).ceil() * dt;
    let elastic = run(
        dir.path(),
        "pair",
        &scene(&format!("dt = {dt:e}\nt_end = {t_end:e}"), "", &bodies()),
    );
    let (n, peak) = elastic.contact();
    eprintln!(
        "pair: {n} steps of {dt:e} s, Hertz {t_c:e} s; peak {:e} m, Hertz {d_max:e} m",
        peak * d2
    );
    assert_duration(n, dt, t_c);
    assert_peak(peak * d2, d_max, STEPS);
    // The one-dimensional elastic impact: u₁ = ((m₁ − m₂)v₁ + 2m₂v₂)/(m₁ + m₂).
    let u1 = ((m1 - m2) * v - 2.0 * m2 * v) / (m1 + m2);
    let u2 = (2.0 * m1 * v - (m2 - m1) * v) / (m1 + m2);
    let (o1, o2) = (elastic.final_v(0)[0], elastic.final_v(1)[0]);
    assert!(
        (o1 - u1).abs() <= 1e-6 * v && (o2 - u2).abs() <= 1e-6 * v,
        "speeds after {o1}, {o2}; elastic impact {u1}, {u2}"
    );

    let e_pair = 0.5;
    let dt = t_c / 200.0;
    let t_end = ((gap / (2.0 * v) + 1.5 * t_c) / dt).ceil() * dt;
    let damped = run(
        dir.path(),
        "pair_damped",
        &scene(
            &format!("dt = {dt:e}\nt_end = {t_end:e}"),
            &format!("[contact]\nrestitution = {e_pair}"),
            &bodies(),
        ),
    );
    let (o1, o2) = (damped.final_v(0)[0], damped.final_v(1)[0]);
    let ratio = (o2 - o1) / (2.0 * v);
    assert!(
        (ratio - e_pair).abs() <= 5e-3 * e_pair,
        "relative speed after {} m/s, before {} m/s, e = {e_pair}",
        o2 - o1,
        2.0 * v
    );
    // Momentum is exchanged, not made.
    let p = m1 * o1 + m2 * o2;
    assert!(
        (p - (m1 - m2) * v).abs() <= 1e-12 * (m1 + m2) * v,
        "momentum {p}"
    );
}

/// A sphere (D = 0.008 m) dropped at 0.5 m/s under gravity on a fibre
/// resting on the floor, on the middle of its side (fibre lying along x)
/// and on its top end face (fibre standing): the sphere bounces (it rises
/// after the contact), the sphere–fibre contact was live, and the energy
/// budget closes as well as the same drop of a fibre, crosswise on the
/// side or end-on on the face, does at the same δt.
#[test]
fn a_sphere_dropped_on_a_fibre_side_and_face_bounces() {
    let dir = tempfile::tempdir().unwrap();
    let (dt, t_end) = (2e-7, 2e-3);
    let sim = format!("dt = {dt:e}\nt_end = {t_end:e}\nrotator = \"pcdm\"");
    let world = "[world]\ngravity = [0.0, 0.0, -9.81]";
    let ds = 0.008;
    // Lying along x on the floor (top at z = 0.01), and standing on its
    // end (0.1 µm above the floor, top face at z = 0.025), the sphere's
    // centre 2 mm off the axis.
    for (name, base, top, falling) in [
        (
            "side",
            fibre([0.0, 0.0, 0.005], [1.0, 0.0, 0.0], [0.0; 3]),
            0.01,
            fibre([0.002, 0.0, 0.0151], [0.0, 1.0, 0.0], [0.0, 0.0, -0.5]),
        ),
        (
            "face",
            fibre([0.0, 0.0, 0.012_500_1], [0.0, 0.0, 1.0], [0.0; 3]),
            0.025,
            fibre([0.002, 0.0, 0.0376], [0.0, 0.0, 1.0], [0.0, 0.0, -0.5]),
        ),
    ] {
        let s = sphere(ds, [0.002, 0.0, top + 0.5 * ds + 1e-4], [0.0, 0.0, -0.5]);
        let with_sphere = run(
            dir.path(),
            &format!("sphere_{name}"),
            &scene(&sim, world, &[base.clone(), s]),
        );
        let with_fibre = run(
            dir.path(),
            &format!("fibre_{name}"),
            &scene(&sim, world, &[base, falling]),
        );
        let vz = with_sphere.final_v(1)[2];
        assert!(vz > 0.1, "{name}: the sphere leaves at {vz} m/s");
        let live = with_sphere.rows.iter().map(|r| r.0).max().unwrap();
        assert!(
            live >= 2,
            "{name}: the floor and the sphere on the fibre ({live})"
        );
        let worst = |r: &Run| r.rows.iter().map(|r| r.2.abs()).fold(0.0, f64::max);
        let (sphere_err, fibre_err) = (worst(&with_sphere), worst(&with_fibre));
        eprintln!("{name}: budget error {sphere_err:e} % (a fibre dropped: {fibre_err:e} %)");
        assert!(
            sphere_err <= 3.0 * fibre_err.max(1e-6),
            "{name}: budget error {sphere_err:e} %, a fibre dropped the same way {fibre_err:e} %"
        );
    }
}
