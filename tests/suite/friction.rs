//! Coulomb friction through the command line, against the closed forms of
//! rigid bodies on a frictional floor (references computed here from the
//! scene's inputs):
//! - a sphere launched sliding without spin decelerates at `μ g`, spins up
//!   at `α = 5 μ g/(2R)` and rolls without slip from `t* = 2 v₀/(7 μ g)`
//!   at `v = 5 v₀/7` (Marion & Thornton, Classical Dynamics, the billiard
//!   ball; the impulse balance `m Δv = −R⁻¹ I Δω` with `I = (2/5) m R²`);
//! - on a tilted-gravity floor (angle θ) a sphere rolls with
//!   `a = (5/7) g sin θ` when `μ ≥ (2/7) tan θ`, and slides with
//!   `a = g (sin θ − μ cos θ)` otherwise; a solid cylinder lying across
//!   the slope rolls with `a = (2/3) g sin θ` when `μ ≥ tan θ/3` (the
//!   rolling constraint with `I = (2/5) m R²`, `I = (1/2) m r²`);
//! - a scene at `μ = 0` is the frictionless scene byte for byte, and a
//!   dense frictional bed gives the same bytes at any thread count.

use crate::common::{fibresim, ok, read_bytes};
use std::path::Path;

const G: f64 = 9.81;
const DT: f64 = 1e-6;

/// A scene in the box [−0.2, 0.2]² × [0, 0.4] (floor at z = 0) under
/// `gravity`, with the `[contact]` lines `contact`, one trajectory row per
/// `every` steps, and `bodies`.
fn scene(t_end: f64, gravity: [f64; 3], contact: &str, every: u64, bodies: &str) -> String {
    format!(
        "[simulation]\ndt = {DT}\nt_end = {t_end}\n[world]\ngravity = {gravity:?}\n[contact]\n{contact}\n[output]\ntrajectory_every = {every}\n[box]\nmin = [-0.2, -0.2, 0.0]\nmax = [0.2, 0.2, 0.4]\nyoung = 5e7\npoisson = 0.23\n[material.m]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n{bodies}"
    )
}

/// `[[body]]` of a sphere of diameter `d` touching the floor at x = `x`
/// with velocity `v`.
fn sphere(d: f64, x: f64, v: [f64; 3]) -> String {
    format!("[[body]]\nshape = \"sphere\"\nmaterial = \"m\"\ndiameter = {d}\nposition = [{x}, 0.0, {}]\nvelocity = {v:?}\n", d / 2.0)
}

/// Each trajectory row of body 0: `(t, v, ω)` (world).
type Row = (f64, [f64; 3], [f64; 3]);

/// `fibresim run` of `text`; the trajectory of body 0 and the folder.
fn run(dir: &Path, name: &str, text: &str) -> Vec<Row> {
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(&file, text).unwrap();
    let out = dir.join(name);
    ok(fibresim(&[
        "run",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]));
    let csv = String::from_utf8(read_bytes(&out.join("trajectory.csv"))).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let cols = ["t", "vx", "vy", "vz", "wx", "wy", "wz"].map(col);
    lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            let [t, vx, vy, vz, wx, wy, wz] = cols.map(|c| f[c]);
            (t, [vx, vy, vz], [wx, wy, wz])
        })
        .collect()
}

/// The mean acceleration along x between the rows at `t1` and `t2`.
fn acceleration(rows: &[Row], t1: f64, t2: f64) -> f64 {
    let at = |t: f64| {
        rows.iter()
            .find(|r| (r.0 - t).abs() < 0.5 * DT)
            .unwrap_or_else(|| panic!("a row at t = {t}"))
    };
    (at(t2).1[0] - at(t1).1[0]) / (t2 - t1)
}

