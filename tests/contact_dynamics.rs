//! Contact dynamics with whole runs (issue 3, item 7). Each reference value is a
//! conservation law, a symmetry, or the closed-form Hertz collision time.

mod common;
use common::*;
use fibresim::integrate::rotate::RotatorKind;
use fibresim::run::integrate_observed;
use fibresim::scenario::Scene;
use glam::DVec3;

const FIBRE: &str = r#"
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
young = 5e7
poisson = 0.35
"#;

fn scene(sim: &str, extra: &str, bodies: &[&str]) -> Scene {
    let mut t = format!("[simulation]\n{sim}\n{extra}\n");
    for b in bodies {
        t += &format!("[[body]]\n{FIBRE}{b}\n");
    }
    scene_str(&t)
}

const BOX: &str = "[world]\ngravity = [0.0, 0.0, -9.81]\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nyoung = 5e7\npoisson = 0.23\n";

fn momentum(s: &Scene, w: &fibresim::integrate::step::World) -> (DVec3, DVec3) {
    let mut p = DVec3::ZERO;
    let mut l = DVec3::ZERO;
    for (b, st) in s.bodies.iter().zip(&w.states) {
        p += b.mass * st.v;
        let spin = st.rot.q * (b.inertia.principal * st.rot.omega_b);
        l += b.mass * st.x.cross(st.v) + spin;
    }
    (p, l)
}

/// Two free fibres crossed at 90°, head-on at 1 m/s each (no walls, no gravity).
/// Hertz collision time for `m* δ'' = −k δ^{3/2}`: `t_c = 2 (δ_max/v) ∫₀¹ dx/√(1−x^{5/2})`,
/// `δ_max = (5 m* v²/(4k))^{2/5}`, and the integral is `(2/5) B(2/5, 1/2)
/// = (2/5) Γ(2/5) Γ(1/2)/Γ(9/10)` (Γ values from Abramowitz & Stegun, Table 6.1).
#[test]
fn head_on_collision_conserves_and_lasts_the_hertz_time() {
    let s = scene(
        "dt = 1e-7\nt_end = 0.03",
        "",
        &[
            "position = [-0.0101, 0.0, 0.0]\naxis = [0.0, 1.0, 0.0]\nvelocity = [1.0, 0.0, 0.0]",
            "position = [0.0101, 0.0, 0.0]\naxis = [0.0, 0.0, 1.0]\nvelocity = [-1.0, 0.0, 0.0]",
        ],
    );
    for kind in [RotatorKind::Pcdm, RotatorKind::Leapfrog] {
        let mut s = s.clone();
        s.sim.rotator = kind;
        let w0 = fibresim::integrate::step::World::new(&s);
        let (p0, l0) = momentum(&s, &w0);
        let e0: f64 = s.bodies.iter().map(|b| 0.5 * b.mass * 1.0).sum();
        let mut touching_steps = 0u64;
        let w = integrate_observed(&s, |w| {
            if w.contact_stats().unwrap().touching > 0 {
                touching_steps += 1;
            }
        })
        .unwrap();
        let (p, l) = momentum(&s, &w);
        let e: f64 = s
            .bodies
            .iter()
            .zip(&w.states)
            .map(|(b, st)| {
                0.5 * b.mass * st.v.length_squared() + b.inertia.kinetic_energy(st.rot.omega_b)
            })
            .sum();
        // Closed-form collision time.
        let b = &s.bodies[0];
        let e_star = 1.0 / (2.0 * (1.0 - 0.35f64.powi(2)) / 5e7);
        let r_star: f64 = 1.0 / (2.0 / 0.01 + 2.0 / 0.01);
        let k = 4.0 / 3.0 * e_star * r_star.sqrt();
        let m_star = b.mass / 2.0;
        let v = 2.0;
        let d_max = (5.0 * m_star * v * v / (4.0 * k)).powf(0.4);
        let integral =
            0.4 * 2.218_159_543_757_688 * std::f64::consts::PI.sqrt() / 1.068_628_702_119_319_4;
        let t_c = 2.0 * d_max / v * integral;
        let t_sim = touching_steps as f64 * 1e-7;
        println!(
            "{kind}: t_c sim {t_sim:.6e} s, closed form {t_c:.6e} s; |dp| {:.1e}, |dL| {:.1e}, dE/E {:.1e}",
            (p - p0).length(),
            (l - l0).length(),
            (e - e0) / e0
        );
        assert!((t_sim - t_c).abs() < 2e-3 * t_c, "{t_sim} vs {t_c}");
        assert!((p - p0).length() < 1e-15);
        assert!((l - l0).length() < 1e-15);
        // Central collision: nothing should spin.
        assert!(w.states.iter().all(|st| st.rot.omega_b.length() < 1e-9));
        assert!(((e - e0) / e0).abs() < 1e-6);
        // Elastic: the fibres separate with the speeds they came in with.
        assert!((w.states[0].v.x + 1.0).abs() < 1e-6 && (w.states[1].v.x - 1.0).abs() < 1e-6);
    }
}

