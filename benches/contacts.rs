//! Test case 2 (nine fibres, δt = 1e-7 s, 2 s = 2e7 steps) on one thread: wall
//! time, ns per step and the share of the step spent in contact detection and
//! forces. A `--bench`-style command, not criterion: one run is 2e7 steps.
//!
//! `cargo bench --bench contacts` runs the whole 2 s twice: once as `fibresim
//! run` does (outputs included: the wall time) and once as a bare step loop
//! with the stage clocks (the shares; the clocks cost four clock reads a
//! step). `-- --quick` runs 0.5 s,
//! which holds the first wall and fibre contacts (t ≈ 0.22 s).

use fibresim::integrate::rotate::Pcdm;
use fibresim::integrate::step::{StageTimes, World};
use fibresim::run::{run, RunOptions};
use std::time::Instant;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/nine_fibres.toml");
    let mut scene = fibresim::scenario::load(std::path::Path::new(path)).unwrap();
    let t_end = if quick { 0.5 } else { 2.0 };
    let steps = (t_end / scene.sim.dt()).round() as u64;
    scene.sim =
        fibresim::scenario::SimParams::with_steps(scene.sim.dt(), steps, scene.sim.rotator(), None)
            .unwrap();
    let steps = scene.sim.steps() as f64;

    // The run as `fibresim run` does it (outputs included), for the wall time.
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions {
        out_dir: dir.path().to_path_buf(),
        ..Default::default()
    };
    let start = Instant::now();
    let outcome = run(&scene, &opts).expect("stable");
    let wall = start.elapsed().as_secs_f64();

    let mut w = World::new(&scene);
    w.timers = Some(StageTimes::default());
    while w.step < scene.sim.steps() {
        w.step::<Pcdm>().expect("stable");
    }
    let t = w.timers.unwrap();
    let builds = w.contacts.as_ref().map_or(0, |c| c.neighbour_builds());
    // (Of the clocked run: the scene's rotator is pcdm, so it is the same
    // run as the timed one.)
    let k = w
        .contacts
        .as_ref()
        .map(|c| c.kernel_counters())
        .unwrap_or_default();
    let total = (t.integrate + t.forces + t.guards).as_secs_f64();
    let share = |d: std::time::Duration| 100.0 * d.as_secs_f64() / total;
    assert_eq!(outcome.steps, scene.sim.steps());
    println!(
        "test case 2, pcdm, {} steps on one thread (as `fibresim run`): wall {wall:.2} s, {:.0} ns/step ({:.1} ns/body-step)",
        scene.sim.steps(),
        wall * 1e9 / steps,
        wall * 1e9 / steps / scene.bodies.len() as f64,
    );
    println!(
        "stage shares (clocked run): contact detection + forces {:.0} %, integration {:.0} %, guards {:.0} %",
        share(t.forces),
        share(t.integrate),
        share(t.guards)
    );
    println!(
        "neighbour-list builds: {builds} (one per {:.0} steps); end-involved feature scans: {} ({:.3} per step), of which fell back to the iterative search: {}; parry calls: {}",
        steps / builds.max(1) as f64,
        k.end_scans,
        k.end_scans as f64 / steps,
        k.fallbacks,
        k.parry_calls
    );
}