/// (a) A sphere (D = 1 cm) launched at v₀ = 0.5 m/s without spin on a
/// floor of μ = 0.3: `v(t) = v₀ − μ g t`, `ω(t) = 5 μ g t/(2R)` until
/// `t* = 2 v₀/(7 μ g)` (48.5 ms), then `v = 5 v₀/7`, `ω = v/R`.
/// The sphere starts touching at no overlap (a box admits no body through
/// its floor) and sinks to its resting overlap in a few damped bounces
/// (e = 0.3) while the cap follows the normal force: the sliding phase
/// from 2 ms on is held to 1.5e-3 v₀ on v and on ωR (a friction impulse
/// off by Δp shifts ωR by (5/2) Δp/m). The rolling speed does not depend
/// on that history (the angular momentum about the contact line,
/// `m v R + I ω`, is kept: `v = 5 v₀/7` exactly), and is held to 2e-4 v₀.
/// The ledger books the work of friction: the energy lost is
/// `(2/7) (1/2) m v₀²` (the kinetic energy at `5 v₀/7` with `I ω² = (2/5)
/// m v²`), to 2e-3 relative (the start's normal damping adds a little),
/// and the full budget closes to 1e-3 %.
#[test]
fn a_sliding_sphere_spins_up_and_rolls_at_five_sevenths() {
    let dir = tempfile::tempdir().unwrap();
    let (d, v0, mu) = (0.01, 0.5, 0.3);
    let r = d / 2.0;
    let text = scene(
        0.08,
        [0.0, 0.0, -G],
        &format!("restitution = 0.3\nfriction = {mu}"),
        1000,
        &sphere(d, -0.15, [v0, 0.0, 0.0]),
    );
    let rows = run(dir.path(), "slide", &text);
    let t_star = 2.0 * v0 / (7.0 * mu * G);
    let mut worst = (0.0f64, 0.0f64);
    for &(t, v, w) in &rows {
        let (v_ref, w_ref) = if t < t_star {
            (v0 - mu * G * t, 5.0 * mu * G * t / (2.0 * r))
        } else {
            (5.0 * v0 / 7.0, 5.0 * v0 / (7.0 * r))
        };
        // Within a step's worth of rows of t*, the kink is not resolved.
        if t < 2e-3 || (t - t_star).abs() < 2e-3 {
            continue;
        }
        worst.0 = worst.0.max((v[0] - v_ref).abs());
        worst.1 = worst.1.max(((w[1] - w_ref) * r).abs());
        assert!(v[1].abs() < 1e-12 && w[0].abs() < 1e-9 && w[2].abs() < 1e-9);
    }
    eprintln!(
        "sliding sphere: worst |Δv| {:.3e} m/s, |Δω R| {:.3e} m/s",
        worst.0, worst.1
    );
    assert!(
        worst.0 < 1.5e-3 * v0 && worst.1 < 1.5e-3 * v0,
        "worst |Δv| {:e}, |Δω R| {:e} (tolerance {:e})",
        worst.0,
        worst.1,
        1.5e-3 * v0
    );
    let energy = String::from_utf8(read_bytes(&dir.path().join("slide/energy.csv"))).unwrap();
    let mut lines = energy.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let last: Vec<f64> = (lines.last().unwrap().split(','))
        .map(|x| x.parse().unwrap())
        .collect();
    let (lost, error) = (
        last[col("e_dissipated")],
        last[col("energy_error_full_pct")],
    );
    let m = 1100.0 * std::f64::consts::PI * d * d * d / 6.0;
    let lost_ref = 2.0 / 7.0 * 0.5 * m * v0 * v0;
    eprintln!("dissipated {lost:e} J, closed form {lost_ref:e} J; full budget error {error:e} %");
    assert!(
        (lost / lost_ref - 1.0).abs() < 2e-3,
        "dissipated {lost:e} J, closed form {lost_ref:e} J"
    );
    assert!(error.abs() < 1e-3, "full budget error {error} %");
    let (_, v, w) = rows.last().unwrap();
    let rolling = 5.0 * v0 / 7.0;
    eprintln!(
        "rolling: v {:.3e}, ω R {:.3e} from 5 v₀/7",
        v[0] - rolling,
        w[1] * r - rolling
    );
    assert!(
        (v[0] - rolling).abs() < 2e-4 * v0,
        "rolls at {}, 5 v0/7 = {rolling}",
        v[0]
    );
    assert!(
        (w[1] * r - rolling).abs() < 2e-4 * v0,
        "ω R = {}, 5 v0/7 = {rolling}",
        w[1] * r
    );
}

