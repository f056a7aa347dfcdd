//! The friction springs' energy in energy.csv (`e_spring`), through the
//! command line.
//!
//! Reference: a sphere (radius R) sliding on a wall, without normal
//! damping (η_t = 0), holds its spring at the Coulomb cap, `k_t |ξ| = μ
//! F_n`, so `½ k_t |ξ|² = (μ F_n)²/(2 k_t)`. With Hertz `F_n = k δ^{3/2}`,
//! `k = (4/3) E* √R`, and Mindlin `k_t = 8 G* √(R δ)`, that is `μ² k²
//! δ^{5/2}/(16 G* √R)`, and over the Hertz energy `U = (2/5) k δ^{5/2}`
//! the ratio is a constant of the materials:
//! `e_spring / e_elastic = (5/24) μ² E*/G*` (Hertz; Mindlin, J. Appl.
//! Mech. 16 (1949) 259), with `1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂` and
//! `1/G* = (2−ν₁)/G₁ + (2−ν₂)/G₂`, `G = E/(2(1+ν))`.

use crate::common::{fibresim, ok, read_bytes};

/// energy.csv of `dir/name`: the header and the rows.
fn energy(dir: &std::path::Path, name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = String::from_utf8(read_bytes(&dir.join(name).join("energy.csv"))).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// `fibresim run` of the scene `text` into `dir/name`.
fn run(dir: &std::path::Path, name: &str, text: &str) {
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(&file, text).unwrap();
    let out = dir.join(name);
    ok(fibresim(&[
        "run",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--every",
        "20",
        "-q",
    ]));
}

/// A sphere (D = 1 cm) dropped from 1 mm above a floor of μ = 0.3 while
/// moving at 0.5 m/s along it, elastic (no restitution), for 50 ms: it
/// flies, lands sliding, bounces off, flies and lands again. `e_spring` is
/// in the file, never negative, exactly 0 in every row where nothing
/// touches, and `(5/24) μ² E*/G*` times `e_elastic` in every row of the
/// first landing (it slides throughout: its contact point moves at ~0.5
/// m/s; by the second it nearly rolls and sticks at times); to 1e-9
/// relative, the rounding of the two energies. The full budget (with
/// `e_spring` and `e_dissipated`) closes as well as the frictionless
/// run's (within 1.5 times its largest error). Without friction the file
/// has neither column.
#[test]
fn the_spring_energy_is_booked_apart_and_the_budget_closes() {
    let dir = tempfile::tempdir().unwrap();
    let (d, mu, h) = (0.01, 0.3, 1e-3);
    let (e_s, nu_s, e_w, nu_w) = (5e7, 0.35, 5e7, 0.23);
    let scene = |contact: &str| {
        format!(
            "[simulation]\ndt = 1e-6\nt_end = 0.05\n[world]\ngravity = [0.0, 0.0, -9.81]\n{contact}\n[box]\nmin = [-0.2, -0.2, 0.0]\nmax = [0.2, 0.2, 0.4]\nyoung = {e_w}\npoisson = {nu_w}\n[material.m]\ndensity = 1100.0\nyoung = {e_s}\npoisson = {nu_s}\n[[body]]\nshape = \"sphere\"\nmaterial = \"m\"\ndiameter = {d}\nposition = [-0.1, 0.0, {}]\nvelocity = [0.5, 0.0, 0.0]\n",
            d / 2.0 + h
        )
    };
    run(
        dir.path(),
        "rough",
        &scene(&format!("[contact]\nfriction = {mu}")),
    );
    run(dir.path(), "smooth", &scene(""));

    let (header, _) = energy(dir.path(), "smooth");
    assert!(
        !header
            .iter()
            .any(|h| h == "e_spring" || h == "e_dissipated"),
        "{header:?}"
    );

    let (header, rows) = energy(dir.path(), "rough");
    let col = |name: &str| header.iter().position(|h| h == name).expect(name);
    let (t, spring, elastic, contacts, error) = (
        col("t"),
        col("e_spring"),
        col("e_elastic"),
        col("contacts"),
        col("energy_error_full_pct"),
    );
    let e_star = 1.0 / ((1.0 - nu_s * nu_s) / e_s + (1.0 - nu_w * nu_w) / e_w);
    let g = |e: f64, nu: f64| e / (2.0 * (1.0 + nu));
    let g_star = 1.0 / ((2.0 - nu_s) / g(e_s, nu_s) + (2.0 - nu_w) / g(e_w, nu_w));
    let ratio = 5.0 / 24.0 * mu * mu * e_star / g_star;
    let (mut touching, mut flying, mut worst) = (0, 0, 0.0f64);
    let budget = rows.iter().map(|r| r[error].abs()).fold(0.0, f64::max);
    let (h, smooth) = energy(dir.path(), "smooth");
    let e = h.iter().position(|h| h == "energy_error_full_pct").unwrap();
    let budget_smooth = smooth.iter().map(|r| r[e].abs()).fold(0.0, f64::max);
    eprintln!("full budget error: {budget:e} % with friction, {budget_smooth:e} % without");
    for r in &rows {
        assert!(r[spring] >= 0.0, "{r:?}");
        if r[contacts] == 0.0 {
            flying += 1;
            assert_eq!(r[spring], 0.0, "nothing touches: {r:?}");
        } else if r[elastic] > 0.0 && r[t] < 0.03 {
            touching += 1;
            worst = worst.max((r[spring] / (ratio * r[elastic]) - 1.0).abs());
        }
    }
    eprintln!("e_spring/e_elastic: worst relative deviation {worst:e} from {ratio} over {touching} rows ({flying} in flight)");
    assert!(
        touching > 20 && flying > 1000,
        "{touching} rows touching, {flying} flying"
    );
    assert!(worst < 1e-9, "e_spring/e_elastic off {ratio} by {worst:e}");
    // The frictionless run's error is the integrator's (Verlet's on the
    // Hertz contact); friction adds its own work to the ledger, exactly.
    assert!(
        budget < 1.5 * budget_smooth,
        "full budget error {budget:e} %, frictionless {budget_smooth:e} %"
    );
}

/// A sphere (D = 1 cm) launched at 0.5 m/s along a floor of μ = 0.3 with
/// a restitution of 0.3 slides until `t* = 2 v₀/(7 μ g)` (48.5 ms). Once
/// its start's bounces are damped (from 20 ms on) it rests on the floor at
/// the Hertz overlap `m g = k δ^{3/2}` and its spring holds the cap,
/// `e_spring = (μ m g)²/(2 k_t)`, `k_t = 8 G* √(R δ)`, to 1e-6 relative
/// (a sliding spring holds the cap, `ξ = −f/k_t`: the damping takes no
/// part in it; Luding's reset `ξ = −(f + η_t v_t)/k_t` would store a spring
/// orders of magnitude longer, docs/contacts.md).
#[test]
fn a_damped_sliding_spring_holds_the_cap_energy() {
    let dir = tempfile::tempdir().unwrap();
    let (d, mu, g) = (0.01, 0.3, 9.81);
    let (e_s, nu_s, e_w, nu_w) = (5e7, 0.35, 5e7, 0.23);
    let text = format!(
        "[simulation]\ndt = 1e-6\nt_end = 0.045\n[world]\ngravity = [0.0, 0.0, -{g}]\n[contact]\nrestitution = 0.3\nfriction = {mu}\n[box]\nmin = [-0.2, -0.2, 0.0]\nmax = [0.2, 0.2, 0.4]\nyoung = {e_w}\npoisson = {nu_w}\n[material.m]\ndensity = 1100.0\nyoung = {e_s}\npoisson = {nu_s}\n[[body]]\nshape = \"sphere\"\nmaterial = \"m\"\ndiameter = {d}\nposition = [-0.15, 0.0, {}]\nvelocity = [0.5, 0.0, 0.0]\n",
        d / 2.0
    );
    run(dir.path(), "slide", &text);
    let (header, rows) = energy(dir.path(), "slide");
    let col = |name: &str| header.iter().position(|h| h == name).expect(name);
    let (t, spring) = (col("t"), col("e_spring"));
    let r = d / 2.0;
    let m = 1100.0 * std::f64::consts::PI * d * d * d / 6.0;
    let e_star = 1.0 / ((1.0 - nu_s * nu_s) / e_s + (1.0 - nu_w * nu_w) / e_w);
    let shear = |e: f64, nu: f64| e / (2.0 * (1.0 + nu));
    let g_star = 1.0 / ((2.0 - nu_s) / shear(e_s, nu_s) + (2.0 - nu_w) / shear(e_w, nu_w));
    let overlap = (m * g / (4.0 / 3.0 * e_star * r.sqrt())).powf(2.0 / 3.0);
    let k_t = 8.0 * g_star * (r * overlap).sqrt();
    let held = (mu * m * g).powi(2) / (2.0 * k_t);
    let mut worst = 0.0f64;
    for row in rows.iter().filter(|row| row[t] > 0.02) {
        worst = worst.max((row[spring] / held - 1.0).abs());
    }
    eprintln!("sliding spring: e_spring off (μ m g)²/(2 k_t) = {held:e} J by {worst:e}");
    assert!(worst < 1e-6, "e_spring off {held:e} J by {worst:e}");
}
