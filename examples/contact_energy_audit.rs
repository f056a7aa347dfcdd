//! Contact energy audit: replay a run from a checkpoint and check every live
//! contact's force and torque against central finite differences of its
//! potential. This is how the end-on-end torque bug and the side–side/end
//! regime switch were found (docs/contacts.md, "History").
//!
//! ```sh
//! fibresim run scenarios/nine_fibres.toml --t-end 1.2036 --checkpoint-every 12036000 --out /tmp/a
//! cargo run --release --example contact_energy_audit -- /tmp/a/checkpoint.json 1.2040 200
//! ```
//! Arguments: checkpoint, end time, print every N steps, and optionally a
//! step from which every contact's pose is printed in full.

use fibresim::body::Shape;
use fibresim::contact::*;
use fibresim::integrate::step::World;
use fibresim::output::Checkpoint;
use glam::{DQuat, DVec3};

/// Poses whose gradient mismatch exceeds this are printed in full (to paste
/// into a regression test).
const DUMP_ABOVE: f64 = 1e-3;

type Kernel<'a> = &'a dyn Fn(&FibreGeom, &mut Vec<ContactPoint>);

/// Potential, force and torque on `a` from one kernel.
fn evaluate(a: &FibreGeom, law: &HertzLaw, kernel: Kernel) -> (f64, DVec3, DVec3, usize) {
    let mut pts = vec![];
    kernel(a, &mut pts);
    let (mut u, mut f, mut t) = (0.0, DVec3::ZERO, DVec3::ZERO);
    for p in &pts {
        u += p.weight * law.energy(p.overlap);
        let fi = p.weight * law.force(p.overlap) * p.normal;
        f += fi;
        t += (p.point - a.centre).cross(fi) - law.energy(p.overlap) * p.weight_grad;
    }
    (u, f, t, pts.len())
}

/// Largest relative mismatch between the returned force/torque and −∇U.
fn audit(a: &FibreGeom, law: &HertzLaw, kernel: Kernel) -> Option<(f64, f64, usize)> {
    let (u, f, t, n) = evaluate(a, law, kernel);
    if n == 0 {
        return None;
    }
    let eps = 1e-8;
    let scale = f.length().max(1e-12);
    let mut worst: f64 = 0.0;
    for k in 0..3 {
        let shift = |s: f64| FibreGeom {
            centre: a.centre + s * DVec3::AXES[k],
            ..*a
        };
        let turn = |s: f64| FibreGeom {
            axis: DQuat::from_axis_angle(DVec3::AXES[k], s) * a.axis,
            ..*a
        };
        let gf = -(evaluate(&shift(eps), law, kernel).0 - evaluate(&shift(-eps), law, kernel).0)
            / (2.0 * eps);
        let gt = -(evaluate(&turn(eps), law, kernel).0 - evaluate(&turn(-eps), law, kernel).0)
            / (2.0 * eps);
        worst = worst
            .max((gf - f[k]).abs() / scale)
            .max((gt - t[k]).abs() / (scale * a.radius));
    }
    Some((u, worst, n))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let c = Checkpoint::read(std::path::Path::new(&args[1])).expect("checkpoint");
    let until: f64 = args[2].parse().expect("end time");
    let every: u64 = args.get(3).map_or(200, |s| s.parse().expect("N"));
    // Optional: print every contact's full pose from this step on.
    let dump_from: u64 = args.get(4).map_or(u64::MAX, |s| s.parse().expect("step"));
    let scene = fibresim::run::scene_from_checkpoint(&c, Some(until)).expect("scene");
    let mut w = World::new(&scene);
    let (states, aux, _) =
        fibresim::output::checkpoint::restore(&c, &scene, 0).expect("checkpoint of this scene");
    let damped = fibresim::output::checkpoint::restore_damping(&c, &scene)
        .expect("checkpoint of this scene");
    w.restore(states, aux, c.step, c.memory.clone());
    if let Some(d) = damped {
        w.restore_damping(d);
    }
    let e0 = w.e0_full;
    let geom = |w: &World, i: usize| {
        let Shape::Fibre { diameter, length } = scene.bodies[i].shape else {
            panic!("fibres only")
        };
        FibreGeom {
            centre: w.states[i].x,
            // The stage's axis, bit for bit.
            axis: fibresim::math::body_x_axis(w.states[i].rot.q),
            radius: 0.5 * diameter,
            half_length: 0.5 * length,
        }
    };
    let walls = scene.walls.as_ref().map(box_walls).unwrap_or_default();
    // The audit's own kernel calls (the world's stage keeps its own).
    let counters = std::cell::Cell::new(KernelCounters::default());
    while w.step < scene.sim.steps() {
        w.step_kind(scene.sim.rotator()).expect("step");
        if !w.step.is_multiple_of(every) {
            continue;
        }
        println!(
            "step {} t {:.7} full-budget error {:+.4e} %",
            w.step,
            w.time(),
            (w.ledger.total_full() - e0) / e0 * 100.0
        );
        let n = scene.bodies.len();
        for i in 0..n {
            let (bi, mi, gi) = (&scene.bodies[i], scene.material(i), geom(&w, i));
            for j in i + 1..n {
                let (bj, mj, gj) = (&scene.bodies[j], scene.material(j), geom(&w, j));
                let law = HertzLaw::fibre_fibre(
                    bi.shape.diameter(),
                    mi.young,
                    mi.poisson,
                    bj.shape.diameter(),
                    mj.young,
                    mj.poisson,
                );
                let kernel = |a: &FibreGeom, out: &mut Vec<ContactPoint>| {
                    let mut k = counters.get();
                    contact_fibre_fibre(a, &gj, out, &mut k);
                    counters.set(k);
                };
                if let Some((u, worst, k)) = audit(&gi, &law, &kernel) {
                    let sin = gi.axis.cross(gj.axis).length();
                    println!("  {i}-{j}: {k} points, U {u:.3e} J, |sin| {sin:.4}, worst gradient mismatch {worst:.1e}");
                    if worst > DUMP_ABOVE || w.step >= dump_from {
                        println!("    A = {gi:?}\n    B = {gj:?}");
                    }
                }
            }
            if let Some(wl) = &scene.walls {
                let law = HertzLaw::fibre_wall(
                    bi.shape.diameter(),
                    mi.young,
                    mi.poisson,
                    wl.young,
                    wl.poisson,
                );
                for (k, wall) in walls.iter().enumerate() {
                    if let Some((u, worst, m)) =
                        audit(&gi, &law, &|a, out| contact_fibre_wall(a, wall, out))
                    {
                        println!("  {i}-wall{k}: {m} points, U {u:.3e} J, worst gradient mismatch {worst:.1e}");
                        if worst > DUMP_ABOVE || w.step >= dump_from {
                            println!("    fibre = {gi:?}\n    wall = {wall:?}");
                        }
                    }
                }
            }
        }
    }
    let stage = w.contacts.as_ref().map(|c| c.kernel_counters());
    for (name, k) in [
        ("run", stage.unwrap_or_default()),
        ("audit", counters.get()),
    ] {
        println!(
            "parry ({name}): {} calls, {} answers rejected, {} 'no contact' verdicts not confirmed",
            k.parry_calls, k.parry_rejects, k.parry_unconfirmed
        );
    }
}