/// Gravity `g` tilted by `theta` about y: down the slope is +x.
fn tilted(theta: f64) -> [f64; 3] {
    let (s, c) = theta.sin_cos();
    [G * s, 0.0, -G * c]
}

/// (b) A sphere at rest on a floor tilted by 20°: it rolls with
/// `a = (5/7) g sin θ` at μ = 0.3 ≥ (2/7) tan θ = 0.104 (and ω = v/R), and
/// slides with `a = g (sin θ − μ cos θ)` at μ = 0.05. The acceleration is
/// measured between 20 and 60 ms (past the start's settling);
/// tolerance 1e-3 relative.
#[test]
fn a_sphere_on_a_slope_rolls_or_slides() {
    let dir = tempfile::tempdir().unwrap();
    let theta = 20f64.to_radians();
    let (d, r) = (0.01, 0.005);
    for (mu, a_ref, rolls) in [
        (0.3, 5.0 / 7.0 * G * theta.sin(), true),
        (0.05, G * (theta.sin() - 0.05 * theta.cos()), false),
    ] {
        let text = scene(
            0.06,
            tilted(theta),
            &format!("restitution = 0.3\nfriction = {mu}"),
            1000,
            &sphere(d, -0.15, [0.0; 3]),
        );
        let rows = run(dir.path(), &format!("slope_{mu}"), &text);
        let a = acceleration(&rows, 0.02, 0.06);
        eprintln!(
            "sphere, μ = {mu}: a = {a} m/s², closed form {a_ref} (deviation {:.2e})",
            a / a_ref - 1.0
        );
        assert!(
            (a / a_ref - 1.0).abs() < 1e-3,
            "μ = {mu}: a = {a}, closed form {a_ref}"
        );
        let (_, v, w) = rows.last().unwrap();
        let slip = v[0] - w[1] * r;
        if rolls {
            assert!(slip.abs() < 1e-3 * v[0], "rolls without slip: {slip:e} m/s");
        } else {
            assert!(slip > 0.1 * v[0], "slides: slip {slip:e} m/s of {}", v[0]);
        }
    }
}

/// (c) A solid fibre (D = 1 cm, L = 2.5 cm) lying across a floor tilted by
/// 20° (axis along y, horizontal, across the slope) rolls with
/// `a = (2/3) g sin θ` at μ = 0.3 ≥ tan θ/3 = 0.121. Its two end rims
/// carry it (a slot each). Measured between 20 and 60 ms; tolerance 1e-3
/// relative.
#[test]
fn a_fibre_across_a_slope_rolls_at_two_thirds() {
    let dir = tempfile::tempdir().unwrap();
    let theta = 20f64.to_radians();
    let fibre = "[[body]]\nshape = \"fibre\"\nmaterial = \"m\"\ndiameter = 0.01\nlength = 0.025\nposition = [-0.15, 0.0, 0.005]\naxis = [0.0, 1.0, 0.0]\n";
    let text = scene(
        0.06,
        tilted(theta),
        "restitution = 0.3\nfriction = 0.3",
        1000,
        fibre,
    );
    let rows = run(dir.path(), "fibre_slope", &text);
    let a = acceleration(&rows, 0.02, 0.06);
    let a_ref = 2.0 / 3.0 * G * theta.sin();
    eprintln!(
        "fibre across the slope: a = {a} m/s², closed form {a_ref} (deviation {:.2e})",
        a / a_ref - 1.0
    );
    assert!(
        (a / a_ref - 1.0).abs() < 1e-3,
        "a = {a}, closed form {a_ref}"
    );
}

