//! The whole `fibresim run scenarios/torque_fibre.toml --dt 1e-7` (1e6 steps,
//! default output cadence), through the library entry point the CLI uses.
//! Run: `cargo bench --bench run`.

use criterion::{criterion_group, criterion_main, Criterion};
use fibresim::run::{run, RunOptions};
use fibresim::scenario;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/torque_fibre.toml");
    let mut scene = scenario::load(std::path::Path::new(path)).unwrap();
    scene.sim =
        scenario::SimParams::new(1e-7, 0.1, scene.sim.rotator(), None, "bench", "--").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions {
        out_dir: dir.path().to_path_buf(),
        progress: false,
        ..Default::default()
    };
    let mut g = c.benchmark_group("run");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    g.bench_function("torque_fibre_1e6_steps", |b| {
        b.iter(|| run(&scene, &opts).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
