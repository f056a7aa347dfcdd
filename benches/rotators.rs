//! ns per body-step of each rotator on test case 4.
//!
//! Three figures per rotator: the whole `World::step` with the paper's torque
//! (what a run pays), with a zero torque (the rotator's own arithmetic plus
//! the step's bookkeeping), and on the torque-free asymmetric top. `torque_eval/tc4` is one evaluation of the three
//! compiled torque components.
//! Run: `cargo bench --bench rotators`.

use criterion::{criterion_group, criterion_main, Criterion};
use fibresim::integrate::rotate::{Rotator, RotatorKind, RotatorVisitor};
use fibresim::integrate::step::World;
use fibresim::scenario::{self, Scene};
use std::hint::black_box;
use std::time::{Duration, Instant};

fn tc4(zero_torque: bool) -> Scene {
    let text = include_str!("../scenarios/torque_fibre.toml");
    let text = if zero_torque {
        text.replace(
            r#"torque = ["5e-4*sin(200*pi*t)", "1e-5*exp(3+24*t)", "1e-5*5^(52*t)"]"#,
            r#"torque = ["0", "0", "0"]"#,
        )
    } else {
        text.to_string()
    };
    let mut s = scenario::parse_str(&text, "tc4").unwrap();
    s.sim = scenario::SimParams::with_steps(1e-7, s.sim.steps(), s.sim.rotator(), None).unwrap();
    s
}

/// `n` steps with the rotator the visitor is called with (one dispatch).
struct Steps<'a, 's>(&'a mut World<'s>, u64);

impl RotatorVisitor for Steps<'_, '_> {
    type Output = ();
    fn visit<R: Rotator>(self) {
        for _ in 0..self.1 {
            let _ = black_box(self.0.step::<R>());
        }
    }
}

/// Time `iters` steps, restarting from t = 0 every 1e6 steps (T = 0.1 s).
fn time_steps(scene: &Scene, kind: RotatorKind, iters: u64) -> Duration {
    let mut total = Duration::ZERO;
    let mut left = iters;
    while left > 0 {
        let n = left.min(1_000_000);
        let mut w = World::new(scene);
        let start = Instant::now();
        kind.visit(Steps(&mut w, n));
        total += start.elapsed();
        black_box(&w.states);
        left -= n;
    }
    total
}

/// The torque-free asymmetric top (`scenarios/asymmetric_top.toml`): free
/// rotation alone, no contacts.
fn asymmetric_top() -> Scene {
    let text = include_str!("../scenarios/asymmetric_top.toml");
    scenario::parse_str(text, "asymmetric top").unwrap()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("body_step");
    for (label, scene) in [
        ("tc4", tc4(false)),
        ("zero_torque", tc4(true)),
        ("asym_free", asymmetric_top()),
    ] {
        for kind in RotatorKind::ALL {
            g.bench_function(format!("{}/{label}", kind.name()), |b| {
                b.iter_custom(|iters| time_steps(&scene, kind, iters))
            });
        }
    }
    g.finish();

    let scene = tc4(false);
    let torque = scene.torques[0].torque.clone();
    c.bench_function("torque_eval/tc4", |b| {
        let mut t = 0.0;
        b.iter(|| {
            t += 1e-9;
            black_box(torque.at(black_box(t)))
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
