//! One fibre–fibre kernel call per pose (issue 10, item 5): criterion
//! medians of `contact_fibre_fibre` for a live pair of each feature type and
//! for the near misses a broad phase hands over. Test case 1's fibre
//! (D = 10 mm, L = 25 mm), live overlaps 10 µm, poses placed in closed form
//! (`common/poses.rs`). Before the timings, each pose's contact count, depth and kernel
//! counters are printed, so a reader can see that a "live" pose touches.
//! Run: `cargo bench --bench kernels` (about 1 min).

use criterion::{criterion_group, criterion_main, Criterion};
use fibresim::contact::{contact_fibre_fibre, KernelCounters};
use std::hint::black_box;
use std::time::Duration;

#[path = "common/poses.rs"]
mod poses;
use poses::poses;

fn bench(c: &mut Criterion) {
    let poses = poses();
    for (name, a, b) in &poses {
        let (mut out, mut k) = (vec![], KernelCounters::default());
        contact_fibre_fibre(a, b, &mut out, &mut k);
        let depth = out.iter().map(|p| p.overlap).fold(0.0, f64::max);
        eprintln!(
            "{name}: {} contact point(s), deepest {depth:.3e} m, counters {k:?}",
            out.len()
        );
    }
    let mut g = c.benchmark_group("fibre_fibre");
    for (name, a, b) in &poses {
        let mut out = Vec::with_capacity(8);
        let mut k = KernelCounters::default();
        g.bench_function(*name, |bch| {
            bch.iter(|| {
                out.clear();
                contact_fibre_fibre(black_box(a), black_box(b), &mut out, &mut k);
                black_box(out.len())
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
