//! One fibre–fibre kernel call per pose: criterion
//! medians of `contact_fibre_fibre` for a live pair of each feature type and
//! for the near misses a broad phase hands over. Test case 1's fibre
//! (D = 10 mm, L = 25 mm), live overlaps 10 µm, poses placed in closed form
//! (`common/poses.rs`). Before the timings, each pose's contact count, depth and kernel
//! counters are printed, so a reader can see that a "live" pose touches.
//! The second group, `remembered`, times the same call for a pair that
//! remembers its last scan (`contact/fibre_fibre/coherence.rs`): one scan
//! makes the memory, then each call runs the winner's kernel (no motion, so
//! the memory never runs out); a pose whose scan made no memory (a blend, a
//! crossing, a miss the capsules settle) is left out.
//! Run: `cargo bench --bench kernels` (about 1 min).

use criterion::{criterion_group, criterion_main, Criterion};
use fibresim::contact::{
    contact_fibre_fibre, contact_fibre_fibre_remembering, KernelCounters, PairMemory,
};
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
    let mut g = c.benchmark_group("remembered");
    for (name, a, b) in &poses {
        let (mut out, mut k) = (Vec::with_capacity(8), KernelCounters::default());
        let mut memory = PairMemory::default();
        contact_fibre_fibre_remembering(a, b, &mut out, &mut k, Some((&mut memory, 0.0)));
        if memory == PairMemory::default() {
            continue;
        }
        g.bench_function(*name, |bch| {
            bch.iter(|| {
                out.clear();
                let m = Some((&mut memory, 0.0));
                contact_fibre_fibre_remembering(black_box(a), black_box(b), &mut out, &mut k, m);
                black_box(out.len())
            })
        });
        assert!(k.remembered > 0, "{name} is remembered");
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
