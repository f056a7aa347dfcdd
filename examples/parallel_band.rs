//! A parallel pair of fibres sliding through the line-contact band, and
//! the tangential force it keeps: a measurement of a known defect of the
//! friction springs' slot rule (docs/contacts.md, "Friction", "Not yet").
//!
//! A lies on B (both along x, pressed 20 µm), slides along x at 0.2 m/s and
//! turns about z at 1 rad/s from 3.4° to −3.4°, through the parallel band
//! (|sin| < 0.035: the line contact's two points, blended with the
//! crossing's single point down to |sin| 0.02). The contact slides
//! throughout, so the tangential force should stay at the Coulomb cap:
//! `|F_xy|/(μ F_z)` ≈ 1 (within 0.2 %: the blended normals are not exactly
//! z). Where a slot (the point's rank in the kernel's output) meets a point
//! without its spring, the force drops and climbs back over tens of steps.
//! This prints every drop of more than 1 % in one step after the first
//! 1000 steps (the new contact's spring loading).
//!
//!     cargo run --release --example parallel_band

use glam::{DQuat, DVec3};

fn main() {
    let (d, l, mu, dt) = (0.01, 0.03, 0.3, 1e-6);
    let text = format!(
        "[simulation]\ndt = {dt}\nt_end = 0.001\n[contact]\nfriction = {mu}\n[material.m]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n[[body]]\nshape = \"fibre\"\nmaterial = \"m\"\ndiameter = {d}\nlength = {l}\nposition = [0.0, 0.0, 0.00998]\naxis = [1.0, 0.0, 0.0]\n[[body]]\nshape = \"fibre\"\nmaterial = \"m\"\ndiameter = {d}\nlength = {l}\nposition = [0.0, 0.0, 0.0]\naxis = [1.0, 0.0, 0.0]\n[guards]\nstart_overlap_ratio = 0.01\n"
    );
    let scene = fibresim::scenario::parse_str(&text, "parallel_band.toml").expect("loads");
    let mut stage =
        fibresim::contact::stage::ContactStage::new(&scene.bodies, &scene.materials, None)
            .with_friction(scene.friction, dt);
    let (v, w, phi0) = (DVec3::new(0.2, 0.0, 0.0), -1.0, 0.06);
    let steps = (2.0 * phi0 / -w / dt) as usize;
    let mut rows = vec![];
    for k in 0..steps {
        let t = k as f64 * dt;
        let mut states = scene.initial.clone();
        states[0].x = DVec3::new(0.0, 0.0, 0.00998) + v * t;
        states[0].v = v;
        states[0].rot.q = DQuat::from_rotation_z(phi0 + w * t);
        states[0].rot.omega_b = DVec3::new(0.0, 0.0, w);
        let mut force = vec![DVec3::ZERO; 2];
        let mut torque = vec![DVec3::ZERO; 2];
        stage.compute(&scene.bodies, &states, &mut force, &mut torque);
        let f = force[0];
        rows.push((
            (phi0 + w * t).sin(),
            (f.x * f.x + f.y * f.y).sqrt() / (mu * f.z),
        ));
    }
    let above = rows[1000..].iter().map(|r| r.1).fold(0.0, f64::max);
    println!("largest |F_t|/(μ F_n) after the loading: {above:.5} (the cap: 1)");
    let mut drops = 0;
    for k in 1001..rows.len() {
        if rows[k - 1].1 - rows[k].1 > 1e-2 {
            drops += 1;
            println!(
                "at sin {:.4}: |F_t|/(μ F_n) {:.4} -> {:.4}",
                rows[k].0,
                rows[k - 1].1,
                rows[k].1
            );
        }
    }
    println!("{drops} one-step drops of more than 1 % of the cap");
}
