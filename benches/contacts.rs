//! Test case 2 (nine fibres, δt = 1e-7 s) on one thread: wall time, ns per step
//! and the share of the step spent in contact detection and forces.
//! A `--bench`-style command, not criterion: one run is 2e7 steps.
//!
//! `cargo bench --bench contacts` runs 0.2 s of simulated time (2e6 steps) three
//! times and prints the medians; `cargo bench --bench contacts -- --full` runs
//! the whole 2 s once.

use fibresim::integrate::rotate::Pcdm;
use fibresim::integrate::step::{StageTimes, World};
use std::time::Instant;

fn main() {
    let full = std::env::args().any(|a| a == "--full");
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/nine_fibres.toml");
    let mut scene = fibresim::scenario::load(std::path::Path::new(path)).unwrap();
    let t_end = if full { 2.0 } else { 0.2 };
    scene.sim.steps = (t_end / scene.sim.dt).round() as u64;
    let repeats = if full { 1 } else { 3 };
    let mut results = vec![];
    for _ in 0..repeats {
        // Untimed run: the end-to-end wall time without stage clocks.
        let mut w = World::new(&scene);
        let start = Instant::now();
        while w.step < scene.sim.steps {
            w.step::<Pcdm>().expect("stable");
        }
        let wall = start.elapsed().as_secs_f64();
        // Timed run: the stage shares.
        let mut w = World::new(&scene);
        w.timers = Some(StageTimes::default());
        while w.step < scene.sim.steps {
            w.step::<Pcdm>().expect("stable");
        }
        let t = w.timers.unwrap();
        let total = (t.integrate + t.forces + t.guards).as_secs_f64();
        results.push((
            wall,
            t.forces.as_secs_f64() / total,
            t.integrate.as_secs_f64() / total,
        ));
    }
    results.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (wall, forces, integrate) = results[results.len() / 2];
    let steps = scene.sim.steps as f64;
    println!(
        "test case 2, pcdm, {} steps: wall {:.3} s ({:.0} ns/step, {:.0} ns/body-step); contact detection+forces {:.0} %, integration {:.0} %; projected 2e7 steps: {:.1} s",
        scene.sim.steps,
        wall,
        wall * 1e9 / steps,
        wall * 1e9 / steps / 9.0,
        forces * 100.0,
        integrate * 100.0,
        wall / steps * 2e7
    );
}