/// A fibre dropped flat (axis parallel to the floor) bounces back to its start
/// height with no spin: both ends touch together, so the torques cancel.
#[test]
fn flat_drop_returns_to_start_height_without_spin() {
    let z0 = 0.02;
    let s = scene(
        "dt = 1e-6\nt_end = 0.12\nrotator = \"pcdm\"",
        BOX,
        &[&format!(
            "position = [0.5, 0.5, {z0}]\naxis = [1.0, 0.0, 0.0]"
        )],
    );
    let mut apex_after_bounce: f64 = 0.0;
    let mut bounced = false;
    let mut max_spin: f64 = 0.0;
    integrate_observed(&s, |w| {
        let st = w.states[0];
        if st.v.z > 0.0 {
            bounced = true;
        }
        if bounced {
            apex_after_bounce = apex_after_bounce.max(st.x.z);
        }
        max_spin = max_spin.max(st.rot.omega_b.length());
    })
    .unwrap();
    println!("flat drop: apex {apex_after_bounce:.9} m (start {z0}), max |w| {max_spin:.1e} rad/s");
    assert!(bounced);
    assert!(
        (apex_after_bounce - z0).abs() < 1e-6 * z0 * 100.0,
        "{apex_after_bounce}"
    );
    assert!(max_spin < 1e-8, "{max_spin}");
}

/// A fibre dropped on its end face bounces straight up, no tilt, no drift.
#[test]
fn end_on_drop_bounces_straight() {
    let z0 = 0.03;
    let s = scene(
        "dt = 1e-6\nt_end = 0.12\nrotator = \"pcdm\"",
        BOX,
        &[&format!(
            "position = [0.5, 0.5, {z0}]\naxis = [0.0, 0.0, 1.0]"
        )],
    );
    let mut bounced = false;
    let mut apex: f64 = 0.0;
    let w = integrate_observed(&s, |w| {
        let st = w.states[0];
        bounced |= st.v.z > 0.0;
        if bounced {
            apex = apex.max(st.x.z);
        }
    })
    .unwrap();
    let st = w.states[0];
    println!(
        "end-on drop: apex {apex:.9} (start {z0}), v_xy {:.1e}, |w| {:.1e}",
        st.v.truncate().length(),
        st.rot.omega_b.length()
    );
    assert!(bounced);
    assert!((apex - z0).abs() < 1e-4 * z0, "{apex}");
    assert!(st.v.truncate().length() < 1e-9);
    assert!(st.rot.omega_b.length() < 1e-8);
    assert!(((st.rot.q * DVec3::X) - DVec3::Z).length() < 1e-9);
}

/// Two fibres, mirror images about the plane x = 0.5 (positions and speeds exact
/// in binary), tilted 10° in the y–z plane and thrown at each other over the
/// floor: corner impacts on the floor, then a side–side contact between them.
/// The motion stays mirror-symmetric.
#[test]
fn symmetric_drop_stays_symmetric() {
    let (c, s10) = (10f64.to_radians().cos(), 10f64.to_radians().sin());
    let s = scene(
        "dt = 1e-6\nt_end = 0.15\nrotator = \"pcdm\"",
        BOX,
        &[
            &format!("position = [0.484375, 0.5, 0.03125]\naxis = [0.0, {c}, {s10}]\nvelocity = [0.25, 0.0, 0.0]"),
            &format!("position = [0.515625, 0.5, 0.03125]\naxis = [0.0, {c}, {s10}]\nvelocity = [-0.25, 0.0, 0.0]"),
        ],
    );
    let mirror = |v: DVec3| DVec3::new(-v.x, v.y, v.z);
    let mut worst: f64 = 0.0;
    let mut touched_each_other = false;
    integrate_observed(&s, |w| {
        let (a, b) = (w.states[0], w.states[1]);
        let pos = (a.x - DVec3::new(1.0 - b.x.x, b.x.y, b.x.z)).length();
        let vel = (a.v - mirror(b.v)).length();
        // A mirrored axis is the same fibre up to the sign of its axis.
        let (ax, bx) = (a.rot.q * DVec3::X, mirror(b.rot.q * DVec3::X));
        let axis = (ax - bx).length().min((ax + bx).length());
        worst = worst.max(pos).max(vel).max(axis);
        // Parallel axes: the fibres touch when their centres are closer than D.
        touched_each_other |= b.x.x - a.x.x < 0.01;
    })
    .unwrap();
    println!("symmetric drop: largest asymmetry {worst:.1e}");
    assert!(
        touched_each_other,
        "the test must include a fibre–fibre contact"
    );
    assert!(worst < 1e-9, "{worst}");
}

/// Test case 1 over its first bounce (0.33 s, δt = 1e-7): the full-budget energy
/// error stays below 0.2 %, the paper's Fig. 2 bound for all methods.
#[test]
fn test_case_1_first_bounce_energy_bounded() {
    let mut s = scene_file("single_fibre.toml");
    s.sim.steps = 3_300_000;
    for kind in [RotatorKind::Pcdm, RotatorKind::Leapfrog] {
        s.sim.rotator = kind;
        let e = |w: &fibresim::integrate::step::World| {
            fibresim::energy::Ledger::measure(&s.bodies, &w.states, s.gravity, w.elastic)
                .total_full()
        };
        let e0 = e(&fibresim::integrate::step::World::new(&s));
        let mut worst: f64 = 0.0;
        let mut contact = false;
        integrate_observed(&s, |w| {
            worst = worst.max(((e(w) - e0) / e0).abs() * 100.0);
            contact |= w.contact_stats().unwrap().touching > 0;
        })
        .unwrap();
        println!("test case 1, first bounce, {kind}: max full-budget error {worst:.3e} %");
        assert!(contact);
        assert!(worst < 0.2, "{kind}: {worst}");
    }
}