/// (d) `friction = 0` (and `wall_friction = 0`) is the frictionless
/// scene: the same bytes in the trajectory and the energy rows.
#[test]
fn zero_friction_is_the_frictionless_scene_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let body = sphere(0.01, -0.15, [0.5, 0.0, 0.0]);
    let bytes = |name: &str, contact: &str| {
        let text = scene(0.01, [0.0, 0.0, -G], contact, 100, &body);
        run(dir.path(), name, &text);
        let out = dir.path().join(name);
        ["trajectory.csv", "energy.csv"].map(|f| read_bytes(&out.join(f)))
    };
    let plain = bytes("plain", "restitution = 0.3");
    let zero = bytes(
        "zero",
        "restitution = 0.3\nfriction = 0.0\nwall_friction = 0.0",
    );
    assert!(plain == zero, "friction = 0 changed the outputs");
    // And friction does change them (the comparison can fail).
    let some = bytes("some", "restitution = 0.3\nfriction = 0.3");
    assert!(plain[0] != some[0]);
}

/// (e) A dense frictional mixed bed (fibres and spheres, μ = 0.4 body and
/// wall, e = 0.5): the same bytes on 1, 2, 4 and 3 threads.
#[test]
fn a_frictional_mixed_bed_gives_the_same_bytes_at_any_thread_count() {
    let text = crate::common::packed_mixed_scene(6, 8, 8, 6e-4)
        + "[contact]\nrestitution = 0.5\nfriction = 0.4\n";
    crate::threads::same_bytes_with_any_thread_count(&text);
}

/// Negative or non-finite coefficients are refused (exit 2), naming the
/// key.
#[test]
fn a_negative_friction_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (key, value) in [("friction", "-0.1"), ("wall_friction", "nan")] {
        let text = scene(
            0.01,
            [0.0, 0.0, -G],
            &format!("{key} = {value}"),
            100,
            &sphere(0.01, 0.0, [0.0; 3]),
        );
        let file = dir.path().join("bad.toml");
        std::fs::write(&file, text).unwrap();
        let o = fibresim(&[
            "run",
            file.to_str().unwrap(),
            "-o",
            dir.path().join("bad").to_str().unwrap(),
            "-q",
        ]);
        assert_eq!(o.status.code(), Some(2), "{key} = {value}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(key) && err.contains(">= 0"),
            "{key} = {value}: {err}"
        );
    }
}

/// A frictional run's checkpoint is not resumed (its springs are not in
/// it): refused with exit 2, naming friction, before anything runs.
#[test]
fn a_frictional_checkpoint_is_not_resumed() {
    let dir = tempfile::tempdir().unwrap();
    let text = scene(
        2e-3,
        [0.0, 0.0, -G],
        "friction = 0.3",
        100,
        &sphere(0.01, 0.0, [0.1, 0.0, 0.0]),
    );
    let file = dir.path().join("f.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.path().join("f");
    ok(fibresim(&[
        "run",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--checkpoint-every",
        "1000",
        "-q",
    ]));
    let o = fibresim(&[
        "run",
        "--resume",
        out.join("checkpoint.json").to_str().unwrap(),
        "--t-end",
        "3e-3",
        "-q",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("friction") && err.contains("rerun from the start"),
        "{err}"
    );
}

/// A bed settled from a frictional scene keeps its friction (a property of
/// the bodies, not a settling aid as the damping is): the written scenario
/// loads with the same two coefficients, and without the restitution.
#[test]
fn a_settled_frictional_bed_keeps_its_friction() {
    let dir = tempfile::tempdir().unwrap();
    let contact = "restitution = 0.3\nfriction = 0.4\nwall_friction = 0.25";
    let text = scene(
        1e-3,
        [0.0, 0.0, -G],
        contact,
        100,
        &sphere(0.01, 0.0, [0.0; 3]),
    );
    let file = dir.path().join("s.toml");
    std::fs::write(&file, text).unwrap();
    let bed = dir.path().join("bed.toml");
    let out = dir.path().join("o");
    let o = fibresim(&[
        "settle",
        file.to_str().unwrap(),
        "--ke-per-fibre",
        "1",
        "--check-every",
        "100",
        "--write",
        bed.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let written = fibresim::scenario::load(&bed).expect("the settled bed loads");
    let f = written.friction.expect("the bed keeps its friction");
    assert_eq!((f.body, f.wall), (0.4, 0.25));
    assert!(written.damping.is_none());
}
