//! What friction costs: a settled fibre bed stepped frictionless and
//! frictional at equal fibres and threads, in alternated rounds, printing
//! each law's median fibre-steps/s and the frictional ones' cost over
//! their frictionless partner (a `--bench`-style command, not criterion:
//! one sample is hundreds of steps of a whole bed).
//!
//! ```sh
//! cargo bench --bench friction                                  # bed_1k, 1 thread
//! cargo bench --bench friction -- FILE --steps 2000 --rounds 5 --threads 2
//! ```
//!
//! The four laws: elastic, damped (restitution 0.5), frictional (μ = 0.3,
//! elastic normal) and frictional damped (μ = 0.3, restitution 0.5). The
//! honest pair is frictional damped against damped (a frictional bed
//! normally has a restitution); frictional against elastic is printed too.
//! Each round runs every law once, in turn, from the same settled state.

#[path = "common/stepping.rs"]
mod stepping;
use fibresim::contact::damping::Restitution;
use fibresim::contact::tangential::Friction;
use fibresim::integrate::step::World;
use fibresim::scenario::Scene;
use std::time::Instant;
use stepping::{median, Steps};

fn main() {
    let args = stepping::args();
    let flag = |name: &str| stepping::flag(&args, name);
    let steps: u64 = flag("--steps").map_or(2000, |s| s.parse().expect("--steps N"));
    let rounds: usize = flag("--rounds").map_or(5, |s| s.parse().expect("--rounds N"));
    let threads: usize = flag("--threads").map_or(1, |s| s.parse().expect("--threads N"));
    let file = args
        .iter()
        .find(|a| a.ends_with(".toml"))
        .cloned()
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/bed_1k.toml").into());
    let bed = fibresim::scenario::load(std::path::Path::new(&file)).expect("the bed loads");
    let law = |restitution: Option<f64>, mu: Option<f64>| Scene {
        damping: restitution.map(|e| Restitution { fibre: e, wall: e }),
        friction: mu.map(|mu| Friction { body: mu, wall: mu }),
        ..bed.clone()
    };
    let laws = [
        ("elastic", law(None, None)),
        ("damped (e = 0.5)", law(Some(0.5), None)),
        ("frictional (mu = 0.3)", law(None, Some(0.3))),
        ("frictional damped", law(Some(0.5), Some(0.3))),
    ];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let n = bed.bodies.len() as f64;
    let mut rates = vec![vec![]; laws.len()];
    for _ in 0..rounds {
        for (rate, (_, scene)) in rates.iter_mut().zip(&laws) {
            pool.install(|| {
                let mut w = World::new(scene);
                scene.sim.rotator().visit(Steps(&mut w, 2)); // warm the buffers
                let start = Instant::now();
                scene.sim.rotator().visit(Steps(&mut w, steps));
                rate.push(n * steps as f64 / start.elapsed().as_secs_f64());
            });
        }
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "{file}: {n} fibres, {steps} steps, {threads} thread(s), medians of {rounds} alternated rounds (load average after: {})",
        load.trim()
    );
    let medians: Vec<f64> = rates.into_iter().map(median).collect();
    for ((name, _), m) in laws.iter().zip(&medians) {
        println!("  {name:<24} {m:.4e} fibre-steps/s");
    }
    let cost = |a: usize, b: usize| 100.0 * (medians[b] / medians[a] - 1.0);
    println!(
        "  frictional damped over damped: {:+.1} % time; frictional over elastic: {:+.1} %",
        cost(3, 1),
        cost(2, 0)
    );
}
